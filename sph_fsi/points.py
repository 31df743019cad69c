"""What a simulation shows, as NumPy: the moving particles of each phase, the fixed ones, and their point layouts.

ROS-free (no rclpy, no message packages): shared by the node (sph_fsi.publishing, sph_fsi.runner), the message builders
(sph_fsi.messages) and the recorders (sph_fsi.recording), which also run from the command line without ROS.

`~/particles` points: float32 x y z [m], vx vy vz [m/s], pressure [Pa], von_mises [Pa], uint8 phase
(1 fluid, 2 solid, 3 a wall that moves: its velocity from its motion, pressure and von Mises 0), padded from 33 to
36 bytes. `~/walls` points: float32 x y z [m], the walls that stay.
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

and for each wall driven by commands (parts.<name>.motion = ros), `parts/<name>/...`:

    pose          geometry_msgs/msg/PoseStamped: where its motion_point is, and its turn from the built pose
    wrench        geometry_msgs/msg/WrenchStamped: the water's force N and moment N m about that point
    pose_cmd      geometry_msgs/msg/PoseStamped, taken: the pose to reach over motion_period (relative to the
                  built pose: the point's position and the turn); recorded as applied, stamped when it applied
    twist_cmd     geometry_msgs/msg/TwistStamped, taken: linear m/s and angular rad/s velocities; recorded so

Their values are `probe_readings(sim)` (Simulation.probe_readings: at the end of the last outer step), so every
output (topics, MCAP, Rerun) reports the same numbers as the time series.
"""
import numpy as np

from sph_fsi_core.numerics.tensors import von_mises

__all__ = ["PHASE_FLUID", "PHASE_SOLID", "PHASE_WALL", "PHASE_CODES", "PARTICLE_DTYPE", "WALL_DTYPE", "moving_particles",
           "wall_positions", "particle_points", "pack_particles", "topic_plan", "topic_type", "TOPIC_TYPES",
           "PROBE_QUANTITIES", "QUANTITY_TYPES", "probe_kinds", "probe_topic", "probe_readings", "probe_values"]

PHASE_FLUID = 1
PHASE_SOLID = 2
PHASE_WALL = 3          # a wall that moves (parts.<name>.motion): ~/particles, not ~/walls
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
    rows, velocity = moving_walls(sim)
    if len(rows):
        parts.append((PHASE_WALL, sim.boundary.pos[rows], velocity, np.zeros(len(rows)), np.zeros(len(rows))))
    return parts


def moving_walls(sim):
    """(rows of the boundary, velocities) of the walls that move (sph_fsi_core.boundary.Boundary.moving_walls); the
    boundary's walls block holds the scene's walls in their own order, so the rows index sim.walls too."""
    boundary = getattr(sim, "boundary", None)
    if boundary is None or not boundary.moving:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 3))
    return boundary.moving_walls()


def wall_positions(sim):
    """Positions of every particle that never moves: wall particles, fixed fluid particles, the solid's clamp."""
    parts = []
    walls = getattr(sim, "walls", None)
    if walls is not None:
        rows, _ = moving_walls(sim)
        parts.append(np.delete(walls.pos, rows, axis=0) if len(rows) else walls.pos)
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
    if topic.startswith("parts/"):
        return PART_TYPES[topic.rsplit("/", 1)[1]]
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


# a commanded wall's topics (parts/<name>/<what>): what the node publishes, and the commands it takes (recorded)
PART_TYPES = {"pose": "geometry_msgs/msg/PoseStamped", "wrench": "geometry_msgs/msg/WrenchStamped",
              "pose_cmd": "geometry_msgs/msg/PoseStamped", "twist_cmd": "geometry_msgs/msg/TwistStamped"}


def part_topic(name, what):
    return f"parts/{name}/{what}"


def commanded_parts(sim):
    """The scene's walls driven by commands (parts.<name>.motion = ros), in file order."""
    boundary = getattr(sim, "boundary", None)
    return boundary.commanded() if boundary is not None else []


def quaternion(rotation):
    """(x, y, z, w) of a rotation matrix (Shepperd's method: the largest of the four first)."""
    r = np.asarray(rotation, dtype=np.float64)
    trace = r[0, 0] + r[1, 1] + r[2, 2]
    if trace > 0.0:
        s = 2.0 * np.sqrt(1.0 + trace)
        q = ((r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, 0.25 * s)
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * np.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k])
        q = [0.0, 0.0, 0.0, (r[k, j] - r[j, k]) / s]
        q[i], q[j], q[k] = 0.25 * s, (r[j, i] + r[i, j]) / s, (r[k, i] + r[i, k]) / s
    return tuple(float(v) for v in q)


def rotation_matrix(x, y, z, w):
    """The rotation matrix of a quaternion (x, y, z, w), normalised first (ValueError for one of length 0)."""
    norm = float(np.sqrt(x * x + y * y + z * z + w * w))
    if not norm > 0.0:
        raise ValueError("the orientation's quaternion has length 0")
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def command_numbers(what, msg):
    """(stamp s, numbers) of a command message, a live one (rclpy) or one read back from MCAP (mcap_ros2's decoded
    object: the same fields): a pose_cmd's ((x, y, z), (qx, qy, qz, qw)), a twist_cmd's (linear, angular)."""
    stamp = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
    if what == "pose_cmd":
        p, q = msg.pose.position, msg.pose.orientation
        return stamp, ((p.x, p.y, p.z), (q.x, q.y, q.z, q.w))
    v, w = msg.twist.linear, msg.twist.angular
    return stamp, ((v.x, v.y, v.z), (w.x, w.y, w.z))


def command_values(point, what, numbers):
    """The boundary's command (kind, values) of a command topic's numbers (sph_fsi_core.boundary.Boundary.command):
    a pose_cmd's (position, quaternion) -> ('pose', (rotation, position - point)), the wall's motion_point `point`
    to go to the position, turned by the quaternion from the built pose; a twist_cmd's (linear, angular) ->
    ('velocity', ...). The same numbers give the same bits (a replay's commands are a run's). ValueError for a
    quaternion of length 0."""
    first, second = (np.asarray(v, dtype=np.float64) for v in numbers)
    if what == "pose_cmd":
        return "pose", (rotation_matrix(*second), first - point)
    return "velocity", (first, second)


def part_readings(sim):
    """{name: {'position': (x, y, z) m, 'orientation': (x, y, z, w), 'force': N, 'moment': N m}} of each commanded
    wall now: its motion's point and turn, and the water's wrench on it about that point from the last fluid step
    (zero before the first)."""
    out = {}
    for name in commanded_parts(sim):
        position, rotation = sim.boundary.part_pose(name)
        force = moment = np.zeros(3)
        rows = sim.boundary.part_rows(name)
        if sim.fluid_phase is not None and sim.fluid_phase.steps:
            force, moment = sim.fluid_phase.wrench(rows, position)
        out[name] = {"position": _plain(position), "orientation": quaternion(rotation), "force": _plain(force),
                     "moment": _plain(moment)}
    return out


def topic_plan(sim):
    """Names of the scene-dependent topics this simulation has (module docstring)."""
    names = set()
    for name in commanded_parts(sim):
        names.update(part_topic(name, what) for what in PART_TYPES)
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
