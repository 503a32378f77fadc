# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
A fleet on one machine: a base station and six robots, each a network namespace.

The system ``fleet`` (FLEET below, built in the test's own workspace on
test_workspace's install) includes pubsub_system once per robot, each on its
robot's host (a subsystem's ``host``): on each robot a publisher of maps at
2 Hz and a subscriber of them; on base the manager and a watcher of robot1's
maps. Each robot's ``bringup --host`` runs its two instances in one process, the
manager on base brings all 13 up, watches them, and brings them down on
Ctrl-C. Discovery crosses the link by multicast, or, with multicast dropped on
the link, through a Fast DDS discovery server on base (``ROS_DISCOVERY_SERVER``
on every host, the manager a super client: ``bringup --check`` shows why).
During a steady window the test prints what the links of base and of a robot
carry and the CPU base's processes take, in each mode (pytest's ``measured``
section); it asserts that the system works, not those figures (bench/
measures). docs/runtime.md ("Deploying it") is the guide this test backs.
"""

from __future__ import annotations

import contextlib
import json
import os
from pathlib import Path
import re
import signal
import subprocess
import sys
import time
from typing import Callable, Iterator

import pytest

from colcon_robmosys.devtools import netns, ros_env
from colcon_robmosys.devtools.ros_env import Background, free_domain_id
from colcon_robmosys.devtools.system import wait_until
from conftest import assert_no_traceback, BuiltWorkspace, hosts_of, requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

SYSTEM = 'fleet'
ROBOTS = tuple(f'robot{n}' for n in range(1, 7))
FLEET = """\
robmosys: 1
systems:
  - package: fleet
    license: Apache-2.0
    maintainers: [{name: Fleet Team, email: fleet@example.com}]
    description: pubsub_system on each of six robots, a watcher of robot1 on base.
    processes: shared
    subsystems:
%s
    instances:
      watcher: {component: subscriber, after: [robot1.publisher]}
    connections:
      - {from: robot1.publisher.pMap, to: watcher.rMap}
""" % '\n'.join(f'      {r}: {{system: pubsub_system, host: {r}}}' for r in ROBOTS)
#: every managed instance: a publisher and a subscriber per robot, the watcher on base
INSTANCES = sorted([f'{r}.{n}' for r in ROBOTS for n in ('publisher', 'subscriber')] +
                   ['watcher'])
#: the manager's heartbeat, in seconds (the guide's)
HEARTBEAT = 1.0
#: the port of the discovery server on base (Fast DDS's default)
SERVER_PORT = 11811
#: seconds of the steady window in which base's link and CPU are measured
STEADY = float(os.environ.get('ROBMOSYS_FLEET_STEADY', '10'))
PROBE = Path(__file__).resolve().parent / 'harness' / 'ros_probe.py'


@pytest.fixture(scope='module')
def network(tmp_path_factory) -> Iterator[netns.Network]:
    """Return base and the robots, made once for the module and removed after it."""
    yield from hosts_of(('base', *ROBOTS), tmp_path_factory)


@pytest.fixture(scope='module')
def fleet_built(test_workspace_built: BuiltWorkspace, tmp_path_factory
                ) -> tuple[Path, dict[str, str]]:
    """Return the fleet's install (its system package only, on test_workspace's), sourced."""
    root = tmp_path_factory.mktemp('fleet_ws')
    (root / 'src' / SYSTEM).mkdir(parents=True)
    (root / 'src' / SYSTEM / 'robmosys.yaml').write_text(FLEET)
    env = test_workspace_built.env(free_domain_id())
    result = ros_env.run([str(Path(sys.prefix) / 'bin' / 'colcon'), 'build',
                          '--event-handlers', 'console_cohesion+'],
                         env=env, cwd=root, timeout=900)
    assert result.returncode == 0, result.stdout + result.stderr
    assert re.findall(r'Finished <<< (\w+)', result.stdout) == [SYSTEM], result.stdout
    return root / 'install', ros_env.workspace_env(root / 'install', env)


class Fleet:
    """The processes of the fleet on its hosts: each robot's bringup, the manager, a server."""

    def __init__(self, network: netns.Network, built: tuple[Path, dict[str, str]],
                 stack: contextlib.ExitStack, server: bool) -> None:
        self.network = network
        self._stack = stack
        self._install, env = built
        base = dict(env, ROS_DOMAIN_ID=str(free_domain_id()))
        self.env = {h: network.env(h, base) for h in network.hosts}
        #: where the discovery server listens, if there is one
        self.server_address = f'{network.hosts["base"].address}:{SERVER_PORT}' if server \
            else ''
        if server:
            for host_env in self.env.values():
                # every host a client of the server on base, base included
                host_env['ROS_DISCOVERY_SERVER'] = self.server_address
        self.hosts: dict[str, Background] = {}
        self.manager: Background | None = None
        self.server: Background | None = None

    def bringup(self, *args: str) -> list[str]:
        """Return the command line of the fleet's bringup."""
        return [sys.executable, str(self._install / SYSTEM / 'lib' / SYSTEM / 'bringup'),
                *args]

    def start_server(self) -> Background:
        """Start a Fast DDS discovery server on base, on base's address (the guide's command)."""
        address = self.network.hosts['base'].address
        self.server = self._stack.enter_context(self.network.background(
            'base', ['fastdds', 'discovery', '--server-id', '0', '--udp-address', address,
                     '--udp-port', str(SERVER_PORT)], self.env['base']))
        return self.server

    def start_robots(self) -> None:
        """Start each robot's bringup: its instances, in one process."""
        for robot in ROBOTS:
            self.hosts[robot] = self._stack.enter_context(self.network.background(
                robot, self.bringup('--host', robot), self.env[robot]))

    def manager_env(self) -> dict[str, str]:
        """Return the environment of the manager and of tools that read the whole graph."""
        env = dict(self.env['base'])
        if self.server_address:
            # a client of a discovery server learns only the endpoints that match its
            # own: the watch compares the whole graph, a super client receives it all
            env['ROS_SUPER_CLIENT'] = 'TRUE'
        return env

    def start_manager(self) -> Background:
        """Start the manager on base, with the guide's heartbeat."""
        self.manager = self._stack.enter_context(self.network.background(
            'base', self.bringup('--heartbeat', str(HEARTBEAT)), self.manager_env()))
        return self.manager

    def ask(self, service: str) -> dict[str, object] | None:
        """Call one of the manager's Trigger services from base; return its answer."""
        result = self.network.run('base', [sys.executable, str(PROBE), 'trigger',
                                           f'/{SYSTEM}_bringup/{service}'],
                                  self.env['base'], timeout=120)
        assert result.returncode == 0, result.stdout + result.stderr
        return json.loads(result.stdout.splitlines()[-1])

    def output(self) -> str:
        """Return what every process printed, host by host."""
        parts = [('base', self.manager), ('server', self.server)] + list(self.hosts.items())
        return '\n'.join(f'--- {h}:\n{p.output()}' for h, p in parts if p is not None)


