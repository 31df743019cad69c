"""The scene file as a user meets it: malformed files refused in one line naming the file, the part and the key, the
bad value and what is allowed (exit status 2, nothing written); what the keys are (`sph-fsi keys`); scenes that run
but cannot mean what they say warned about; water poured around an obstacle; sites on a shared face; water that
leaves the domain recorded, and stopped only where the scene asks (exit status 4)."""
import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import yaml

from sph_fsi.cli import main
from sph_fsi_core.diagnostics import Diverged, WaterLost
from sph_fsi_core.fluid.lost_water import LostWater
from sph_fsi_core.geometry.lattice import Lattice, filled, outer_shell, site_keys
from sph_fsi_core.geometry.parts import JUDGE_KINDS, MOTIONS, PROBE_KINDS, ROLES, SHAPES, judge_params, \
    part_params, probe_params, reference
from sph_fsi_core.geometry.shapes import Shape
from sph_fsi_core.scene import SceneError, defaults_yaml, load_scene
from sph_fsi_core.scenes import build_scene
from sph_fsi_core.simulation import Simulation

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "config" / "examples"

TANK = {"name": "tank", "role": "wall", "shape": "box", "size": [0.3, 0.1, 0.3], "position": [0.15, 0.05, 0.15],
        "side": "outside", "open": "+z"}
WATER = {"name": "water", "role": "water", "shape": "box", "size": [0.1, 0.1, 0.1], "position": [0.05, 0.05, 0.05]}


def scene(tmp_path, parts, name="scene.yaml", **sections):
    tree = {"scene": {"builder": "geometry", "end_time": 0.002}, "numerics": {"spacing": 0.01},
            "output": {"timeseries_interval": 0.001, "snapshot_interval": 0.0}, **sections, "parts": parts}
    path = tmp_path / name
    path.write_text(yaml.safe_dump(tree, sort_keys=False))
    return str(path)


def refused(capsys, tmp_path, args):
    """Run `sph-fsi run ARGS --out OUT`: exit status 2, one line on stderr (returned), nothing on stdout, no OUT."""
    out = tmp_path / "out" / "run"
    code = main(["run", *args, "--out", str(out)])
    stdout, stderr = capsys.readouterr()
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    assert code == 2, stderr
    assert len(lines) == 1 and stdout == "", stderr
    assert not (tmp_path / "out").exists()
    assert "np.float64" not in lines[0] and "Traceback" not in stderr
    return lines[0]


# ---- the keys of the lists, listed ---------------------------------------------------------------------------

def test_the_reference_lists_every_key_an_entry_can_have_by_role_shape_and_kind():
    """reference() (the source of `sph-fsi keys`, config/defaults.yaml's and the README's list keys) holds every
    key a part of any role and shape, a probe or a judge of any kind declares, under entries that name it."""
    groups = [(which, entries.replace(",", " ").split(), {p.key.rsplit(".", 1)[1] for p in params})
              for which, entries, params in reference()]

    def listed(which, *words):
        return set().union(*(keys for w, named, keys in groups
                             if w == which and (named[0] == "every" or set(words) & set(named))))

    for role in ROLES:
        for shape in SHAPES:
            motions = MOTIONS if role == "wall" else ("none",)
            declared = set().union(*({p.key.rsplit(".", 1)[1] for p in part_params("p", role, shape, motion)}
                                     for motion in motions))
            assert declared | {"name"} == listed("parts", role, shape), (role, shape)
    for kind in PROBE_KINDS:
        assert {p.key.rsplit(".", 1)[1] for p in probe_params("p", kind)} | {"name"} == listed("probes", kind), kind
    for kind in JUDGE_KINDS:
        assert {p.key.rsplit(".", 1)[1] for p in judge_params("j", kind)} | {"name"} == listed("judge", kind), kind
    assert listed("parts", "cylinder") - listed("parts") == {"radius", "length"}


def _under(text, heading):
    """The lines of config/defaults.yaml's list block under `heading` (a `#   ...:` line), up to the next one."""
    lines = text.splitlines()
    start = lines.index(heading) + 1
    end = next(i for i in range(start, len(lines) + 1) if i == len(lines) or not lines[i].startswith("#     "))
    return lines[start:end]


