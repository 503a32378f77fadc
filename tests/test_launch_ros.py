# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The generated launch files, run for real by launch_ros where it is installed.

launch and launch_ros are not on PyPI: on a machine without a ROS 2 install these
tests skip, and tests/test_systems.py checks the launch files by reading them.
"""

from __future__ import annotations

import contextlib
import importlib.util
from pathlib import Path
import re
import shutil
import signal
import subprocess
import sys
import time

import pytest

from colcon_robmosys.devtools.ros_env import background
from colcon_robmosys.devtools.system import wait_until
from conftest import assert_no_traceback, BuiltWorkspace, requires_ros

#: launch_ros on this Python's path (a sourced ROS 2 or the prefix of shared/verify): asked
#: before any fixture runs, so that no workspace is built for tests that skip
LAUNCH_ROS_MISSING = importlib.util.find_spec('launch_ros') is None
pytestmark = [pytest.mark.integration, requires_ros, pytest.mark.skipif(
    LAUNCH_ROS_MISSING, reason='launch_ros is not installed (it is not on PyPI): the launch '
    'files are read and compared with the model in test_systems.py')]

LAUNCHER = """
import sys
from launch import LaunchDescription, LaunchService
from launch.actions import IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource
service = LaunchService(argv=sys.argv[2:])
service.include_launch_description(LaunchDescription([
    IncludeLaunchDescription(PythonLaunchDescriptionSource(sys.argv[1]))]))
sys.exit(service.run())
"""

RECEIVED = re.compile(r'got map data: width 16, height 16')


@pytest.fixture
def launch_env(test_workspace_built, domain_id):
    return test_workspace_built.env(domain_id)


@pytest.mark.parametrize('launch_files', [
    ['pubsub_system.launch.py'],
    ['pubsub_system.publisher.launch.py', 'pubsub_system.subscriber.launch.py'],
    # the name of the last release, an alias that includes pubsub_system.launch.py
    ['activate.py']])
def test_activate_brings_the_system_up(test_workspace_built, launch_env, launch_files):
    share = test_workspace_built.share('pubsub_system')
    with contextlib.ExitStack() as stack:
        processes = [stack.enter_context(background(
            [sys.executable, '-c', LAUNCHER, str(share / 'launch' / name)], env=launch_env))
            for name in launch_files]

        def output():
            return ''.join(p.output() for p in processes)

        assert wait_until(lambda: len(RECEIVED.findall(output())) >= 2, timeout=30), output()


def test_a_system_of_subsystems_comes_up_with_every_node_in_its_namespace(
        test_workspace_built, launch_env, domain_id):
    """fleet_system: pubsub_system in /robot1 and /robot2, and a watcher of robot1's maps."""
    from colcon_robmosys.devtools.system import LifecycleDriver
    share = test_workspace_built.share('fleet_system')
    with background([sys.executable, '-c', LAUNCHER,
                     str(share / 'launch' / 'fleet_system.launch.py')],
                    env=launch_env) as launched:
        def heard(node: str) -> bool:
            return re.search(rf'\[{node}\]: got map data', launched.output()) is not None
        assert wait_until(lambda: all(heard(n) for n in (
            'robot1.subscriber', 'robot2.subscriber', 'watcher')), timeout=60), \
            launched.output()
        with LifecycleDriver(domain_id) as driver:
            for fqn in ('/robot1/publisher', '/robot2/subscriber', '/watcher'):
                assert driver.state(fqn) == 'active', fqn
            assert driver.parameters('/robot2/publisher', ['noOfScans']) == {'noOfScans': 3}


def test_launch_leaves_the_nodes_unconfigured(test_workspace_built, launch_env, domain_id):
    from colcon_robmosys.devtools.system import LifecycleDriver
    share = test_workspace_built.share('pubsub_system')
    with background([sys.executable, '-c', LAUNCHER,
                     str(share / 'launch' / 'pubsub_system.nodes.launch.py')], env=launch_env):
        with LifecycleDriver(domain_id) as driver:
            assert driver.state('/publisher') == 'unconfigured'
            assert driver.state('/subscriber') == 'unconfigured'
            assert driver.parameters('/publisher', ['indoor', 'noOfScans']) == \
                {'indoor': True, 'noOfScans': 3}


