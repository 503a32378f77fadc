# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""What of a system runs on this host already, read from /proc; processes that end with bringup."""

import json
import os
import subprocess
import sys
import threading
import time

from conftest import wait_until
import pytest
from robmosys_runtime.hosting import running
from robmosys_runtime.hosting.cpp_container import program_arguments
from robmosys_runtime.hosting.processes import command, SharedArguments
from robmosys_runtime.hosting.running import look, MARK, mark, running_nodes, wait_gone
from robmosys_runtime.hosting.supervision import before_start, ELSEWHERE, Processes

SLEEP = [sys.executable, '-c', 'import time; time.sleep(60)']


def _instance(name, namespace='', **extra):
    return dict({'instance': name, 'package': 'rclpy', 'executable': name, 'name': name,
                 'namespace': namespace, 'fqn': f"{namespace.rstrip('/')}/{name}",
                 'remappings': [['scan', '/laser/scan']], 'host': '', 'managed': True,
                 'location': f'robmosys.yaml:{len(name)}:5'}, **extra)


def test_the_nodes_a_command_line_names_as_the_runtime_and_launch_ros_write_them():
    # bringup's own command line of an instance (launch_ros' is the same)
    assert running_nodes(command(_instance('laser', '/robot1', command=['laser']),
                                 'params.yaml')) == ['/robot1/laser']
    assert running_nodes(command(_instance('laser', command=['laser']), 'p.yaml')) == ['/laser']
    # by hand, the namespace first, or after other arguments; a rule of one node
    for argv in (['x', '--ros-args', '-r', '__ns:=/robot1', '--remap', '__node:=laser'],
                 ['x', '--ros-args', '-r', '__node:=laser', '-p', 'a:=1', '-r',
                  '__ns:=/robot1/'],
                 ['x', '--ros-args', '-r', 'talker:__node:=laser', '-r', 'talker:__ns:=robot1']):
        assert running_nodes(argv) == ['/robot1/laser'], argv
    # no renaming, no node that one can name from here
    assert running_nodes(['x', '--ros-args', '-r', 'scan:=/laser/scan', '-p', 'r:=1']) == []
    # ros2 run <package> <executable>: a generated component's node is its executable's name
    assert running_nodes(['python3', '/ws/install/talker/lib/talker/Talker', '--ros-args',
                          '-r', '__ns:=/robot1']) == ['/robot1/Talker']
    assert running_nodes(['/ws/install/talker/lib/talker/talker_cpp']) == ['/talker_cpp']
    assert running_nodes(['python3', '/ws/install/fleet/lib/fleet/bringup']) == []
    # the C++ container names its instances in turn, each with its own namespace or none
    description = {'package': 'fleet', 'instances': [
        _instance('arm', '/robot1', plugin='fleet::Arm'), _instance('base', plugin='fleet::B'),
        _instance('grip', '/robot1', plugin='fleet::Grip')]}
    argv = program_arguments(description, SharedArguments(
        True, None, None, 'bringup.json', 'params.yaml', ['arm', 'base', 'grip'], []),
        'component_container')
    assert running_nodes(argv) == ['/robot1/arm', '/base', '/robot1/grip', '/fleet_container']


def test_a_shared_python_process_names_the_instances_of_its_description(tmp_path):
    path = tmp_path / 'bringup.json'
    path.write_text(json.dumps({'package': 'fleet', 'instances': [
        _instance('arm', '/robot1'), _instance('base'), _instance('grip')]}))
    argv = [sys.executable, '-m', 'robmosys_runtime.hosting.container', '--activate',
            '--report-fd', '7', str(path), 'params.yaml', 'arm', 'base',
            '--ros-args', '--log-level', 'info']
    assert running_nodes(argv) == ['/robot1/arm', '/base']
    argv[6] = str(tmp_path / 'gone.json')
    assert running_nodes(argv) == []


def _started(argv, **environment):
    """Start a process in this domain and network namespace, with more environment."""
    return subprocess.Popen(argv, env=dict(os.environ, **environment))


def test_what_runs_already_is_found_in_this_domain_only():
    description = {'package': 'fleet', 'instances': [_instance('laser', '/robot1')]}
    domain = os.environ.get('ROS_DOMAIN_ID', '0')
    other = str((int(domain) + 1) % 100)
    node = ['--ros-args', '-r', '__node:=laser', '-r', '__ns:=/robot1']
    here = _started(SLEEP + node)
    there = _started(SLEEP + node, ROS_DOMAIN_ID=other)
    # processes a bringup of the system started: this one (running), and one that ended
    ours = _started(SLEEP, **{MARK: mark('fleet', '', '')})
    dead = _started(SLEEP, **{MARK: json.dumps([2 ** 22 + 7, '1', 'fleet', '', ''])})
    another_system = _started(SLEEP, **{MARK: json.dumps([1, '1', 'tractor', '', ''])})
    another_host = _started(SLEEP, **{MARK: mark('fleet', '', 'robot')})
    try:
        # Popen returned once each runs its program: /proc shows its command line
        found = look(description, '')
        assert found.nodes == {'/robot1/laser': here.pid}
        assert found.left == [dead.pid]
        assert found.bringups == [os.getpid()]
        assert look(description, 'robot').bringups == [os.getpid()]
        assert look(dict(description, namespace='/r2'), '').bringups == []
    finally:
        for process in (here, there, ours, dead, another_system, another_host):
            process.kill()
            process.wait()


