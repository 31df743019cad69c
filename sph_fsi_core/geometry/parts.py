"""The part, probe and judge lists of a geometry scene (scenes/geometry.py), declared as schema keys.

A scene file lists them as YAML sequences of mappings, each with a unique `name`:

    parts:
      - {name: tank, role: wall, shape: box, size: [3.22, 1.0, 1.0], position: [1.61, 0, 0.5], side: outside,
         open: "+z"}
    probes:
      - {name: H2, kind: water_height, position: [0.992, 0.0, 0.0]}

scene.py flattens each entry into keys `parts.<name>.<key>` (`probes.<name>.<key>`, `judge.<name>.<key>`), and
`list_params` declares them as schema.Params, chosen by the entry's role and shape (or kind). So every key of every
part is checked as a section key is (type, range, unknown keys with a near match, one line naming the key), can be
overridden (`--set parts.box.position=[0.7, 0, 0.08]`) and is a ROS parameter of the node. Required keys have no
default: a part without one is refused by name.
"""
import re

from ..numerics.kernels import KERNELS
from ..schema import Param, SceneError

LISTS = ("parts", "probes", "judge")
NAME_RE = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
ROLES = ("water", "wall", "solid", "gate")
SHAPES = ("box", "cylinder", "sphere", "mesh")
FACES = ("-x", "+x", "-y", "+y", "-z", "+z")
PROBE_KINDS = ("point", "displacement", "pressure", "water_height", "force")
AXES = ("x", "y", "z")
JUDGE_KINDS = ("frequency", "mean", "series", "swing", "decay", "impulse")
MOTIONS = ("none", "linear", "sinusoid", "table", "ros")
REQUIRED = None    # a Param default meaning "must be given"


def _p(key, default, unit, description, **kw):
    return Param(key, default, unit, description, **kw)


def _every_part(k):
    return [_p(k + "role", REQUIRED, "", "What the part is: 'water' (filled with water), 'wall' (fixed particles), "
               "'solid' (an elastic body of the solid section's material), 'gate' (a wall gone or lifted at t = 0)",
               kind="str", choices=ROLES),
            _p(k + "shape", REQUIRED, "", "Its shape", kind="str", choices=SHAPES),
            _p(k + "position", (0.0, 0.0, 0.0), "m", "Where the shape's own origin goes (a box's, cylinder's or "
               "sphere's centre; a mesh's file origin)", kind="vec3"),
            _p(k + "rotation", (0.0, 0.0, 0.0), "deg", "Rotation about the world's x, then y, then z axis",
               kind="vec3"),
            _p(k + "order", "x y z", "", "The order its particles are numbered in: the world's axes from the slowest "
               "to the fastest, '-' for descending (a clamp behind a beam's root at x = 0: '-x y z', outward from "
               "its face)", kind="str"),
            _p(k + "lattice_offset", (0.0, 0.0, 0.0), "m", "Its sites counted from geometry.lattice_origin plus this "
               "(whole spacings: the same lattice): at origin + offset + (i + 1/2) dp, which can differ from origin + "
               "(i + 1/2) dp in the last bit; a block of sites counted from its own corner", kind="vec3"),
            _p(k + "move", (0.0, 0.0, 0.0), "m", "Its particles moved by this once placed (whole spacings: they stay "
               "on the lattice): the part its shape describes, again elsewhere (the second of a pair of walls)",
               kind="vec3"),
            _when(k, "part")]


def _when(k, what):
    return _p(k + "when", True, "", f"Whether the {what} is in the scene: false leaves it out as if not listed (an "
              f"expression in the scene's parameters: a part of one variant only)", kind="bool")


def _box(k):
    return [_p(k + "size", REQUIRED, "m", "Edge lengths along the part's own x, y, z axes", kind="vec3")]


def _cylinder(k):
    return [_p(k + "radius", REQUIRED, "m", "Radius", low=0.0, low_inclusive=False, high=1.0e3),
            _p(k + "length", REQUIRED, "m", "Length along the part's own z axis", low=0.0, low_inclusive=False,
               high=1.0e3)]


