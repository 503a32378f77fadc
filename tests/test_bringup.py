# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""``ros2 run <system> bringup``: a whole system in the foreground, on real rclpy.

The bringup executable a system package installs starts every instance, brings
the managed ones up in the order of the model, reports what fails with what it
holds back, and on SIGINT brings the system down, those that came last first,
and exits 0. Its description (``bringup.json``) is the system model's.
"""

from __future__ import annotations

import contextlib
import json
import os
from pathlib import Path
import re
import signal
import sys

import pytest

from colcon_robmosys.devtools.ros_env import background, free_domain_id, run as run_command
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from conftest import assert_no_traceback, BuiltWorkspace, requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

SYSTEM = 'examples_system'


def _bringup(built: BuiltWorkspace, *args: str, domain_id: int | None = None):
    executable = built.install / SYSTEM / 'lib' / SYSTEM / 'bringup'
    return background([sys.executable, str(executable), *args],
                      env=built.env(free_domain_id() if domain_id is None else domain_id),
                      stop_timeout=30)


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
    assert_no_traceback(output)
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
    assert_no_traceback(output)
    assert 'bringup: add_client held back by add_server' in output, output
    assert_no_traceback(output)


def test_an_instance_whose_package_is_not_installed_is_one_line_and_nothing_starts(
        test_workspace_built, tmp_path):
    description = _description(test_workspace_built)
    for instance in description['instances']:
        if instance['instance'] == 'level_sensor':
            instance['package'] = 'not_installed_sensor'
    path = tmp_path / 'bringup.json'
    path.write_text(json.dumps(description))
    domain_id = free_domain_id()
    with _bringup(test_workspace_built, '--description', str(path),
                  domain_id=domain_id) as bringup:
        assert bringup.proc.wait(timeout=60) == 1, bringup.output()
        output = bringup.output()
    assert output.splitlines() == [
        "bringup: error: instance level_sensor needs the package 'not_installed_sensor', "
        'which is not installed (no prefix of AMENT_PREFIX_PATH has it: build it, or source '
        'the install that has it); nothing was started'], output
    # nothing started: no instance's process of the test's domain was left running
    assert [name for name in ('level_watcher', 'receiver', 'add_server')
            if _pids_of(name, domain_id)] == []


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
    assert 'bringup: error: instance level_sensor did not appear within 20 s (no node '\
        '/examples/level_sensor in the ROS graph); not activated because of it: level_watcher' \
        in output, output
    assert 'bringup: 6 of 8 managed instances active' in output, output
    assert_no_traceback(output)


def _trigger(driver: LifecycleDriver, service: str, timeout: float = 120.0):
    from std_srvs.srv import Trigger
    # bring_up and bring_down take as long as the transitions: never asked twice;
    # report only reads, and is asked again when its answer is lost (sent before
    # the answers' direction of the service matched)
    return driver.call(Trigger, f'/{SYSTEM}_bringup/{service}', Trigger.Request(),
                       timeout=timeout, attempt=2.0 if service == 'report' else timeout)


def _states(report: str) -> dict[str, str]:
    return dict(re.findall(r'^(\w+): (\w+)', report, re.MULTILINE))


def _all_up(bringup) -> bool:
    return 'bringup: 8 of 8 managed instances active' in bringup.output()


def test_operators_report_bring_down_and_bring_up_the_system(test_workspace_built):
    domain_id = free_domain_id()
    with _bringup(test_workspace_built, domain_id=domain_id) as bringup, \
            LifecycleDriver(domain_id) as driver:
        assert wait_until(lambda: _all_up(bringup), timeout=90), bringup.output()
        report = _trigger(driver, 'report')
        assert report.success, report.message
        assert set(_states(report.message).values()) == {'active'}, report.message
        assert len(_states(report.message)) == 8, report.message

        down = _trigger(driver, 'bring_down')
        assert down.success, down.message
        order = re.findall(r'deactivate (\w+)', down.message)
        assert order.index('add_client') < order.index('add_server'), down.message
        report = _trigger(driver, 'report')
        assert not report.success
        assert set(_states(report.message).values()) == {'unconfigured'}, report.message
        assert driver.state('/examples/add_server') == 'unconfigured'

        up = _trigger(driver, 'bring_up')
        assert up.success, up.message
        assert 'bringup: 8 of 8 managed instances active' in up.message, up.message
        assert driver.state('/examples/add_server') == 'active'
        assert _trigger(driver, 'report').success
        # data flows again after the new bring-up
        mark = len(bringup.output())
        assert wait_until(lambda: re.search(r'received hi there \d+',
                                            bringup.output()[mark:]) is not None, 30)
        bringup.proc.send_signal(signal.SIGINT)
        assert bringup.proc.wait(timeout=60) == 0, bringup.output()


def test_the_state_of_every_instance_is_on_diagnostics(test_workspace_built):
    from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
    domain_id = free_domain_id()
    with _bringup(test_workspace_built, '--diagnostics-period', '0.2',
                  domain_id=domain_id) as bringup, LifecycleDriver(domain_id) as driver:
        arrays: list = []
        driver.node.create_subscription(DiagnosticArray, '/diagnostics', arrays.append, 10)
        assert wait_until(lambda: _all_up(bringup), timeout=90), bringup.output()

        def all_ok() -> bool:
            driver.spin(0.1)
            # a status per instance, and one per connection (the conformance watch's)
            return bool(arrays) and len(
                [s for s in arrays[-1].status if ' -> ' not in s.name]) == 8 and all(
                s.level == DiagnosticStatus.OK for s in arrays[-1].status)
        assert wait_until(all_ok, timeout=20), arrays[-1:] or bringup.output()
        status = {s.name: s for s in arrays[-1].status}
        sender = status[f'{SYSTEM}: sender']
        assert sender.hardware_id == '/examples/sender'
        assert {v.key: v.value for v in sender.values}['state'] == 'active'


def _pids_of(node_name: str, domain_id: int) -> list[int]:
    """
    Return the pids of the processes bringup started for an instance, in a ROS domain.

    By its ROS domain, which is the test's own: tests of other sessions (CI runs
    Kilted's and Jazzy's side by side) run instances of the same names.
    """
    pids = []
    for entry in Path('/proc').iterdir():
        if not entry.name.isdigit():
            continue
        try:
            argv = (entry / 'cmdline').read_bytes().split(b'\0')
            environ = (entry / 'environ').read_bytes().split(b'\0')
        except OSError:
            continue
        if f'__node:={node_name}'.encode() in argv and \
                f'ROS_DOMAIN_ID={domain_id}'.encode() in environ:
            pids.append(int(entry.name))
    return pids


def _pid_of(node_name: str, domain_id: int) -> int:
    """Return the pid of the one process bringup started for an instance, in a ROS domain."""
    pids = _pids_of(node_name, domain_id)
    assert pids, f'no process of {node_name}'
    return pids[0]


def test_an_instance_marked_respawn_comes_back_to_the_state_of_the_system(
        test_workspace_built, tmp_path):
    description = _description(test_workspace_built)
    for instance in description['instances']:
        if instance['instance'] == 'add_server':
            instance['respawn'] = True
    path = tmp_path / 'bringup.json'
    path.write_text(json.dumps(description))
    domain_id = free_domain_id()
    with _bringup(test_workspace_built, '--description', str(path), '--respawn-delay', '0.5',
                  domain_id=domain_id) as bringup, LifecycleDriver(domain_id) as driver:
        assert wait_until(lambda: _all_up(bringup), timeout=90), bringup.output()
        first = _pid_of('add_server', domain_id)
        os.kill(first, signal.SIGKILL)
        assert wait_until(lambda: 'instance add_server exited with code -9: starting it '
                          'again (respawn 1)' in bringup.output(), 20), bringup.output()
        # started again, and brought back to active: the system is whole again
        assert wait_until(lambda: bringup.output().count('instance add_server is active') == 2,
                          60), bringup.output()
        assert _pid_of('add_server', domain_id) != first
        assert driver.state('/examples/add_server') == 'active'
        assert wait_until(lambda: _trigger(driver, 'report').success, 30), \
            _trigger(driver, 'report').message


def test_the_heartbeat_notices_an_instance_that_stops_answering_or_leaves_active(
        test_workspace_built, tmp_path):
    domain_id = free_domain_id()
    with _bringup(test_workspace_built, '--heartbeat', '0.5',
                  domain_id=domain_id) as bringup, LifecycleDriver(domain_id) as driver:
        assert wait_until(lambda: _all_up(bringup), timeout=90), bringup.output()
        # someone deactivates an instance behind the manager's back
        assert driver.transition('/examples/receiver', 'deactivate')
        # (its transition event may tell the manager before the heartbeat does)
        assert wait_until(lambda: 'instance receiver is inactive, not active ('
                          in bringup.output(), 20), bringup.output()
        # a process that hangs (stopped) answers nothing
        pid = _pid_of('level_watcher', domain_id)
        os.kill(pid, signal.SIGSTOP)
        try:
            assert wait_until(lambda: 'instance level_watcher does not answer (heartbeat)'
                              in bringup.output(), 30), bringup.output()
            report = _trigger(driver, 'report')
            assert not report.success
            states = _states(report.message)
            assert states['receiver'] == 'failed' and states['level_watcher'] == 'unknown', \
                report.message
        finally:
            os.kill(pid, signal.SIGCONT)
        assert wait_until(lambda: 'instance level_watcher answers again (heartbeat)'
                          in bringup.output(), 30), bringup.output()


def test_the_smoke_test_of_every_example_system_passes_under_colcon_test(
        test_workspace_built):
    systems = [p for p in ('examples_system', 'pubsub_system', 'dummy_robot_bringup',
                           'handwritten_system')
               if (test_workspace_built.install / p).is_dir()]
    assert 'examples_system' in systems
    built = test_workspace_built
    result = built.colcon('test', '--packages-select', *systems,
                          '--event-handlers', 'console_direct+')
    assert result.returncode == 0, result.stdout + result.stderr
    for system in systems:
        results = built.colcon('test-result', '--test-result-base', str(built.build / system),
                               '--all', '--verbose', timeout=120)
        assert results.returncode == 0, results.stdout + results.stderr
        assert f'{built.build / system}/test_results/{system}/smoke_test.xunit.xml' in \
            results.stdout, results.stdout
        assert re.search(r'Summary: \d+ tests?, 0 errors, 0 failures, 0 skipped',
                         results.stdout), results.stdout


def test_the_smoke_test_fails_when_a_connection_carries_nothing(test_workspace_built,
                                                                tmp_path):
    description = _description(test_workspace_built)
    # a connection of the model whose publisher never publishes
    description['connections'].append({
        'name': '/examples/nobody/speaks', 'entity': 'publisher', 'type': 'std_msgs/msg/String',
        'from': 'nobody.speaks', 'to': 'receiver.listens'})
    path = tmp_path / 'bringup.json'
    path.write_text(json.dumps(description))
    # the same timeout bounds the wait for the watch's first clean answer: a watch
    # that compares 3 s after the last instance came up needs more than 5 s on a
    # loaded machine (it once answered a difference of the start within 5 s)
    problems = _smoke(test_workspace_built, description_file=str(path),
                      timeout=10.0)
    assert problems[0] == 'no message on nobody.speaks -> receiver.listens ' \
        '(/examples/nobody/speaks, std_msgs/msg/String) within 10 s', '\n'.join(problems)
    assert len(problems) == 2 and problems[1].startswith('what the system printed:'), \
        '\n'.join(problems)


def test_the_smoke_test_fails_when_the_system_does_not_come_up(test_workspace_built,
                                                               tmp_path):
    path = _broken_description(test_workspace_built, tmp_path, add_server=[
        sys.executable, '-c', 'import sys; sys.exit(3)'])
    problems = _smoke(test_workspace_built, description_file=str(path),
                      bring_up_timeout=60.0, bringup_args=['--timeout', '10'])
    assert problems[0] == 'the system did not come up: bringup exited with code 1', problems
    assert 'instance add_server exited with code 3' in problems[-1], problems


def _smoke(built: BuiltWorkspace, **kwargs) -> list:
    """Run robmosys_runtime.tools.smoke in a process of its own, in the workspace's environment."""
    script = ('import json, sys; from robmosys_runtime.tools import smoke; '
              f'print(json.dumps(smoke.run({SYSTEM!r}, **json.loads(sys.argv[1]))))')
    result = run_command([sys.executable, '-c', script, json.dumps(kwargs)],
                         env=built.env(free_domain_id()), timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    return json.loads(result.stdout.splitlines()[-1])


def _processes_with(marker: str) -> list[int]:
    """Return the pids of the processes whose command line holds marker."""
    pids = []
    for entry in Path('/proc').iterdir():
        try:
            if entry.name.isdigit() and marker.encode() in (entry / 'cmdline').read_bytes():
                pids.append(int(entry.name))
        except OSError:
            continue
    return pids


def _descendants(root: int) -> set[int]:
    """Return the pids of the processes that root started, and theirs."""
    found: set[int] = set()
    todo = [root]
    while todo:
        pid = todo.pop()
        with contextlib.suppress(OSError):
            for task in Path(f'/proc/{pid}/task').iterdir():
                children = [int(c) for c in (task / 'children').read_text().split()]
                found.update(children)
                todo += children
    return found


def test_shared_processes_run_the_python_instances_in_one_process(test_workspace_built,
                                                                  tmp_path):
    description = _description(test_workspace_built)
    path = tmp_path / 'bringup.json'
    path.write_text(json.dumps(description))
    with _bringup(test_workspace_built, '--description', str(path), '--shared') as bringup:
        assert wait_until(lambda: _all_up(bringup), timeout=90), bringup.output()
        assert wait_until(lambda: re.search(r'received hi there \d+', bringup.output())
                          is not None, timeout=30), bringup.output()
        # one process holds the eight nodes: none of them has a process of its own
        containers = [p for p in _processes_with('robmosys_runtime.hosting.container')
                      if str(path).encode() in Path(f'/proc/{p}/cmdline').read_bytes()]
        assert len(containers) == 1, containers
        # (of this bringup: other tests may run the same install beside it)
        assert not [p for p in _processes_with('__node:=sender')
                    if p in _descendants(bringup.proc.pid)]
        bringup.proc.send_signal(signal.SIGINT)
        assert bringup.proc.wait(timeout=60) == 0, bringup.output()
        output = bringup.output()
    # the process brought its instances down itself, in the order of the model
    # reversed, and told bringup each step
    assert len(re.findall(r'bringup: cleanup \w+', output)) == 8, output
    order = re.findall(r'bringup: deactivate (\w+)', output)
    for after, before in (('add_client', 'add_server'), ('level_watcher', 'level_sensor'),
                          ('fibonacci_client', 'fibonacci_server')):
        assert order.index(after) < order.index(before), output
    assert_no_traceback(output)


def test_instances_on_another_host_are_brought_up_by_the_manager(test_workspace_built,
                                                                 tmp_path):
    description = _description(test_workspace_built)
    remote = {'sender', 'add_server', 'fibonacci_server', 'level_sensor'}
    for instance in description['instances']:
        if instance['instance'] in remote:
            instance['host'] = 'robot'
    path = tmp_path / 'bringup.json'
    path.write_text(json.dumps(description))
    domain_id = free_domain_id()
    # two "hosts": two bringup processes in one domain, on loopback
    with _bringup(test_workspace_built, '--description', str(path), '--host', 'robot',
                  domain_id=domain_id) as robot, \
            _bringup(test_workspace_built, '--description', str(path),
                     domain_id=domain_id) as manager:
        assert wait_until(lambda: _all_up(manager), timeout=90), \
            manager.output() + robot.output()
        assert 'bringup: host robot: started add_server, fibonacci_server, level_sensor, ' \
            'sender' in robot.output(), robot.output()
        # the receiver runs here, the sender there: data flows between the hosts
        assert wait_until(lambda: re.search(r'received hi there \d+', manager.output())
                          is not None, timeout=30), manager.output()
        manager.proc.send_signal(signal.SIGINT)
        assert manager.proc.wait(timeout=60) == 0, manager.output()
        steps = re.findall(r'bringup: (deactivate|cleanup) (\w+)', manager.output())
        assert {n for s, n in steps if s == 'cleanup'} >= remote, manager.output()
        robot.proc.send_signal(signal.SIGINT)
        assert robot.proc.wait(timeout=60) == 0, robot.output()
        assert_no_traceback(manager.output() + robot.output())


def test_a_host_without_instances_is_an_error(test_workspace_built):
    with _bringup(test_workspace_built, '--host', 'nowhere') as bringup:
        assert bringup.proc.wait(timeout=60) == 1, bringup.output()
        assert 'bringup: error: no instance of the system runs on the host nowhere' in \
            bringup.output()


def test_attached_the_manager_brings_up_nodes_it_did_not_start(test_workspace_built):
    """What <system>.launch.py runs: the nodes started by the launch, the manager attached."""
    from harness.launch_files import nodes_launch_file, read_launch_file
    share = test_workspace_built.share(SYSTEM)
    nodes = read_launch_file(nodes_launch_file(share), share)
    domain_id = free_domain_id()
    env = test_workspace_built.env(domain_id)
    with contextlib.ExitStack() as stack:
        started = [stack.enter_context(background(n.command(test_workspace_built.install),
                                                  env=env)) for n in nodes]
        driver = stack.enter_context(LifecycleDriver(domain_id))
        # ros2 launch hands its executables ROS arguments: the manager takes them
        with _bringup(test_workspace_built, '--attach', '--ros-args', '--log-level', 'info',
                      domain_id=domain_id) as bringup:
            assert wait_until(lambda: _all_up(bringup), timeout=90), bringup.output()
            assert _trigger(driver, 'report').success
            bringup.proc.send_signal(signal.SIGINT)
            assert bringup.proc.wait(timeout=30) == 0, bringup.output()
            assert 'bringup: deactivate' not in bringup.output(), bringup.output()
        # ending the nodes is the launch's: they are still there, and active
        assert driver.state('/examples/add_server') == 'active'
        assert all(p.proc.poll() is None for p in started)
