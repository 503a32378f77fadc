# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The tools around a system that are not its manager, each usable on its own.

- :mod:`.arguments`: the arguments of a system's start (``use_sim_time``,
  ``log_level``, ``namespace``, ``params_file``), with one meaning for
  ``ros2 launch`` and ``bringup``;
- :mod:`.paramfile` and :mod:`.paramcheck`: an operator's parameter file, read
  as rcl reads it and checked against the system offline (``check_params``);
- :mod:`.locations`: the model files the reports point at (the user's, or its copy);
- :mod:`.smoke`: the smoke test a system package installs.

May import: the component side (the modules at the top of robmosys_runtime).
Imported by: the system manager (:mod:`robmosys_runtime.system`), the
generated system packages, and colcon-robmosys itself (``paramcheck``).
"""
