"""The node's parameters: its own table (NODE_PARAMS), one parameter per scene key, their ROS descriptors, value
conversion between rclpy and the schema, and the checks a startup value or a change must pass.

Importable without ROS: the descriptor types are imported where a descriptor is made, so the ROS-free runner
(sph_fsi.runner) and its tests use the same table.
"""
import sys

from sph_fsi_core.scene import load_scene
from sph_fsi_core.schema import Param, SceneError

__all__ = ["NODE_PARAMS", "RECORDING_PARAMS", "AT_RESET", "HIDDEN_SCENE_KEYS", "StartupError", "node_defaults",
           "scene_parameters", "descriptor_for", "to_ros_value", "from_ros_value", "parameter_overrides",
           "startup_values", "check_changes", "is_foreign"]

# The node's own parameters, described like scene keys (validated with Param.coerce).
NODE_PARAMS = {p.key: p for p in [
    Param("scene", "", "", "Scene: a built-in name or a YAML path ('' = the default scene)", kind="str"),
    Param("end_time", 0.0, "s", "Simulated time at which the run ends (0 = the scene's scene.end_time)",
          low=0.0, high=1.0e3, rebuild=False),
    Param("publish_period", 0.005, "s", "Simulated time between publishes (rounded up to whole outer steps "
          "of output.timeseries_interval)", low=0.0, low_inclusive=False, high=10.0, rebuild=False),
    Param("realtime_factor", 0.0, "1", "Simulated seconds per wall second (0 = as fast as possible)", low=0.0,
          high=1.0e6, rebuild=False),
    Param("frame_id", "map", "", "frame_id of every stamped message", kind="str", rebuild=False),
    Param("qos", "reliable", "", "QoS of the streamed topics (~/walls is always reliable, transient-local)",
          kind="str", choices=("reliable", "sensor_data")),
    Param("on_end", "stay", "", "At end_time: 'stay' (keep serving, report finished) or 'exit' (exit status 0)",
          kind="str", choices=("stay", "exit"), rebuild=False),
    Param("lockstep", False, "", "With walls driven by commands (parts.<name>.motion = ros): before each outer step, "
          "wait until every such wall has a command stamped at or after the simulated time (a closed loop runs "
          "the same whatever the host's speed; while it waits, the frame it waits on goes out again every second)",
          kind="bool", rebuild=False),
    # Recordings (sph_fsi.recording): opened when the simulation is built; each ~/reset closes the files and
    # starts new ones named <stem>_<n><suffix> (n = 1, 2, ...).
    Param("mcap_path", "", "", "Record the node's topics to this MCAP file ('' = no MCAP recording)", kind="str"),
    Param("mcap_compression", "zstd", "", "MCAP chunk compression", kind="str", choices=("zstd", "lz4", "none")),
    Param("rrd_path", "", "", "Record to this Rerun .rrd file ('' = no Rerun recording)", kind="str"),
    Param("rerun_connect", "", "", "Stream live to a Rerun viewer at host:port or rerun+http://host:port/proxy "
          "('' = off)", kind="str"),
    Param("record_interval", 0.005, "s", "Simulated time between recorded frames, independent of publish_period "
          "(whole outer steps; 0 = every outer step)", low=0.0, high=10.0),
    Param("out_dir", "", "", "Write timeseries.csv and summary.json (error against the scene's reference, wall "
          "time) here when the run ends, diverges, is reset or stopped ('' = off; <dir>_<n> after each reset)",
          kind="str"),
    # Checkpoints (sph_fsi_core/checkpoint.py)
    Param("restart_from", "", "", "At startup, continue the run this checkpoint holds (its scene and settings; "
          "no scene keys with it) instead of building the scene at t = 0; a ~/reset then starts that scene "
          "at t = 0 ('' = off; read at startup only)", kind="str"),
    Param("checkpoint_path", "", "", "Where ~/write_checkpoint writes ('' = <out_dir>/checkpoint.ckpt)",
          kind="str", rebuild=False),
]}
# Node parameters read at startup only (a change later is refused).
STARTUP_ONLY = ("restart_from",)
RECORDING_PARAMS = ("mcap_path", "mcap_compression", "rrd_path", "rerun_connect", "record_interval", "out_dir")
# Node parameters that apply at the next ~/reset (the others at once).
AT_RESET = ("scene", "qos") + RECORDING_PARAMS
# Scene keys not exposed as parameters: the builder follows from the scene.
HIDDEN_SCENE_KEYS = {"scene.builder"}
# Parameters rclpy declares itself, and prefixes of ROS-level overrides we leave alone.
FOREIGN_PARAMS = {"use_sim_time", "start_type_description_service"}
FOREIGN_PREFIXES = ("qos_overrides.",)

