"""The package's shape, checked statically from the sources: the layering that the folders promise holds.

- no import cycle between the modules of sph_fsi_core (imports inside functions count too);
- no module imports another module's private (underscore) name, nor reads or writes a private attribute that
  another module's classes own (`sim._x` where `self._x` is set in simulation.py, read from diagnostics.py);
- the floors (FLOORS): a module imports only modules of its own room (its package or file) or of a lower floor, so
  no arrow runs back up: the physics know no scene, what states a scene's answer sits below the scenes, what runs
  scenes and writes reports above them;
- sph_fsi_core never imports sph_fsi (the node, the CLI, the recorders only read the core's state).

The last test runs the checks on a made-up package with each fault, so a check that can no longer fail is noticed.
"""
import ast
import textwrap
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
# sph_fsi_core's rooms (its subpackages and top-level modules) floor by floor, the ground first
FLOORS = (
    ("errors",),                                                 # the user's errors
    ("numerics", "state", "diagnostics", "motion"),              # shared numerics, the particle arrays, motions
    ("solid", "fluid", "coupling", "boundary", "probes", "vtk_snapshots"),   # the phases and what reads them
    ("schema", "jit_cache"),                                     # every key; the kernels' cache
    ("geometry", "memory_guard", "checkpoint"),                  # shapes on the lattice, guards, checkpoints
    ("answers",),                                                # what a scene's answer is judged against
    ("scenes",),                                                 # the builders
    ("scene",),                                                  # loading a scene file
    ("simulation",),                                             # the time loop
    ("run", "precompile"),                                       # runs, compiling ahead
    ("validation",),                                             # what runs scenes and writes the reports
)


def modules(root, package):
    """{dotted module name: path} of every module under root/package."""
    out = {}
    for path in (root / package).rglob("*.py"):
        parts = path.relative_to(root).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        out[name] = path
    return out


def imports(name, path, known):
    """[(imported module, [imported names])] of one module, relative imports resolved, names that are modules
    resolved to those modules."""
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[:len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            names = []
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                if sub in known:
                    found.append((sub, []))
                else:
                    names.append(alias.name)
            if names:
                found.append((target, names))
        elif isinstance(node, ast.Import):
            found += [(alias.name, []) for alias in node.names]
    return found


def graph(root, package):
    known = modules(root, package)
    return known, {name: imports(name, path, known) for name, path in known.items()}


def cycles(known, edges):
    """Modules that can reach themselves through imports (a package's __init__ importing its own modules does not
    count: that is how a package exports, not a dependency)."""
    deps = {m: {t for t, _ in edges[m] if t in known and not t.startswith(m + ".")} for m in known}
    bad = []
    for start in sorted(known):
        seen, stack = set(), list(deps[start])
        while stack:
            m = stack.pop()
            if m == start:
                bad.append(start)
                break
            if m not in seen:
                seen.add(m)
                stack += deps[m]
    return bad


def private_imports(known, edges):
    return [f"{m} imports {t}.{n}" for m in sorted(known) for t, names in edges[m] for n in names
            if n.startswith("_") and not n.startswith("__") and t in known]


def private_attributes_owned(path):
    """Private attribute names a module's classes own: assigned as `self._x` (or `cls._x`) or declared in a class
    body (methods included)."""
    owned = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if (isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store) and isinstance(node.value, ast.Name)
                and node.value.id in ("self", "cls")):
            owned.add(node.attr)
        elif isinstance(node, ast.ClassDef):
            for item in node.body:
                if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    owned.add(item.name)
                elif isinstance(item, (ast.Assign, ast.AnnAssign)):
                    targets = item.targets if isinstance(item, ast.Assign) else [item.target]
                    owned |= {t.id for t in targets if isinstance(t, ast.Name)}
    return {name for name in owned if name.startswith("_") and not name.startswith("__")}


