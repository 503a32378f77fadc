# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Systems compose: a system includes others as subsystems under a namespace.

The pubsub system of test_workspace is deployed twice by one system, which also
connects a watcher of its own to a port of one of them. What the system package
starts is checked here, and test_workspace's fleet_system (the same, built) runs;
tests/test_underlays.py runs a system whose subsystem comes from an underlay, and
tests/test_launch_ros.py launches fleet_system.
"""

from __future__ import annotations

import json
from pathlib import Path
import shutil
import sys

import pytest
import yaml

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.devtools.ros_env import background, free_domain_id
from colcon_robmosys.devtools.system import wait_until
from colcon_robmosys.generators import generate_package, plan_package
from colcon_robmosys.mapping.system import plan_system
from colcon_robmosys.model.files import model_dependencies
from colcon_robmosys.model.types import System
from conftest import requires_ros, TEST_WORKSPACE

TWO_ROBOTS = """\
robmosys: 1
systems:
  - package: two_robots
    license: Apache-2.0
    maintainers: [{name: A, email: a@example.com}]
    subsystems:
      robot1: {system: pubsub_system}
      robot2: {system: pubsub_system, namespace: /fleet/robot2}
      flat: {system: pubsub_system, namespace: /}
    instances:
      watcher: {component: subscriber, namespace: ops, after: [robot1.publisher]}
    connections:
      - {from: robot1.publisher.pMap, to: watcher.rMap}
"""


def _load(tmp_path: Path, model: str = TWO_ROBOTS):
    src = tmp_path / 'src'
    for package in ('simple_msgs', 'publisher', 'subscriber', 'pubsub_system'):
        shutil.copytree(TEST_WORKSPACE / 'src' / package, src / package)
    (src / 'two_robots').mkdir()
    (src / 'two_robots' / 'robmosys.yaml').write_text(model)
    result = load_workspace(find_model_files([src]), InterfaceIndex([Path(sys.prefix)]))
    assert result.errors == []
    return result


def test_the_instances_of_subsystems_join_the_system_in_their_namespace(tmp_path):
    result = _load(tmp_path)
    system = result.workspace.model('two_robots')
    assert isinstance(system, System)
    assert [(i.name, i.namespace, i.node_name, i.after) for i in system.instances] == [
        ('watcher', '/ops', 'watcher', ('robot1.publisher',)),
        ('robot1.publisher', '/robot1', 'publisher', ()),
        ('robot1.subscriber', '/robot1', 'subscriber', ()),
        ('robot2.publisher', '/fleet/robot2', 'publisher', ()),
        ('robot2.subscriber', '/fleet/robot2', 'subscriber', ()),
        ('flat.publisher', '', 'publisher', ()),
        ('flat.subscriber', '', 'subscriber', ()),
    ]
    # the subsystem's parameters come along
    publisher = system.instance('robot2.publisher')
    assert dict(publisher.parameters) == {'indoor': True, 'noOfScans': 3}
    # a change of the subsystem's model regenerates the system; colcon builds it first
    assert 'pubsub_system' in model_dependencies(system)
    assert result.warnings_of('two_robots') == []


#: a fleet: the pubsub system once per robot, each on its robot's host, a watcher on the
#: manager's host
FLEET = """\
robmosys: 1
systems:
  - package: fleet
    license: Apache-2.0
    maintainers: [{name: A, email: a@example.com}]
    subsystems:
      robot1: {system: pubsub_system, host: robot1}
      robot2: {system: pubsub_system, host: robot2}
    instances:
      watcher: {component: subscriber, after: [robot1.publisher]}
    connections:
      - {from: robot1.publisher.pMap, to: watcher.rMap}
"""


def test_the_instances_of_a_subsystem_run_on_its_host(tmp_path):
    result = _load(tmp_path, FLEET)
    system = result.workspace.model('fleet')
    assert isinstance(system, System)
    assert [(i.name, i.host) for i in system.instances] == [
        ('watcher', ''), ('robot1.publisher', 'robot1'), ('robot1.subscriber', 'robot1'),
        ('robot2.publisher', 'robot2'), ('robot2.subscriber', 'robot2')]
    out = tmp_path / 'out'
    generate_package(plan_package(result.workspace, 'fleet'), out)
    # each robot has its launch files, and the manager knows where each instance runs
    assert {p.name for p in (out / 'launch').glob('fleet.on_*.launch.py')} == {
        'fleet.on_robot1.launch.py', 'fleet.on_robot1.nodes.launch.py',
        'fleet.on_robot2.launch.py', 'fleet.on_robot2.nodes.launch.py'}
    description = json.loads((out / 'bringup.json').read_text())
    assert {i['instance']: i['host'] for i in description['instances']} == {
        'watcher': '', 'robot1.publisher': 'robot1', 'robot1.subscriber': 'robot1',
        'robot2.publisher': 'robot2', 'robot2.subscriber': 'robot2'}


def test_an_instance_of_a_subsystem_keeps_a_host_of_its_own(tmp_path):
    """A subsystem's host is where its instances run that do not name one."""
    arm = ('robmosys: 1\nsystems:\n  - package: arm_system\n    license: Apache-2.0\n'
           '    maintainers: [{name: A, email: a@example.com}]\n    instances:\n'
           '      publisher: {component: publisher, host: arm}\n'
           '      subscriber: {component: subscriber}\n'
           '    connections:\n      - {from: publisher.pMap, to: subscriber.rMap}\n')
    (tmp_path / 'src' / 'arm_system').mkdir(parents=True)
    (tmp_path / 'src' / 'arm_system' / 'robmosys.yaml').write_text(arm)
    result = _load(tmp_path, FLEET.replace('pubsub_system, host: robot2',
                                           'arm_system, host: robot2'))
    system = result.workspace.model('fleet')
    assert {i.name: i.host for i in system.instances if i.name.startswith('robot2.')} == {
        'robot2.publisher': 'arm', 'robot2.subscriber': 'robot2'}


