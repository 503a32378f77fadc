# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The manager's view of the processes of a host's instances."""

import sys

from conftest import wait_until
import pytest
from robmosys_runtime.processes import (
    container_fqn, container_node, NotInstalled, plan_processes, Processes)


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


def _instance(name, package, **extra):
    return dict({'instance': name, 'package': package, 'executable': name, 'name': name,
                 'namespace': '', 'remappings': [], 'host': ''}, **extra)


def test_instances_whose_package_is_not_installed_are_named_before_anything_starts():
    description = {'package': 'a_system', 'instances': [
        _instance('sensor', 'no_such_sensor_package'),
        _instance('twin', 'no_such_sensor_package'),
        _instance('watcher', 'no_such_watcher_package'),
        _instance('driver', 'no_such_driver_package', command=['/bin/true']),
        _instance('remote', 'no_such_remote_package', host='robot')]}
    with pytest.raises(NotInstalled) as raised:
        plan_processes(description, 'bringup.json', 'params.yaml')
    # one line per package, every instance that needs it; an instance with a
    # command of its own, or on another host, needs nothing installed here
    assert raised.value.problems == [
        "instances sensor, twin need the package 'no_such_sensor_package', which is not "
        'installed (no prefix of AMENT_PREFIX_PATH has it: build it, or source the install '
        'that has it)',
        "instance watcher needs the package 'no_such_watcher_package', which is not "
        'installed (no prefix of AMENT_PREFIX_PATH has it: build it, or source the install '
        'that has it)']


def test_each_host_has_a_container_of_its_own_moved_with_the_system():
    # node names are unique across hosts: robot1's container is not the manager's
    assert container_node('fleet') == 'fleet_container'
    assert container_node('fleet', 'robot1') == 'fleet_robot1_container'
    assert container_fqn({'package': 'fleet'}) == '/fleet_container'
    assert container_fqn({'package': 'fleet', 'namespace': '/site'},
                         'robot1') == '/site/fleet_robot1_container'
