# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The system manager: a system started, brought up, served and brought down.

- :mod:`.bringup`: ``ros2 run <system> bringup``, its options and its three
  ways to run: the manager, a host's part, the one-shot check;
- :mod:`.manager`: the manager's node, its services for operators and
  ``/diagnostics``;
- :mod:`.activation`, :mod:`.levels`, :mod:`.lifecycle_calls`: the managed
  instances configured and activated in the model's order, and brought down;
- :mod:`.drift`: instances seen out of ``active`` outside the manager's
  transitions (their transition events, the heartbeat), and back;
- :mod:`.heartbeat`: every managed instance asked its state, in step;
- :mod:`.launching`: what the launch files of a system give every node;
- :mod:`.page`: the manager's page (``--web``), bound before anything
  starts, given what the manager knows and its actions.

May import: every other room. Imported by: the generated system packages
(their ``bringup`` executable and launch files); by nothing of the runtime.
"""