def _sphere(k):
    return [_p(k + "radius", REQUIRED, "m", "Radius", low=0.0, low_inclusive=False, high=1.0e3)]


def _mesh(k):
    return [_p(k + "file", REQUIRED, "", "Mesh file (STL, OBJ or PLY; a closed surface), relative to the scene "
               "file", kind="str"),
            _p(k + "scale", 1.0, "1", "Factor from the file's units to metres (0.001 for millimetres)", low=0.0,
               low_inclusive=False, high=1.0e6)]


def _water(k):
    return [_p(k + "velocity", (0.0, 0.0, 0.0), "m/s", "Initial velocity of the water", kind="vec3"),
            _p(k + "standing_wave_amplitude", 0.0, "m", "With standing_wave_length: linear theory's standing wave "
               "along x, eta = a cos(k (x - x0)) sin(omega t), omega^2 = g k tanh(k d), started at t = 0 (after "
               "fluid.settle_time) by its velocity field with the surface flat (answers/linear_waves.py), added to "
               "the water's velocity; its depth d and floor are the part's (0: none)", low=0.0, high=1.0e3),
            _p(k + "standing_wave_length", 0.0, "m", "The standing wave's length L = 2 pi / k, needed with an "
               "amplitude (a mode of the water: its period along x whole wavelengths, or its length between walls "
               "whole half wavelengths; else a warning)", low=0.0, high=1.0e3),
            _p(k + "standing_wave_antinode", 0.0, "m", "x0: the x of an antinode, where the surface rises first",
               low=-1.0e3, high=1.0e3)]


def _wall(k):
    return [_p(k + "side", "inside", "", "Where its particle layers go: 'inside' the shape's surface (an obstacle) "
               "or 'outside' it (a tank whose inside is the shape)", kind="str", choices=("inside", "outside")),
            _p(k + "layers", 0, "1", "Particle layers of the wall (0: the fewest that reach 2h)", kind="int", low=0,
               high=20),
            _p(k + "open", "", "", "Faces left open with side = outside, e.g. '+z' for a tank's top (a box: -x, +x, "
               "-y, +y, -z, +z of its own axes; a cylinder: -z, +z), space-separated", kind="str")]


def _gate(k):
    return [_p(k + "release", "instant", "", "At t = 0 the gate is gone ('instant') or starts moving at "
               "lift_velocity ('lifted'); with fluid.settle_time it holds the water while it settles", kind="str",
               choices=("instant", "lifted")),
            _p(k + "lift_velocity", (0.0, 0.0, 1.0), "m/s", "The lifted gate's velocity", kind="vec3"),
            _p(k + "lift_travel", 0.0, "m", "How far the lifted gate moves (0: until its lowest particle is 2h "
               "above the water's top)", low=0.0, high=1.0e3)]


def _motion(k):
    return [_p(k + "motion", "none", "", "How the wall moves, a rigid body from where it is built (motion.py): 'none', "
               "'linear' (motion_velocity from motion_start), 'sinusoid' (a translation along motion_axis, or a "
               "rotation about it through motion_point), 'table' (poses read from motion_file), 'ros' (commanded on "
               "the node's ~/parts/<name>/pose_cmd or twist_cmd)", kind="str", choices=MOTIONS)]


def _motion_linear(k):
    return [_p(k + "motion_velocity", REQUIRED, "m/s", "The wall's constant velocity", kind="vec3"),
            _p(k + "motion_start", 0.0, "s", "When it starts moving", low=0.0, high=1.0e4),
            _p(k + "motion_travel", 0.0, "m", "How far it moves, then stops (0: without end)", low=0.0, high=1.0e3)]


def _motion_point(k, what):
    return _p(k + "motion_point", (0.0, 0.0, 0.0), "m", f"The point {what}", kind="vec3")


