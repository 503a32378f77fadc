# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Moved to :mod:`colcon_robmosys.devtools.ros_env` (bench/ and tools/ use it too).

Kept so that tests written before the move still import it.
"""

from colcon_robmosys.devtools.ros_env import *  # noqa: F401,F403
from colcon_robmosys.devtools.ros_env import FASTDDS_PROFILE  # noqa: F401
