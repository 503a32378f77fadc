# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Tools for developers of colcon-robmosys: run ROS 2 on loopback, drive systems.

Tests, benchmarks (bench/) and the demo (tools/demo.py) share them; nothing of
the pipeline imports them.
"""
