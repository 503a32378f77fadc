# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""``ros2 run <system> bringup``: a whole system in the foreground, on real rclpy.

The bringup executable a system package installs starts every instance, brings
the managed ones up in the order of the model, reports what fails with what it
holds back, and on SIGINT brings the system down, those that came last first,
and exits 0. Its description (``bringup.json``) is the system model's.
"""

from __future__ import annotations

import json
from pathlib import Path
import re
import signal
import sys

import pytest

from colcon_robmosys.devtools.ros_env import background, free_domain_id
from colcon_robmosys.devtools.system import wait_until
from conftest import BuiltWorkspace, requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

SYSTEM = 'examples_system'


def _bringup(built: BuiltWorkspace, *args: str):
    executable = built.install / SYSTEM / 'lib' / SYSTEM / 'bringup'
    return background([sys.executable, str(executable), *args],
                      env=built.env(free_domain_id()), stop_timeout=30)


def _description(built: BuiltWorkspace) -> dict:
    return json.loads((built.share(SYSTEM) / 'bringup.json').read_text())


def test_the_description_is_the_system_model(test_workspace_built):
    description = _description(test_workspace_built)
    instances = {i['instance']: i for i in description['instances']}
    assert set(instances) == {'receiver', 'sender', 'add_server', 'add_client',
                              'fibonacci_server', 'fibonacci_client', 'level_sensor',
                              'level_watcher'}
    assert instances['add_client']['after'] == ['add_server']
    assert instances['add_client']['fqn'] == '/examples/add_client'
    assert description['params_file'] == 'cfg/params.yaml'


def test_bringup_brings_the_system_up_and_down_on_sigint(test_workspace_built):
    with _bringup(test_workspace_built) as bringup:
        assert wait_until(lambda: 'bringup: 8 of 8 managed instances active' in
                          bringup.output(), timeout=90), bringup.output()
        # data flows: the system works as under ros2 launch
        assert wait_until(lambda: re.search(r'received hi there \d+', bringup.output())
                          is not None, timeout=30), bringup.output()
        bringup.proc.send_signal(signal.SIGINT)
        assert bringup.proc.wait(timeout=60) == 0, bringup.output()
        output = bringup.output()
    assert 'Traceback' not in output, output
    steps = re.findall(r'bringup: (deactivate|cleanup) (\w+)', output)
    # every managed instance went down, each deactivated before its cleanup,
    # and the clients before the servers they come after
    assert sorted(n for s, n in steps if s == 'deactivate') == sorted(
        i['instance'] for i in _description(test_workspace_built)['instances'])
    order = [n for s, n in steps if s == 'deactivate']
    assert order.index('add_client') < order.index('add_server')
    assert order.index('fibonacci_client') < order.index('fibonacci_server')
    assert order.index('level_watcher') < order.index('level_sensor')


def _broken_description(built: BuiltWorkspace, tmp_path: Path, **commands) -> Path:
    """Return a copy of the description where some instances run other commands."""
    description = _description(built)
    for instance in description['instances']:
        if instance['instance'] in commands:
            instance['command'] = commands[instance['instance']]
    path = tmp_path / 'bringup.json'
    path.write_text(json.dumps(description))
    return path


def test_an_instance_that_crashes_is_reported_with_what_it_holds_back(
        test_workspace_built, tmp_path):
    # the server dies at once: its client, which comes after it, is held back
    crash = [sys.executable, '-c', 'import sys; sys.exit(3)']
    path = _broken_description(test_workspace_built, tmp_path, add_server=crash)
    with _bringup(test_workspace_built, '--description', str(path), '--exit-on-failure',
                  '--timeout', '20') as bringup:
        assert bringup.proc.wait(timeout=120) == 1, bringup.output()
        output = bringup.output()
    assert 'bringup: error: instance add_server exited with code 3; not activated because '\
        'of it: add_client' in output, output
    assert 'bringup: 6 of 8 managed instances active' in output, output
    assert 'Traceback' not in output, output
    assert 'bringup: add_client held back by add_server' in output, output
    assert 'Traceback' not in output, output


def test_an_instance_that_never_answers_is_reported_within_its_timeout(
        test_workspace_built, tmp_path):
    # a process that runs but offers no lifecycle service (ends on SIGINT, quietly)
    silent = [sys.executable, '-c',
              'import signal, time; signal.signal(signal.SIGINT, signal.SIG_DFL); '
              'time.sleep(600)']
    path = _broken_description(test_workspace_built, tmp_path, level_sensor=silent)
    with _bringup(test_workspace_built, '--description', str(path), '--exit-on-failure',
                  '--start-timeout', '20') as bringup:
        assert bringup.proc.wait(timeout=120) == 1, bringup.output()
        output = bringup.output()
    assert 'bringup: error: instance level_sensor did not appear within 20 s; not '\
        'activated because of it: level_watcher' in output, output
    assert 'bringup: 6 of 8 managed instances active' in output, output
    assert 'Traceback' not in output, output
