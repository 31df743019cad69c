"""ros2msg schema text for MCAP, assembled from the installed .msg files (no rclpy, no rosidl_runtime_py).

The text is the type's own .msg file, then for each type it depends on (depth first, each once) a line of 80
'=' and `MSG: pkg/Type` (the short form: Rerun's decoder fails on `pkg/msg/Type`) followed by that .msg file.
This is what rosbag2 writes. The files are looked up under `<prefix>/share/<pkg>/msg/<Type>.msg` for the
prefixes on AMENT_PREFIX_PATH and the running Python's prefix (where the ROS wheels install them).
"""
import os
import re
import sys
from functools import lru_cache
from pathlib import Path

__all__ = ["msgdef_text", "msg_file", "MsgdefError"]

SEPARATOR = "=" * 80
_PRIMITIVES = {"bool", "byte", "char", "float32", "float64", "int8", "uint8", "int16", "uint16", "int32",
               "uint32", "int64", "uint64", "string", "wstring"}


class MsgdefError(LookupError):
    pass


def _prefixes():
    seen = []
    for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) + [sys.prefix]:
        if p and p not in seen:
            seen.append(p)
    return seen


def msg_file(pkg, name):
    """Path of pkg/msg/name.msg in the first prefix that has it."""
    for prefix in _prefixes():
        path = Path(prefix) / "share" / pkg / "msg" / f"{name}.msg"
        if path.is_file():
            return path
    raise MsgdefError(f"{pkg}/msg/{name}.msg not found under share/ of {', '.join(_prefixes())}")


def _split(full):
    """'sensor_msgs/msg/PointCloud2' or 'sensor_msgs/PointCloud2' -> ('sensor_msgs', 'PointCloud2')."""
    parts = full.split("/")
    if len(parts) == 3 and parts[1] == "msg":
        return parts[0], parts[2]
    if len(parts) == 2:
        return parts[0], parts[1]
    raise MsgdefError(f"not a message type name: {full!r}")


def _dependencies(pkg, text):
    """Complex field types of a .msg text, as (pkg, Type), in order of appearance."""
    out = []
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        ftype, rest = (re.split(r"\s+", line, maxsplit=1) + [""])[:2]
        if re.match(r"^\s*\w+\s*=", rest):
            continue   # a constant (TYPE NAME=VALUE): always a primitive
        base = re.sub(r"\[.*\]$", "", ftype)
        base = re.sub(r"<=\d+$", "", base)
        if base in _PRIMITIVES:
            continue
        if "/" in base:
            dep = _split(base)
        elif base == "Header":
            dep = ("std_msgs", "Header")
        else:
            dep = (pkg, base)
        out.append(dep)
    return out


@lru_cache(maxsize=None)
def msgdef_text(full_name):
    """The ros2msg schema text of e.g. 'sensor_msgs/msg/PointCloud2'."""
    pkg, name = _split(full_name)
    root = msg_file(pkg, name).read_text()
    parts, seen = [root.rstrip("\n")], {(pkg, name)}

    def visit(p, text):
        for dep in _dependencies(p, text):
            if dep in seen:
                continue
            seen.add(dep)
            dep_text = msg_file(*dep).read_text()
            parts.append(f"{SEPARATOR}\nMSG: {dep[0]}/{dep[1]}\n{dep_text.rstrip(chr(10))}")
            visit(dep[0], dep_text)

    visit(pkg, root)
    return "\n".join(parts) + "\n"