def test_sph_fsi_keys_lists_the_part_probe_and_judge_keys(capsys):
    assert main(["keys", "--yaml"]) == 0
    text, _ = capsys.readouterr()
    assert text == defaults_yaml() == (REPO / "config" / "defaults.yaml").read_text()
    for heading, line in (("#   shape cylinder:", "#     radius: required  # [m] Radius"),
                          ("#   shape cylinder:", "#     length: required  # [m] Length along the part's own z"),
                          ("#   shape sphere:", "#     radius: required"), ("#   shape box:", "#     size: required"),
                          ("#   shape mesh:", "#     scale: 1.0  # [1] Factor"),
                          ("#   role solid:", "#     clamp_lo: [0.0, 0.0, 0.0]"),
                          ("#   kind force:", "#     part: required"),
                          ("#   kind series:", "#     file_column: required")):
        assert any(ln.startswith(line) for ln in _under(text, heading)), (heading, line)
    assert main(["keys", "hydrostatic"]) == 0
    text, _ = capsys.readouterr()
    rows = {}
    for line in text.splitlines():
        if not line.startswith("#"):
            rows[line.split()[0]] = rows.get(line.split()[0], "") + line + "\n"   # a key of several kinds: a row each
    assert "shape cylinder" in rows["parts.<name>.length"] and "required" in rows["parts.<name>.length"]
    assert "kind point, displacement, pressure or water_height" in rows["probes.<name>.position"]
    assert "kind frequency, mean or swing" in rows["judge.<name>.reference"]
    assert "= 0.0            [1] in [0, 1); kind decay" in rows["judge.<name>.reference"]


# ---- refusals: one line naming the file, the part and the key; exit status 2; nothing written ---------------

def test_a_refusal_found_while_building_comes_before_the_run_is_announced_or_its_directory_made(tmp_path, capsys):
    wall = {"name": "post", "role": "wall", "shape": "box", "size": [0.06, 0.06, 0.06], "position": [0.3, 0.05, 0.05]}
    path = scene(tmp_path, [TANK, WATER, wall])
    line = refused(capsys, tmp_path, [path])
    assert line.startswith(f"sph-fsi: {path}: parts.post: overlaps parts.tank at 108 lattice site(s)")
    assert "e.g. [0.305, 0.025, 0.025] m" in line


def test_an_empty_part_list_is_refused_naming_parts_not_the_fluid_section(tmp_path, capsys):
    path = tmp_path / "empty.yaml"
    path.write_text("scene: {builder: geometry}\nfluid: {density: 1000.0}\nparts: []\n")
    line = refused(capsys, tmp_path, [str(path)])
    assert line.startswith(f"sph-fsi: {path}: parts: none; allowed: at least one part"), line
    # a section the parts do not make names what would make it
    path = scene(tmp_path, [TANK], fluid={"density": 1000.0})
    line = refused(capsys, tmp_path, [path])
    assert "fluid.density: this scene has no 'fluid' section" in line and "a part of role water" in line


@pytest.mark.parametrize("which, override, named", [
    ("parts", "parts.nosuch.position=[0, 0, 0]", "no part named 'nosuch'; allowed: one of 'tank', 'water'"),
    ("parts", "parts.watr.size=[0.1, 0.1, 0.1]", "no part named 'watr' (did you mean 'water'?); allowed: one of"),
    ("probes", "probes.levl.position=[0, 0, 0]", "no probe named 'levl' (did you mean 'level'?)"),
    ("judge", "judge.nosuch.reference=1.0", "no judge named 'nosuch'; allowed: one of 'mean_level'"),
])
def test_an_override_of_a_missing_part_probe_or_judge_names_the_ones_there_are(tmp_path, capsys, which, override,
                                                                              named):
    path = scene(tmp_path, [TANK, WATER], probes=[{"name": "level", "kind": "water_height",
                                                   "position": [0.05, 0.05, 0.0]}],
                 judge=[{"name": "mean_level", "kind": "mean", "column": "level", "reference": 0.1}])
    line = refused(capsys, tmp_path, [path, "--set", override])
    assert line.startswith(f"sph-fsi: {override.split('=')[0]} = ") and named in line, line
    assert "missing" not in line
    # an entry the overrides make whole (its role and shape) is a new part, not a misspelt one
    spec = load_scene(path, ["parts.extra.role=wall", "parts.extra.shape=sphere", "parts.extra.radius=0.03",
                             "parts.extra.position=[0.2, 0.05, 0.2]"])
    assert spec["parts.extra.radius"] == 0.03


