# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""colcon extension that turns RobMoSys models into ROS 2 packages."""

__version__ = '0.1.0'
