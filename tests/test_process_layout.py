# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The process layout of a system, the same through bringup and its launch files.

With ``processes: shared`` (the default from 20 instances on a host) the
Python instances of a launch file share one process and the C++ instances of
the manager's host one component container, as ``bringup`` runs them; Ctrl-C
ends every process of a 20-instance system within 5 s, with another system
loading the machine, and never needs SIGKILL. The launch files run for real
in tests/test_launch_ros.py (launch_ros is not on PyPI).
"""

from __future__ import annotations

import ast
import contextlib
import json
import os
from pathlib import Path
import re
import shutil
import signal
import sys
import time
from typing import Iterator

import pytest
import yaml

from colcon_robmosys.devtools.ros_env import background, free_domain_id
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from colcon_robmosys.generators import generate_package, plan_package
from colcon_robmosys.mapping.launch import SHARED_FROM
from conftest import (assert_no_traceback, BuiltWorkspace, colcon, requires_ros,
                      ros_missing_reason, TEST_WORKSPACE)
from harness.launch_files import read_launch_file

#: seconds Ctrl-C may take to end every process of a system (issue 28)
CTRL_C_BOUND = 5.0
#: the environment variable that marks the processes of one run
MARKER = 'ROBMOSYS_TEST_RUN'


def crowd_model(instances: int, cpp: bool = False, processes: str = '') -> dict:
    """Return a system of publisher and subscriber pairs of test_workspace (C++: one pair)."""
    count = instances // 2
    pairs = [(f'pub_{i}', 'publisher') for i in range(count - cpp)]
    pairs += [('pub_cpp', 'cpp_publisher')] if cpp else []
    body = {'package': 'crowd_system', 'name': 'Crowd', 'license': 'Apache-2.0',
            'maintainers': [{'name': 'Test Team', 'email': 'test@example.com'}],
            'instances': {}, 'connections': []}
    for pub, component in pairs:
        sub = pub.replace('pub_', 'sub_')
        body['instances'][pub] = {'component': component}
        body['instances'][sub] = {
            'component': 'cpp_subscriber' if component.startswith('cpp') else 'subscriber'}
        body['connections'].append({'from': f'{pub}.pMap', 'to': f'{sub}.rMap'})
    if processes:
        body['processes'] = processes
    return {'robmosys': 1, 'systems': [body]}


def _generate(tmp_path: Path, model: dict) -> Path:
    src = tmp_path / 'src'
    shutil.copytree(TEST_WORKSPACE / 'src', src, ignore=shutil.ignore_patterns('__pycache__'))
    (src / 'crowd_system').mkdir()
    (src / 'crowd_system' / 'robmosys.yaml').write_text(yaml.safe_dump(model, sort_keys=False))
    out = tmp_path / 'out'
    from test_systems import _load
    generate_package(plan_package(_load(src), 'crowd_system'), out)
    return out


def _calls(path: Path, name: str) -> list[ast.Call]:
    tree = ast.parse(path.read_text())
    return [n for n in ast.walk(tree) if isinstance(n, ast.Call) and ast.unparse(n.func) == name]


def _shared_command(call: ast.Call) -> list[str]:
    return [ast.unparse(e) for e in next(k.value for k in call.keywords if k.arg == 'cmd').elts]


def _shared_processes(launch: Path) -> dict[str, list[str]]:
    """Return module -> the command of the ExecuteProcess that runs it, of a launch file."""
    commands = [_shared_command(c) for c in _calls(launch, 'ExecuteProcess')]
    return {ast.literal_eval(c[2]).rsplit('.', 1)[-1]: c for c in commands
            if c[0] == 'sys.executable'}


def _imported(launch: Path) -> set[str]:
    """Return the modules a launch file imports from."""
    return {n.module for n in ast.walk(ast.parse(launch.read_text()))
            if isinstance(n, ast.ImportFrom) and n.module}


def test_a_shared_system_starts_processes_as_bringup_does(tmp_path):
    out = _generate(tmp_path, crowd_model(6, cpp=True, processes='shared'))
    description = json.loads((out / 'bringup.json').read_text())
    assert description['processes'] == 'shared'
    python = [i['instance'] for i in description['instances'] if i['python_class']]
    cpp = [i['instance'] for i in description['instances'] if i['plugin']]
    assert python and cpp
    for name in ('crowd_system.launch.py', 'crowd_system.nodes.launch.py'):
        launch = out / 'launch' / name
        # no instance in a process of its own
        assert read_launch_file(launch, out) == []
        shared = _shared_processes(launch)
        assert sorted(shared) == ['container', 'cpp_container']
        # python -m robmosys_runtime.[cpp_]container [--activate] DESCRIPTION PARAMS
        # INSTANCE... --ros-args ..., as bringup; the file with the manager has each
        # process bring up what it can and write what it brought up where the
        # manager reads it (--told-file); the description, the parameters and the
        # ROS arguments are those of the launch arguments (robmosys_runtime.system.launching)
        for module, told, instances in (('container', 'arguments.told_file', python),
                                        ('cpp_container', 'arguments.cpp_told_file', cpp)):
            cmd = shared[module]
            self_activating = ["'--activate'", "'--report-file'", told]
            assert (cmd[3:6] == self_activating) == (name == 'crowd_system.launch.py')
            cmd = [c for c in cmd if c not in self_activating]
            assert cmd[:5] == ['sys.executable', "'-m'", f"'robmosys_runtime.hosting.{module}'",
                               'arguments.description', 'arguments.params_file']
            assert cmd[-2:] == ["'--ros-args'", '*arguments.ros_arguments']
            assert [ast.literal_eval(e) for e in cmd[5:-2]] == instances
        if name == 'crowd_system.launch.py':
            # the manager is a plain process too, lib/crowd_system/bringup
            [manager] = [c for c in _calls(launch, 'ExecuteProcess')
                         if _shared_command(c)[0] == 'arguments.bringup']
            assert _shared_command(manager)[1:] == [
                "'--attach'", "'--told-file'", 'arguments.told_file', '*arguments.manager']
        # every process a plain one: launching them imports no launch_ros (nor rclpy)
        assert not {m for m in _imported(launch) if m.startswith('launch_ros')}, name
    # one instance alone: a process of its own, launch_ros's LifecycleNode
    [node] = read_launch_file(out / 'launch' / 'crowd_system.pub_cpp.nodes.launch.py', out)
    assert node.name == 'pub_cpp'
    assert 'launch_ros.actions' in _imported(
        out / 'launch' / 'crowd_system.pub_cpp.nodes.launch.py')


def test_one_shared_instance_runs_in_the_shared_process_as_under_bringup(tmp_path):
    # the system's own files start its one Python instance as bringup does, in
    # the shared process that tells the manager it brought it up: in a process
    # of its own, it told nothing, and the manager waited 10 s before it asked
    model = crowd_model(2, processes='shared')
    del model['systems'][0]['instances']['sub_0']
    model['systems'][0]['connections'] = []
    out = _generate(tmp_path, model)
    for name in ('crowd_system.launch.py', 'crowd_system.nodes.launch.py'):
        launch = out / 'launch' / name
        assert read_launch_file(launch, out) == []
        assert _shared_processes(launch)['container'][-3] == "'pub_0'"
    # the file of the instance alone has no manager: a process of its own
    [node] = read_launch_file(out / 'launch' / 'crowd_system.pub_0.launch.py', out)
    assert node.name == 'pub_0'


def test_each_host_runs_its_cpp_instances_in_a_container_of_its_own(tmp_path):
    model = crowd_model(8, cpp=True, processes='shared')
    # the C++ pair on robot1, one Python pair on robot2, the rest on the manager's host
    for name, instance in model['systems'][0]['instances'].items():
        instance['host'] = {'pub_cpp': 'robot1', 'sub_cpp': 'robot1', 'pub_0': 'robot2',
                            'sub_0': 'robot2'}.get(name, '')
        if not instance['host']:
            del instance['host']
    out = _generate(tmp_path, model)
    launch = out / 'launch'
    # the robot's file runs its C++ instances in its container, as bringup --host
    # does; the container is named after the host of its instances (cpp_container)
    robot1 = _shared_processes(launch / 'crowd_system.on_robot1.nodes.launch.py')
    assert sorted(robot1) == ['cpp_container']
    assert [ast.literal_eval(e) for e in robot1['cpp_container'][5:-2]] == [
        'pub_cpp', 'sub_cpp']
    # the other robot has Python instances only, in one process; the manager's host
    # has no C++ instance left, so no container
    assert sorted(_shared_processes(launch / 'crowd_system.on_robot2.nodes.launch.py')) == [
        'container']
    assert sorted(_shared_processes(launch / 'crowd_system.nodes.launch.py')) == ['container']


def test_systems_share_processes_by_default_from_a_size_on(tmp_path):
    def layout(model: dict) -> str:
        shutil.rmtree(tmp_path, ignore_errors=True)
        tmp_path.mkdir()
        out = _generate(tmp_path, model)
        return json.loads((out / 'bringup.json').read_text())['processes']
    assert SHARED_FROM == 20
    assert layout(crowd_model(SHARED_FROM)) == 'shared'
    assert layout(crowd_model(SHARED_FROM - 2)) == 'per_instance'
    # what the model says wins
    assert layout(crowd_model(SHARED_FROM, processes='per_instance')) == 'per_instance'
    assert layout(crowd_model(4, processes='shared')) == 'shared'


def build_crowd(root: Path, instances: int, cpp: bool = False) -> BuiltWorkspace:
    """Build crowd_system with the packages it needs of a copy of test_workspace."""
    src = root / 'src'
    shutil.copytree(TEST_WORKSPACE / 'src', src, ignore=shutil.ignore_patterns('__pycache__'))
    (src / 'crowd_system').mkdir()
    (src / 'crowd_system' / 'robmosys.yaml').write_text(
        yaml.safe_dump(crowd_model(instances, cpp), sort_keys=False))
    result = colcon(['build', '--packages-up-to', 'crowd_system'], cwd=root)
    assert result.returncode == 0, result.stdout + result.stderr
    return BuiltWorkspace(root, result.stdout)


def marked_env(built: BuiltWorkspace, domain_id: int) -> dict:
    """Return the environment of a built workspace, with a marker of this run."""
    env = built.env(domain_id)
    env[MARKER] = f'{os.getpid()}-{time.monotonic_ns()}'
    return env


def processes_marked(marker: str) -> list[int]:
    """Return the processes whose environment holds a run's marker."""
    wanted = f'{MARKER}={marker}'.encode()
    found = []
    for entry in Path('/proc').iterdir():
        with contextlib.suppress(OSError):
            if entry.name.isdigit() and \
                    wanted in (entry / 'environ').read_bytes().split(b'\0'):
                found.append(int(entry.name))
    return found