def foreign_private_attributes(paths):
    """`obj._x` outside `self`/`cls` where `_x` is owned by another module's classes: [(module path, line, name)]."""
    owners = {}
    for path in paths:
        for name in private_attributes_owned(path):
            owners.setdefault(name, set()).add(path)
    bad = []
    for path in paths:
        for node in ast.walk(ast.parse(path.read_text())):
            if (isinstance(node, ast.Attribute) and node.attr in owners and path not in owners[node.attr]
                    and not (isinstance(node.value, ast.Name) and node.value.id in ("self", "cls"))):
                bad.append((path.name, node.lineno, node.attr))
    return sorted(bad)


def floor_of(module, core, floors):
    """(floor, room) of a module of `core` (None for the package itself, its face)."""
    parts = module.split(".")
    if len(parts) < 2:
        return None
    for level, rooms in enumerate(floors):
        if parts[1] in rooms:
            return level, parts[1]
    raise AssertionError(f"{module}: on no floor of FLOORS; give its room a floor")


def layer_violations(known, edges, core, floors=FLOORS):
    """Imports that run back up (to a higher floor, or across rooms of one floor), and imports of sph_fsi."""
    bad = []
    for m in sorted(known):
        here = floor_of(m, core, floors)
        for t, _ in edges[m]:
            if t.split(".")[0] == "sph_fsi":
                bad.append(f"{m} imports {t}")
                continue
            if here is None or t.split(".")[0] != core:
                continue
            there = floor_of(t, core, floors)
            if there is not None and there[1] != here[1] and there[0] >= here[0]:
                bad.append(f"{m} imports {t}")
    return bad


def test_core_has_no_import_cycle():
    known, edges = graph(REPO, "sph_fsi_core")
    assert len(known) > 30
    assert cycles(known, edges) == []


def test_no_module_imports_a_private_name():
    for package in ("sph_fsi_core", "sph_fsi"):
        known, edges = graph(REPO, package)
        assert private_imports(known, edges) == [], package


def test_no_module_reaches_into_another_modules_private_attributes():
    paths = [p for package in ("sph_fsi_core", "sph_fsi", "bench") for p in (REPO / package).rglob("*.py")]
    assert len(paths) > 40
    assert foreign_private_attributes(paths) == []


def test_no_import_runs_back_up_a_floor():
    known, edges = graph(REPO, "sph_fsi_core")
    assert any(m.startswith("sph_fsi_core.solid.") for m in known)
    assert layer_violations(known, edges, "sph_fsi_core") == []


def test_the_checks_catch_each_fault(tmp_path):
    files = {
        "bad/__init__.py": "",
        "bad/a.py": "from .b import helper\n",
        "bad/b.py": "def f():\n    from .a import x\nfrom .c import _secret\n",
        "bad/c.py": "_secret = 1\n",
        "bad/solid/__init__.py": "",
        "bad/solid/stepper.py": "from ..simulation import Simulation\nimport sph_fsi.node\n",
        "bad/simulation.py": "class Sim:\n    def __init__(self):\n        self._positions = 0\n"
                             "    def copy(self, other):\n        return other._positions\n",
        "bad/diagnostics.py": "def trip(sim):\n    return sim._positions\n",
    }
    for rel, text in files.items():
        path = tmp_path / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text))
    known, edges = graph(tmp_path, "bad")
    assert cycles(known, edges) == ["bad.a", "bad.b"]
    assert private_imports(known, edges) == ["bad.b imports bad.c._secret"]
    floors = (("c", "diagnostics"), ("solid",), ("a", "b", "simulation"))
    assert layer_violations(known, edges, "bad", floors) == [
        "bad.a imports bad.b", "bad.b imports bad.a",     # two rooms of one floor
        "bad.solid.stepper imports bad.simulation",       # an arrow back up
        "bad.solid.stepper imports sph_fsi.node"]
    assert foreign_private_attributes(sorted((tmp_path / "bad").rglob("*.py"))) == [("diagnostics.py", 2,
                                                                                       "_positions")]
