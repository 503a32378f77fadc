# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The manager's view of the processes of a host's instances."""

import sys

from conftest import wait_until
from robmosys_runtime.processes import Processes


def test_a_process_is_starting_then_running_then_exited():
    exits = []
    processes = Processes(on_exit=lambda name, code: exits.append((name, code)))
    # the manager's services answer before every process is started
    assert processes.state('laser') == 'starting'
    processes.start('laser', [sys.executable, '-c', 'import time; time.sleep(60)'])
    processes.start('short', [sys.executable, '-c', 'raise SystemExit(3)'])
    processes.watch()
    try:
        assert processes.state('laser') == 'running'
        assert wait_until(lambda: processes.state('short') == 'exited')
        assert wait_until(lambda: ('short', 3) in exits)
    finally:
        processes.stop(timeout=5.0)
    assert processes.state('laser') == 'exited'
