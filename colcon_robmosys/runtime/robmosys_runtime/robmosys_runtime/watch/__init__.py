# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The conformance watch: the running system held to its model.

- :mod:`.conformance`: the model against what runs, without rclpy: what
  differs, at which line of the model;
- :mod:`.graph`: what the ROS graph shows of the model's names;
- :mod:`.states`: the lifecycle states nodes tell on their transition events;
- :mod:`.watcher`: the watch of the system manager, every check period;
- :mod:`.check`: ``bringup --check``, the running system compared once.

May import: the component side and :mod:`robmosys_runtime.hosting` (its
output). Imported by: the system manager.
"""