def test_a_directory_is_said_to_be_a_directory(tmp_path, capsys):
    folder = tmp_path / "scene.yaml"
    folder.mkdir()
    line = refused(capsys, tmp_path, [str(folder)])
    assert line == f"sph-fsi: scene file '{folder}': a directory, not a file; allowed: a YAML scene file or a " \
                   f"built-in scene's name"
    (tmp_path / "fin.stl").mkdir()
    path = scene(tmp_path, [TANK, WATER, {"name": "fin", "role": "wall", "shape": "mesh", "file": "fin.stl"}],
                 name="with_mesh.yaml")
    line = refused(capsys, tmp_path, [path])
    assert line.startswith(f"sph-fsi: {path}: parts.fin.file = '{tmp_path / 'fin.stl'}': a directory, not a file")


def test_an_unreadable_mesh_is_named_as_not_a_mesh_of_the_formats_allowed(tmp_path, capsys):
    """Random bytes in an .stl: trimesh's loader reaches for an optional module (charset_normalizer); the user
    hears about the file, not the module."""
    (tmp_path / "noise.stl").write_bytes(np.random.default_rng(1).integers(0, 256, 2000, dtype=np.uint8).tobytes())
    (tmp_path / "noise.ply").write_text("solid nothing\n")
    for name, kind in (("noise.stl", "an STL"), ("noise.ply", "a PLY")):
        path = scene(tmp_path, [TANK, WATER, {"name": "fin", "role": "wall", "shape": "mesh", "file": name}],
                     name=f"{name}.yaml")
        line = refused(capsys, tmp_path, [path])
        assert line == (f"sph-fsi: {path}: parts.fin.file = '{tmp_path / name}': cannot be read as {kind} mesh; "
                        f"allowed: an STL, OBJ or PLY file of a closed surface"), line


def test_a_flat_mesh_encloses_no_volume(tmp_path, capsys):
    import trimesh
    square = trimesh.Trimesh(vertices=[[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0.1, 0.1, 0]],
                             faces=[[0, 1, 2], [1, 3, 2], [0, 2, 1], [1, 2, 3]], process=False)   # both sides
    square.export(str(tmp_path / "flat.stl"))
    path = scene(tmp_path, [TANK, WATER, {"name": "fin", "role": "wall", "shape": "mesh", "file": "flat.stl",
                                          "position": [0.2, 0.0, 0.1]}])
    line = refused(capsys, tmp_path, [path])
    assert line == (f"sph-fsi: {path}: parts.fin.file = '{tmp_path / 'flat.stl'}': encloses no volume (its vertices "
                    f"lie in one plane); allowed: a closed surface around a volume"), line


def test_clamp_messages_print_plain_numbers(tmp_path, capsys):
    beam = {"name": "beam", "role": "solid", "shape": "box", "size": [0.044, 0.006, 0.004],
            "position": [0.018, 0.0, 0.0], "clamp_lo": [0.0, 0.0, 0.0], "clamp_hi": [-0.01, 0.01, 0.01]}
    tree = {"scene": {"builder": "geometry", "gravity": [0.0, 0.0, 0.0]}, "numerics": {"spacing": 0.001}}
    path = scene(tmp_path, [beam], **{k: v for k, v in tree.items() if k != "scene"})
    line = refused(capsys, tmp_path, [path])
    assert line == (f"sph-fsi: {path}: parts.beam.clamp_hi = [-0.01, 0.01, 0.01]: not above clamp_lo = [0, 0, 0] on "
                    f"every axis; allowed: a box with clamp_lo < clamp_hi (or both equal: no clamp)"), line
    beam.update(clamp_lo=[0.5, 0.5, 0.5], clamp_hi=[0.6, 0.6, 0.6])
    path = scene(tmp_path, [beam], numerics={"spacing": 0.001})
    line = refused(capsys, tmp_path, [path])
    assert line.startswith(f"sph-fsi: {path}: parts.beam.clamp_lo: the clamp box [[0.5, 0.5, 0.5], [0.6, 0.6, 0.6]] "
                           f"holds none of the part's particles"), line


