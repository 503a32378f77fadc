# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""One node name each: no two nodes of a running system share a fully qualified name.

The system manager's node is ``/<system>_bringup`` (moved with ``--namespace``);
its helper nodes have names of their own: ``/_<system>_bringup_states`` follows the
instances' transition events (``/<system>_bringup_watch`` listens to topics that no
generated component publishes, absent here: the components keep their send times). Tools
that look a node up by name (``ros2 param``, ``ros2 node info``, lifecycle
services) need each name once: the ROS graph is read here from a probe node,
as those tools read it.
"""

from __future__ import annotations

import collections
import signal
import sys
import time

import pytest

from colcon_robmosys.devtools.ros_env import background, free_domain_id
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from conftest import assert_no_traceback, BuiltWorkspace, requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

SYSTEM = 'pubsub_system'


def node_names(driver: LifecycleDriver) -> list[str]:
    """Return the fully qualified name of every node of the graph, as often as it is there."""
    return [f"{namespace.rstrip('/')}/{name}"
            for name, namespace in driver.node.get_node_names_and_namespaces()]


def shared_names(driver: LifecycleDriver, expected: set[str], seconds: float = 4.0) -> list:
    """
    Wait for the expected nodes, then read the graph for a while; return the names seen twice.

    A second node of a name shows once its participant is discovered, which
    takes up to about 3 s here: the graph is read again and again meanwhile.
    """
    assert wait_until(lambda: expected <= set(node_names(driver)), timeout=60), \
        sorted(node_names(driver))
    twice: set[str] = set()
    deadline = time.monotonic() + seconds
    while True:
        twice |= {n for n, count in collections.Counter(node_names(driver)).items()
                  if count > 1}
        if time.monotonic() >= deadline:
            return sorted(twice)
        time.sleep(0.1)


def _bringup(built: BuiltWorkspace, domain_id: int, *args: str):
    executable = built.install / SYSTEM / 'lib' / SYSTEM / 'bringup'
    return background([sys.executable, str(executable), '--check-period', '0.5', *args],
                      env=built.env(domain_id), stop_timeout=30)


@pytest.mark.parametrize('options, where', [
    ((), ''),
    (('--shared',), ''),
    (('--namespace', 'robot1'), '/robot1'),
], ids=['per-instance', 'shared', 'namespace'])
def test_no_two_nodes_of_a_running_system_share_a_name(test_workspace_built, options, where):
    domain_id = free_domain_id()
    with _bringup(test_workspace_built, domain_id, *options) as bringup, \
            LifecycleDriver(domain_id) as driver:
        assert wait_until(lambda: 'bringup: 2 of 2 managed instances active' in
                          bringup.output(), timeout=90), bringup.output()
        manager = f'{where}/{SYSTEM}_bringup'
        # the transition events are followed once the system is up, on a node of their own
        states = f'{where}/_{SYSTEM}_bringup_states'
        expected = {manager, states, f'{where}/publisher', f'{where}/subscriber'}
        assert shared_names(driver, expected) == [], sorted(node_names(driver))
        bringup.proc.send_signal(signal.SIGINT)
        assert bringup.proc.wait(timeout=60) == 0, bringup.output()
        assert_no_traceback(bringup.output())


def test_a_name_given_to_the_manager_names_its_node_only(test_workspace_built):
    """What launch_ros' ``Node(..., name=...)`` hands the manager: a ``__node`` remapping."""
    domain_id = free_domain_id()
    with _bringup(test_workspace_built, domain_id, '--ros-args', '-r',
                  '__node:=site_manager') as bringup, LifecycleDriver(domain_id) as driver:
        assert wait_until(lambda: 'bringup: 2 of 2 managed instances active' in
                          bringup.output(), timeout=90), bringup.output()
        expected = {'/site_manager', '/_site_manager_states', '/publisher', '/subscriber'}
        assert shared_names(driver, expected) == [], sorted(node_names(driver))
        assert f'/{SYSTEM}_bringup' not in node_names(driver)
        bringup.proc.send_signal(signal.SIGINT)
        assert bringup.proc.wait(timeout=60) == 0, bringup.output()
