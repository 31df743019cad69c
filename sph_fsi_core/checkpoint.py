"""Checkpoints: a run's whole state in one file, to continue it later to the bit.

What is kept: the Simulation as it stands between two outer steps (every particle array, the neighbour lists and
the positions they were built at, the solid's fit rows, the fluid's and the coupling's work arrays, the time, the
step counters, the warnings, the resolved scene), the run's time series so far and its snapshot schedule. A run
continued from a checkpoint takes the same steps on the same numbers as one that never stopped: the same
positions, velocities, stresses, densities and time series, bit for bit (test/test_checkpoint.py). Timings (wall
time, particle-steps/s) count the continued run's own stepping plus what the checkpoint had.

File: a first line naming the format, one line of JSON (format, sph_fsi version, a fingerprint of the simulator's
source, scene, simulated time, payload length and SHA-256), then the payload (a pickle). A file that is not a
checkpoint, is cut short or altered (length, checksum), or was written by another version of the simulator (a
different source fingerprint: the same state would not step the same way) is refused with one line saying which.
The payload is a pickle: load only checkpoints you wrote (as with any pickle, loading runs what it names).
Writes go to a temporary file in the same directory, then replace the old one: a checkpoint is whole or absent.
"""
import hashlib
import json
import os
import pickle
import time
from pathlib import Path

from . import __version__
from .schema import SceneError

MAGIC = b"sph_fsi checkpoint\n"
FORMAT = 1
SUFFIX = ".ckpt"


class CheckpointError(SceneError):
    """A file that cannot be continued from (bad input: exit status 2, one line)."""


def source_fingerprint():
    """SHA-256 (16 hex digits) of the simulator's Python source, sph_fsi_core/**/*.py, in path order."""
    root = Path(__file__).resolve().parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        digest.update(str(path.relative_to(root)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


def write_checkpoint(run, path):
    """Write `run`'s state (sph_fsi_core.run.Run, between outer steps) to `path`; returns the path."""
    path = Path(path)
    sim = run.sim
    state = {"sim": sim, "rows": run.log.rows, "setup_s": run.log.setup_s, "stepping_s": run.log.stepping_s,
             "snapshots": run.snapshots, "next_snapshot": run.next_snapshot, "stopped": run.stopped}
    payload = pickle.dumps(state, protocol=pickle.HIGHEST_PROTOCOL)
    header = {"format": FORMAT, "version": __version__, "source": source_fingerprint(), "scene": sim.spec.name,
              "time": sim.time, "outer_steps": sim.outer_steps, "written": time.strftime("%Y-%m-%dT%H:%M:%S"),
              "bytes": len(payload), "sha256": hashlib.sha256(payload).hexdigest()}
    tmp = path.with_name(path.name + ".partial")
    with open(tmp, "wb") as f:
        f.write(MAGIC)
        f.write(json.dumps(header).encode() + b"\n")
        f.write(payload)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)
    return path


def read_header(path):
    """The checkpoint's header (dict) and the open file positioned at the payload; CheckpointError if it is not
    one or cannot be read."""
    path = Path(path)
    try:
        f = open(path, "rb")
    except OSError as exc:
        raise CheckpointError(f"checkpoint {str(path)!r}: cannot be read ({exc.strerror or exc}); allowed: a "
                              f"file written by sph-fsi run --checkpoint-interval or the node's ~/write_checkpoint")
    if f.read(len(MAGIC)) != MAGIC:
        f.close()
        raise CheckpointError(f"checkpoint {str(path)!r}: not an sph_fsi checkpoint (its first line is not "
                              f"{MAGIC.decode().strip()!r}); allowed: a file written by sph-fsi run "
                              f"--checkpoint-interval or the node's ~/write_checkpoint")
    try:
        header = json.loads(f.readline().decode())
        if not isinstance(header, dict):
            raise ValueError
    except (ValueError, UnicodeDecodeError):
        f.close()
        raise CheckpointError(f"checkpoint {str(path)!r}: damaged (its header is not readable)") from None
    return header, f


def read_checkpoint(path):
    """The state write_checkpoint kept, after checking the format, the version and the payload."""
    header, f = read_header(path)
    with f:
        here = {"format": FORMAT, "version": __version__, "source": source_fingerprint()}
        theirs = {k: header.get(k) for k in here}
        if theirs != here:
            raise CheckpointError(
                f"checkpoint {str(path)!r}: written by another version of the simulator (format {theirs['format']}, "
                f"sph_fsi {theirs['version']}, source {theirs['source']}; this is format {FORMAT}, sph_fsi "
                f"{__version__}, source {here['source']}); allowed: a checkpoint of this version (a changed "
                f"simulator would not continue the run the same way: run the scene again)")
        payload = f.read()
    if len(payload) != header.get("bytes") or hashlib.sha256(payload).hexdigest() != header.get("sha256"):
        what = "cut short" if len(payload) < (header.get("bytes") or 0) else "altered"
        raise CheckpointError(f"checkpoint {str(path)!r}: damaged ({what}: {len(payload)} of "
                              f"{header.get('bytes')} payload bytes, checksum "
                              f"{'differs' if what == 'altered' else 'not checked'}); allowed: a whole checkpoint")
    try:
        return pickle.loads(payload)
    except Exception as exc:   # a checksum-valid payload that does not load: a bug, said plainly
        raise CheckpointError(f"checkpoint {str(path)!r}: does not load ({type(exc).__name__}: {exc})") from None