# ---- a free body ----------------------------------------------------------------------------------------------

def test_a_solid_without_a_clamp_is_a_free_body_that_runs(tmp_path, capsys):
    beam = {"name": "beam", "role": "solid", "shape": "box", "size": [0.012, 0.004, 0.004],
            "velocity": [0.0, 0.0, 0.01]}
    path = scene(tmp_path, [beam], numerics={"spacing": 0.001})
    out = tmp_path / "free"
    assert main(["run", path, "--set", "scene.gravity=[0, 0, 0]", "--end-time", "0.002", "--out", str(out)]) == 0
    _, err = capsys.readouterr()
    note = "parts.beam: no clamp box (clamp_lo = clamp_hi): a free body (solid.clamp = mirrored mirrors only the " \
           "parts with one)"
    assert f"sph-fsi: {note}" in err and "warning" not in err, err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "finished" and summary["notes"] == [note] and summary["particles"]["solid_moving"] \
        == summary["particles"]["solid"] == 12 * 4 * 4
    # the body drifts as one: its momentum is kept
    series = np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)
    assert series["kinetic_energy"][-1] == pytest.approx(0.5 * 1000.0 * 0.012 * 0.004 * 0.004 * 0.01 ** 2, rel=1e-3)
    # under gravity with nothing to carry it, it runs with a warning: no wall holds a solid up
    built, _ = build_scene("geometry", load_scene(path).values)
    assert len(built.warnings) == 1 and built.warnings[0].startswith("parts.beam: a free body (no clamp_lo, "
                                                                     "clamp_hi) under scene.gravity with no water")
    assert "falls through them" in built.warnings[0]


# ---- scenes that run but cannot mean what they say -----------------------------------------------------------

def test_water_outside_every_tank_and_a_dry_probe_run_with_warnings(tmp_path, capsys):
    beside = dict(WATER, position=[0.6, 0.05, 0.05])
    probes = [{"name": "p_air", "kind": "pressure", "position": [0.15, 0.05, 0.4]},
              {"name": "p_wall", "kind": "pressure", "position": [0.0, 0.05, 0.02]},
              {"name": "h_none", "kind": "water_height", "position": [0.45, 0.2, 0.0]},
              {"name": "p_far", "kind": "pressure", "position": [5.0, 0.0, 0.0]}]
    path = scene(tmp_path, [TANK, beside], probes=probes)
    out = tmp_path / "warned"
    assert main(["run", path, "--out", str(out)]) == 0
    _, err = capsys.readouterr()
    warnings = json.loads((out / "summary.json").read_text())["warnings"]
    assert len(warnings) == 4, warnings
    assert warnings[0] == ("parts.water: 1000 of its 1000 particles have no wall, gate or solid below them along "
                           "scene.gravity (water outside every tank): that water will only fall, and leave the domain")
    assert warnings[1].startswith("probes.p_air.position = [0.15, 0.05, 0.4]: in mid-air, ")
    assert warnings[2].startswith("probes.h_none.position = [0.45, 0.2, 0]: no wall, gate, solid or water within")
    assert warnings[3].startswith("probes.p_far.position = [5, 0, 0]: outside the domain box")
    for w in warnings:       # in the log as the run starts
        assert f"sph-fsi: warning: {w}" in err
    # water in no tank at all
    built, _ = build_scene("geometry", load_scene(scene(tmp_path, [beside], name="alone.yaml")).values)
    assert built.warnings == [warnings[0]]
    # the examples and a tank of water mean what they say
    for path, overrides in ((EXAMPLES / "hydrostatic_geometry.yaml", []), (EXAMPLES / "cantilever_geometry.yaml", []),
                            (REPO / "test" / "data" / "geometry_probes.yaml", []),
                            (REPO / "config" / "spheric2_dam_break.yaml", ["numerics.spacing=0.055"]),
                            (EXAMPLES / "spheric2_elastic_fin.yaml", [])):
        built, _ = build_scene("geometry", load_scene(str(path), overrides).values)
        assert built.warnings == [] and not any("free body" in n for n in built.notes), path.name