def test_another_bringup_of_the_system_is_found_by_its_command_line(tmp_path):
    program = tmp_path / 'lib' / 'fleet' / 'bringup'
    program.parent.mkdir(parents=True)
    program.write_text('import time; time.sleep(60)\n')
    description = {'package': 'fleet', 'namespace': '/r1', 'instances': []}
    checking = _started([sys.executable, str(program), '--check', '--namespace', 'r1'])
    elsewhere = _started([sys.executable, str(program), '--namespace=/r1', '--host', 'robot'])
    attached = _started([sys.executable, str(program), '--attach', '--namespace=/r1/'])
    try:
        assert look(description, '').bringups == [attached.pid]
        assert look(description, 'robot').bringups == [elsewhere.pid]
        assert look(dict(description, namespace=''), '').bringups == []
    finally:
        for process in (checking, elsewhere, attached):
            process.kill()
            process.wait()


def test_before_start_takes_a_running_node_as_it_is_and_refuses_a_second_bringup(capsys):
    description = {'package': 'fleet', 'instances': [
        _instance('laser', '/robot1'), _instance('arm', '/robot1'),
        _instance('remote', '/robot1', host='robot')]}
    here = _started(SLEEP + ['--ros-args', '-r', '__node:=laser', '-r', '__ns:=/robot1'])
    try:
        local = before_start(description, '', lambda: False)
        assert [i['host'] for i in local['instances']] == [ELSEWHERE, '', 'robot']
        assert capsys.readouterr().out == (
            'bringup: robmosys.yaml:5:5: warning: instance laser: node /robot1/laser runs '
            f'already (process {here.pid}), not started by this manager: taken as it is\n')
        # a bringup --host robot of the system is running: this one starts nothing
        marked = _started(SLEEP, **{MARK: mark('fleet', '', 'robot')})
        try:
            assert before_start(description, 'robot', lambda: False) is None
            assert capsys.readouterr().err == (
                'bringup: error: a bringup --host robot of this system runs on this host '
                f'already (process {os.getpid()}); nothing was started\n')
        finally:
            marked.kill()
            marked.wait()
    finally:
        here.kill()
        here.wait()


def test_what_a_dead_bringup_left_is_waited_for_then_killed():
    ending = _started([sys.executable, '-c', 'import time; time.sleep(0.5)'])
    stuck = _started(SLEEP)
    start = time.monotonic()
    # the zombie of an ended child of this process counts as gone
    threading.Thread(target=ending.wait, daemon=True).start()
    assert wait_gone([ending.pid], timeout=10.0) == []
    assert time.monotonic() - start < 5.0
    assert wait_gone([stuck.pid], timeout=0.5) == [stuck.pid]
    assert stuck.wait(timeout=5) == -9


def test_processes_started_from_a_thread_that_ended_live_on_and_end_with_bringup():
    """PR_SET_PDEATHSIG fires when the thread that forked ends: each starts from one that lives."""
    processes = Processes(on_exit=None, end_with_parent=True,
                          mark=mark('fleet', '', ''))
    respawn = threading.Thread(target=processes.start, args=('laser', SLEEP))
    respawn.start()
    respawn.join()
    try:
        time.sleep(0.5)
        assert processes.state('laser') == 'running'
        process = processes._processes['laser']
        with open(f'/proc/{process.pid}/environ', 'rb') as stream:
            assert f'{MARK}={mark("fleet", "", "")}'.encode() in stream.read().split(b'\0')
    finally:
        assert processes.stop(timeout=5.0)


def test_the_processes_of_a_killed_bringup_end_with_it():
    code = ('import sys, time; from robmosys_runtime.hosting.supervision import Processes; '
            'p = Processes(None, end_with_parent=True); '
            'p.start("a", [sys.executable, "-c", "import time; time.sleep(60)"]); '
            'print(p._processes["a"].pid, flush=True); time.sleep(60)')
    bringup = subprocess.Popen([sys.executable, '-c', code], stdout=subprocess.PIPE, text=True,
                               env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))
    child = int(bringup.stdout.readline())
    bringup.kill()
    bringup.wait()
    assert wait_until(lambda: not running._alive(child), timeout=5.0)


@pytest.mark.parametrize('argv, found', [
    (['/x/lib/fleet/bringup'], ('', '')),
    (['python3', '/x/lib/fleet/bringup', '--host=robot', '--namespace', '/r1'], ('robot', '/r1')),
    (['python3', '/x/lib/fleet/bringup', '--check'], None),
    (['timeout', '60', 'python3', '/x/lib/fleet/bringup'], None),
    (['python3', '/x/lib/tractor/bringup'], None),
])
def test_a_bringup_is_known_by_its_program_and_options(argv, found):
    assert running._bringup_of(argv, 'fleet') == found