def _motion_sinusoid(k):
    return [_p(k + "motion_axis", (1.0, 0.0, 0.0), "", "The translation's direction, or the rotation's axis (any "
               "length but 0)", kind="vec3"),
            _p(k + "motion_rotation", False, "", "A rotation about motion_axis through motion_point (amplitude in "
               "degrees) instead of a translation along it (amplitude in m)", kind="bool"),
            _p(k + "motion_amplitude", REQUIRED, "m or deg", "A: s(t) = A r(t) (sin(2 pi f t + phase) - sin(phase)), "
               "the stroke's half", low=-1.0e3, high=1.0e3),
            _p(k + "motion_frequency", REQUIRED, "Hz", "f", low=0.0, low_inclusive=False, high=1.0e4),
            _p(k + "motion_phase", 0.0, "deg", "The phase at t = 0 (the wall starts where it is built whatever "
               "it is)", low=-360.0, high=360.0),
            _p(k + "motion_ramp", 0.0, "s", "r(t) = (1 - cos(pi t / ramp)) / 2 up to ramp, 1 after (0: none): "
               "a smooth start from rest", low=0.0, high=1.0e4),
            _motion_point(k, "the rotation's axis passes through")]


def _motion_table(k):
    return [_p(k + "motion_file", REQUIRED, "", "CSV of poses, relative to the scene file: rows t, x, y, z (m) "
               "and optionally rx, ry, rz (degrees about x, then y, then z through motion_point), a header row and "
               "'#' comments allowed; linearly interpolated, held beyond its first and last rows", kind="str"),
            _motion_point(k, "the table's rotations turn about")]


def _motion_ros(k):
    return [_p(k + "motion_max_speed", REQUIRED, "m/s", "The fastest any of its particles may move: a command "
               "asking more is refused (and the water's step is kept short enough for it)", low=0.0,
               low_inclusive=False, high=1.0e3),
            _p(k + "motion_period", 0.01, "s", "A pose command is reached over this time from the pose the wall has "
               "when it applies, at a constant velocity (the controller's period)", low=0.0, low_inclusive=False,
               high=1.0e3),
            _motion_point(k, "its commanded rotations and angular velocities turn about")]


def _solid(k):
    return [_p(k + "clamp_lo", (0.0, 0.0, 0.0), "m", "Low corner of the clamp box: the body's particles inside it "
               "are its clamp (clamp_lo = clamp_hi: none, a free body)", kind="vec3"),
            _p(k + "clamp_hi", (0.0, 0.0, 0.0), "m", "High corner of the clamp box", kind="vec3"),
            _p(k + "velocity", (0.0, 0.0, 0.0), "m/s", "Initial velocity of the body", kind="vec3"),
            _p(k + "mode_tip_velocity", (0.0, 0.0, 0.0), "m/s", "Initial velocity in the first bending mode of a "
               "cantilever (Satake et al. eqs. (12)-(14)) from the clamp face along its normal, the free end moving "
               "at this velocity (0: none)", kind="vec3"),
            _p(k + "mode_length", 0.0, "m", "The length the mode's shape is scaled to (0: from the clamp face to "
               "the free end's particles plus half a spacing)", low=0.0, high=1.0e3),
            _p(k + "unreached_clamp", "keep", "", "With solid.clamp = mirrored, its clamp particles no moving "
               "particle comes within 2h + dp of: 'keep' them in the solid, or 'leave_out': they become the water's "
               "walls where they were built (the rigid holder they stand for; gone without water), and no solid pass "
               "steps them (a long clamp: scenes/built.without_unreached_clamp)", kind="str",
               choices=("keep", "leave_out"))]


def _every_probe(k):
    return [_p(k + "kind", REQUIRED, "", "What it measures: 'point' (displacement and velocity of the solid's "
               "material point nearest to position), 'displacement' (the mean displacement of the solid's moving "
               "particles inside a box), 'pressure' (the water's pressure at a point on a wall), "
               "'water_height' (the free surface above position's (x, y), over its z), 'force' (the water's force on "
               "a part)", kind="str", choices=PROBE_KINDS),
            _when(k, "probe")]


def _probe_position(k):
    return [_p(k + "position", REQUIRED, "m", "Where it measures", kind="vec3")]


