"""Scenes: strict YAML loading, `--set` overrides, and the resolved settings a builder turns into particles.

A scene file is nested YAML (`section: {key: value}`) in SI units, z up. Resolution order: schema defaults,
then the builder's defaults, then the solid's scheme (`solid.scheme` fills in the detailed keys of
solid/schemes.py), then the file, then overrides; so a detailed key set in the file or by an override beats the
scheme, and a new scheme given later (`SceneSpec.with_overrides`) is expanded again under the keys set explicitly.
Unknown keys, wrong types, out-of-range values and duplicate keys are SceneErrors naming the key.
"""
import difflib
import os
import re
import sys
from dataclasses import dataclass
from pathlib import Path

import yaml

from . import memory_guard
from .geometry.declared import declarations, is_declaration, overlaid, value_of
from .geometry.expressions import ExpressionError, evaluate, namespace, refusal
from .geometry.parts import LISTS, NAME_RE, REQUIRED, check_required, reference
from .schema import COMMON, PHASE_NAMES, SECTIONS_BY_PHASE, Schema, SceneError, check_combinations
from .scenes import BUILDERS, DEFAULT_SCENE, build_scene
from .solid.schemes import scheme_values

__all__ = ["SceneError", "SceneSpec", "load_scene", "builtin_scene_path", "builtin_scenes", "parse_override"]


class _StrictLoader(yaml.SafeLoader):
    """SafeLoader with YAML 1.2 floats (so 1.859e6 is a number, not a string) and no duplicate keys."""


_FLOAT_RE = re.compile(r"""^(?:[-+]?(?:[0-9][0-9_]*)\.[0-9_]*(?:[eE][-+]?[0-9]+)?
    |[-+]?(?:[0-9][0-9_]*)(?:[eE][-+]?[0-9]+)
    |\.[0-9_]+(?:[eE][-+]?[0-9]+)?
    |[-+]?\.(?:inf|Inf|INF)
    |\.(?:nan|NaN|NAN))$""", re.X)
_StrictLoader.yaml_implicit_resolvers = {
    k: [(tag, regexp) for tag, regexp in v if tag != "tag:yaml.org,2002:float"]
    for k, v in yaml.SafeLoader.yaml_implicit_resolvers.items()}
_StrictLoader.add_implicit_resolver("tag:yaml.org,2002:float", _FLOAT_RE, list("-+0123456789."))


def _no_duplicates(loader, node, deep=False):
    seen = set()
    for key_node, _ in node.value:
        key = loader.construct_object(key_node, deep=deep)
        if key in seen:
            raise SceneError(f"{key}: duplicate key (line {key_node.start_mark.line + 1}); allowed: each key once "
                             f"per section")
        seen.add(key)
    return loader.construct_mapping(node, deep)


_StrictLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _no_duplicates)


def parse_yaml(text, origin="<string>"):
    try:
        return yaml.load(text, Loader=_StrictLoader)
    except SceneError:
        raise
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" (line {mark.line + 1}, column {mark.column + 1})" if mark else ""
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise SceneError(f"{origin}: not valid YAML{where}: {problem}") from None


def _flatten_list(section, body, flat):
    """A list section (geometry.parts.LISTS: parts, probes, judge) as keys `section.<name>.<key>`."""
    if not isinstance(body, list):
        raise SceneError(f"{section}: expected a list of mappings, each with a name, got {type(body).__name__}")
    seen = set()
    for i, entry in enumerate(body):
        if not isinstance(entry, dict):
            raise SceneError(f"{section}[{i}]: expected a mapping of keys, got {type(entry).__name__}")
        name = entry.get("name")
        if not isinstance(name, str) or not NAME_RE.match(name):
            raise SceneError(f"{section}[{i}].name = {name!r}: expected a name; allowed: letters, digits and '_', "
                             f"starting with a letter (it names the entry's keys and its ROS parameters)")
        if name in seen:
            raise SceneError(f"{section}.{name}: duplicate name ({section}[{i}]); allowed: each name once")
        seen.add(name)
        for key, value in entry.items():
            if key == "name":
                continue
            if not isinstance(key, str):
                raise SceneError(f"{section}.{name}: key {key!r} is not a string")
            if isinstance(value, dict):
                raise SceneError(f"{section}.{name}.{key}: nested sections are not allowed")
            flat[f"{section}.{name}.{key}"] = value


def _flatten(tree, origin):
    if tree is None:
        raise SceneError(f"{origin}: the scene is empty")
    if not isinstance(tree, dict):
        raise SceneError(f"{origin}: a scene is a mapping of sections, got {type(tree).__name__}")
    flat = {}
    for section, body in tree.items():
        if not isinstance(section, str):
            raise SceneError(f"{origin}: section name {section!r} is not a string")
        if section in LISTS:
            _flatten_list(section, body, flat)
            continue
        if not isinstance(body, dict):
            raise SceneError(f"{section}: expected a mapping of keys, got {type(body).__name__}")
        for key, value in body.items():
            if isinstance(value, dict) and section != "geometry":   # geometry/declared.py: a declaration
                raise SceneError(f"{section}.{key}: nested sections are not allowed")
            flat[f"{section}.{key}"] = value
    return flat