_DBL_MAX = sys.float_info.max
_INT64 = 2 ** 63 - 1


class StartupError(Exception):
    """Bad startup parameters: one line naming the parameter and the allowed values."""


def node_defaults():
    """{node parameter: default value}."""
    return {key: p.default for key, p in NODE_PARAMS.items()}


def scene_parameters(spec):
    """{scene key: Param} of the keys the node exposes as parameters for this scene."""
    return {k: p for k, p in spec.schema.params.items() if k not in HIDDEN_SCENE_KEYS}


def is_foreign(name):
    """A parameter rclpy or ROS itself handles (use_sim_time, qos_overrides.*): neither ours nor refused."""
    return name in FOREIGN_PARAMS or name.startswith(FOREIGN_PREFIXES)


def descriptor_for(p, rebuild_note=True):
    """ParameterDescriptor for a schema Param: description with unit and range, ROS range where bounded.

    ROS ranges are inclusive (step 0 = continuous); exclusive bounds are enforced by Param.coerce in the
    callback. dynamic_typing lets 2000000 (an integer) stand for a double; the callback coerces and refuses
    wrong types with a reason of its own.
    """
    from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor, ParameterType
    ros_types = {"float": ParameterType.PARAMETER_DOUBLE, "int": ParameterType.PARAMETER_INTEGER,
                 "bool": ParameterType.PARAMETER_BOOL, "str": ParameterType.PARAMETER_STRING,
                 "vec3": ParameterType.PARAMETER_DOUBLE_ARRAY}
    unit = f" [{p.unit}]" if p.unit and p.unit != "1" else ""
    when = ("applies at the next ~/reset" if p.rebuild else "applies at once") if rebuild_note else ""
    d = ParameterDescriptor(name=p.key, type=ros_types[p.kind],
                            description=f"{p.description}{unit}; {p.range_text()}" + (f"; {when}" if when else ""),
                            additional_constraints=p.range_text(), dynamic_typing=True)
    if p.low is not None or p.high is not None:
        if p.kind == "float":
            d.floating_point_range = [FloatingPointRange(
                from_value=float(p.low) if p.low is not None else -_DBL_MAX,
                to_value=float(p.high) if p.high is not None else _DBL_MAX, step=0.0)]
        elif p.kind == "int":
            d.integer_range = [IntegerRange(from_value=int(p.low) if p.low is not None else -_INT64,
                                            to_value=int(p.high) if p.high is not None else _INT64, step=0)]
    return d


def to_ros_value(value):
    return list(value) if isinstance(value, tuple) else value


def from_ros_value(value):
    """rclpy values -> plain Python (arrays -> lists) for Param.coerce."""
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    try:
        return [v.item() if hasattr(v, "item") else v for v in value]
    except TypeError:
        return value