def _probe_box(k):
    return [_p(k + "size", REQUIRED, "m", "Edge lengths of the box, centred on position, whose moving solid particles "
               "it follows (a beam's free end: one spacing along the beam, the body's width across)", kind="vec3")]


def _probe_pressure(k):
    return [_p(k + "part", "", "", "A moving wall the probe rides on: its position is where it is when the wall is "
               "built, and it moves with it ('': stays where it is)", kind="str"),
            _p(k + "inset", 0.0, "m", "How far into the water it reads, from position along the wall's normal (about "
               "1.5 h reads the water beside the wall where its kernel is full; 0: at position)", low=0.0,
               high=1.0e3),
            _p(k + "normal", (0.0, 0.0, 0.0), "1", "The wall's normal into the water, for inset ([0, 0, 0]: away from "
               "the wall particles within 2h of position, their centroid)", kind="vec3")]


def _probe_area(k):
    return [_p(k + "span_x", 0.0, "m", "With span_y: the mean height over a rectangle span_x by span_y centred on "
               "position, of vertical lines about a spacing apart (a level's mean, whatever its waves; 0: the line "
               "through position)", low=0.0, high=1.0e3),
            _p(k + "span_y", 0.0, "m", "The rectangle's length along y", low=0.0, high=1.0e3)]


def _probe_kernel(k):
    return [_p(k + "smoothing_ratio", 0.0, "1", "The probe's own h / dp, 1 to 2: it reads the water through a kernel "
               "(a pressure's Shepard average, a water height's filled half) that reaches 2h, so a wider h reads over "
               "more of the water (0: the water's, numerics.smoothing_ratio)", low=0.0, high=2.0),
            _p(k + "kernel", "water", "", "The probe's kernel: 'water' (fluid.kernel), or one of numerics/kernels.py's "
               "by name", kind="str", choices=("water",) + tuple(KERNELS))]


def _probe_part(k):
    return [_p(k + "part", REQUIRED, "", "The wall, gate or solid part the water pushes", kind="str")]


def _every_judge(k):
    return [_p(k + "kind", REQUIRED, "", "How a time-series column is judged: 'frequency' (its dominant frequency "
               "against reference), 'mean' (its mean over [from, to] against reference), 'series' (against a "
               "measured series in a CSV file), 'swing' (its standard deviation over [from, to] as a fraction of "
               "reference), 'decay' (the fraction of its oscillation's amplitude lost per period), 'impulse' (the "
               "water's change of momentum against the impulse of the walls' forces on it)", kind="str",
               choices=JUDGE_KINDS),
            _p(k + "column", REQUIRED, "", "The timeseries.csv column judged (a probe's, e.g. 'tip_dz', 'P1', 'H2')",
               kind="str"),
            _p(k + "source", "", "", "Where the reference comes from (shown in the summary)", kind="str"),
            _p(k + "from", 0.0, "s", "Judged from this simulated time", low=0.0, high=1.0e3),
            _p(k + "to", 0.0, "s", "Judged up to this simulated time (0: the run's end)", low=0.0, high=1.0e3),
            _when(k, "judge")]


def _judge_reference(k):
    return [_p(k + "reference", REQUIRED, "", "The reference value (Hz for a frequency; the column's unit for a "
               "mean, and for a swing the scale it is measured against)"),
            _p(k + "tolerance", 0.0, "1", "Relative error allowed (0: reported, not checked)", low=0.0, high=10.0),
            _p(k + "baseline_from", 0.0, "s", "With baseline_to: the column judged as its change from its mean over "
               "[baseline_from, baseline_to] (a level's rise, whatever the probe reads at rest)", low=0.0, high=1.0e3),
            _p(k + "baseline_to", 0.0, "s", "The baseline's end (0: no baseline, the column as it is)", low=0.0,
               high=1.0e3)]


