# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""RobMoSys models in RobMoSys terms: types, loading with line marks, the schema.

No ROS 2 decision and no colcon here: the layers above read these types.
"""
