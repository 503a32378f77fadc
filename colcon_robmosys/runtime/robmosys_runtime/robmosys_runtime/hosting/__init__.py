# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The processes of a system's instances: how they are started, and what they tell.

- :mod:`.processes`: the command line of each process, one per instance or
  shared (a Python process, a C++ component container), as the launch files
  have them;
- :mod:`.supervision`: those processes started, watched and stopped, ending
  with the ``bringup`` that started them;
- :mod:`.running`: what of a system runs on this host already (/proc), before
  a ``bringup`` starts anything;
- :mod:`.container` and :mod:`.cpp_container`: the shared processes, which
  bring their instances up and down by themselves;
- :mod:`.told` and :mod:`.reports`: what the shared processes tell the
  manager, on a pipe or in a file, before it joins the ROS graph;
- :mod:`.output`: the one way the run-time side prints a line.

May import: the component side. Imported by: the conformance watch
(:mod:`robmosys_runtime.watch`, for its output) and the system manager.
"""
