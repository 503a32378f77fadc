# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The manager dies, its instances die; a manager started again makes no second copy.

``ros2 run <system> bringup`` killed (SIGKILL: nothing of it runs any more)
leaves no process of its system behind, whether each instance has a process
of its own or they share one; started again at once, it waits for what the
dead one left to end before it starts anything; and a node of the model that
runs already, started by hand, is taken as it is: never a second node of one
name in the ROS graph.
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import sys
import time
from typing import Iterator

import pytest
from test_node_names import node_names, shared_names
from test_process_layout import marked_env, MARKER, processes_marked

from colcon_robmosys.devtools.ros_env import background, free_domain_id
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from conftest import assert_no_traceback, BuiltWorkspace, requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

SYSTEM = 'pubsub_system'
#: every node of the system, the manager's with them (the watch is off: its node is
#: tests/test_node_names.py's)
NODES = {'/publisher', '/subscriber', f'/{SYSTEM}_bringup'}
LAYOUTS = pytest.mark.parametrize('layout', ['--per-instance', '--shared'])


@pytest.fixture
def marked(test_workspace_built) -> Iterator[dict]:
    """Yield a marked environment of a domain of its own; kill what is left of it at the end."""
    env = marked_env(test_workspace_built, free_domain_id())
    try:
        yield env
    finally:
        # what a manager that died left running (the bug these tests catch)
        for pid in processes_marked(env[MARKER]):
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)


def _bringup(built: BuiltWorkspace, env: dict, *args: str):
    executable = built.install / SYSTEM / 'lib' / SYSTEM / 'bringup'
    return background([sys.executable, str(executable), '--check-period', '0', *args],
                      env=env, stop_timeout=30)


def _up(bringup) -> bool:
    return 'bringup: 2 of 2 managed instances active' in bringup.output()


def _instance_processes(marker: str, bringup_pid: int) -> list[int]:
    """Return the marked processes but the bringup's own."""
    return [p for p in processes_marked(marker) if p != bringup_pid]


@LAYOUTS
def test_a_killed_manager_leaves_no_process(test_workspace_built, marked, layout):
    with _bringup(test_workspace_built, marked, layout) as bringup:
        assert wait_until(lambda: _up(bringup), timeout=90), bringup.output()
        assert _instance_processes(marked[MARKER], bringup.proc.pid)
        os.kill(bringup.proc.pid, signal.SIGKILL)
        bringup.proc.wait(timeout=10)
        # each instance's process got SIGTERM as the manager died, and ends as at Ctrl-C
        assert wait_until(lambda: not processes_marked(marked[MARKER]), timeout=10), \
            [(p, open(f'/proc/{p}/cmdline', 'rb').read()) for p in
             processes_marked(marked[MARKER])]


def _no_second_node(driver: LifecycleDriver) -> list:
    """
    Return the names the graph holds twice, once what ended before is out of it.

    A process that ends as its manager is killed sometimes says no goodbye
    that other participants hear (Fast DDS), and a killed one never does: its
    node stays in their graphs until its lease ends (20 s). A second process
    of a name stays there for good.
    """
    deadline = time.monotonic() + 40
    while True:
        twice = shared_names(driver, NODES)
        if not twice or time.monotonic() > deadline:
            return twice


@LAYOUTS
def test_a_manager_started_again_waits_for_what_the_dead_one_left(
        test_workspace_built, marked, layout):
    domain_id = int(marked['ROS_DOMAIN_ID'])
    with LifecycleDriver(domain_id) as driver:
        with _bringup(test_workspace_built, marked, layout) as first:
            assert wait_until(lambda: _up(first), timeout=90), first.output()
            assert shared_names(driver, NODES, seconds=0.5) == []
            left = _instance_processes(marked[MARKER], first.proc.pid)
            # slow to end: stopped, they take the SIGTERM of the manager's death
            # only when they go on
            for pid in left:
                os.kill(pid, signal.SIGSTOP)
            os.kill(first.proc.pid, signal.SIGKILL)
            first.proc.wait(timeout=10)
        with _bringup(test_workspace_built, marked, layout) as again:
            assert wait_until(lambda: f'bringup: waiting for the {len(left)} processes that a '
                              'manager of this system which ended left to end' in
                              again.output(), timeout=30), again.output()
            time.sleep(1.0)
            # nothing started meanwhile
            assert set(processes_marked(marked[MARKER])) == {again.proc.pid, *left}
            for pid in left:
                os.kill(pid, signal.SIGCONT)
            assert wait_until(lambda: _up(again), timeout=90), again.output()
            assert not set(left) & set(processes_marked(marked[MARKER]))
            assert len(_instance_processes(marked[MARKER], again.proc.pid)) == len(left)
            assert _no_second_node(driver) == [], (sorted(node_names(driver)), again.output())
            again.proc.send_signal(signal.SIGINT)
            assert again.proc.wait(timeout=60) == 0, again.output()
            assert_no_traceback(again.output())


