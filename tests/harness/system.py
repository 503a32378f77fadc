# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Moved to :mod:`colcon_robmosys.devtools.system` (bench/ and tools/ use it too).

Kept so that tests written before the move still import it.
"""

from colcon_robmosys.devtools.system import *  # noqa: F401,F403