# ---- water poured around an obstacle -------------------------------------------------------------------------

def test_walls_and_solids_take_the_waters_sites_and_say_how_many(tmp_path):
    tank = dict(TANK, size=[0.4, 0.4, 0.3], position=[0.2, 0.2, 0.15])
    water = dict(WATER, size=[0.4, 0.4, 0.2], position=[0.2, 0.2, 0.1])
    cylinder = {"name": "cylinder", "role": "wall", "shape": "cylinder", "radius": 0.08, "length": 0.3,
                "position": [0.2, 0.2, 0.15]}
    spec = load_scene(scene(tmp_path, [tank, water, cylinder]))
    built, _ = build_scene("geometry", spec.values)
    lattice = Lattice(0.01)
    inside = lattice.positions(filled(lattice, Shape("cylinder", np.array([0.08, 0.3]), np.eye(3),
                                                     np.array([0.2, 0.2, 0.15]))))
    in_water = inside[inside[:, 2] < 0.2]
    assert built.fluid.count == 40 * 40 * 20 - len(in_water)
    assert built.notes == [f"parts.cylinder took {len(in_water)} of the 32000 lattice sites of parts.water (a wall, "
                           f"gate or solid takes the water's sites it overlaps, an obstacle's or a solid's every site "
                           f"inside its surface)"]
    # none inside the obstacle (its hollow included), and none nearer a wall than the lattice's spacing
    r = np.hypot(built.fluid.pos[:, 0] - 0.2, built.fluid.pos[:, 1] - 0.2)
    assert r.min() > 0.08
    walls = built.walls.pos
    nearest = min(np.sqrt(((walls - p) ** 2).sum(axis=1)).min() for p in built.fluid.pos[r < 0.1])
    assert nearest == pytest.approx(0.01)
    assert built.parts["water"][0] == "fluid" and len(built.parts["water"][1]) == built.fluid.count
    # a solid takes them too; walls, gates and solids still may not overlap each other
    post = {"name": "post", "role": "solid", "shape": "box", "size": [0.06, 0.06, 0.06], "position": [0.1, 0.1, 0.05]}
    built, _ = build_scene("geometry", load_scene(scene(tmp_path, [tank, water, post], name="s.yaml"),
                                                  ["solid.scheme=gray2001"]).values)
    assert built.fluid.count == 32000 - 216 and built.solid.count == 216 and "parts.post took 216" in built.notes[0]
    gate = dict(cylinder, name="door", role="gate", position=[0.2, 0.2, 0.15], radius=0.05)
    with pytest.raises(SceneError, match="parts.door: overlaps parts.cylinder at"):
        build_scene("geometry", load_scene(scene(tmp_path, [tank, water, cylinder, gate], name="g.yaml")).values)
    # water with nothing left of it is refused by name
    small = dict(WATER, size=[0.04, 0.04, 0.04], position=[0.2, 0.2, 0.1])
    with pytest.raises(SceneError, match=r"parts.water: holds no lattice site once parts.cylinder took theirs"):
        build_scene("geometry", load_scene(scene(tmp_path, [tank, small, cylinder], name="w.yaml")).values)