def test_dummy_robot_activates_in_order_and_wires_every_connection(
        test_workspace_built, launch_env, domain_id):
    """dummy_robot_bringup.launch.py: every connection carries data, the spare idles."""
    from colcon_robmosys.devtools.system import LifecycleDriver
    from test_dummy_robot_system import _model, effective_parameters, expected_report
    system, components = _model()
    wanted = set()
    for connection in system.connections:
        ends = sorted((connection.source.instance, connection.target.instance),
                      key=lambda i: components[i].package == 'dummy_robot_monitor')
        provider = system.instance(ends[0])
        wanted.add(expected_report(components[ends[0]],
                                   effective_parameters(provider, components[ends[0]])))
    share = test_workspace_built.share('dummy_robot_bringup')
    fqns = {i.name: f'{i.namespace}/{i.name}' for i in system.instances}
    with contextlib.ExitStack() as stack:
        driver = stack.enter_context(LifecycleDriver(domain_id))
        launched = stack.enter_context(background(
            [sys.executable, '-c', LAUNCHER,
             str(share / 'launch' / 'dummy_robot_bringup.launch.py')],
            env=launch_env))

        managed = [i for i in system.instances if i.activate]

        def up() -> bool:
            output = launched.output()
            return all(w in output for w in wanted) and \
                len(re.findall(r'instance \w+ is active', output)) >= len(managed)

        assert wait_until(up, timeout=60, period=0), launched.output()
        # each managed instance was activated once, after those it comes after: the
        # activation says so as it goes (transition events are volatile, and a test
        # that watches them misses some, as an activation that waited for them did)
        active = re.findall(r'instance (\w+) is active', launched.output())
        assert sorted(active) == sorted(i.name for i in managed), launched.output()
        for instance in managed:
            assert driver.state(fqns[instance.name]) == 'active'
            for before in instance.after:
                assert active.index(before) < active.index(instance.name), active
        assert driver.state('/spare/laser_spare') == 'unconfigured'
        assert driver.state('/dummy_robot/monitor') == 'active'


def test_ctrl_c_of_a_system_reports_no_failure(test_workspace_built, launch_env):
    """An ordinary Ctrl-C is no failure: no instance is reported, no traceback."""
    share = test_workspace_built.share('pubsub_system')
    with background([sys.executable, '-c', LAUNCHER,
                     str(share / 'launch' / 'pubsub_system.launch.py')],
                    env=launch_env) as launched:
        assert wait_until(lambda: len(RECEIVED.findall(launched.output())) >= 2, timeout=30), \
            launched.output()
        launched.proc.send_signal(signal.SIGINT)
        launched.proc.wait(timeout=30)
        output = launched.output()
    assert 'instance' not in output.split('SIGINT')[-1], output
    assert_no_traceback(output)
    assert 'finalized' not in output, output


@pytest.fixture(scope='module')
def hosted_built(tmp_path_factory) -> BuiltWorkspace:
    """Return test_workspace with pubsub_system's publisher on a host of its own."""
    from conftest import build_workspace, TEST_WORKSPACE
    src = tmp_path_factory.mktemp('hosted_src') / 'src'
    shutil.copytree(TEST_WORKSPACE / 'src', src, ignore=shutil.ignore_patterns('__pycache__'))
    model = src / 'pubsub_system' / 'robmosys.yaml'
    text = model.read_text()
    assert '      publisher:\n        component: publisher\n' in text
    model.write_text(text.replace('      publisher:\n        component: publisher\n',
                                  '      publisher:\n        component: publisher\n'
                                  '        host: robot\n'))
    return build_workspace(src, tmp_path_factory.mktemp('hosted_ws'),
                           '--packages-up-to', 'pubsub_system')


def test_two_hosts_as_two_launches_in_one_domain(launch_env, hosted_built, domain_id):
    """<system>.on_<host>.nodes.launch.py on the robot, <system>.launch.py with the manager."""
    # launch_env first: without launch_ros it skips before the workspace is built
    env = hosted_built.env(domain_id)
    launch = hosted_built.share('pubsub_system') / 'launch'
    with background([sys.executable, '-c', LAUNCHER,
                     str(launch / 'pubsub_system.on_robot.nodes.launch.py')],
                    env=env) as robot, \
            background([sys.executable, '-c', LAUNCHER,
                        str(launch / 'pubsub_system.launch.py')], env=env) as manager:
        # the subscriber here receives from the publisher there, once the manager
        # brought both up
        assert wait_until(lambda: len(RECEIVED.findall(manager.output())) >= 2, timeout=60), \
            manager.output() + robot.output()
        assert 'bringup: 2 of 2 managed instances active' in manager.output()
        for launched in (manager, robot):
            launched.proc.send_signal(signal.SIGINT)
            launched.proc.wait(timeout=30)
        assert_no_traceback(manager.output() + robot.output())


#: ros2 launch's way with arguments: name:=value, given to the included file
ARGUMENTS_LAUNCHER = """
import sys
from launch import LaunchDescription, LaunchService
from launch.actions import IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource
arguments = [tuple(a.split(':=', 1)) for a in sys.argv[2:]]
service = LaunchService()
service.include_launch_description(LaunchDescription([IncludeLaunchDescription(
    PythonLaunchDescriptionSource(sys.argv[1]), launch_arguments=arguments)]))
sys.exit(service.run())
"""