def parameter_overrides(node):
    """{name: plain value} of every parameter override given to `node` (--ros-args -p, --params-file).

    The one read of rclpy's private `Node._parameter_overrides` (rclpy 7.1, Jazzy), kept here on purpose: the node
    must see every override before it declares anything, to refuse an unknown or bad key at startup (exit status
    2, one line naming the key) and to know which scene's keys to declare. rclpy has no public getter for the
    override list. Its public route, Node(automatically_declare_parameters_from_overrides=True), declares each
    override first, statically typed from its raw value and with an empty descriptor, publishes it on
    /parameter_events, and leaves ROS-level keys (qos_overrides.*) declared; the node would then undeclare and
    redeclare its own keys: more parameter events, and a startup failure inside rclpy (not a line naming the
    key) for a value rclpy cannot type. If rclpy renames the attribute, no override is seen (defaults only).
    """
    return {k: from_ros_value(p.value) for k, p in getattr(node, "_parameter_overrides", {}).items()}


def startup_values(overrides):
    """(node values, the scene spec with its overrides, its scene parameters) from startup overrides; raises
    StartupError naming the first bad or unknown key."""
    node_values = {}
    for key, p in NODE_PARAMS.items():
        value = p.default
        if key in overrides:
            try:
                value = p.coerce(overrides[key])
            except SceneError as exc:
                raise StartupError(str(exc)) from None
        node_values[key] = value
    restored = None
    try:
        if node_values["restart_from"]:
            from sph_fsi_core.checkpoint import read_checkpoint
            restored = read_checkpoint(node_values["restart_from"])
            base = restored["sim"].spec
        else:
            base = load_scene(node_values["scene"] or None)
    except SceneError as exc:
        raise StartupError(str(exc)) from None
    scene_params = scene_parameters(base)
    if restored is not None:
        given = [k for k in overrides if k in scene_params or k == "scene"]
        if given:
            raise StartupError(f"restart_from = {node_values['restart_from']!r} continues the checkpoint's own "
                               f"scene and settings; allowed: no scene keys with it (given: {', '.join(given)})")
        node_values["_restored"] = restored
    unknown = [k for k in overrides if k not in NODE_PARAMS and k not in scene_params and not is_foreign(k)]
    for key in unknown:
        try:
            base.schema.check_key(key, set(base.schema.sections()) | {"fluid", "solid", "walls", "coupling"})
            why = f"{key}: not a parameter of this node"
        except SceneError as exc:
            why = str(exc)
        raise StartupError(f"{why} (parameters: {', '.join(NODE_PARAMS)}, and the scene's keys: "
                           f"see `sph-fsi keys {base.name}`)")
    scene_overrides = {}
    for key, p in scene_params.items():
        if key in overrides:
            try:
                scene_overrides[key] = p.coerce(overrides[key])
            except SceneError as exc:
                raise StartupError(str(exc)) from None
    try:
        spec = base.with_overrides(scene_overrides) if scene_overrides else base
    except SceneError as exc:
        raise StartupError(str(exc)) from None
    return node_values, spec, scene_params


def check_changes(changes, scene_params, desired):
    """(reason if refused else None, plan) for [(name, plain value)]; no side effects.

    plan = (node changes {key: value}, scene changes {key: value}, the desired spec with the scene changes)."""
    node_changes, scene_changes = {}, {}
    for name, value in changes:
        if name in NODE_PARAMS:
            try:
                value = NODE_PARAMS[name].coerce(value)
                if name == "scene":
                    load_scene(value or None)
            except SceneError as exc:
                msg = str(exc)
                return (msg if msg.startswith(name) else f"{name} = {value!r}: {msg}"), None
            if name in STARTUP_ONLY:
                return f"{name}: read at startup only; allowed: set it when starting the node", None
            node_changes[name] = value
        elif name in scene_params:
            try:
                scene_changes[name] = scene_params[name].coerce(value)
            except SceneError as exc:
                return str(exc), None
        elif is_foreign(name):
            continue
        else:
            return f"{name}: not a parameter of this node", None
    candidate = desired
    if scene_changes:
        try:
            candidate = desired.with_overrides(scene_changes)
        except SceneError as exc:
            return str(exc), None
    return None, (node_changes, scene_changes, candidate)
