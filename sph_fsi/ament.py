"""The ament index for the PyPI-wheel ROS: rclpy and the message packages find their share/ files through it."""
import os
import sys

__all__ = ["ensure_ament_prefix"]


def ensure_ament_prefix():
    """ament_index_python needs the venv prefix on AMENT_PREFIX_PATH (the wheels install share/<pkg> there).
    Call before importing rclpy (the node, replay)."""
    prefix = sys.prefix
    if os.path.isdir(os.path.join(prefix, "share", "ament_index")):
        parts = [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
        if prefix not in parts:
            os.environ["AMENT_PREFIX_PATH"] = os.pathsep.join([prefix] + parts)