def parse_override(text):
    """'solid.young_modulus=2e6' -> ('solid.young_modulus', 2000000.0), the value parsed as YAML."""
    if "=" not in text:
        raise SceneError(f"--set {text!r}: expected KEY=VALUE")
    key, raw = text.split("=", 1)
    key = key.strip()
    if not re.fullmatch(r"[a-z_]+\.[A-Za-z0-9_]+(\.[a-z0-9_]+)?", key):
        raise SceneError(f"--set {text!r}: KEY must look like section.name (or parts.<part>.name)")
    return key, parse_yaml(raw, origin=f"--set {key}") if raw.strip() else ""


_ENTRY = {"parts": ("part", "role"), "probes": ("probe", "kind"), "judge": ("judge", "kind")}


def check_entry_names(known, overrides):
    """SceneError for an override of a list entry's key (`parts.<name>.<key>`) in a geometry scene whose entry is not
    among the `known` keys' (the file's) and is not made whole by the overrides (they give no role or kind): the entry
    is misnamed. The message lists the list's names, a near match first."""
    if known.get("scene.builder") != "geometry":
        return      # another builder has no lists: its schema refuses the section
    for key, value in overrides.items():
        which, _, rest = key.partition(".")
        if which not in _ENTRY or rest.count(".") != 1:
            continue
        name = rest.split(".")[0]
        names = list(dict.fromkeys(k.split(".")[1] for k in known if k.startswith(which + ".")
                                   and k.count(".") == 2))
        what, defining = _ENTRY[which]
        if name in names or f"{which}.{name}.{defining}" in overrides:
            continue
        near = difflib.get_close_matches(name, names, n=1, cutoff=0.6)
        hint = f" (did you mean {near[0]!r}?)" if near else ""
        allowed = ("one of " + ", ".join(repr(n) for n in names)) if names else f"none (the scene has no {which})"
        raise SceneError(f"{key} = {value!r}: the scene has no {what} named {name!r}{hint}; allowed: {allowed}, or "
                         f"a new {what} given its {defining} too")


def _config_dirs():
    here = Path(__file__).resolve().parent
    dirs = [here.parent / "config", Path(sys.prefix) / "share" / "sph_fsi" / "config"]
    for prefix in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
        if prefix:
            dirs.append(Path(prefix) / "share" / "sph_fsi" / "config")
    return [d for d in dirs if d.is_dir()]


def builtin_scene_path(name):
    for d in _config_dirs():
        p = d / f"{name}.yaml"
        if p.is_file():
            return p
    return None


def builtin_scenes():
    """{name: path} of the built-in scenes (config/*.yaml except defaults.yaml)."""
    found = {}
    for d in _config_dirs():
        for p in sorted(d.glob("*.yaml")):
            if p.stem != "defaults" and p.stem not in found:
                found[p.stem] = p
    return found


@dataclass
class SceneSpec:
    """A validated scene: its builder, its schema and every key's value."""
    builder: str
    schema: Schema
    values: dict
    source: str

    def __getitem__(self, key):
        return self.values[key]

    @property
    def name(self):
        return self.values["scene.name"]

    phases: tuple = ()

    def with_overrides(self, overrides):
        """A new spec with `overrides` ({key: value}) applied and validated. The keys set so far (file, earlier
        overrides) stay set; a new `solid.scheme` fills in every detailed key that none of them sets."""
        file_keys = self.file_keys - set(overrides)
        try:
            check_entry_names(self._explicit, overrides)
            spec = _resolve(self.builder, overlaid(self._explicit, overrides), self.source)
        except SceneError as exc:
            raise naming_the_file(exc, self.source, file_keys) from None
        spec.file_keys = file_keys
        return spec

    def build(self):
        """The scene's particles as a run starts from them, built and checked (scenes.build_scene: (Built, clamp
        particles left out)); a refusal names the scene file where it is about a key or a part the file set."""
        try:
            return build_scene(self.builder, self.values)
        except SceneError as exc:
            raise naming_the_file(exc, self.source, self.file_keys) from None

    _explicit: dict = None
    file_keys: frozenset = frozenset()     # the keys the scene file set that no override replaced
    # a geometry scene's keys written as expressions {key: as written}, and its derived quantities {key: (expression,
    # unit, description, value)} (geometry/declared.py)
    expressions: dict = None
    derived: dict = None


