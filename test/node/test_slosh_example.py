"""The closed-loop example (examples/slosh_controller.py): a controller in this process damps a tank's sloshing with
a paddle driven through the node's topics, in lockstep. Measured: the sloshing's amplitude over 1-2 s with the
controller against without (config/examples/sloshing_tank.yaml at 20 mm: 1,200 water particles); and the driven
run's recording, replayed headless from its commands (`sph-fsi run --commands`), moves the paddle to the same bits.
ROS_DOMAIN_ID: the run's base + 5 (test_node.py takes base and base + 1, test_replay.py + 2, test_probe_topics.py
+ 3, test_part_topics.py + 4)."""
import importlib.util
import os
import random
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
_BASE = int(os.environ.get("ROS_DOMAIN_ID") or random.Random().randint(1, 100))
DOMAIN = 1 + (_BASE + 5) % 100


def _example():
    spec = importlib.util.spec_from_file_location("slosh_controller", REPO / "examples" / "slosh_controller.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _poses(path):
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    with open(path, "rb") as fh:
        reader = make_reader(fh, decoder_factories=[DecoderFactory()])
        return [(m.header.stamp.sec, m.header.stamp.nanosec, m.pose.position.x, m.pose.position.z)
                for _, _, _, m in reader.iter_decoded_messages(topics=["/sph_fsi/parts/paddle/pose"])]


def test_the_controller_damps_the_sloshing_and_its_run_replays_to_the_bit(tmp_path, monkeypatch):
    monkeypatch.setenv("ROS_DOMAIN_ID", str(DOMAIN))
    example = _example()
    still = example.run(0.0, 0.02, 2.0, tmp_path)
    driven = example.run(1.0, 0.02, 2.0, tmp_path)
    before = dict(example.amplitudes(still))
    after = dict(example.amplitudes(driven))
    assert before[0.0] > 0.008                       # it sloshes: about 10 mm over the first half second
    for start in (1.0, 1.5):
        assert after[start] < 0.3 * before[start], (start, after, before)
    assert max(abs(x) for x in driven["paddle"]) > 0.005 and max(abs(x) for x in still["paddle"]) == 0.0
    replay = tmp_path / "replay.mcap"
    done = subprocess.run([sys.executable, "-m", "sph_fsi.cli", "run", str(example.SCENE), "--set",
                           "numerics.spacing=0.02", "--end-time", "2.0", "--commands", str(driven["mcap"]),
                           "--mcap", str(replay), "--record-interval", "0", "--out", str(tmp_path / "replay")],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    live, again = _poses(driven["mcap"]), _poses(replay)
    assert len(live) >= 200 and live == again
