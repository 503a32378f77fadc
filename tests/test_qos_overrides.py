# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""An instance overrides the QoS of its ports: the checks and cfg/params.yaml.

The connections of a system are checked with the QoS its instances give their
ports, and the system's parameter file carries them as ROS 2's own
``qos_overrides.<topic>.<publisher|subscription>.<policy>`` parameters of the
instance's node (tests/test_qos_launch.py runs them). The broken cases are in
tests/models/invalid/system_qos_override_*.yaml.
"""

from __future__ import annotations

from pathlib import Path
import re

import pytest
import yaml

from colcon_robmosys.check import load_workspace
from colcon_robmosys.generators import generate_package, plan_package
from colcon_robmosys.mapping.qos import resolve_qos
from colcon_robmosys.mapping.system import plan_system
from colcon_robmosys.model.types import Component, System
from harness.fake_ament import fake_ament_index

VALID = sorted((Path(__file__).parent / 'models' / 'valid').glob('*.yaml'))

COMPONENTS = """\
robmosys: 1
defaults:
  license: Apache-2.0
  maintainers: [{name: A, email: a@example.com}]
components:
  - name: Camera
    package: cam
    language: python
    ports:
      pImage: {pattern: push, role: provided, type: std_msgs/msg/Header,
               qos: {reliability: best_effort}}
  - name: Recorder
    package: rec
    language: cpp
    ports:
      rImage: {pattern: push, role: required, type: std_msgs/msg/Header}
"""


def _system(package: str, body: str) -> str:
    """Return the model of a system: its package, then its body."""
    return ('robmosys: 1\nsystems:\n'
            f'  - package: {package}\n'
            '    license: Apache-2.0\n'
            '    maintainers: [{name: A, email: a@example.com}]\n' + body)


#: The components' own QoS do not match; the camera's override makes them.
ROBOT = _system('robot', """\
    instances:
      camera: {component: cam, qos: {pImage: {reliability: reliable, deadline: 0.25}}}
      recorder: {component: rec, qos: {rImage: {depth: 1}}}
    connections:
      - {from: camera.pImage, to: recorder.rImage}