def _judge_series(k):
    return [_p(k + "file", REQUIRED, "", "CSV of the measurement ('#' comment lines, a header row, time in its "
               "first column), relative to the scene file, or 'reference_data:<name>' for the package's",
               kind="str"),
            _p(k + "file_column", REQUIRED, "", "The file's column judged against", kind="str"),
            _p(k + "scale", 1.0, "1", "Factor on the simulated column before the comparison", low=-1.0e6,
               high=1.0e6),
            _p(k + "average", 0.0, "s", "Both series averaged over this centred window first (0: as sampled)",
               low=0.0, high=10.0),
            _p(k + "rms_tolerance", 0.0, "", "RMS difference allowed, in the column's unit (0: reported, not "
               "checked)", low=0.0),
            _p(k + "threshold", 0.0, "", "With a value: the first time each series reaches it (an impact), and "
               "each series' peak from then to `to`", ),
            _p(k + "onset_tolerance", 0.0, "s", "Allowed difference of those first times (0: not checked)",
               low=0.0, high=10.0),
            _p(k + "peak_tolerance", 0.0, "1", "Allowed relative difference of the peaks (0: not checked)",
               low=0.0, high=10.0)]


def _judge_decay(k):
    return [_p(k + "reference", 0.0, "1", "The fraction of the amplitude lost per period expected (0: none, as an "
               "inviscid answer); the error is the measured loss less it", low=0.0, high=1.0, high_inclusive=False),
            _p(k + "tolerance", 0.0, "1", "Loss per period allowed beyond the reference (0: reported, not checked)",
               low=0.0, high=1.0)]


def _judge_impulse(k):
    return [_p(k + "forces", REQUIRED, "", "The force probes' columns along the column's axis whose impulse the "
               "water's momentum (column: a fluid_momentum_ column) must balance, comma-separated (e.g. "
               "'box_fx, floor_fx'): every wall the water touches, along an axis gravity does not act on", kind="str"),
            _p(k + "tolerance", 0.0, "1", "Largest imbalance allowed, as a fraction of the largest impulse (0: "
               "reported, not checked)", low=0.0, high=10.0)]


# Which entries have which keys, in the order an entry's keys are declared: (the entries, as the reference names
# them; the roles and shapes (parts) or kinds (probes, judges) that have them; their declarations).
PART_GROUPS = (("every part", ROLES, SHAPES, _every_part),
               ("shape box", ROLES, ("box",), _box),
               ("shape cylinder", ROLES, ("cylinder",), _cylinder),
               ("shape sphere", ROLES, ("sphere",), _sphere),
               ("shape mesh", ROLES, ("mesh",), _mesh),
               ("role water", ("water",), SHAPES, _water),
               ("role wall or gate", ("wall", "gate"), SHAPES, _wall),
               ("role gate", ("gate",), SHAPES, _gate),
               ("role wall", ("wall",), SHAPES, _motion),
               ("role solid", ("solid",), SHAPES, _solid))
# a moving wall's keys, by its motion (role wall)
MOTION_GROUPS = (("wall, motion linear", ("linear",), _motion_linear),
                 ("wall, motion sinusoid", ("sinusoid",), _motion_sinusoid),
                 ("wall, motion table", ("table",), _motion_table),
                 ("wall, motion ros", ("ros",), _motion_ros))
PROBE_GROUPS = (("every probe", PROBE_KINDS, _every_probe),
                ("kind point, displacement, pressure or water_height", ("point", "displacement", "pressure",
                                                                        "water_height"), _probe_position),
                ("kind displacement", ("displacement",), _probe_box),
                ("kind pressure", ("pressure",), _probe_pressure),
                ("kind water_height", ("water_height",), _probe_area),
                ("kind pressure or water_height", ("pressure", "water_height"), _probe_kernel),
                ("kind force", ("force",), _probe_part))
JUDGE_GROUPS = (("every judge", JUDGE_KINDS, _every_judge),
                ("kind frequency, mean or swing", ("frequency", "mean", "swing"), _judge_reference),
                ("kind series", ("series",), _judge_series),
                ("kind decay", ("decay",), _judge_decay),
                ("kind impulse", ("impulse",), _judge_impulse))


