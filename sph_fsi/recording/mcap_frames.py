"""Frames of a recorded run drawn from its MCAP file, what Foxglove's 3D panel shows of it: the `~/particles` cloud
at chosen simulated times, the water coloured by pressure and the solid by von Mises stress, over the `~/walls`.

    python -m sph_fsi.recording.mcap_frames RUN.mcap --times 0.0 0.45 0.8 --out frames.png

Each time gets a side view (x-z) and a view from above (x-y); a frame is the recording's last at or before the time.
The numbers drawn are the message's own (sph_fsi.messages.cloud_to_structured), so the picture checks the recording.
"""
import argparse
from pathlib import Path

import numpy as np

PARTICLES = "/sph_fsi/particles"
WALLS = "/sph_fsi/walls"


def read_clouds(path, times):
    """({time: structured points} at the recording's last frame at or before each time, walls (N, 3))."""
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    from ..messages import cloud_to_structured
    frames, walls = {}, None
    wanted = sorted(times)
    with open(path, "rb") as fh:
        reader = make_reader(fh, decoder_factories=[DecoderFactory()])
        for _schema, channel, message, msg in reader.iter_decoded_messages(topics=[PARTICLES, WALLS]):
            t = message.log_time * 1e-9
            if channel.topic == WALLS:
                if walls is None:
                    w = cloud_to_structured(msg)
                    walls = np.stack([w["x"], w["y"], w["z"]], axis=1)
                continue
            for target in wanted:
                if t <= target + 1e-9:
                    frames[target] = (t, cloud_to_structured(msg))
    return frames, (walls if walls is not None else np.zeros((0, 3)))


def draw(path, times, out, title=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    frames, walls = read_clouds(path, times)
    fig, axes = plt.subplots(len(times), 2, figsize=(15, 3.2 * len(times)), squeeze=False,
                             gridspec_kw={"width_ratios": [1.0, 1.0]})
    for row, target in zip(axes, times):
        if target not in frames:
            continue
        t, pts = frames[target]
        fluid = pts["phase"] == 1
        solid = pts["phase"] == 2
        for ax, (i, j, names) in zip(row, ((0, 2, ("x [m]", "z [m]")), (0, 1, ("x [m]", "y [m]")))):
            keys = ("x", "y", "z")
            if len(walls):
                ax.scatter(walls[:, i], walls[:, j], s=0.2, c="0.85", rasterized=True)
            ax.scatter(pts[keys[i]][fluid], pts[keys[j]][fluid], s=0.3, c=pts["pressure"][fluid] * 1e-3,
                       cmap="plasma", vmin=0.0, vmax=6.0, rasterized=True)
            if solid.any():
                ax.scatter(pts[keys[i]][solid], pts[keys[j]][solid], s=1.5, c=pts["von_mises"][solid] * 1e-3,
                           cmap="viridis", vmin=0.0, vmax=40.0, rasterized=True)
            if len(walls):     # the tank's box: spray that leaves it is not followed
                lo, hi = walls.min(axis=0), walls.max(axis=0)
                pad = 0.05 * float((hi - lo).max())
                ax.set_xlim(lo[i] - pad, hi[i] + pad)
                ax.set_ylim(lo[j] - pad, hi[j] + (0.5 if j == 2 else 1.0) * pad)
            ax.set_aspect("equal")
            ax.set_xlabel(names[0])
            ax.set_ylabel(names[1])
            ax.set_title(f"t = {t:.2f} s, {'side' if j == 2 else 'from above'}", fontsize=9)
    fig.suptitle(title or f"{Path(path).name}: water by pressure (0-6 kPa, plasma), solid by von Mises stress "
                          f"(0-40 kPa, viridis)")
    fig.tight_layout(rect=(0.0, 0.0, 1.0, 0.97))
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("mcap")
    parser.add_argument("--times", type=float, nargs="+", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--title", default=None)
    args = parser.parse_args(argv)
    print(draw(args.mcap, args.times, args.out, args.title))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