def test_an_instance_named_after_the_launch_files_of_a_subsystem_host_is_an_error(tmp_path):
    src = tmp_path / 'src'
    for package in ('simple_msgs', 'publisher', 'subscriber', 'pubsub_system'):
        shutil.copytree(TEST_WORKSPACE / 'src' / package, src / package)
    (src / 'fleet').mkdir()
    (src / 'fleet' / 'robmosys.yaml').write_text(FLEET.replace('watcher:', 'on_robot2:')
                                                 .replace('watcher.rMap', 'on_robot2.rMap'))
    result = load_workspace(find_model_files([src]), InterfaceIndex([Path(sys.prefix)]))
    assert [d.message for d in result.errors] == [
        "instance name 'on_robot2' is the name of the launch files of the host 'robot2'"]


def test_the_system_package_starts_every_node_under_its_name(tmp_path):
    result = _load(tmp_path)
    plan = plan_system(result.workspace.model('two_robots'), result.workspace)
    nodes = {n.instance: (n.fqn, n.name, dict(n.remappings)) for n in plan.nodes}
    assert nodes == {
        'watcher': ('/ops/watcher', 'watcher', {'rMap': '/robot1/publisher/pMap'}),
        'robot1.publisher': ('/robot1/publisher', 'publisher',
                             {'pMap': '/robot1/publisher/pMap'}),
        'robot1.subscriber': ('/robot1/subscriber', 'subscriber',
                              {'rMap': '/robot1/publisher/pMap'}),
        'robot2.publisher': ('/fleet/robot2/publisher', 'publisher',
                             {'pMap': '/fleet/robot2/publisher/pMap'}),
        'robot2.subscriber': ('/fleet/robot2/subscriber', 'subscriber',
                              {'rMap': '/fleet/robot2/publisher/pMap'}),
        'flat.publisher': ('/publisher', 'publisher', {'pMap': '/publisher/pMap'}),
        'flat.subscriber': ('/subscriber', 'subscriber', {'rMap': '/publisher/pMap'}),
    }
    out = tmp_path / 'out'
    generate_package(plan_package(result.workspace, 'two_robots'), out)
    params = yaml.safe_load((out / 'cfg' / 'params.yaml').read_text())
    assert set(params) == {'/robot1/publisher', '/fleet/robot2/publisher', '/publisher'}
    package_xml = (out / 'package.xml').read_text()
    assert '<exec_depend>publisher</exec_depend>' in package_xml
    assert '<exec_depend>subscriber</exec_depend>' in package_xml
    # the manager knows each instance by its name in the system, and its node
    description = json.loads((out / 'bringup.json').read_text())
    watcher = next(i for i in description['instances'] if i['instance'] == 'watcher')
    assert watcher['after'] == ['robot1.publisher']
    assert {(i['instance'], i['fqn']) for i in description['instances']} == {
        (instance, fqn) for instance, (fqn, _, _) in nodes.items()}
    launch = (out / 'launch' / 'two_robots.robot2.publisher.launch.py').read_text()
    # in the namespace the launch argument 'namespace' moves the system to
    assert "name='publisher'" in launch and "namespace=arguments.moved('/fleet/robot2')" \
        in launch


@pytest.mark.integration
@requires_ros
def test_fleet_system_runs_two_robots_and_a_watcher(test_workspace_built):
    """test_workspace's fleet_system: pubsub_system in /robot1 and /robot2."""
    bringup = test_workspace_built.install / 'fleet_system' / 'lib' / 'fleet_system' / 'bringup'
    with background([sys.executable, str(bringup)],
                    env=test_workspace_built.env(free_domain_id()), stop_timeout=30) as running:
        assert wait_until(lambda: 'bringup: 5 of 5 managed instances active' in
                          running.output(), timeout=120), running.output()
        assert wait_until(lambda: all(
            f'[{node}]: got map data' in running.output()
            for node in ('robot1.subscriber', 'robot2.subscriber', 'watcher')),
            timeout=30), running.output()
