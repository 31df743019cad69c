"""Checkpoint and restart (sph_fsi_core/checkpoint.py, `sph-fsi run --checkpoint-interval / --restart`): a run
continued from a checkpoint is the same to the bit as one that never stopped (the cantilever, the dam break and a
coupled gate: positions, velocities, stresses, densities, pressures and the time series), in this process and in
a new one; files that are not whole checkpoints of this version are refused with one line."""
import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from sph_fsi_core import checkpoint
from sph_fsi_core.checkpoint import CheckpointError, read_checkpoint, write_checkpoint
from sph_fsi_core.run import Run, step_counts
from sph_fsi_core.scene import load_scene

CASES = {   # scene, overrides, outer steps before the checkpoint and after it
    "cantilever": ("cantilever", ["geometry.length=0.02"], 12, 12),
    "dam_break": ("dam_break", [], 10, 10),
    "coupled_gate": ("elastic_gate", ["numerics.spacing=0.002", "solid.scheme=gray2001"], 6, 6),
}
FIELDS = {"solid": ("pos", "vel", "rho", "stress"), "fluid": ("pos", "vel", "rho", "pressure")}


def _state(run):
    out = {}
    for phase, names in FIELDS.items():
        s = getattr(run.sim, phase)
        if s is not None:
            out.update({f"{phase}.{n}": getattr(s, n).copy() for n in names})
    return out


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_continued_run_is_the_same_to_the_bit(case, tmp_path):
    scene, overrides, before, after = CASES[case]
    spec = load_scene(scene, overrides)
    straight = Run(spec)
    for _ in range(before + after):
        assert straight.advance()
    first = Run(spec)
    for _ in range(before):
        assert first.advance()
    path = write_checkpoint(first, tmp_path / "c.ckpt")
    del first
    continued = Run(None, restored=read_checkpoint(path))
    assert continued.sim.outer_steps == before
    for _ in range(after):
        assert continued.advance()
    a, b = _state(straight), _state(continued)
    assert a.keys() == b.keys() and len(a) >= 4
    for key in a:
        assert np.array_equal(a[key], b[key]), key
    assert continued.log.rows == straight.log.rows       # every sample, every column, to the bit
    assert continued.sim.time == straight.sim.time and step_counts(continued.sim) == step_counts(straight.sim)


def _cli(*args, **kw):
    env = dict(os.environ, NUMBA_NUM_THREADS="1", PYTHONUNBUFFERED="1")
    return subprocess.run([sys.executable, "-m", "sph_fsi.cli", *args], capture_output=True, text=True, env=env,
                          timeout=600, **kw)


SMALL = ["--set", "geometry.length=0.02"]


def test_cli_sigint_writes_a_checkpoint_and_restart_finishes_to_the_bit(tmp_path):
    """SIGINT mid-run: a checkpoint is written and named; `--restart` in a new process runs it to the end with the
    same time series and final snapshot as a run that was never stopped."""
    end = "0.03"
    straight = _cli("run", "cantilever", *SMALL, "--end-time", end, "--out", str(tmp_path / "straight"))
    assert straight.returncode == 0, straight.stderr
    ckpt = tmp_path / "stopped" / "checkpoint.ckpt"
    env = dict(os.environ, NUMBA_NUM_THREADS="1", PYTHONUNBUFFERED="1")
    proc = subprocess.Popen([sys.executable, "-m", "sph_fsi.cli", "run", "cantilever", *SMALL, "--end-time", end,
                             "--checkpoint-interval", "0.002", "--out", str(tmp_path / "stopped")],
                            stderr=subprocess.PIPE, text=True, env=env)
    deadline = time.monotonic() + 300
    while not ckpt.exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    err = proc.communicate(timeout=300)[1]
    assert proc.returncode == 130, err
    assert f"checkpoint at t = " in err and f"sph-fsi run --restart {ckpt}" in err, err
    header, f = checkpoint.read_header(ckpt)
    f.close()
    assert 0.0 < header["time"] < float(end) and header["scene"] == "cantilever"
    resumed = _cli("run", "--restart", str(ckpt), "--out", str(tmp_path / "resumed"))
    assert resumed.returncode == 0, resumed.stderr
    assert "from its checkpoint at t = " in resumed.stderr
    assert (tmp_path / "resumed" / "timeseries.csv").read_bytes() == \
        (tmp_path / "straight" / "timeseries.csv").read_bytes()
    last = sorted((tmp_path / "straight" / "snapshots").glob("*.npz"))[-1]
    a, b = np.load(last), np.load(tmp_path / "resumed" / "snapshots" / last.name)
    assert all(np.array_equal(a[k], b[k]) for k in a.files)
    s = json.loads((tmp_path / "resumed" / "summary.json").read_text())
    assert s["status"] == "finished" and s["simulated_time_s"] == pytest.approx(float(end))


def _refusal(path, *extra):
    r = _cli("run", "--restart", str(path), *extra)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    return lines[0]


def test_files_that_are_not_whole_checkpoints_of_this_version_are_refused(tmp_path):
    run = Run(load_scene("cantilever", ["geometry.length=0.02"]))
    run.advance()
    good = write_checkpoint(run, tmp_path / "good.ckpt")
    blob = good.read_bytes()
    assert not (tmp_path / "good.ckpt.partial").exists()

    (tmp_path / "scene.yaml").write_text("scene:\n  builder: cantilever\n")
    assert "not an sph_fsi checkpoint" in _refusal(tmp_path / "scene.yaml")
    assert "cannot be read" in _refusal(tmp_path / "missing.ckpt")

    (tmp_path / "short.ckpt").write_bytes(blob[:-1000])
    assert "damaged (cut short" in _refusal(tmp_path / "short.ckpt")
    altered = bytearray(blob)
    altered[-500] ^= 0xFF
    (tmp_path / "altered.ckpt").write_bytes(bytes(altered))
    assert "damaged (altered" in _refusal(tmp_path / "altered.ckpt")

    newline = blob.index(b"\n", len(checkpoint.MAGIC))
    header = json.loads(blob[len(checkpoint.MAGIC):newline])
    header["source"] = "0123456789abcdef"
    other = checkpoint.MAGIC + json.dumps(header).encode() + blob[newline:]
    (tmp_path / "other.ckpt").write_bytes(other)
    line = _refusal(tmp_path / "other.ckpt")
    assert "another version of the simulator" in line and "0123456789abcdef" in line
    assert checkpoint.source_fingerprint() in line

    assert "without a scene" in _refusal(good, "--set", "solid.young_modulus=2e6")
    with pytest.raises(CheckpointError, match="damaged"):
        read_checkpoint(tmp_path / "altered.ckpt")
    assert read_checkpoint(good)["sim"].outer_steps == 1