def test_a_site_on_a_shared_face_belongs_to_one_part_and_the_water_keeps_its_volume(tmp_path):
    """Faces on lattice planes (sites at 0.005 + 0.01 i, a box from 0.005 to 0.205): a box holds the sites on its
    low faces and not those on its high faces, so a water box filling a tank's inside holds its volume's worth
    (30 x 10 x 20 sites) and the tank's walls take none of its sites; two boxes sharing a face share no site and
    leave none out."""
    tank = dict(TANK, size=[0.3, 0.1, 0.3], position=[0.155, 0.055, 0.155])      # its inside from 0.005
    water = dict(WATER, size=[0.3, 0.1, 0.2], position=[0.155, 0.055, 0.105])
    built, _ = build_scene("geometry", load_scene(scene(tmp_path, [tank, water])).values)
    assert built.fluid.count == 30 * 10 * 20 and built.notes == []
    assert built.fluid.pos[:, 2].min() == pytest.approx(0.005) and built.fluid.pos[:, 2].max() == pytest.approx(0.195)
    inside = np.all((built.walls.pos > 0.005 - 1e-9) & (built.walls.pos < [0.305, 0.105, 1.0]), axis=1)
    assert not inside.any()           # no wall site in the tank's inside, [0.005, 0.305) x [0.005, 0.105) x ...
    gap = min(np.sqrt(((built.walls.pos - p) ** 2).sum(axis=1)).min() for p in built.fluid.pos[::7])
    assert gap == pytest.approx(0.01)
    # the same tank and water off the lattice's planes hold as many
    shifted = [dict(p, position=[x - 0.005 for x in p["position"]]) for p in (tank, water)]
    moved, _ = build_scene("geometry", load_scene(scene(tmp_path, shifted, name="off.yaml")).values)
    assert moved.fluid.count == built.fluid.count and moved.walls.count == built.walls.count
    # two boxes with a face on a lattice plane, rotated or not: every site of their union in exactly one of them
    lattice = Lattice(0.01)
    for rotation in (np.eye(3), np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])):
        a = Shape("box", np.array([0.1, 0.1, 0.1]), rotation, np.array([0.055, 0.055, 0.055]))
        b = Shape("box", np.array([0.1, 0.1, 0.1]), rotation, np.array([0.155, 0.055, 0.055]))
        both = Shape("box", np.array([0.2, 0.1, 0.1]), np.eye(3), np.array([0.105, 0.055, 0.055]))
        sa, sb, sab = filled(lattice, a), filled(lattice, b), filled(lattice, both)
        lo, counts = np.zeros(3, dtype=np.int64), np.full(3, 64)
        ka, kb, kab = (set(site_keys(s, lo, counts)) for s in (sa, sb, sab))
        assert not ka & kb and ka | kb == kab and len(sa) == len(sb) == 1000
    # a tank's walls outside the shape: its inner face's sites belong to its inside, not to its walls
    walls = outer_shell(lattice, Shape("box", np.array([0.1, 0.1, 0.1]), np.eye(3), np.full(3, 0.055)), 3)
    assert lattice.positions(walls).min() == pytest.approx(-0.025) and lattice.positions(walls).max() == \
        pytest.approx(0.125)


# ---- water that leaves: recorded, the run goes on; stopped only at the scene's fraction ----------------------

FALLING = [{"name": "water", "role": "water", "shape": "box", "size": [0.05, 0.05, 0.05],
            "position": [0.025, 0.025, 0.025]}]


def test_water_that_leaves_is_recorded_and_the_run_goes_on(tmp_path, capsys):
    """Water with no tank falls out of a domain box reaching 5 mm past its particles: no divergence; the summary
    and the log say how much left, from when, over which face."""
    path = scene(tmp_path, FALLING, geometry={"domain_margin": 0.005})
    out = tmp_path / "falling"
    assert main(["run", path, "--end-time", "0.06", "--out", str(out)]) == 0
    stdout, err = capsys.readouterr()
    summary = json.loads((out / "summary.json").read_text())
    lost = summary["fluid_lost"]
    assert summary["status"] == "finished" and summary["stable"] and summary["diverged"] is None
    # in free fall by 60 ms it has fallen 17.7 mm: its lowest layer of 5 x 5 (at 5 mm) is out, the next (15 mm)
    # about to be; those held on the box's floor then push some of the next ones out sideways
    n = lost["particles"]
    assert lost["particles"] == summary["fluid_particles_lost"] and 25 <= n < 75 and lost["fraction"] == n / 125
    assert sum(lost["faces"].values()) == n and lost["faces"]["-z"] >= 25 and "nearest_walls" not in lost
    # the lowest leaves after 5 mm from rest, t = sqrt(2 x 0.005 / 9.81) = 31.9 ms, seen at the next outer step
    assert 0.0319 <= lost["first_time_s"] <= 0.0319 + 0.001 + 1e-9
    assert sum("water began to leave" in w for w in summary["warnings"]) == 1
    faces = ", ".join(f"{face} {count}" for face, count in lost["faces"].items())
    assert f"water lost: {n} water particle(s) ({100 * n / 125:.3g} % of the water) left the domain box from t = " \
           f"{lost['first_time_s']:.6g} s, held still where they left: over its faces {faces}" in stdout
    assert "diverged" not in err and "sph-fsi: warning: parts.water: 125 of its 125 particles have no wall" in err


