# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
One system across hosts that are network namespaces, on real rclpy.

Three hosts (colcon_robmosys/devtools/netns.py) share one link: ``base`` runs the system
manager, ``robot1`` and ``robot2`` the instances of examples_system, each
connection from one robot to the other. Discovery crosses the link by
multicast, or, with multicast dropped on the link, by ``ROS_STATIC_PEERS``.
The scenarios of a deployment follow: the system comes up, a robot's link goes
down and comes back, a robot's host dies and its ``bringup`` starts again,
the operator stops everything with Ctrl-C. docs/runtime.md ("A system on
several hosts") is the guide these tests back.
"""

from __future__ import annotations

import contextlib
import json
import os
from pathlib import Path
import re
import signal
import sys
import time
from typing import Any, Iterator

import pytest
from test_cpp_system import requires_rclcpp

from colcon_robmosys.devtools import netns
from colcon_robmosys.devtools.ros_env import Background, free_domain_id
from colcon_robmosys.devtools.system import wait_until
from conftest import assert_no_traceback, BuiltWorkspace, hosts_of, requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

SYSTEM = 'examples_system'
HOSTS = {'robot1': ('sender', 'add_server', 'fibonacci_server', 'level_sensor'),
         'robot2': ('receiver', 'add_client', 'fibonacci_client', 'level_watcher')}
#: what robot2 prints when data of robot1 reached it, on each connection of the model
CROSSED = {'sText': r'received hi there \d+', 'qAdd': r'(blocking|callback) answer: ',
           'aFibonacci': r'(blocking|callback) result: ', 'eLevel': r'event: level \d+'}
#: the connections whose data flows all along: level_watcher ends its activations after
#: 12 events (the event example shows how), so events stop by design
FLOWING = ('sText', 'qAdd', 'aFibonacci')
#: the manager's heartbeat, in seconds
HEARTBEAT = 1.0
#: the conformance watch's check period, bringup's default (--check-period)
CHECK_PERIOD = 1.0
PROBE = Path(__file__).resolve().parent / 'harness' / 'ros_probe.py'


@pytest.fixture(scope='module')
def network(tmp_path_factory) -> Iterator[netns.Network]:
    """Return the three hosts, made once for the module and removed after it."""
    yield from hosts_of(('base', *HOSTS), tmp_path_factory)


def _placed(built: BuiltWorkspace, package: str, hosts: dict[str, tuple[str, ...]],
            folder: Path) -> Path:
    """Return a system's bringup.json with its instances on the hosts of hosts."""
    description = json.loads((built.share(package) / 'bringup.json').read_text())
    for instance in description['instances']:
        instance['host'] = next(h for h, names in hosts.items() if instance['instance'] in names)
    placed = folder / 'bringup.json'
    placed.write_text(json.dumps(description))
    return placed


@pytest.fixture(scope='module')
def description(test_workspace_built: BuiltWorkspace, tmp_path_factory) -> Path:
    """Return examples_system's bringup.json with its instances on the two robots."""
    return _placed(test_workspace_built, SYSTEM, HOSTS, tmp_path_factory.mktemp('description'))


class System:
    """The processes of the system on the hosts: each host's bringup, the manager."""

    def __init__(self, network: netns.Network, built: BuiltWorkspace, description: Path,
                 stack: contextlib.ExitStack, static_peers: bool, package: str = SYSTEM) -> None:
        self.network = network
        self.description = description
        self.package = package
        self._built = built
        self._stack = stack
        base = built.env(free_domain_id())
        self.env = {h: network.env(h, base, static_peers) for h in network.hosts}
        self.hosts: dict[str, Background] = {}
        self.manager: Background | None = None
        #: when a test cut a robot's link (time.monotonic())
        self.cut = 0.0

    def bringup(self, host: str, *args: str) -> list[str]:
        """Return the command line of the system's bringup with the model of the test."""
        return [sys.executable,
                str(self._built.install / self.package / 'lib' / self.package / 'bringup'),
                '--description', str(self.description), *args]

    def start_host(self, host: str) -> Background:
        """Start a robot's bringup (--host), in one process for its instances."""
        self.hosts[host] = self._stack.enter_context(self.network.background(
            host, self.bringup(host, '--host', host, '--shared'), self.env[host]))
        return self.hosts[host]

    def start_manager(self) -> Background:
        """Start the system manager on base, with a heartbeat."""
        self.manager = self._stack.enter_context(self.network.background(
            'base', self.bringup('base', '--heartbeat', str(HEARTBEAT)), self.env['base']))
        return self.manager

    def ask(self, what: str, *names: str) -> Any:
        """Ask the system from base (ros_probe.py); return its answer."""
        result = self.network.run('base', [sys.executable, str(PROBE), what, *names],
                                  self.env['base'], timeout=120)
        assert result.returncode == 0, result.stdout + result.stderr
        return json.loads(result.stdout.splitlines()[-1])

    def report(self) -> dict[str, str]:
        """Return the state of each instance, as the manager's ~/report tells it."""
        answer = self.ask('trigger', f'/{SYSTEM}_bringup/report')
        assert answer is not None, 'the manager did not answer ~/report'
        return dict(re.findall(r'^(\w+): (\w+)', answer['message'], re.MULTILINE))

    def smoke(self) -> list[str]:
        """Run the system's smoke test on base (the runtime's tools.smoke); return its problems."""
        script = ('import json, sys; from robmosys_runtime.tools import smoke; '
                  'print(json.dumps(smoke.run(sys.argv[1], description_file=sys.argv[2])))')
        result = self.network.run('base', [sys.executable, '-c', script, self.package,
                                           str(self.description)], self.env['base'], timeout=300)
        assert result.returncode == 0, result.stdout + result.stderr
        return json.loads(result.stdout.splitlines()[-1])

    def output(self) -> str:
        """Return what every process printed, host by host."""
        parts = [('base', self.manager)] + list(self.hosts.items())
        return '\n'.join(f'--- {h}:\n{p.output()}' for h, p in parts if p is not None)


def _crossed(output: str, ports: tuple[str, ...] = tuple(CROSSED)) -> list[str]:
    """Return the connections of ports whose data did not reach robot2 in output."""
    return [port for port in ports if not re.search(CROSSED[port], output)]


def _stopped_on_sigint(process: Background, timeout: float = 60.0) -> int:
    process.proc.send_signal(signal.SIGINT)
    return process.proc.wait(timeout=timeout)


def test_with_multicast_the_smoke_test_and_the_watch_pass_across_hosts(
        network, test_workspace_built, description):
    assert network.multicast_passes('robot1', 'base'), 'multicast does not pass the link'
    with contextlib.ExitStack() as stack:
        system = System(network, test_workspace_built, description, stack, static_peers=False)
        robots = [system.start_host(h) for h in HOSTS]
        # the smoke test every system package has, run on base: it starts the
        # manager, which brings the robots' instances up; every connection
        # carries data to base, and the conformance watch finds no difference
        problems = system.smoke()
        assert problems == [], '\n'.join(problems) + system.output()
        # and from robot1 to robot2, on every connection
        assert _crossed(system.hosts['robot2'].output()) == [], system.output()
        for robot in robots:
            assert _stopped_on_sigint(robot) == 0, system.output()
        assert_no_traceback(system.output())


#: mixed_system on two robots: robot1 runs every C++ instance in its component
#: container, robot2 the Python ones in one process; data crosses both ways
MIXED = 'mixed_system'
MIXED_HOSTS = {'robot1': ('cpp_pub', 'cpp_sub', 'sender', 'receiver', 'server', 'client',
                          'cpp_sensor', 'cpp_watcher'),
               'robot2': ('py_pub', 'py_sub', 'py_client', 'py_sensor', 'py_watcher')}
#: what each robot prints when data of the other reached it
MIXED_CROSSED = {'robot1': (r'got map data: width \d+', r'event: level \d+'),
                 'robot2': (r'got map data: width \d+', r'(blocking|callback) answer: ',
                            r'event: level \d+')}


@requires_rclcpp
def test_a_cpp_container_on_a_robot_is_brought_up_and_down_by_the_manager_on_base(
        network, test_workspace_built, tmp_path):
    placed = _placed(test_workspace_built, MIXED, MIXED_HOSTS, tmp_path)
    every = sorted(n for names in MIXED_HOSTS.values() for n in names)
    with contextlib.ExitStack() as stack:
        system = System(network, test_workspace_built, placed, stack, static_peers=False,
                        package=MIXED)
        robots = {h: system.start_host(h) for h in MIXED_HOSTS}
        manager = system.start_manager()
        assert wait_until(lambda: f'bringup: {len(every)} of {len(every)} managed instances '
                          'active' in manager.output(), 120), system.output()
        # robot1's C++ instances are nodes of one container process on robot1
        containers = [pid for pid in network.pids('robot1')
                      if b'component_container' in _cmdline(pid)]
        assert len(containers) == 1, system.output()
        for host, crossed in MIXED_CROSSED.items():
            assert wait_until(lambda: all(re.search(c, robots[host].output())
                                          for c in crossed), 30), \
                f'{host} got no data of the other robot\n{system.output()}'
        assert _stopped_on_sigint(manager) == 0, system.output()
        steps = re.findall(r'bringup: (deactivate|cleanup) (\w+)', manager.output())
        assert sorted(n for s, n in steps if s == 'cleanup') == every, system.output()
        for robot in robots.values():
            assert _stopped_on_sigint(robot) == 0, system.output()
        # the container ended with its robot's bringup
        assert wait_until(lambda: not network.pids('robot1'), 30), system.output()
        assert_no_traceback(system.output())


def _cmdline(pid: int) -> bytes:
    try:
        return Path(f'/proc/{pid}/cmdline').read_bytes()
    except OSError:
        return b''


@pytest.fixture(scope='module')
def system(network, test_workspace_built, description) -> Iterator[System]:
    """
    Return the system up on the hosts, discovery by ROS_STATIC_PEERS, multicast dropped.

    The robots start first and the manager after them, as on a real site
    where the robots are switched on before the operator's station.
    """
    network.set_multicast(False)
    try:
        assert not network.multicast_passes('robot1', 'base'), 'multicast still passes'
        with contextlib.ExitStack() as stack:
            system = System(network, test_workspace_built, description, stack,
                            static_peers=True)
            for host in HOSTS:
                system.start_host(host)
            system.start_manager()
            yield system
    finally:
        network.set_multicast(True)


def _up(system: System, timeout: float = 120.0) -> None:
    assert system.manager is not None
    assert wait_until(lambda: 'bringup: 8 of 8 managed instances active' in
                      system.manager.output(), timeout), system.output()


def test_without_multicast_every_instance_becomes_active_and_data_crosses_hosts(system):
    _up(system)
    robot2 = system.hosts['robot2']
    assert wait_until(lambda: _crossed(robot2.output()) == [], 30), \
        f'{_crossed(robot2.output())} carried nothing\n{system.output()}'
    assert set(system.report().values()) == {'active'}, system.output()
    conformance = system.ask('trigger', f'/{SYSTEM}_bringup/conformance')
    assert wait_until(lambda: system.ask('trigger', f'/{SYSTEM}_bringup/conformance')[
        'success'], 30), conformance


def _said_of(output: str, names: tuple[str, ...], what: str) -> list[str]:
    """Return the instances of names the manager has not said what of, in output."""
    return [n for n in names if f'instance {n} {what}' not in output]


def test_a_robot_whose_link_goes_down_is_reported_and_the_others_run_on(system):
    _up(system)
    assert system.manager is not None
    mark = len(system.manager.output())
    cut = system.cut = time.monotonic()
    system.network.set_link('robot1', up=False)
    assert wait_until(lambda: not _said_of(system.manager.output()[mark:], HOSTS['robot1'],
                                           'does not answer (heartbeat)'), 30, 0.05), \
        system.output()
    noticed = time.monotonic() - cut
    # three heartbeats missed, the first of them at most one heartbeat after the cut
    # (2 s more for a loaded machine)
    assert noticed < 4 * HEARTBEAT + 2.0, f'reported after {noticed:.1f} s'
    states = system.report()
    assert {n: states[n] for n in HOSTS['robot1']} == dict.fromkeys(HOSTS['robot1'],
                                                                    'unknown'), states
    assert {n: states[n] for n in HOSTS['robot2']} == dict.fromkeys(HOSTS['robot2'],
                                                                    'active'), states
    assert system.hosts['robot2'].proc.poll() is None
    assert system.hosts['robot1'].proc.poll() is None


def test_when_the_link_comes_back_its_instances_are_active_again_nothing_restarted(system):
    assert system.manager is not None
    mark = len(system.manager.output())
    robot2_mark = len(system.hosts['robot2'].output())
    # a long loss: down past the lease, the hosts have forgotten each other's
    # participants and discover them again (ROS_STATIC_PEERS: no multicast)
    time.sleep(max(0.0, system.cut + netns.LEASE + 2.0 - time.monotonic()))
    system.network.set_link('robot1', up=True)
    assert wait_until(lambda: not _said_of(system.manager.output()[mark:], HOSTS['robot1'],
                                           'answers again (heartbeat)'), 60), system.output()
    assert set(system.report().values()) == {'active'}, system.output()
    robot2 = system.hosts['robot2']
    assert wait_until(lambda: _crossed(robot2.output()[robot2_mark:], FLOWING) == [], 30), \
        f'{_crossed(robot2.output()[robot2_mark:], FLOWING)} carried nothing since\n' \
        f'{system.output()}'
    # they kept their state: nothing was brought up again
    assert ' is active' not in system.manager.output()[mark:], system.output()
    # the watch says what a fresh participant sees: the manager's graph lost the
    # names of robot1's nodes with the lease (rmw_fastrtps does not get them
    # back), which is no difference of the system's
    met = time.monotonic()
    assert wait_until(lambda: system.ask('trigger', f'/{SYSTEM}_bringup/conformance')[
        'success'], 10 * CHECK_PERIOD), system.output()
    time.sleep(max(0.0, met + 10 * CHECK_PERIOD - time.monotonic()))
    conformance = system.ask('trigger', f'/{SYSTEM}_bringup/conformance')
    assert conformance['success'], conformance['message'] + system.output()
    since = system.manager.output()[mark:]
    assert '_NODE_NAME_UNKNOWN_' not in since and 'is not in the ROS graph' not in \
        since.split('answers again (heartbeat)', 1)[-1], system.output()


def test_a_robot_whose_bringup_is_killed_comes_back_to_the_state_of_the_system(system):
    _up(system)
    assert system.manager is not None
    mark = len(system.manager.output())
    # its instances end with it: none lives on to meet its double
    os.kill(system.hosts['robot1'].proc.pid, signal.SIGKILL)
    assert wait_until(lambda: not system.network.pids('robot1'), 30), \
        f'left on robot1: {system.network.pids("robot1")}\n{system.output()}'
    assert wait_until(lambda: not _said_of(system.manager.output()[mark:], HOSTS['robot1'],
                                           'does not answer (heartbeat)'), 30), system.output()
    robot2_mark = len(system.hosts['robot2'].output())
    system.start_host('robot1')
    assert wait_until(lambda: not _said_of(system.manager.output()[mark:], HOSTS['robot1'],
                                           'is active'), 90), system.output()
    assert set(system.report().values()) == {'active'}, system.output()
    robot2 = system.hosts['robot2']
    assert wait_until(lambda: _crossed(robot2.output()[robot2_mark:], FLOWING) == [], 30), \
        f'{_crossed(robot2.output()[robot2_mark:], FLOWING)} carried nothing since\n' \
        f'{system.output()}'
    # robot2's instances were not brought up again
    assert _said_of(system.manager.output()[mark:], HOSTS['robot2'], 'is active') == \
        list(HOSTS['robot2']), system.output()


def test_a_manager_killed_and_started_again_takes_the_running_instances_as_they_are(system):
    # the operator's station dies (SIGKILL: no cleanup) while the robots run on;
    # a new manager finds them active and brings nothing up again
    _up(system)
    assert system.manager is not None
    os.kill(system.manager.proc.pid, signal.SIGKILL)
    system.manager.proc.wait(timeout=30)
    robot2 = system.hosts['robot2']
    robot2_mark = len(robot2.output())
    assert wait_until(lambda: _crossed(robot2.output()[robot2_mark:], FLOWING) == [], 30), \
        f'without a manager, {_crossed(robot2.output()[robot2_mark:], FLOWING)} stopped\n' \
        f'{system.output()}'
    manager = system.start_manager()
    _up(system)
    assert ' is active' not in manager.output(), system.output()
    assert set(system.report().values()) == {'active'}, system.output()
    assert all(host.proc.poll() is None for host in system.hosts.values()), system.output()


def test_ctrl_c_on_the_manager_brings_every_host_down_and_each_host_exits_0(system):
    _up(system)
    assert system.manager is not None
    assert _stopped_on_sigint(system.manager) == 0, system.output()
    steps = re.findall(r'bringup: (deactivate|cleanup) (\w+)', system.manager.output())
    every = sorted(n for names in HOSTS.values() for n in names)
    assert sorted(n for s, n in steps if s == 'cleanup') == every, system.output()
    # the robots' nodes still run, unconfigured: the system is down, not gone
    states = system.ask('states', *[f'/examples/{n}' for n in every])
    assert set(states.values()) == {'unconfigured'}, states
    for robot in system.hosts.values():
        assert _stopped_on_sigint(robot) == 0, system.output()
    assert_no_traceback(system.output())
