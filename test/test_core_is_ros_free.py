"""The simulator core and the command line must work without ROS.

Two independent checks:
- dynamic: in a fresh interpreter where every ROS module is made unimportable, import every module of
  sph_fsi_core and sph_fsi.cli;
- static: no file under sph_fsi_core/ mentions a ROS module in an import (even a guarded, optional one).

The last two tests run both checks on a deliberately bad package, so a check that can no longer fail is noticed.
"""
import ast
import subprocess
import sys
import textwrap
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

# Top-level module names that belong to ROS (exact names, prefixes and suffixes).
DENY_EXACT = {
    'rclpy', 'rcl', 'rmw', 'rpyutils', 'builtin_interfaces', 'ament_index_python', 'message_filters',
    'sensor_msgs', 'std_msgs', 'std_srvs', 'geometry_msgs', 'diagnostic_msgs', 'rosgraph_msgs',
    'visualization_msgs', 'rcl_interfaces', 'launch', 'launch_ros', 'launch_testing', 'ros2cli',
}
DENY_PREFIXES = ('rcl', 'rosidl', 'rmw', 'ros2', 'tf2', 'launch', 'ament_')
DENY_SUFFIXES = ('_msgs', '_srvs', '_interfaces')


def is_ros_module(name):
    top = name.split('.')[0]
    return top in DENY_EXACT or top.startswith(DENY_PREFIXES) or top.endswith(DENY_SUFFIXES)


# Runs in a child interpreter. argv: root to put first on sys.path, package to walk, extra modules to import.
CHILD = textwrap.dedent('''
    import importlib, importlib.abc, pkgutil, sys, traceback

    DENY_EXACT = {deny_exact!r}
    DENY_PREFIXES = {deny_prefixes!r}
    DENY_SUFFIXES = {deny_suffixes!r}

    def is_ros_module(name):
        top = name.split('.')[0]
        return top in DENY_EXACT or top.startswith(DENY_PREFIXES) or top.endswith(DENY_SUFFIXES)

    class DenyRos(importlib.abc.MetaPathFinder):
        def find_spec(self, fullname, path=None, target=None):
            if is_ros_module(fullname):
                raise ImportError('ROS module %r imported by ROS-free code' % fullname, name=fullname)
            return None

    root, package, extra = sys.argv[1], sys.argv[2], sys.argv[3:]
    already = {{m for m in sys.modules if is_ros_module(m)}}
    sys.meta_path.insert(0, DenyRos())
    sys.path.insert(0, root)

    failures, imported = [], []

    def load(name):
        try:
            importlib.import_module(name)
            imported.append(name)
        except BaseException:
            failures.append((name, traceback.format_exc()))

    def walk_error(name):
        failures.append((name, traceback.format_exc()))

    load(package)
    pkg = sys.modules.get(package)
    if pkg is not None:
        for info in pkgutil.walk_packages(pkg.__path__, package + '.', onerror=walk_error):
            load(info.name)
    for name in extra:
        load(name)

    leaked = sorted({{m for m in sys.modules if is_ros_module(m)}} - already)
    if leaked:
        failures.append(('<sys.modules>', 'ROS modules loaded: %s' % leaked))
    if len(imported) < 2 and not failures:
        failures.append((package, 'no modules found under %s' % package))
    for name, tb in failures:
        print('FAILED to import %s without ROS:\\n%s' % (name, tb), file=sys.stderr)
    print('imported:', ' '.join(imported))
    if failures:
        sys.exit(1)
    print('OK')
''').format(deny_exact=sorted(DENY_EXACT), deny_prefixes=DENY_PREFIXES, deny_suffixes=DENY_SUFFIXES)


def import_without_ros(root, package, *extra):
    """Import `package`, all its submodules and `extra` in a child interpreter where ROS is unimportable."""
    return subprocess.run(
        [sys.executable, '-c', CHILD, str(root), package, *extra],
        cwd=str(root), capture_output=True, text=True, timeout=600,
    )


def ros_imports_in(folder):
    """(file, line, module) for every import of a ROS module in the .py files under `folder`."""
    found = []
    for path in sorted(Path(folder).rglob('*.py')):
        tree = ast.parse(path.read_text(encoding='utf-8'), filename=str(path))
        for node in ast.walk(tree):
            names = []
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names = [node.module]
            elif (isinstance(node, ast.Call) and node.args and isinstance(node.args[0], ast.Constant)
                  and isinstance(node.args[0].value, str)
                  and getattr(node.func, 'attr', getattr(node.func, 'id', None)) in ('import_module', '__import__')):
                names = [node.args[0].value]
            found += [(str(path), node.lineno, n) for n in names if is_ros_module(n)]
    return found


def test_core_and_cli_import_without_ros():
    result = import_without_ros(REPO, 'sph_fsi_core', 'sph_fsi.cli')
    assert result.returncode == 0, result.stdout + result.stderr
    assert 'OK' in result.stdout


def test_core_has_no_ros_imports():
    core = REPO / 'sph_fsi_core'
    assert any(core.rglob('*.py')), 'sph_fsi_core/ has no Python files'
    found = ros_imports_in(core)
    assert not found, 'ROS imports in the simulator core: %s' % found


def _bad_package(tmp_path):
    pkg = tmp_path / 'badcore'
    (pkg / 'sub').mkdir(parents=True)
    (pkg / '__init__.py').write_text('')
    (pkg / 'fine.py').write_text('import math\n')
    (pkg / 'sub' / '__init__.py').write_text('')
    (pkg / 'sub' / 'node.py').write_text('try:\n    from std_msgs.msg import Float64\nexcept ImportError:\n'
                                         '    Float64 = None\nimport rclpy.node\n')
    return pkg


def test_dynamic_check_catches_a_ros_import(tmp_path):
    _bad_package(tmp_path)
    result = import_without_ros(tmp_path, 'badcore')
    assert result.returncode != 0
    assert 'badcore.sub.node' in result.stderr and 'rclpy' in result.stderr
    assert 'OK' not in result.stdout


def test_static_check_catches_a_ros_import(tmp_path):
    found = ros_imports_in(_bad_package(tmp_path))
    assert sorted(m for _, _, m in found) == ['rclpy.node', 'std_msgs.msg']
