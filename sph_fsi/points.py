"""What a simulation shows, as NumPy: the moving particles of each phase, the fixed ones, and their point layouts.

ROS-free (no rclpy, no message packages): shared by the node (sph_fsi.publishing, sph_fsi.runner), the message builders
(sph_fsi.messages) and the recorders (sph_fsi.recording), which also run from the command line without ROS.

`~/particles` points: float32 x y z [m], vx vy vz [m/s], pressure [Pa], von_mises [Pa], uint8 phase
(1 fluid, 2 solid), padded from 33 to 36 bytes. `~/walls` points: float32 x y z [m].
A phase the scene does not have (`sim.fluid` / `sim.solid` / `sim.walls` None or absent) contributes nothing.

Topics (`topic_plan`, names relative to the node, `topic_type`): particles, walls, tip_displacement (a probe named
'tip'), strain_energy (a solid), and one per probe quantity (sph_fsi_core.probes), `probes/<name>/<quantity>`:

    kind          topics                                  message type, what it carries
    displacement  probes/<name>/displacement              geometry_msgs/msg/Vector3Stamped: (dx, dy, dz) m
    point         probes/<name>/displacement, /velocity   Vector3Stamped: (dx, dy, dz) m; (vx, vy, vz) m/s
    pressure      probes/<name>/pressure                  sensor_msgs/msg/FluidPressure: fluid_pressure Pa, variance 0
    water_height  probes/<name>/surface                   geometry_msgs/msg/PointStamped: the free surface's point
                                                          (x, y, z) m above the probe's position
    force         probes/<name>/force                     geometry_msgs/msg/WrenchStamped: force N, torque 0

Their values are `probe_readings(sim)` (Simulation.probe_readings: at the end of the last outer step), so every
output (topics, MCAP, Rerun) reports the same numbers as the time series.
"""
import numpy as np

from sph_fsi_core.numerics.tensors import von_mises

__all__ = ["PHASE_FLUID", "PHASE_SOLID", "PHASE_CODES", "PARTICLE_DTYPE", "WALL_DTYPE", "moving_particles",
           "wall_positions", "particle_points", "pack_particles", "topic_plan", "topic_type", "TOPIC_TYPES",
           "PROBE_QUANTITIES", "QUANTITY_TYPES", "probe_kinds", "probe_topic", "probe_readings", "probe_values"]

PHASE_FLUID = 1
PHASE_SOLID = 2
PHASE_CODES = {"fluid": PHASE_FLUID, "solid": PHASE_SOLID}