def _received(fleet: Fleet) -> list[str]:
    """Return the subscribers that have received no map yet."""
    assert fleet.manager is not None
    missing = [f'{r}.subscriber' for r in ROBOTS
               if f'[{r}.subscriber]: got map data' not in fleet.hosts[r].output()]
    return missing + ([] if '[watcher]: got map data' in fleet.manager.output()
                      else ['watcher'])


def _cpu_seconds(pid: int) -> float:
    """Return the CPU time a process has taken (user and system), 0 for one that ended."""
    try:
        fields = Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


def _link_bytes(network: netns.Network, host: str) -> tuple[int, int]:
    """Return the bytes a host's link interface received and sent so far."""
    shown = subprocess.run(['ip', '-n', network.hosts[host].namespace, '-s', '-j', 'link',
                            'show', 'eth0'], capture_output=True, text=True, timeout=30,
                           check=True)
    stats = json.loads(shown.stdout)[0]['stats64']
    return stats['rx']['bytes'], stats['tx']['bytes']


def _what(pid: int) -> str:
    try:
        command = Path(f'/proc/{pid}/cmdline').read_bytes().decode(errors='replace')
    except OSError:
        return 'ended'
    if 'fastdds' in command or 'fast-discovery-server' in command:
        return 'discovery server'
    return 'instances' if 'hosting.container' in command else 'manager'


def _measure(fleet: Fleet, mode: str, seconds: float) -> str:
    """Return what base's and a robot's links carried, and base's CPU, over seconds."""
    pids = fleet.network.pids('base')
    cpu = {p: _cpu_seconds(p) for p in pids}
    links = ('base', ROBOTS[-1])
    before = {h: _link_bytes(fleet.network, h) for h in links}
    start = time.monotonic()
    time.sleep(seconds)
    after = {h: _link_bytes(fleet.network, h) for h in links}
    elapsed = time.monotonic() - start
    taken: dict[str, float] = {}
    for pid in pids:
        what = _what(pid)
        taken[what] = taken.get(what, 0.0) + _cpu_seconds(pid) - cpu[pid]
    carried = '; '.join(
        f"{h}'s link received {(after[h][0] - before[h][0]) / elapsed / 1024:.1f} KiB/s, "
        f'sent {(after[h][1] - before[h][1]) / elapsed / 1024:.1f} KiB/s' for h in links)
    figures = ', '.join(f'{what} {100 * t / elapsed:.1f} %' for what, t in sorted(taken.items()))
    return (f'fleet of {len(ROBOTS)} robots, {mode}, over {elapsed:.0f} s: {carried}; '
            f'CPU on base (of one core): {figures}')


