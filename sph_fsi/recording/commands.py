"""The commands a recorded run applied, read back from its MCAP file: a replay gives them to a new run of the same
scene (`sph-fsi run SCENE --commands FILE.mcap`), each stamped with the time it applied, so the replay applies
each at the same fluid step and runs to the same bits (sph_fsi_core.boundary.Boundary.command). ROS-free: the
messages are decoded from the file's own schemas (mcap_ros2)."""
import re

from sph_fsi.points import command_numbers, command_values

__all__ = ["read_commands", "check_parts", "queue_commands"]

_COMMAND = re.compile(r".*/parts/([A-Za-z][A-Za-z0-9_]*)/(pose_cmd|twist_cmd)\Z")


def read_commands(path):
    """[(part, stamp s, 'pose_cmd' or 'twist_cmd', numbers)] of the file's command channels, in stamp order; a
    pose's numbers (position, quaternion (x, y, z, w)), a twist's (linear, angular). ValueError naming the file
    when it cannot be read."""
    from mcap.exceptions import McapError
    from mcap_ros2.decoder import DecoderFactory
    from mcap.reader import make_reader
    out = []
    try:
        with open(path, "rb") as fh:
            reader = make_reader(fh, decoder_factories=[DecoderFactory()])
            for _, channel, _, msg in reader.iter_decoded_messages():
                match = _COMMAND.match(channel.topic)
                if match is None:
                    continue
                part, what = match.groups()
                stamp, numbers = command_numbers(what, msg)
                out.append((part, stamp, what, numbers))
    except (OSError, McapError) as exc:
        raise ValueError(f"--commands {str(path)!r}: not a readable MCAP recording ({exc}); allowed: a file "
                         f"recorded by sph-fsi run --mcap or the node's mcap_path") from None
    return sorted(out, key=lambda c: c[1])


def check_parts(commands, values, source="--commands"):
    """ValueError naming a command's part that the scene (its resolved `values`) does not drive by commands."""
    allowed = sorted({key.split(".")[1] for key, value in values.items()
                      if key.startswith("parts.") and key.endswith(".motion") and value == "ros"})
    for part, *_ in commands:
        if part not in allowed:
            raise ValueError(f"{source}: a command for part {part!r}, which this scene does not drive by commands; "
                             f"allowed: " + (", ".join(allowed) or "none (no part with motion: ros)"))


def queue_commands(sim, commands, source="--commands"):
    """Give `commands` (read_commands) to the simulation's boundary, as the node gives a topic's; ValueError naming
    a part that the scene does not drive by commands."""
    boundary = sim.boundary
    for part, stamp, what, numbers in commands:
        motion = boundary.part_motion(part) if boundary is not None else None
        if motion is None or part not in boundary.commanded():
            allowed = ", ".join(boundary.commanded()) if boundary is not None else ""
            raise ValueError(f"{source}: a command for part {part!r}, which this scene does not drive by commands; "
                             f"allowed: " + (allowed or "none (no part with motion: ros)"))
        kind, values = command_values(motion.point, what, numbers)
        boundary.command(part, stamp, kind, values, (what, numbers))