def part_params(name, role, shape, motion="none"):
    """The Params of part `name` with this role, shape and (a wall's) motion."""
    k = f"parts.{name}."
    out = [p for _, roles, shapes, declare in PART_GROUPS if role in roles and shape in shapes for p in declare(k)]
    if role == "wall":
        out += [p for _, motions, declare in MOTION_GROUPS if motion in motions for p in declare(k)]
    return out


def probe_params(name, kind):
    k = f"probes.{name}."
    return [p for _, kinds, declare in PROBE_GROUPS if kind in kinds for p in declare(k)]


def judge_params(name, kind):
    k = f"judge.{name}."
    return [p for _, kinds, declare in JUDGE_GROUPS if kind in kinds for p in declare(k)]


def reference():
    """Every key an entry of each list may have, by role and shape or kind: [(list, which entries, [Param])], the
    Params' keys `<list>.<name>.<key>` with `<name>` as written. The one source of `sph-fsi keys`' listing,
    config/defaults.yaml's and the README's table."""
    out = []
    for which, groups in (("parts", [(g[0], g[3]) for g in PART_GROUPS] + [(g[0], g[2]) for g in MOTION_GROUPS]),
                          ("probes", [(g[0], g[2]) for g in PROBE_GROUPS]),
                          ("judge", [(g[0], g[2]) for g in JUDGE_GROUPS])):
        k = f"{which}.<name>."
        for i, (entries, declare) in enumerate(groups):
            params = declare(k)
            if i == 0:
                params = [_p(k + "name", REQUIRED, "", "Its name, unique in the list: letters, digits and '_', "
                             f"starting with a letter (its keys are {which}.<name>.<key>)", kind="str")] + params
            out.append((which, entries, params))
    return out


def _shown(value):
    """A default as the README's table shows it."""
    if isinstance(value, tuple):
        return "[" + ", ".join(f"{v:g}" for v in value) + "]"
    if isinstance(value, str):
        return f"`{value}`" if value else "''"
    return f"{value:g}"


def reference_table(width=120):
    """The README's table of the list keys (reference()): a row per list and group of entries, each key with its
    unit, its default or `required`, and its choices; a group's keys run on in rows of their own (blank first
    cells) to stay within `width` characters."""
    lines = ["| list | entries | keys (unit) = default, or required |", "|---|---|---|"]
    for which, entries, params in reference():
        cells = []
        for p in params:
            text = f"`{p.key.rsplit('.', 1)[1]}`" + (f" ({p.unit})" if p.unit and p.unit != "1" else "")
            if p.default is REQUIRED:
                text += " required" + (": " + " / ".join(f"`{c}`" for c in p.choices) if p.choices else "")
            else:
                text += f" = {_shown(p.default)}"
                others = [f"`{c}`" for c in p.choices if c != p.default]
                text += f" (or {', '.join(others)})" if others else ""
            cells.append(text)
        head = f"| `{which}` | {entries} | "
        row = head
        for cell in cells:
            more = cell if row == head else f"; {cell}"
            if len(row) + len(more) + 2 > width and row != head:
                lines.append(row + " |")
                row, more = "| | | ", cell
                head = row
            row += more
        lines.append(row + " |")
    return lines


def list_entries(flat, which, listed=False):
    """{name: {key: value}} of list `which` in the flat keys, in file order: the entries in the scene (`when` not
    false), or with `listed` every one the file lists."""
    out = {}
    prefix = which + "."
    for key, value in flat.items():
        if key.startswith(prefix) and key.count(".") == 2:
            _, name, sub = key.split(".")
            out.setdefault(name, {})[sub] = value
    return out if listed else {name: keys for name, keys in out.items() if keys.get("when", True) is not False}


def _choice(flat, key, choices):
    value = flat.get(key)
    if value is None:
        raise SceneError(f"{key}: missing; allowed: one of " + ", ".join(repr(c) for c in choices))
    if not isinstance(value, str) or value not in choices:
        raise SceneError(f"{key} = {value!r}: not a known choice; allowed: one of "
                         + ", ".join(repr(c) for c in choices))
    return value