@LAYOUTS
def test_a_manager_started_again_at_once_makes_no_second_copy(test_workspace_built, marked,
                                                              layout):
    domain_id = int(marked['ROS_DOMAIN_ID'])
    with LifecycleDriver(domain_id) as driver:
        with _bringup(test_workspace_built, marked, layout) as first:
            assert wait_until(lambda: _up(first), timeout=90), first.output()
            assert shared_names(driver, NODES, seconds=0.5) == []
            count = len(_instance_processes(marked[MARKER], first.proc.pid))
            os.kill(first.proc.pid, signal.SIGKILL)
            first.proc.wait(timeout=10)
        # at once: what the first left may still be on its way out
        with _bringup(test_workspace_built, marked, layout) as again:
            assert wait_until(lambda: _up(again), timeout=90), again.output()
            assert len(_instance_processes(marked[MARKER], again.proc.pid)) == count, \
                again.output()
            assert _no_second_node(driver) == [], (sorted(node_names(driver)), again.output())
            again.proc.send_signal(signal.SIGINT)
            assert again.proc.wait(timeout=60) == 0, again.output()
            assert_no_traceback(again.output())


@LAYOUTS
def test_a_node_of_the_model_started_by_hand_is_taken_as_it_is(test_workspace_built, marked,
                                                               layout):
    built = test_workspace_built
    domain_id = int(marked['ROS_DOMAIN_ID'])
    description = json.loads((built.share(SYSTEM) / 'bringup.json').read_text())
    publisher = next(i for i in description['instances'] if i['instance'] == 'publisher')
    # as an operator starts it: ros2 run publisher PeriodicPublisher --ros-args -r ...
    by_hand = [sys.executable, str(built.install / 'publisher' / 'lib' / 'publisher' /
                                   publisher['executable']),
               '--ros-args', '-r', '__node:=publisher', '--params-file',
               str(built.share(SYSTEM) / 'cfg' / 'params.yaml')]
    for source, target in publisher['remappings']:
        by_hand += ['-r', f'{source}:={target}']
    with LifecycleDriver(domain_id) as driver, \
            background(by_hand, env=marked, stop_timeout=30) as hand:
        assert wait_until(lambda: '/publisher' in node_names(driver), timeout=60), \
            hand.output()
        with _bringup(built, marked, layout) as bringup:
            assert wait_until(lambda: _up(bringup), timeout=90), bringup.output()
            assert shared_names(driver, NODES) == [], sorted(node_names(driver))
            # said at the instance's line of the model
            line = f"{publisher['location'].split(':', 1)[1]}: warning: instance publisher: " \
                f'node /publisher runs already (process {hand.proc.pid}), not started by ' \
                'this manager: taken as it is'
            assert line in bringup.output(), bringup.output()
            # brought up by the manager as any instance is, and data flows
            assert driver.state('/publisher') == 'active'
            assert wait_until(lambda: 'got map data' in bringup.output(), 30), \
                bringup.output()
            bringup.proc.send_signal(signal.SIGINT)
            assert bringup.proc.wait(timeout=60) == 0, bringup.output()
            assert_no_traceback(bringup.output())
        # brought down with the system, but its process is not the manager's to end
        assert hand.proc.poll() is None
        assert driver.state('/publisher') == 'unconfigured'