def _bring_up_watch_and_stop(fleet: Fleet, mode: str, record_property,
                             while_up: Callable[[], None] = lambda: None) -> None:
    """
    Run the fleet: all up, data on every robot, nothing differs; then Ctrl-C on each.

    The robots start first, as on a site where they are switched on before
    the operator's station. while_up runs once the fleet was steady a while.
    """
    fleet.start_robots()
    manager = fleet.start_manager()
    assert wait_until(lambda: f'bringup: {len(INSTANCES)} of {len(INSTANCES)} managed '
                      'instances active' in manager.output(), 120), fleet.output()
    assert wait_until(lambda: not _received(fleet), 30), \
        f'no map reached {_received(fleet)}\n{fleet.output()}'
    report = fleet.ask('report')
    assert report is not None and report['success'], f'{report}\n{fleet.output()}'
    states = dict(re.findall(r'^([\w.]+): (\w+)', str(report['message']), re.MULTILINE))
    assert states == dict.fromkeys(INSTANCES, 'active'), report
    assert wait_until(lambda: (fleet.ask('conformance') or {}).get('success'), 30), \
        f"{fleet.ask('conformance')}\n{fleet.output()}"
    measured = _measure(fleet, mode, STEADY)
    print(measured)
    record_property('measured', measured)
    # steady: the watch found nothing all along, every robot still delivers its maps
    assert ': difference: ' not in manager.output(), fleet.output()
    marks = {r: len(fleet.hosts[r].output()) for r in ROBOTS}
    assert wait_until(lambda: all('got map data' in fleet.hosts[r].output()[marks[r]:]
                                  for r in ROBOTS), 10), fleet.output()
    while_up()
    manager.proc.send_signal(signal.SIGINT)
    assert manager.proc.wait(timeout=60) == 0, fleet.output()
    steps = re.findall(r'bringup: (deactivate|cleanup) ([\w.]+)', manager.output())
    assert sorted(n for s, n in steps if s == 'cleanup') == INSTANCES, fleet.output()
    for robot in fleet.hosts.values():
        robot.proc.send_signal(signal.SIGINT)
        assert robot.proc.wait(timeout=60) == 0, fleet.output()
    assert_no_traceback(fleet.output())


def test_with_multicast_the_manager_on_base_brings_up_and_watches_six_robots(
        network, fleet_built, record_property):
    assert network.multicast_passes('robot1', 'base'), 'multicast does not pass the link'
    with contextlib.ExitStack() as stack:
        fleet = Fleet(network, fleet_built, stack, server=False)
        _bring_up_watch_and_stop(fleet, 'multicast', record_property)


def test_with_a_discovery_server_on_base_and_no_multicast_the_fleet_comes_up_watched(
        network, fleet_built, record_property):
    network.set_multicast(False)
    try:
        assert not network.multicast_passes('robot1', 'base'), 'multicast still passes'
        with contextlib.ExitStack() as stack:
            fleet = Fleet(network, fleet_built, stack, server=True)
            server = fleet.start_server()

            def checked_once() -> None:
                # bringup --check reads the whole graph as the watch does: as a super
                # client it finds the system as the model says, as a plain client of
                # the server it misses every endpoint it does not match itself
                check = fleet.network.run('base', fleet.bringup('--check'),
                                          fleet.manager_env(), timeout=120)
                assert (check.returncode, check.stdout) == (0, ''), \
                    check.stdout + check.stderr + fleet.output()
                plain = fleet.network.run('base', fleet.bringup('--check'), fleet.env['base'],
                                          timeout=120)
                assert plain.returncode == 1, plain.stdout + plain.stderr
                assert 'node /robot3/subscriber has no subscription on ' \
                    '/robot3/publisher/pMap' in plain.stdout, plain.stdout + plain.stderr

            _bring_up_watch_and_stop(fleet, 'discovery server', record_property, checked_once)
            assert server.proc.poll() is None, fleet.output()
    finally:
        network.set_multicast(True)