def _resolve(builder_name, flat, origin):
    if builder_name not in BUILDERS:
        raise SceneError(f"scene.builder = {builder_name!r}: unknown; allowed: one of "
                         + ", ".join(repr(b) for b in sorted(BUILDERS)))
    builder = BUILDERS[builder_name]
    own = [p.key.split(".", 1)[1] for p in builder.geometry if p.section == "geometry"]
    declared, derived = [], {}
    if builder.expressions:      # geometry/declared.py: the scene's own parameters and derived quantities
        declared, derived = declarations(flat, own)
    else:
        found = next((k for k, v in flat.items() if k.startswith("geometry.") and is_declaration(v)), None)
        if found:
            raise SceneError(f"{found}: a declared parameter belongs to a geometry scene (scene.builder: geometry); "
                             f"allowed: this builder's own keys")
    # a geometry scene's phases and keys follow from its part, probe and judge lists (geometry/parts.py)
    phases = builder.phases_of(flat) if builder.phases_of is not None else builder.phases
    listed = builder.list_params(flat) if builder.list_params is not None else []
    schema = Schema.for_builder(phases, builder.geometry + listed + declared)
    all_sections = ({p.section for params in SECTIONS_BY_PHASE.values() for p in params} | {"geometry"}
                    | set(PHASE_NAMES) | set(LISTS))
    values = {k: p.default for k, p in schema.params.items()}
    values.update(builder.defaults)
    explicit, deferred = {}, {}
    absent = builder.absent_sections
    for key, value in flat.items():
        if key in derived:
            continue
        param = schema.check_key(key, all_sections, absent)
        raw = value_of(value) if is_declaration(value) else value
        if builder.expressions and _takes_expressions(param, own) and _is_expression(param, raw):
            deferred[key] = raw
        else:
            explicit[key] = param.coerce(raw)
    if "solid.scheme" in values:
        values.update(scheme_values(explicit.get("solid.scheme", values["solid.scheme"])))
    values.update(explicit)
    values["scene.builder"] = builder_name
    if not values["scene.name"]:
        values["scene.name"] = builder_name
    if builder.expressions:
        _evaluate(values, schema, declared, derived, deferred)
    check_required(values)
    if builder.resolve_files is not None:
        builder.resolve_files(values, origin)
    check_combinations(values)
    builder.check(values)
    memory_guard.check(builder, values)
    spec = SceneSpec(builder_name, schema, values, origin, tuple(phases))
    spec._explicit = dict(flat)
    spec.expressions = {k: deferred[k] for k in deferred}
    spec.derived = {k: (text, unit, description, values[k]) for k, (text, unit, description) in derived.items()}
    return spec


def _takes_expressions(param, own):
    """Whether a key's value may be an expression (geometry/expressions.py): a part's, probe's or judge's key, and
    the geometry builder's own keys; not a declared parameter (it is the input) nor another section's key."""
    section, _, name = param.key.partition(".")
    return section in LISTS or (section == "geometry" and name in own)


def _is_expression(param, raw):
    """A number or a switch written as text, a choice that is not one of them, or text that starts with '='."""
    if param.kind == "vec3":
        return isinstance(raw, (list, tuple)) and any(isinstance(v, str) for v in raw)
    if param.kind == "str":
        return isinstance(raw, str) and (raw.startswith("=") or bool(param.choices) and raw not in param.choices)
    return isinstance(raw, str)


def _evaluate(values, schema, declared, derived, deferred):
    """In place: the derived quantities (in file order, each in the parameters and those before it), then every
    expression of `deferred` {key: raw value}, each coerced and checked as its key (SceneError naming the key and
    its expression)."""
    names = {p.key.split(".", 1)[1]: values[p.key] for p in declared}
    for key, (text, _, _) in derived.items():
        try:
            values[key] = names[key.split(".", 1)[1]] = evaluate(text, namespace(values, names))
        except ExpressionError as exc:
            raise refusal(key, text, exc) from None
    space = namespace(values, names)
    for key, raw in deferred.items():
        param = schema.params[key]
        items = raw if param.kind == "vec3" else [raw]
        out = []
        for item in items:
            if not isinstance(item, str):
                out.append(item)
                continue
            text = item[1:] if param.kind == "str" and item.startswith("=") else item
            if param.choices and text.strip().isidentifier() and text.strip() not in space.names:
                param.coerce(item)          # a word that names nothing: a misspelt choice, refused as one
            try:
                out.append(evaluate(text, space))
            except ExpressionError as exc:
                raise refusal(key, item, exc) from None
        result = out if param.kind == "vec3" else out[0]
        try:
            values[key] = param.coerce(result)
        except SceneError as exc:
            raise SceneError(str(exc).replace(f"{key} = ", f"{key} = {raw!r} = ", 1)) from None