""")


@pytest.fixture(scope='module')
def index(tmp_path_factory):
    return fake_ament_index(tmp_path_factory.mktemp('ament_prefix'))


def _load(tmp_path: Path, index, **models: str):
    paths = []
    for name, text in {'components': COMPONENTS, **models}.items():
        (tmp_path / name).mkdir(parents=True)
        paths.append(tmp_path / name / 'robmosys.yaml')
        paths[-1].write_text(text)
    return load_workspace(paths, index)


def _params(system: System, workspace) -> dict[str, dict]:
    return {n.fqn: dict(n.values) for n in plan_system(system, workspace).params}


def test_the_instance_s_qos_is_the_component_s_overridden(index):
    workspace = load_workspace(VALID, index).workspace
    system = workspace.model('demo_system')
    talker = workspace.model('demo_talker')
    assert isinstance(system, System) and isinstance(talker, Component)
    instance = system.instance('talker')
    port = talker.port('pGrid')
    # sensor_data, depth 3 in the component; depth 10, reliable in the system
    base, overridden = resolve_qos(port.qos), resolve_qos(instance.qos_of('pGrid', port.qos))
    assert (base.depth, base.reliability) == (3, 'best_effort')
    assert (overridden.depth, overridden.reliability) == (10, 'reliable')
    # the other ports, and the other instances of the component, keep theirs
    assert instance.qos_of('sLog', talker.port('sLog').qos) == talker.port('sLog').qos
    assert system.instance('listener').qos == ()


def test_the_parameter_file_holds_ros_2_s_qos_overrides(index):
    workspace = load_workspace(VALID, index).workspace
    params = _params(workspace.model('demo_system'), workspace)
    # a connected port: its remapped name; the node's own parameters stay
    talker = params['/robot1/talker']
    assert talker['qos_overrides./robot1/talker/pGrid.publisher.depth'] == 10
    assert talker['qos_overrides./robot1/talker/pGrid.publisher.reliability'] == 'reliable'
    assert talker['rate'] == 20
    # an unconnected port keeps its own name, in the node's namespace;
    # keep_all, and the deadline in nanoseconds as ROS 2 reads it
    spare = params['/robot2/arm/spare']
    assert {k: v for k, v in spare.items() if k.startswith('qos')} == {
        'qos_overrides./robot2/arm/rGrid.subscription.history': 'keep_all',
        'qos_overrides./robot2/arm/rGrid.subscription.deadline': 500_000_000}


def test_an_override_can_make_a_connection_that_the_components_could_not(tmp_path, index):
    result = _load(tmp_path, index, robot=ROBOT)
    assert result.errors == []
    params = _params(result.workspace.model('robot'), result.workspace)
    assert params == {
        '/camera': {'qos_overrides./camera/pImage.publisher.reliability': 'reliable',
                    'qos_overrides./camera/pImage.publisher.deadline': 250_000_000},
        # a C++ instance: the same parameters (rclcpp's QosOverridingOptions)
        '/recorder': {'qos_overrides./camera/pImage.subscription.depth': 1}}


def test_the_generated_parameter_file_reads_back_as_the_overrides(tmp_path, index):
    result = _load(tmp_path, index, robot=ROBOT)
    out = tmp_path / 'out'
    generate_package(plan_package(result.workspace, 'robot'), out)
    params = yaml.safe_load((out / 'cfg' / 'params.yaml').read_text())
    assert params['/camera']['ros__parameters'] == {
        'qos_overrides./camera/pImage.publisher.reliability': 'reliable',
        'qos_overrides./camera/pImage.publisher.deadline': 250_000_000}


def test_a_subsystem_s_override_moves_with_it_and_is_reported_once(tmp_path, index):
    fleet = _system('fleet', '    subsystems:\n      robot1: {system: robot}\n')
    result = _load(tmp_path, index, robot=ROBOT, fleet=fleet)
    assert result.errors == []
    params = _params(result.workspace.model('fleet'), result.workspace)
    assert params['/robot1/recorder'] == {
        'qos_overrides./robot1/camera/pImage.subscription.depth': 1}
    # an override that breaks the connection: one message, in the subsystem's file
    broken = ROBOT.replace('depth: 1', 'durability: transient_local')
    result = _load(tmp_path / 'broken', index, robot=broken, fleet=fleet)
    assert [(Path(d.location.path).parent.name, d.location.line, d.message)
            for d in result.errors] == [
        ('robot', 8, "incompatible QoS between 'pImage' (writer) and 'rImage' (reader): a "
         'transient-local reader cannot receive from a volatile writer (with the QoS '
         "instance 'recorder' gives 'rImage' here; the connection is at line 10)")]


def test_the_documented_override_is_what_the_parameter_file_holds(tmp_path, index):
    docs = (Path(__file__).resolve().parent.parent / 'docs' / 'model-format.md').read_text()
    blocks = re.findall(r'^```yaml\n(.*?)^```', docs, re.MULTILINE | re.DOTALL)
    # (a model may start with the modeline that names its schema)
    models = [b for b in blocks if re.match(r'(#.*\n)*robmosys: 1\n', b) and 'grid_' in b][:4]
    override = next(yaml.safe_load(b) for b in blocks if 'rGrid: {reliability' in b)
    expected = next(yaml.safe_load(b) for b in blocks if b.startswith('# cfg/params.yaml'))
    system = yaml.safe_load(models[3])
    system['systems'][0]['instances']['monitor'].update(override['instances']['monitor'])
    models[3] = yaml.safe_dump(system)
    result = _load(tmp_path, index, **{f'm{i}': text for i, text in enumerate(models)})
    assert [str(d) for d in result.errors] == []
    out = tmp_path / 'out'
    generate_package(plan_package(result.workspace, 'grid_system'), out)
    params = yaml.safe_load((out / 'cfg' / 'params.yaml').read_text())
    assert params['/ops/monitor'] == expected['/ops/monitor']
