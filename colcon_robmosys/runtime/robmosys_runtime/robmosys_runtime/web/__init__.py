# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The system manager's page: the model's diagram, coloured by what runs.

- :mod:`.view`: what the page shows (each instance's state, each connection's
  differences, parameter values), read once per period, and its changes;
- :mod:`.server`: the page over HTTP (``bringup --web PORT``), its files
  (``page.html``, ``page.js``, ``page.css``), server-sent events, and the
  token that changes need.

May import: the component side, hosting (its output) and watch. Imported by:
the system manager (:mod:`robmosys_runtime.system.page`).
"""