@contextlib.contextmanager
def loaded_machine(command: list[str], env: dict) -> Iterator[None]:
    """Run another system beside the test's, in a domain of its own, until the block ends."""
    other = dict(env, ROS_DOMAIN_ID=str(free_domain_id()), **{MARKER: 'load'})
    with background(command, env=other, stop_timeout=30):
        yield


def ctrl_c(process, marker: str) -> tuple[float, str]:
    """Send SIGINT to a process group; return the seconds until every marked process ended."""
    signalled = time.monotonic()
    os.killpg(process.proc.pid, signal.SIGINT)
    assert wait_until(lambda: not processes_marked(marker), timeout=60, period=0.02), \
        processes_marked(marker)
    return time.monotonic() - signalled, process.output()


@pytest.fixture(scope='module')
def crowd_built(tmp_path_factory) -> BuiltWorkspace:
    """Return crowd_system of 20 Python instances (shared by default), built."""
    if ros_missing_reason():
        pytest.skip(ros_missing_reason())
    return build_crowd(tmp_path_factory.mktemp('crowd'), 20)


@pytest.mark.integration
@requires_ros
def test_ctrl_c_of_bringup_ends_20_shared_instances_within_bounds_under_load(
        crowd_built, domain_id):
    env = marked_env(crowd_built, domain_id)
    bringup = [sys.executable,
               str(crowd_built.install / 'crowd_system' / 'lib' / 'crowd_system' / 'bringup')]
    with loaded_machine(bringup, env), background(bringup, env=env, stop_timeout=30) as run:
        assert wait_until(lambda: 'bringup: 20 of 20 managed instances active' in
                          run.output(), timeout=180), run.output()
        assert wait_until(lambda: len(re.findall(r'got map data', run.output())) >= 10,
                          timeout=30), run.output()
        # the process brought its instances up itself: the manager found them active
        assert not re.search(r'instance \w+ is active', run.output()), run.output()
        # one process for the twenty nodes, beside bringup
        shared = b'robmosys_runtime.hosting.container'
        assert [p for p in processes_marked(env[MARKER])
                if shared in Path(f'/proc/{p}/cmdline').read_bytes()]
        assert len(processes_marked(env[MARKER])) == 2, processes_marked(env[MARKER])
        took, output = ctrl_c(run, env[MARKER])
        assert run.proc.wait(timeout=1) == 0, output
    assert took <= CTRL_C_BOUND, f'{took:.2f} s:\n{output}'
    assert 'SIGKILL' not in output, output
    assert_no_traceback(output)
    assert len(re.findall(r'bringup: cleanup \w+', output)) == 20, output


