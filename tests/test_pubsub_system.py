# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The publisher/subscriber example, built by colcon and run on real ROS 2."""

from __future__ import annotations

import contextlib
import re

import pytest

from colcon_robmosys.devtools.ros_env import background
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from conftest import requires_ros
from harness.launch_files import nodes_launch_file, read_launch_file

pytestmark = [pytest.mark.integration, requires_ros]

RECEIVED = re.compile(r'got map data: width (\d+), height (\d+)')


def test_installed_layout(test_workspace_built):
    """Every generated package is installed as a hand-written one would be."""
    install = test_workspace_built.install
    for package in ('simple_msgs', 'publisher', 'subscriber', 'pubsub_system', 'map_tools'):
        assert (install / package / 'share' / package / 'package.xml').is_file(), package
        assert (install / package / 'share' / 'ament_index' / 'resource_index' / 'packages' /
                package).is_file(), package
    assert (install / 'publisher' / 'lib' / 'publisher' / 'PeriodicPublisher').is_file()
    assert (install / 'subscriber' / 'lib' / 'subscriber' / 'Subscriber').is_file()
    share = test_workspace_built.share('pubsub_system')
    names = {p.name for p in (share / 'launch').iterdir()}
    stems = ['pubsub_system', 'pubsub_system.publisher', 'pubsub_system.subscriber']
    assert names == {f'{stem}{kind}.launch.py' for stem in stems for kind in ('', '.nodes')} | {
        'launch.py', 'activate.py', 'launch.publisher.py', 'activate.publisher.py',
        'launch.subscriber.py', 'activate.subscriber.py'}
    assert (share / 'cfg' / 'params.yaml').is_file()


def test_messages_are_importable(test_workspace_built, domain_id):
    """The message package built through rosidl is usable from rclpy."""
    from colcon_robmosys.devtools.ros_env import run
    import sys
    code = ('from simple_msgs.msg import Map, OGM\n'
            'm = Map(); m.ogm.width = 16; m.ogm.data = [-1, 0, 100]\n'
            'print(type(m.ogm).__name__, m.ogm.width, list(m.ogm.data))\n')
    result = run([sys.executable, '-c', code], env=test_workspace_built.env(domain_id),
                 timeout=60)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ['OGM', '16', '[-1,', '0,', '100]']


def test_hand_written_package_uses_generated_messages(test_workspace_built, domain_id):
    """A package.xml package that depends on simple_msgs builds after it and uses it."""
    from colcon_robmosys.devtools.ros_env import run
    install = test_workspace_built.install
    result = run([str(install / 'map_tools' / 'lib' / 'map_tools' / 'map_cells'), '3', '7'],
                 env=test_workspace_built.env(domain_id), timeout=30)
    assert result.stdout.strip() == 'cells: 21'


def test_pubsub_system_runs(test_workspace_built, domain_id):
    """Start the nodes as launch.py would, activate them, and see maps arrive."""
    share = test_workspace_built.share('pubsub_system')
    nodes = {n.name: n for n in read_launch_file(nodes_launch_file(share), share)}
    assert set(nodes) == {'publisher', 'subscriber'}
    env = test_workspace_built.env(domain_id)
    install = test_workspace_built.install

    with contextlib.ExitStack() as stack:
        processes = {name: stack.enter_context(background(node.command(install), env=env))
                     for name, node in nodes.items()}
        driver = stack.enter_context(LifecycleDriver(domain_id))
        publisher, subscriber = nodes['publisher'].fqn, nodes['subscriber'].fqn
        for fqn in (publisher, subscriber):
            assert driver.state(fqn) == 'unconfigured'

        # the system's parameter file overrides the component's defaults
        assert driver.parameters(publisher, ['indoor', 'noOfScans']) == \
            {'indoor': True, 'noOfScans': 3}

        # configured but inactive: no activity runs, nothing is published
        assert driver.transition(subscriber, 'configure')
        assert driver.transition(publisher, 'configure')
        assert driver.state(publisher) == 'inactive'
        wait_until(lambda: False, timeout=1.5)
        assert 'Publishing map' not in processes['publisher'].output()
        assert not RECEIVED.search(processes['subscriber'].output())

        assert driver.transition(subscriber, 'activate')
        assert driver.transition(publisher, 'activate')
        assert driver.state(publisher) == 'active'
        assert wait_until(lambda: len(RECEIVED.findall(processes['subscriber'].output())) >= 2,
                          timeout=20), processes['subscriber'].output()
        sizes = set(RECEIVED.findall(processes['subscriber'].output()))
        assert sizes == {('16', '16')}

        # deactivated: the periodic activity stops publishing
        assert driver.transition(publisher, 'deactivate')
        wait_until(lambda: False, timeout=0.6)
        published = processes['publisher'].output().count('Publishing map')
        wait_until(lambda: False, timeout=1.5)
        assert processes['publisher'].output().count('Publishing map') == published