def list_params(flat):
    """The Params of every part, probe and judge the flat keys name (SceneError naming a missing or unknown role,
    shape or kind)."""
    out = []
    for name in list_entries(flat, "parts", listed=True):
        role = _choice(flat, f"parts.{name}.role", ROLES)
        shape = _choice(flat, f"parts.{name}.shape", SHAPES)
        motion = "none"
        if role == "wall" and f"parts.{name}.motion" in flat:
            motion = _choice(flat, f"parts.{name}.motion", MOTIONS)
        out += part_params(name, role, shape, motion)
    for name in list_entries(flat, "probes", listed=True):
        out += probe_params(name, _choice(flat, f"probes.{name}.kind", PROBE_KINDS))
    for name in list_entries(flat, "judge", listed=True):
        out += judge_params(name, _choice(flat, f"judge.{name}.kind", JUDGE_KINDS))
    return out


# what gives a geometry scene each section its parts may leave it without (schema.Schema.check_key)
ABSENT_SECTIONS = {"solid": "a part of role solid", "fluid": "a part of role water",
                   "coupling": "both a solid and a water part"}


def phases_of(flat):
    """The phases a scene of these parts has: water -> fluid, wall and gate -> walls, solid -> solid; coupling where
    there are both a solid and water. SceneError if it lists no part (before its sections are checked: they follow
    from the parts). A part left out by a literal `when: false` gives none; one whose `when` is an expression counts
    (the sections come before the expressions: scenes/geometry.check refuses a phase left without its parts)."""
    names = list_entries(flat, "parts")
    if not names:
        raise SceneError("parts: none; allowed: at least one part (a geometry scene is built from its parts, and its "
                         "sections follow from their roles: 'fluid' from a water part, 'solid' from a solid part)")
    roles = {_choice(flat, f"parts.{name}.role", ROLES) for name in names}
    phases = []
    if "solid" in roles:
        phases.append("solid")
    if "water" in roles:
        phases.append("fluid")
    if roles & {"wall", "gate"}:
        phases.append("walls")
    if "solid" in roles and "water" in roles:
        phases.append("coupling")
    return tuple(phases)


def check_required(values):
    """SceneError naming the first list key that has no value (a required key the file did not give)."""
    for key, value in values.items():
        if value is REQUIRED and key.split(".", 1)[0] in LISTS:
            raise SceneError(f"{key}: missing; allowed: " + {"parts": "every part needs it",
                                                             "probes": "every probe of its kind needs it",
                                                             "judge": "every judge of its kind needs it"}[
                                                                 key.split(".", 1)[0]])


def parse_order(key, text):
    """(axes, signs) of a part's `order` ('-x y z' -> ((0, 1, 2), (-1, 1, 1))), SceneError naming the key."""
    words = text.split()
    axes = [AXES.index(w.lstrip("+-")) if w.lstrip("+-") in AXES else -1 for w in words]
    if len(words) != 3 or sorted(axes) != [0, 1, 2]:
        raise SceneError(f"{key} = {text!r}: not an order of the axes; allowed: x, y and z once each, slowest first, "
                         f"each with '-' for descending (e.g. '-x y z')")
    return tuple(axes), tuple(-1 if w.startswith("-") else 1 for w in words)


def parse_faces(key, text, shape, side):
    """The open faces of a wall part ('+z -x' -> ('+z', '-x')), SceneError naming the key if not allowed."""
    faces = tuple(f for f in re.split(r"[\s,]+", text.strip()) if f)
    allowed = {"box": FACES, "cylinder": ("-z", "+z")}.get(shape, ())
    for f in faces:
        if f not in allowed:
            raise SceneError(f"{key} = {text!r}: {f!r} is not a face of a {shape}; allowed: "
                             + (", ".join(allowed) if allowed else "none (only a box's or a cylinder's faces open)"))
    if faces and side != "outside":
        raise SceneError(f"{key} = {text!r}: open faces belong to a wall built outside its shape (a tank); allowed: "
                         f"'' with side = {side}")
    if len(set(faces)) != len(faces):
        raise SceneError(f"{key} = {text!r}: a face named twice; allowed: each face once")
    return faces
