# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The dummy_robot example, built by colcon and brought up on real ROS 2.

The nodes are started as the generated launch.py says (executables, names,
namespaces, remappings, parameter file), activated through their lifecycle
services in the order activate.py follows, and every connection of the system
model is seen carrying data, with the values the parameter overrides set.
Two systems are brought up so: dummy_robot_bringup (Python components) and
dummy_robot_cpp_bringup (the C++ components cpp_dummy_* with the Python
monitor), which needs rclcpp and skips with the reason where it is missing.
"""

from __future__ import annotations

import contextlib
import json
from pathlib import Path
import sys

import pytest
from test_cpp_system import requires_rclcpp

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.devtools.ros_env import background
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from colcon_robmosys.model.types import Component, Instance, Language, System
from conftest import requires_ros, TEST_WORKSPACE
from harness.launch_files import activation_waves, nodes_launch_file, read_launch_file

pytestmark = [pytest.mark.integration, requires_ros]

SYSTEM = 'dummy_robot_bringup'
CPP_SYSTEM = 'dummy_robot_cpp_bringup'


def _model(package: str = SYSTEM) -> tuple[System, dict[str, Component]]:
    result = load_workspace(find_model_files([TEST_WORKSPACE / 'src']),
                            InterfaceIndex([Path(sys.prefix)]))
    result.raise_errors()
    system = result.workspace.model(package)
    assert isinstance(system, System)
    components = {}
    for instance in system.instances:
        component = result.workspace.model(instance.component)
        assert isinstance(component, Component)
        components[instance.name] = component
    return system, components


def effective_parameters(instance: Instance, component: Component) -> dict[str, object]:
    """Return the values a node of the instance should run with."""
    values = {p.name: p.default for p in component.parameters}
    values.update(instance.parameters)
    for parameter in component.parameters:
        if parameter.type == 'double':
            values[parameter.name] = float(values[parameter.name])
        elif parameter.type.endswith('[]'):
            values[parameter.name] = list(values[parameter.name])
    return values


def expected_report(component: Component, values: dict[str, object]) -> str:
    """Return the line a monitor logs for what an instance publishes.

    The C++ components (cpp_dummy_*) publish what the Python ones do.
    """
    package = component.package.removeprefix('cpp_')
    if package == 'dummy_map_server':
        width, height = values['width'], values['height']
        occupied = 2 * width + 2 * (height - 2)
        return (f"map in {values['frame_id']}: {width} x {height} cells of "
                f"{values['resolution']:.2f} m, {occupied} occupied")
    if package == 'dummy_laser':
        return f"scan from {values['frame_id']}: {values['samples']} ranges"
    assert package == 'dummy_joint_states', component.package
    return f"joint states of {','.join(values['joint_names'])}"


@pytest.mark.parametrize('package', [
    SYSTEM, pytest.param(CPP_SYSTEM, marks=requires_rclcpp)])
def test_dummy_robot_comes_up_in_order_and_every_connection_carries_data(
        test_workspace_built, domain_id, package):
    system, components = _model(package)
    if package == CPP_SYSTEM:
        assert {c.language for c in components.values()} == {Language.CPP, Language.PYTHON}
        assert {c.package for c in components.values()} == {
            'cpp_dummy_map_server', 'cpp_dummy_joint_states', 'cpp_dummy_laser',
            'dummy_robot_monitor'}
    share = test_workspace_built.share(package)
    nodes = {n.name: n for n in read_launch_file(nodes_launch_file(share), share)}
    assert set(nodes) == {i.name for i in system.instances}
    # what the system manager brings up (bringup.json), and in which order
    description = json.loads((share / 'bringup.json').read_text(encoding='utf-8'))
    order = {i['instance']: i['after'] for i in description['instances'] if i['managed']}
    # the map server comes first, the unmanaged spare laser not at all
    assert order['map_server'] == [] and 'laser_spare' not in order
    assert all('map_server' in after for name, after in order.items() if name != 'map_server')
    env = test_workspace_built.env(domain_id)
    install = test_workspace_built.install

    with contextlib.ExitStack() as stack:
        processes = {name: stack.enter_context(background(node.command(install), env=env))
                     for name, node in nodes.items()}
        driver = stack.enter_context(LifecycleDriver(domain_id))

        def output(name: str) -> str:
            return processes[name].output()

        for name, node in nodes.items():
            assert driver.state(node.fqn) == 'unconfigured', output(name)

        # the parameter file of the system reached every node
        for instance in system.instances:
            if instance.parameters:
                names = [n for n, _ in instance.parameters]
                expected = effective_parameters(instance, components[instance.name])
                assert driver.parameters(nodes[instance.name].fqn, names) == \
                    {n: expected[n] for n in names}, instance.name

        for name in order:
            assert driver.transition(nodes[name].fqn, 'configure'), output(name)
        # the manager's order: each instance once those it comes after are active
        for wave in activation_waves(order):
            for name in wave:
                for before in order[name]:
                    assert driver.state(nodes[before].fqn) == 'active'
                assert driver.transition(nodes[name].fqn, 'activate'), output(name)
        assert driver.state(nodes['laser_spare'].fqn) == 'unconfigured'

        # every connection of the model carries data, with the overridden values
        wanted = {}
        for connection in system.connections:
            ends = (connection.source, connection.target)
            provider, consumer = sorted(
                (e.instance for e in ends),
                key=lambda i: components[i].package == 'dummy_robot_monitor')
            instance = system.instance(provider)
            values = effective_parameters(instance, components[provider])
            wanted[(provider, consumer)] = expected_report(components[provider], values)
        assert len(wanted) == len(system.connections) == 8

        def seen() -> set[tuple[str, str]]:
            return {k for k, line in wanted.items() if line in output(k[1])}

        assert wait_until(lambda: seen() == set(wanted), timeout=30), \
            (set(wanted) - seen(), {n: output(n)[-2000:] for n in ('monitor', 'monitor_ops')})
        # overrides in the data: a map of 40 x 30 at 0.25 m, 180 rear samples
        assert 'map in world: 40 x 30 cells of 0.25 m, 136 occupied' in output('monitor')
        assert 'scan from laser_rear: 180 ranges' in output('monitor_ops')
        # the unmanaged laser published nothing: its default frame never shows
        assert 'single_rrbot_hokuyo_laser' not in output('monitor') + output('monitor_ops')