def load_scene(scene=None, overrides=()):
    """Load a scene by built-in name or YAML path (None: the default scene) and apply `KEY=VALUE` overrides."""
    scene = scene or DEFAULT_SCENE
    path = Path(scene)
    if not (path.suffix in (".yaml", ".yml") or os.sep in scene):
        found = builtin_scene_path(scene)
        if found is None:
            raise SceneError(f"scene {scene!r}: no such built-in scene; allowed: one of "
                             + ", ".join(sorted(builtin_scenes())) + ", or a path to a .yaml file")
        path = found
    if path.is_dir():
        raise SceneError(f"scene file {str(path)!r}: a directory, not a file; allowed: a YAML scene file or a "
                         f"built-in scene's name")
    if not path.is_file():
        raise SceneError(f"scene file {str(path)!r}: not found; allowed: a YAML scene file or one of "
                         + ", ".join(sorted(builtin_scenes())))
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise SceneError(f"scene file {str(path)!r}: not UTF-8 text ({exc.reason} at byte {exc.start}); allowed: "
                         f"a YAML text file in UTF-8") from None
    except OSError as exc:
        raise SceneError(f"scene file {str(path)!r}: cannot be read ({exc.strerror or exc}); allowed: a readable "
                         f"YAML file") from None
    try:
        flat = _flatten(parse_yaml(text, origin=str(path)), str(path))
    except SceneError as exc:
        raise (exc if str(exc).startswith(str(path)) else SceneError(f"{path}: {exc}")) from None
    from_file = set(flat)
    parsed = dict(parse_override(item) if isinstance(item, str) else item for item in overrides)
    check_entry_names(flat, parsed)
    overridden = set(parsed)
    try:
        flat = overlaid(flat, parsed)
        builder = flat.get("scene.builder", path.stem if path.stem in BUILDERS else "geometry")
        if not isinstance(builder, str):
            raise SceneError(f"scene.builder = {builder!r}: expected a string naming a builder")
        spec = _resolve(builder, flat, str(path))
    except SceneError as exc:
        raise naming_the_file(exc, path, from_file - overridden) from None
    spec.file_keys = frozenset(from_file - overridden)
    return spec


def naming_the_file(exc, path, file_keys):
    """A SceneError about a key the scene file set, or about a part, probe or judge it lists (`parts.box: ...`,
    `parts: none`), prefixed with the file's path; an override's stays as it is."""
    message = str(exc)
    key = message.split(" ", 1)[0].rstrip(":")
    listed = key.split(".")[0] in LISTS and (key in LISTS or any(k.startswith(key + ".") for k in file_keys))
    if (key in file_keys or listed) and not message.startswith(f"{path}: "):
        return SceneError(f"{path}: {message}")
    return exc


def defaults_yaml():
    """The text of config/defaults.yaml: every key of every phase with its default, unit and range."""
    lines = ["# Every scene key with its default, unit and allowed range. Generated from sph_fsi_core/schema.py",
             "# by `sph-fsi keys --yaml > config/defaults.yaml`; test_scene.py checks that this file is current.",
             ""]
    for phase, params in [("common", COMMON)] + [(k, v) for k, v in SECTIONS_BY_PHASE.items() if k != "common"]:
        section = None
        for p in params:
            if p.section != section:
                section = p.section
                lines.append(f"{section}:" + ("" if phase == "common" else f"  # phase: {phase}"))
            default = list(p.default) if isinstance(p.default, tuple) else p.default
            text = yaml.safe_dump(default, default_flow_style=True).strip().removesuffix("...").strip()
            unit = f" [{p.unit}]" if p.unit else ""
            lines.append(f"  {p.key.split('.', 1)[1]}: {text}  #{unit} {p.description}; {p.range_text()}")
    return "\n".join(lines + list_keys_yaml()) + "\n"


def list_keys_yaml():
    """The keys of a geometry scene's parts, probes and judges by role, shape and kind (geometry/parts.reference),
    as comment lines: each list is a sequence of mappings, so it has no single default to print."""
    lines = ["", "# A geometry scene's lists (scene.builder: geometry): each a sequence of mappings with a unique "
             "name;", "# the keys an entry may have by its role and shape (parts) or kind (probes, judge); "
             "'required': no default."]
    listed = None
    for which, entries, params in reference():
        if which != listed:
            listed = which
            lines.append(f"# {which}:")
        lines.append(f"#   {entries}:")
        for p in params:
            default = list(p.default) if isinstance(p.default, tuple) else p.default
            text = "required" if p.default is REQUIRED else \
                yaml.safe_dump(default, default_flow_style=True).strip().removesuffix("...").strip()
            unit = f" [{p.unit}]" if p.unit else ""
            lines.append(f"#     {p.key.rsplit('.', 1)[1]}: {text}  #{unit} {p.description}; {p.range_text()}")
    return lines
