"""What publishing costs the simulator: the node's frame (particles, tip, strain energy, /clock) against none.

Scene: the paper's gate at 1 mm across the paper's 36 mm (`elastic_gate` with `geometry.span=0.036`, not the
scene's narrowest slab: 59,760 particles; a frame carries the 33,840 moving ones, fluid and solid: the paper's
80,064 less its 46,656 wall particles, which the node publishes once on ~/walls).
The frame is built and published as sph_fsi/publishing.py does on the node's simulation thread (points.particle_points ->
messages.structured_to_cloud, Vector3Stamped, Float64, Clock), through real rclpy publishers with the node's
default QoS, and a subscriber in another process takes every message (so each frame is serialized and sent, as
it is to a viewer).

Measured:
1. the cost of one frame on the simulation thread (median of --repeats);
2. throughput with a frame after every outer step (publish_period = output.timeseries_interval, the densest the
   node publishes) against none, in rounds forward then backward so a drift hits both alike;
3. at 20 Hz: the node publishes on the simulation thread, so 20 frames per wall second take 20 t_frame of every
   second and the simulator keeps 1 - 20 t_frame of it: cost = 1 / (1 - 20 t_frame) - 1. (At 1 mm the gate's outer
   step takes seconds, so the node cannot publish at 20 Hz there; the figure is the budget for the frame.)

    python -m bench.publishing_cost [--spacing 0.001] [--steps 3] [--rounds 2] [--repeats 20]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import textwrap
import time

import numba

from sph_fsi_core.scene import load_scene
from sph_fsi_core.simulation import Simulation

SUBSCRIBER = textwrap.dedent("""
    import sys, rclpy
    from rclpy.qos import QoSProfile
    from sensor_msgs.msg import PointCloud2
    rclpy.init()
    node = rclpy.create_node("bench_subscriber")
    count = [0]
    def on_msg(msg):
        count[0] += 1
    node.create_subscription(PointCloud2, "/bench_publisher/particles", on_msg, QoSProfile(depth=10))
    print("ready", flush=True)
    try:
        while rclpy.ok():
            rclpy.spin_once(node, timeout_sec=0.1)
            if sys.stdin in __import__("select").select([sys.stdin], [], [], 0)[0]:
                break
    finally:
        print(count[0], flush=True)