@pytest.mark.integration
@requires_ros
def test_the_shared_process_of_a_launch_brings_its_instances_down_at_sigint(
        crowd_built, domain_id, tmp_path):
    """What ros2 launch's Ctrl-C does to the shared process: it brings its nodes down itself."""
    from lifecycle_msgs.msg import TransitionEvent
    share = crowd_built.share('crowd_system')
    description = json.loads((share / 'bringup.json').read_text())
    names = [i['instance'] for i in description['instances']]
    told = tmp_path / 'told.json'
    # the command of crowd_system.launch.py's shared process (test_a_shared_system_...)
    command = [sys.executable, '-m', 'robmosys_runtime.hosting.container', '--activate',
               '--report-file', str(told), str(share / 'bringup.json'),
               str(share / description['params_file']), *names, '--ros-args']
    watched = ['pub_0', 'sub_0', 'pub_9']
    events: dict[str, list[str]] = {name: [] for name in watched}
    with background(command, env=crowd_built.env(domain_id), stop_timeout=30) as shared, \
            LifecycleDriver(domain_id) as driver:
        for name in watched:
            driver.node.create_subscription(
                TransitionEvent, f'/{name}/transition_event',
                lambda event, name=name: events[name].append(event.goal_state.label), 10)
        assert wait_until(told.exists, timeout=120), shared.output()
        assert json.loads(told.read_text()) == dict.fromkeys(names, 'active')
        topics = [f'/{name}/transition_event' for name in watched]
        assert wait_until(lambda: all(driver.node.count_publishers(t) for t in topics),
                          timeout=30), shared.output()
        shared.proc.send_signal(signal.SIGINT)
        assert shared.proc.wait(timeout=30) == 0, shared.output()
        # the transition events it published, taken in: those of the bring-up
        # may come before (the subscription matched in time), then the bring-down's
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and \
                any(labels[-1:] != ['unconfigured'] for labels in events.values()):
            driver.executor.spin_once(timeout_sec=0.1)
        output = shared.output()
    down = {name: labels[len(labels) - labels[::-1].index('active'):]
            if 'active' in labels else labels for name, labels in events.items()}
    assert down == dict.fromkeys(
        watched, ['deactivating', 'inactive', 'cleaningup', 'unconfigured']), (events, output)
    assert_no_traceback(output)
