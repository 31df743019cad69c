"""`python -m sph_fsi [--ros-args ...]`: the ROS 2 node (same as the `sph_fsi_node` executable)."""
import sys

from sph_fsi.node import main

if __name__ == "__main__":
    sys.exit(main())