#: what ros2 launch --show-args prints: the arguments a launch file declares
SHOW_ARGS = """
import sys
from launch.launch_description_sources import get_launch_description_from_python_launch_file
description = get_launch_description_from_python_launch_file(sys.argv[1])
for argument in description.get_launch_arguments():
    print(f'{argument.name}|{argument.default_value[0].text if argument.default_value else ""}|'
          f'{argument.description}')
"""


@pytest.mark.parametrize('launch_file', [
    'pubsub_system.launch.py', 'pubsub_system.nodes.launch.py',
    'pubsub_system.publisher.launch.py', 'pubsub_system.subscriber.nodes.launch.py'])
def test_show_args_lists_the_arguments_with_their_descriptions(
        test_workspace_built, launch_env, launch_file):
    share = test_workspace_built.share('pubsub_system')
    shown = subprocess.run(
        [sys.executable, '-c', SHOW_ARGS, str(share / 'launch' / launch_file)],
        env=launch_env, capture_output=True, text=True, timeout=60, check=True).stdout
    arguments = {line.split('|')[0]: line.split('|')[1:] for line in shown.splitlines()}
    # the manager's launch file (it starts bringup --attach) takes its page's too
    manager = {'web', 'web_address'} if launch_file == 'pubsub_system.launch.py' else set()
    assert set(arguments) == {'use_sim_time', 'log_level', 'namespace', 'params_file',
                              'mode'} | manager, shown
    assert arguments['log_level'][0] == 'info'
    assert 'cfg/params.yaml: its values win' in arguments['params_file'][1]
    assert all(description for _, description in arguments.values()), shown


def test_launch_arguments_reach_every_node(test_workspace_built, launch_env, domain_id,
                                           tmp_path):
    """use_sim_time, log_level, namespace and the operator's file, through ros2 launch."""
    from colcon_robmosys.devtools.system import LifecycleDriver
    operator = tmp_path / 'operator.yaml'
    operator.write_text('/robot1/publisher:\n  ros__parameters:\n    noOfScans: 7\n')
    share = test_workspace_built.share('pubsub_system')
    with background([sys.executable, '-c', ARGUMENTS_LAUNCHER,
                     str(share / 'launch' / 'pubsub_system.launch.py'), 'use_sim_time:=true',
                     'log_level:=debug', 'namespace:=robot1', f'params_file:={operator}'],
                    env=launch_env) as launched, LifecycleDriver(domain_id) as driver:
        # the manager moved with the system, and brings the moved nodes up
        assert wait_until(lambda: 'bringup: 2 of 2 managed instances active' in
                          launched.output(), timeout=60), launched.output()
        for fqn in ('/robot1/publisher', '/robot1/subscriber'):
            assert driver.state(fqn) == 'active', fqn
        # the operator's value wins, the system's others stay
        assert driver.parameters('/robot1/publisher', ['use_sim_time', 'indoor', 'noOfScans']) \
            == {'use_sim_time': True, 'indoor': True, 'noOfScans': 7}
        assert driver.parameters('/robot1/subscriber', ['use_sim_time']) == \
            {'use_sim_time': True}
        # the connection moved too: the subscriber is on the publisher's moved topic (the
        # manager's watch may subscribe to it as well: each node's own topics are asked)

        def connected() -> bool:
            published = driver.node.get_publisher_names_and_types_by_node(
                'publisher', '/robot1')
            subscribed = driver.node.get_subscriber_names_and_types_by_node(
                'subscriber', '/robot1')
            return '/robot1/publisher/pMap' in {n for n, _ in published} & \
                {n for n, _ in subscribed}
        assert wait_until(connected, timeout=30), launched.output()
        assert not {('publisher', '/'), ('subscriber', '/')} & set(
            driver.node.get_node_names_and_namespaces())
        assert re.search(r'\[DEBUG\].*publisher', launched.output()), launched.output()


@pytest.mark.parametrize('launch_file', [
    'fleet_system.launch.py', 'fleet_system.nodes.launch.py', 'activate.py',
    'fleet_system.robot1.publisher.launch.py'])