def test_water_lost_beyond_the_scenes_fraction_stops_the_run_as_its_own_outcome(tmp_path, capsys):
    path = scene(tmp_path, FALLING, geometry={"domain_margin": 0.005}, watchdog={"max_fluid_lost": 0.1})
    out = tmp_path / "stopped"
    assert main(["run", path, "--end-time", "0.06", "--out", str(out)]) == 4
    _, err = capsys.readouterr()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "water_lost" and summary["stable"] and summary["diverged"] is None
    assert summary["stopped"]["check"] == "left the domain" and summary["fluid_lost"]["particles"] == 25
    assert "sph-fsi: stopped, water lost (watchdog.max_fluid_lost): left the domain at t = " in err
    assert "more than watchdog.max_fluid_lost = 0.1 of the water (12 particles)" in err and "diverged" not in err
    sim = Simulation(load_scene(path, ["watchdog.max_fluid_lost=0.1"]))
    with pytest.raises(WaterLost) as info:
        while True:
            sim.step()
    assert not isinstance(info.value, Diverged) and info.value.outcome == "water_lost"


def test_the_record_names_the_face_and_the_nearest_wall():
    walls = SimpleNamespace(pos=np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]))
    gate = SimpleNamespace(pos=np.array([[0.0, 1.0, 0.0]]))
    built = SimpleNamespace(domain_lo=np.full(3, -0.5), domain_hi=np.full(3, 1.5), walls=walls, release_walls=gate,
                            parts={"left": ("walls", np.array([0])), "right": ("walls", np.array([1])),
                                   "door": ("gate", np.array([0])), "water": ("fluid", np.arange(4))})
    record, warnings = LostWater(4, built), []
    record.record(np.array([2]), 0.25, np.array([[1.0, 0.1, 1.6]]), warnings)
    record.record(np.array([0, 3]), 0.5, np.array([[-0.6, 0.0, 0.0], [0.1, 1.7, 0.0]]), warnings)
    assert record.summary() == {"particles": 3, "fraction": 0.75, "first_time_s": 0.25,
                                "faces": {"-x": 1, "+y": 1, "+z": 1}, "nearest_walls": {"left": 1, "right": 1,
                                                                                          "door": 1}}
    assert len(warnings) == 1 and "over its +z face (e.g. fluid particle 2, nearest parts.right)" in warnings[0]


def test_a_point_probe_far_from_its_solid_and_an_empty_judging_window_are_said(tmp_path, capsys):
    probes_scene = str(REPO / "test" / "data" / "geometry_probes.yaml")
    built, _ = build_scene("geometry", load_scene(probes_scene, ["probes.tip.position=[0.5, 0.05, 0.15]"]).values)
    assert built.warnings == ["probes.tip.position = [0.5, 0.05, 0.15]: 0.325 m from the nearest moving particle of "
                              "the solid, farther than 2h = 0.026 m; it follows that particle, at [0.175, 0.045, "
                              "0.145] m"], built.warnings
    path = scene(tmp_path, [TANK, WATER], probes=[{"name": "level", "kind": "water_height",
                                                   "position": [0.05, 0.05, 0.0]}],
                 judge=[{"name": "m", "kind": "mean", "column": "level", "reference": 0.1, "from": 0.5, "to": 0.2}])
    line = refused(capsys, tmp_path, [path])
    assert line == (f"sph-fsi: {path}: judge.m.to = 0.2: not after judge.m.from = 0.5 s, so nothing would be judged; "
                    f"allowed: to > from (or 0: the run's end)"), line
