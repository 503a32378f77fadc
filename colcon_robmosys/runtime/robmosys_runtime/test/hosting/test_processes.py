# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The manager's view of the processes of a host's instances."""

import sys

from conftest import wait_until
import pytest
from robmosys_runtime.hosting import processes
from robmosys_runtime.hosting.cpp_container import container_node, main, program_arguments
from robmosys_runtime.hosting.processes import (
    NotInstalled, plan_processes, shared_arguments, SharedArguments)
from robmosys_runtime.hosting.supervision import Processes


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


def test_stop_tells_whether_a_process_needed_sigkill(capfd):
    # bringup exits 1 when it did: a demo or a smoke test that reads its exit
    # status sees a bring-down that was not clean
    polite = Processes(on_exit=None)
    polite.start('laser', [sys.executable, '-c', 'import time; time.sleep(60)'])
    assert polite.stop(timeout=10.0)
    assert polite.state('laser') == 'exited'
    deaf = Processes(on_exit=None)
    for name in ('planner', 'mapper'):
        deaf.start(name, [sys.executable, '-c', 'import signal, sys, time\n'
                          'def deaf_to_sigint():\n'
                          '    time.sleep(60)\n'
                          'signal.signal(signal.SIGINT, signal.SIG_IGN)\n'
                          'print("ready", flush=True)\n'
                          'deaf_to_sigint()'])
    out = []

    def ready():
        out.append(capfd.readouterr().out)
        return ''.join(out).count('ready') == 2
    assert wait_until(ready, timeout=10)
    assert not deaf.stop(timeout=0.5)
    assert wait_until(lambda: deaf.state('planner') == deaf.state('mapper') == 'exited')
    # each one named, and where it hung: SIGABRT made each print its stack
    said = capfd.readouterr().err
    for name in ('planner', 'mapper'):
        assert f'{name} did not end within 0.5 s of SIGINT: SIGABRT, for the stacks of ' \
            'its threads, then SIGKILL' in said
    assert said.count('in deaf_to_sigint') == 2, said


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
    description = {'package': 'fleet', 'namespace': '/site', 'executors': {'cpp': 'events'},
                   'instances': [
                       _instance('arm', 'arm_pkg', plugin='arm_pkg::Arm', host='robot1',
                                 managed=True, after=['base'], namespace='/site/robot1',
                                 remappings=[['cmd', '/site/cmd']], threads=3),
                       _instance('eye', 'eye_pkg', plugin='eye_pkg::Eye', host='robot1',
                                 managed=False, threads=2),
                       _instance('base', 'base_pkg', python_class='base_pkg.node:Base')]}
    args = shared_arguments(['--activate', '--report-fd', '7', 'bringup.json', 'params.yaml',
                             'arm', 'eye', '--ros-args', '--log-level', 'warn'])
    assert args == SharedArguments(True, 7, None, 'bringup.json', 'params.yaml', ['arm', 'eye'],
                                   ['--ros-args', '--log-level', 'warn'])
    # everything counted, nothing for the program to parse but words
    assert program_arguments(description, args, '/p/component_container') == [
        '/p/component_container', 'events', '5', '1', '7', '',
        '2',
        'arm', 'arm_pkg', 'arm_pkg::Arm', '1', '1', 'base',
        '8', '-r', '__node:=arm', '-r', '__ns:=/site/robot1', '--params-file', 'params.yaml',
        '-r', 'cmd:=/site/cmd',
        'eye', 'eye_pkg', 'eye_pkg::Eye', '0', '0',
        '4', '-r', '__node:=eye', '--params-file', 'params.yaml',
        '--ros-args', '-r', '__node:=fleet_robot1_container', '-r', '__ns:=/site',
        '--log-level', 'warn']
    # a file for the launch's manager; no namespace, nothing more for the process
    args = shared_arguments(['--activate', '--report-file', '/tmp/told', 'bringup.json',
                             'params.yaml', 'eye'])
    description['namespace'] = ''
    assert program_arguments(description, args, 'c')[1:7] == [
        'events', '2', '1', '-1', '/tmp/told', '1']
    assert program_arguments(description, args, 'c')[-3:] == [
        '--ros-args', '-r', '__node:=fleet_robot1_container']


def test_a_shared_process_s_command_line_is_refused_when_it_is_not_one(tmp_path, capsys):
    assert shared_arguments(['bringup.json', 'params.yaml']) is None
    assert shared_arguments(['--activate', '--report-fd', 'x', 'b.json', 'p.yaml']) is None
    assert main(['bringup.json']) == 2
    description = tmp_path / 'bringup.json'
    description.write_text(
        '{"package": "fleet", "instances": [{"instance": "base", "python_class": "a:B"}]}')
    assert main([str(description), 'params.yaml', 'base', 'nobody']) == 2
    assert capsys.readouterr().err.splitlines()[-1] == \
        'cpp_container: error: not C++ instances of the system: base, nobody'


def test_cpp_instances_share_the_container_and_python_ones_a_process(tmp_path, monkeypatch):
    # rclpy: a package installed wherever these tests run
    description = {'package': 'fleet', 'processes': 'shared', 'instances': [
        _instance('arm', 'rclpy', plugin='rclpy::Arm', managed=True),
        _instance('base', 'rclpy', python_class='rclpy.node:Base', managed=True),
        _instance('solo', 'rclpy', command=['/bin/true'], plugin='rclpy::Solo')]}
    # a system package built without rclcpp_components has no container: said, nothing started
    monkeypatch.setattr(processes, 'container_program', lambda package: str(tmp_path / 'none'))
    with pytest.raises(NotInstalled) as raised:
        plan_processes(description, 'bringup.json', 'params.yaml')
    assert raised.value.problems == [
        "instance arm needs the component container of the package 'fleet', which was built "
        'without rclcpp_components (build it again where rclcpp_components is installed)']
    (tmp_path / 'none').write_text('')
    groups = plan_processes(description, 'bringup.json', 'params.yaml',
                            report_fds={'C++ instances': 9})
    assert sorted(groups) == ['C++ instances', 'python instances', 'solo']
    assert groups['C++ instances'] == (['arm'], [
        sys.executable, '-m', 'robmosys_runtime.hosting.cpp_container', '--activate',
        '--report-fd', '9', 'bringup.json', 'params.yaml', 'arm'])
    assert groups['python instances'][1][3:] == [
        '--activate', 'bringup.json', 'params.yaml', 'base']
    # another host: nothing brought up there, nothing told
    for instance in description['instances']:
        instance['host'] = 'robot1'
    groups = plan_processes(description, 'bringup.json', 'params.yaml', host='robot1',
                            report_fds={'C++ instances': 9})
    assert groups['C++ instances on robot1'][1][3:] == ['bringup.json', 'params.yaml', 'arm']