def test_a_broken_operators_file_is_refused_before_any_process_starts(
        test_workspace_built, launch_env, tmp_path, launch_file):
    """The launch file checks params_file as check_params does: its lines, nothing started."""
    from test_process_layout import MARKER, processes_marked
    from test_refused_at_start import BROKEN, BROKEN_LINES
    (tmp_path / 'site.yaml').write_text(BROKEN)
    env = dict(launch_env, **{MARKER: f'refused-{launch_file}'})
    share = test_workspace_built.share('fleet_system')
    started: set[int] = set()
    with background([sys.executable, '-c', ARGUMENTS_LAUNCHER,
                     str(share / 'launch' / launch_file), 'params_file:=site.yaml'],
                    env=env, cwd=tmp_path) as launched:
        deadline = time.monotonic() + 60
        while launched.proc.poll() is None and time.monotonic() < deadline:
            # any process of the run but the launch's own is one it started
            started |= set(processes_marked(env[MARKER])) - {launched.proc.pid}
            time.sleep(0.01)
        assert launched.proc.poll() == 1, launched.output()
        output = launched.output()
    assert not started, output
    assert 'process started' not in output, output
    lines = output.splitlines()
    assert [line for line in lines if line.startswith('site.yaml:')] == BROKEN_LINES, output
    assert "Caught exception in launch (see debug for traceback): params_file 'site.yaml' " \
        'does not fit the system fleet_system (3 errors); nothing was started' in output, output
    assert_no_traceback(output)


@pytest.fixture(scope='module')
def crowd_launched_built(tmp_path_factory) -> BuiltWorkspace:
    """Return crowd_system: 20 instances (shared by default), a C++ pair among them."""
    from test_process_layout import build_crowd
    return build_crowd(tmp_path_factory.mktemp('crowd_launched'), 20, cpp=True)


def test_a_shared_system_comes_up_through_its_launch_file_and_ctrl_c_ends_it_in_bounds(
        crowd_launched_built, domain_id, tmp_path):
    """<system>.launch.py runs the Python instances in one process, the C++ in a container.

    With the manager, they are plain processes: the launch imports no
    launch_ros. The launch arguments reach the nodes of both as they reach a
    node of its own (here namespace and an operator's file). Ctrl-C ends every
    process within 5 s, beside another launched system, and launch never
    escalates to SIGTERM or SIGKILL.
    """
    from colcon_robmosys.devtools.system import LifecycleDriver
    from test_process_layout import (
        CTRL_C_BOUND, ctrl_c, loaded_machine, marked_env, MARKER, processes_marked)
    operator = tmp_path / 'operator.yaml'
    operator.write_text('/robot1/pub_0:\n  ros__parameters:\n    noOfScans: 7\n'
                        '/robot1/pub_cpp:\n  ros__parameters:\n    noOfScans: 8\n')
    env = marked_env(crowd_launched_built, domain_id)
    launch = crowd_launched_built.share('crowd_system') / 'launch' / 'crowd_system.launch.py'
    command = [sys.executable, '-c', ARGUMENTS_LAUNCHER, str(launch), 'namespace:=robot1',
               f'params_file:={operator}']
    with loaded_machine(command, env), background(command, env=env, stop_timeout=30) as run:
        assert wait_until(lambda: 'bringup: 20 of 20 managed instances active' in
                          run.output(), timeout=180), run.output()
        # Python -> Python and C++ -> C++, every subscriber
        assert wait_until(lambda: len(set(re.findall(r'[\[.](sub_\w+)[.\]].*got map data',
                                                     run.output()))) == 10, timeout=60), \
            run.output()
        # moved into the namespace, the operator's values theirs: in the shared Python
        # process and in the container alike
        with LifecycleDriver(domain_id) as driver:
            for fqn, scans in (('/robot1/pub_0', 7), ('/robot1/pub_cpp', 8)):
                assert driver.state(fqn) == 'active', fqn
                assert driver.parameters(fqn, ['noOfScans']) == {'noOfScans': scans}, fqn
        # both shared processes brought their instances up and told the manager
        # (--report-file, FILE.cpp): it took none through a transition
        assert not re.search(r'instance \w+ is active', run.output()), run.output()
        marked = processes_marked(env[MARKER])
        commands = [(Path('/proc') / str(p) / 'cmdline').read_bytes() for p in marked]
        assert sum(b'robmosys_runtime.hosting.container' in c for c in commands) == 1, commands
        assert sum(b'__node:=crowd_system_container' in c and
                   b'crowd_system/component_container' in c for c in commands) == 1, commands
        # the launch, the Python instances, the container, the manager
        assert len(marked) == 4, commands
        # every process is a plain one (the manager too, lib/crowd_system/bringup):
        # the launch imported neither launch_ros nor rclpy before it started them
        assert any(b'/lib/crowd_system/bringup\0--attach\0' in c for c in commands), commands
        maps = (Path('/proc') / str(run.proc.pid) / 'maps').read_text()
        assert 'rclpy' not in maps, [line for line in maps.splitlines() if 'rclpy' in line]
        took, output = ctrl_c(run, env[MARKER])
        assert run.proc.wait(timeout=1) == 0, output
    assert took <= CTRL_C_BOUND, f'{took:.2f} s:\n{output}'
    assert 'escalating' not in output and 'SIGKILL' not in output, output
    assert_no_traceback(output)