""")


class FramePublisher:
    """The node's publishers and its frame, without the node's threads."""

    def __init__(self, sim):
        import rclpy
        from geometry_msgs.msg import Vector3Stamped
        from rclpy.qos import QoSProfile
        from rosgraph_msgs.msg import Clock
        from sensor_msgs.msg import PointCloud2
        from std_msgs.msg import Float64
        rclpy.init()
        self.node = rclpy.create_node("bench_publisher")
        qos = QoSProfile(depth=10)
        self.particles = self.node.create_publisher(PointCloud2, "~/particles", qos)
        self.tip = self.node.create_publisher(Vector3Stamped, "~/tip_displacement", qos)
        self.energy = self.node.create_publisher(Float64, "~/strain_energy", qos)
        self.clock = self.node.create_publisher(Clock, "/clock", qos)
        self.sim = sim
        self.sent = 0

    def publish(self):
        from geometry_msgs.msg import Vector3, Vector3Stamped
        from rosgraph_msgs.msg import Clock
        from std_msgs.msg import Float64, Header
        from sph_fsi.messages import stamp_from_seconds, structured_to_cloud
        from sph_fsi.points import particle_points
        sim = self.sim
        header = Header(stamp=stamp_from_seconds(sim.time), frame_id="map")
        self.particles.publish(structured_to_cloud(particle_points(sim), header.stamp, header.frame_id))
        d = sim.probe_displacements()["tip"]
        self.tip.publish(Vector3Stamped(header=header, vector=Vector3(x=float(d[0]), y=float(d[1]), z=float(d[2]))))
        self.energy.publish(Float64(data=float(sim.energies()["strain_energy"])))
        self.clock.publish(Clock(clock=header.stamp))
        self.sent += 1

    def wait_for_subscriber(self, timeout=20.0):
        t0 = time.monotonic()
        while self.particles.get_subscription_count() == 0 and time.monotonic() - t0 < timeout:
            time.sleep(0.05)
        return self.particles.get_subscription_count()

    def close(self):
        import rclpy
        self.node.destroy_node()
        rclpy.shutdown()


def run_config(sim, pub, publish, steps):
    sim0, t0 = sim.time, time.perf_counter()
    for _ in range(steps):
        sim.step()
        if publish:
            pub.publish()
    elapsed = time.perf_counter() - t0
    return {"seconds": elapsed, "throughput": (sim.time - sim0) / elapsed}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--spacing", type=float, default=0.001)
    parser.add_argument("--steps", type=int, default=3, help="outer steps per configuration and round")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=20, help="frames timed for the per-frame cost")
    args = parser.parse_args(argv)
    overrides = [f"numerics.spacing={args.spacing}", "geometry.span=0.036", "output.snapshot_interval=0"]
    if args.spacing > 0.0015:
        overrides.append("geometry.gate_clamp_height=0.004")
    sim = Simulation(load_scene("elastic_gate", overrides))
    sim.step()   # compile, warm up
    env = dict(os.environ)
    sub = subprocess.Popen([sys.executable, "-c", SUBSCRIBER], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                           text=True, env=env)
    pub = FramePublisher(sim)
    try:
        assert sub.stdout.readline().strip() == "ready"
        subscribers = pub.wait_for_subscriber()
        from sph_fsi.points import moving_particles
        moving = sum(len(p[1]) for p in moving_particles(sim))
        result = {"scene": "elastic_gate", "spacing_m": args.spacing, "particles": sim.particle_count,
                  "moving": moving, "threads": numba.get_num_threads(), "cpus": os.cpu_count(),
                  "subscribers": subscribers, "load_average_before": os.getloadavg()[0]}
        times = []
        for _ in range(args.repeats):
            t = time.perf_counter()
            pub.publish()
            times.append(time.perf_counter() - t)
        frame = statistics.median(times)
        result["frame_ms"] = 1e3 * frame
        result["frame_ms_spread"] = [1e3 * min(times), 1e3 * max(times)]
        from sph_fsi.messages import stamp_from_seconds, structured_to_cloud
        from sph_fsi.points import particle_points
        builds = []
        for _ in range(args.repeats):
            t = time.perf_counter()
            structured_to_cloud(particle_points(sim), stamp_from_seconds(sim.time), "map")
            builds.append(time.perf_counter() - t)
        result["cloud_build_ms"] = 1e3 * statistics.median(builds)
        runs = {"off": [], "every outer step": []}
        for rnd in range(args.rounds):
            for name in (list(runs) if rnd % 2 == 0 else list(runs)[::-1]):
                r = run_config(sim, pub, name != "off", args.steps)
                runs[name].append(r)
                print(f"{name:18s} {r['throughput'] * 1e3:.4g} ms simulated per wall s ({r['seconds']:.2f} s)",
                      flush=True)
        off = statistics.median(r["throughput"] for r in runs["off"])
        on = statistics.median(r["throughput"] for r in runs["every outer step"])
        step_seconds = statistics.median(r["seconds"] for r in runs["off"]) / args.steps
        result.update(outer_step_s=step_seconds, outer_step_sim_s=sim.outer_step_duration(),
                      off_sim_per_wall=off, on_sim_per_wall=on, cost_every_outer_step_percent=100 * (off / on - 1),
                      expected_every_outer_step_percent=100 * frame / step_seconds,
                      cost_at_20hz_percent=100 * (1 / (1 - 20 * frame) - 1) if 20 * frame < 1 else float("inf"),
                      load_average_after=os.getloadavg()[0])
    finally:
        sub.stdin.write("stop\n")
        sub.stdin.flush()
        received = sub.stdout.readline().strip()
        sub.wait(timeout=10)
        pub_sent = pub.sent
        pub.close()
    result["frames_sent"] = pub_sent
    result["frames_received"] = int(received) if received.isdigit() else None
    return result


def markdown(r):
    return "\n".join([
        f"Scene `elastic_gate` at {r['spacing_m'] * 1e3:g} mm: {r['particles']:,} particles, {r['moving']:,} in a "
        f"frame; {r['threads']} Numba threads on {r['cpus']} CPUs; one subscriber in another process received "
        f"{r['frames_received']} of {r['frames_sent']} frames; load average {r['load_average_before']:.1f} before, "
        f"{r['load_average_after']:.1f} after. Made by `python -m bench.publishing_cost`.", "",
        "| what | value |", "|---|---|",
        f"| one frame on the simulation thread (PointCloud2 built and published, tip, strain energy, /clock) | "
        f"{r['frame_ms']:.1f} ms (min {r['frame_ms_spread'][0]:.1f}, max {r['frame_ms_spread'][1]:.1f}) |",
        f"| of which building the PointCloud2 (points.particle_points, messages.structured_to_cloud) | "
        f"{r['cloud_build_ms']:.1f} ms |",
        f"| one outer step ({r['outer_step_sim_s'] * 1e3:g} ms simulated) | {r['outer_step_s']:.2f} s |",
        f"| throughput, no frames | {r['off_sim_per_wall'] * 1e3:.4g} ms simulated per wall s |",
        f"| throughput, a frame every outer step | {r['on_sim_per_wall'] * 1e3:.4g} ms simulated per wall s |",
        f"| cost, a frame every outer step: measured (expected t_frame / t_step) | "
        f"{r['cost_every_outer_step_percent']:+.1f} % ({r['expected_every_outer_step_percent']:.2f} %) |",
        f"| cost at 20 frames per wall second: 1 / (1 - 20 t_frame) - 1 | {r['cost_at_20hz_percent']:.1f} % |",
    ]) + "\n"


if __name__ == "__main__":
    res = main()
    print(json.dumps(res, indent=1))
    print(markdown(res))