def _padded(fields):
    """A structured dtype of (name, format) packed in order, itemsize rounded up to a multiple of 4."""
    names, formats, offsets, offset = [], [], [], 0
    for name, fmt in fields:
        names.append(name)
        formats.append(fmt)
        offsets.append(offset)
        offset += np.dtype(fmt).itemsize
    return np.dtype({"names": names, "formats": formats, "offsets": offsets, "itemsize": (offset + 3) // 4 * 4})


PARTICLE_DTYPE = _padded([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("vx", "<f4"), ("vy", "<f4"), ("vz", "<f4"),
                          ("pressure", "<f4"), ("von_mises", "<f4"), ("phase", "u1")])
WALL_DTYPE = _padded([("x", "<f4"), ("y", "<f4"), ("z", "<f4")])


def _movable(state):
    m = getattr(state, "movable", None)
    return np.ones(len(state.pos), bool) if m is None else np.asarray(m, bool)


def moving_particles(sim):
    """Per phase the scene has, its moving particles: [(phase code, pos, vel, pressure, von Mises)]."""
    parts = []
    fluid = getattr(sim, "fluid", None)
    if fluid is not None:
        if getattr(fluid, "movable", None) is None:   # every fluid particle moves: views, no masked copies
            parts.append((PHASE_FLUID, fluid.pos, fluid.vel, fluid.pressure, np.zeros(len(fluid.pos))))
        else:
            m = _movable(fluid)
            parts.append((PHASE_FLUID, fluid.pos[m], fluid.vel[m], fluid.pressure[m], np.zeros(int(m.sum()))))
    solid = getattr(sim, "solid", None)
    if solid is not None:
        m = solid.movable
        velocity = sim.solid_velocity() if hasattr(sim, "solid_velocity") else solid.vel   # stand-ins have vel only
        parts.append((PHASE_SOLID, solid.pos[m], velocity[m], solid.pressure[m], von_mises(solid.stress[m])))
    return parts


def wall_positions(sim):
    """Positions of every particle that never moves: wall particles, fixed fluid particles, the solid's clamp."""
    parts = []
    walls = getattr(sim, "walls", None)
    if walls is not None:
        parts.append(walls.pos)
    for phase in ("fluid", "solid"):
        state = getattr(sim, phase, None)
        if state is not None:
            m = _movable(state)
            if not m.all():
                parts.append(state.pos[~m])
    return np.concatenate(parts) if parts else np.zeros((0, 3))


def pack_particles(parts):
    """[(code, pos, vel, pressure, von Mises)] -> one PARTICLE_DTYPE array, in the order given."""
    n = sum(len(p[1]) for p in parts)
    # Filled as an (n, 9) float32 block (eight float fields and the word holding the phase byte and the padding):
    # whole-column copies, a few times faster than field by field for a frame of the paper's 33 k particles.
    words = np.zeros((n, PARTICLE_DTYPE.itemsize // 4), dtype="<f4")   # zeros: the padding bytes are deterministic
    phase_bytes = words.view(np.uint8).reshape(n, PARTICLE_DTYPE.itemsize)[:, PARTICLE_DTYPE.fields["phase"][1]]
    i = 0
    for code, pos, vel, pressure, vm in parts:
        j = i + len(pos)
        words[i:j, 0:3] = pos
        words[i:j, 3:6] = vel
        words[i:j, 6] = pressure
        words[i:j, 7] = vm
        phase_bytes[i:j] = code
        i = j
    return words.view(PARTICLE_DTYPE).reshape(n)


def particle_points(sim):
    """The ~/particles structured array: the moving particles of every phase, in phase order."""
    return pack_particles(moving_particles(sim))


# the scene-dependent topics other than the probes' (names relative to the node) and their message types
TOPIC_TYPES = {"particles": "sensor_msgs/msg/PointCloud2", "walls": "sensor_msgs/msg/PointCloud2",
               "tip_displacement": "geometry_msgs/msg/Vector3Stamped", "strain_energy": "std_msgs/msg/Float64"}
# probe kind (sph_fsi_core.probes.KINDS) -> the quantities of its readings that get a topic each
PROBE_QUANTITIES = {"displacement": ("displacement",), "point": ("displacement", "velocity"),
                    "pressure": ("pressure",), "water_height": ("surface",), "force": ("force",)}
# a probe topic's quantity (its last name token) -> its message type
QUANTITY_TYPES = {"displacement": "geometry_msgs/msg/Vector3Stamped", "velocity": "geometry_msgs/msg/Vector3Stamped",
                  "pressure": "sensor_msgs/msg/FluidPressure", "surface": "geometry_msgs/msg/PointStamped",
                  "force": "geometry_msgs/msg/WrenchStamped"}


def probe_topic(name, quantity):
    return f"probes/{name}/{quantity}"


def topic_type(topic):
    """A topic_plan name -> its message type ('geometry_msgs/msg/Vector3Stamped')."""
    if topic.startswith("probes/"):
        return QUANTITY_TYPES[topic.rsplit("/", 1)[1]]
    return TOPIC_TYPES[topic]


def probe_kinds(sim):
    """{probe name: kind} in the scene's order (a probe without a kind is a displacement probe, as in
    sph_fsi_core.probes.ProbeSet)."""
    return {p.name: getattr(p, "kind", "displacement") for p in getattr(sim, "probes", None) or []}


def _plain(value):
    return tuple(float(x) for x in value) if np.ndim(value) else float(value)


def probe_readings(sim):
    """{probe name: (kind, {quantity: float or (x, y, z) floats})} at the end of the last outer step: a copy of
    Simulation.probe_readings (a few small dicts; cheap enough for the simulation thread). A simulation without
    probe_readings (a stand-in) gives its probe_displacements as displacement probes."""
    if hasattr(sim, "probe_readings"):
        return {name: (kind, {q: _plain(v) for q, v in values.items()})
                for name, (kind, values) in sim.probe_readings().items()}
    if not hasattr(sim, "probe_displacements"):
        return {}
    return {name: ("displacement", {"displacement": _plain(d)}) for name, d in sim.probe_displacements().items()}


def probe_values(readings):
    """[(topic, quantity, value)] of the probe topics of `readings` (probe_readings), in the scene's order; a kind
    without topics (none at present: PROBE_QUANTITIES has every kind) gives none."""
    out = []
    for name, (kind, values) in readings.items():
        for quantity in PROBE_QUANTITIES.get(kind, ()):
            out.append((probe_topic(name, quantity), quantity, values[quantity]))
    return out


def topic_plan(sim):
    """Names of the scene-dependent topics this simulation has (module docstring)."""
    names = set()
    if moving_particles(sim):
        names.add("particles")
    if len(wall_positions(sim)):
        names.add("walls")
    if any(p.name == "tip" for p in getattr(sim, "probes", [])):
        names.add("tip_displacement")
    if getattr(sim, "solid", None) is not None:
        names.add("strain_energy")
    for name, kind in probe_kinds(sim).items():
        names.update(probe_topic(name, q) for q in PROBE_QUANTITIES.get(kind, ()))
    return names
