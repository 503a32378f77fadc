# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Valid models load into the typed model they describe.

``tests/models/valid`` is one workspace: a service definition, two components
that use it and a system of them, plus a file of several models that share
``defaults``. The example workspace ``test_workspace/src`` is another.
"""

from __future__ import annotations

from pathlib import Path
import re

import pytest

from colcon_robmosys.check import load_model_file, load_workspace
from colcon_robmosys.mapping.qos import resolve_qos, ResolvedQoS
from colcon_robmosys.model.types import (
    Component, InterfaceKind, InterfaceRef, Language, Maintainer,
    ParameterRange, Pattern, Role, ServiceDefinition, Structure, System,
    Workspace)
from harness.fake_ament import EXAMPLE_EXTRA, fake_ament_index

ROOT = Path(__file__).resolve().parent.parent
VALID = sorted((ROOT / 'tests' / 'models' / 'valid').glob('*.yaml'))
EXAMPLES = sorted((ROOT / 'test_workspace' / 'src').glob('*/robmosys.yaml'))
DOCS = ROOT / 'docs' / 'model-format.md'


@pytest.fixture(scope='module')
def loaded(tmp_path_factory):
    """Return the load result of the valid corpus, as one workspace."""
    index = fake_ament_index(tmp_path_factory.mktemp('ament_prefix'))
    return load_workspace(VALID, index)


@pytest.fixture(scope='module')
def workspace(loaded) -> Workspace:
    assert loaded.errors == []
    return loaded.workspace


def _model(workspace: Workspace, package: str, kind: type):
    model = workspace.model(package)
    assert isinstance(model, kind)
    return model


def _line(model_file: Path, text: str) -> int:
    """Return the number of the first line of the file holding the text."""
    lines = model_file.read_text().splitlines()
    return next(i for i, line in enumerate(lines, 1) if text in line)


# every file ---------------------------------------------------------------

@pytest.mark.parametrize('path', VALID, ids=[p.stem for p in VALID])
def test_valid_file_alone(path: Path):
    """Each file is valid on its own (cross-file checks aside)."""
    assert load_model_file(path).models


@pytest.mark.parametrize('path', VALID, ids=[p.stem for p in VALID])
def test_valid_file_in_workspace(path: Path, loaded):
    assert loaded.errors_of(str(path)) == []
    assert str(path) not in loaded.broken_files


def test_only_warnings_are_the_unconnected_spare_ports(loaded):
    system = VALID[0].parent / 'system.yaml'
    line = _line(system, 'spare:')
    assert [(d.severity, d.location.path, d.location.line, d.message)
            for d in loaded.diagnostics] == [
        ('warning', str(system), line,
         f"required port 'spare.{port}' is not connected")
        for port in ('aExplore', 'eAlarm', 'qGetCell', 'rGrid', 'sInbox')]


# service definitions ------------------------------------------------------

def _fields(structure: Structure) -> dict[str, tuple[str, object]]:
    return {f.name: (str(f.type), f.default) for f in structure.fields}


def test_service_definition_package(workspace):
    msgs = _model(workspace, 'demo_msgs', ServiceDefinition)
    info = msgs.info
    assert info.description == 'Interfaces of the demo components.'
    assert info.version == '1.2.3'
    assert info.license == 'Apache-2.0'
    assert info.maintainers == (Maintainer('Demo Team', 'demo@example.com'),)
    assert info.depends == ('builtin_interfaces',)
    assert info.model_file == str(VALID[0].parent / 'service_definition.yaml')
    assert [o.name for o in msgs.communication_objects] == ['Cell', 'Grid']
    assert [q.name for q in msgs.queries] == ['GetCell']
    assert [a.name for a in msgs.actions] == ['Explore']
    assert [e.name for e in msgs.events] == ['Alarm']


def test_fields_types_and_defaults(workspace):
    msgs = _model(workspace, 'demo_msgs', ServiceDefinition)
    grid = msgs.communication_objects[1]
    assert grid.structure.description == 'An occupancy grid.'
    assert _fields(grid.structure) == {
        'header': ('std_msgs/Header', None),
        'origin': ('geometry_msgs/Pose', None),
        'name': ('string<=32', 'grid'),
        'resolution': ('float32', 0.05),
        'visible': ('bool', True),
        'cells': ('demo_msgs/Cell[]', None),
        'corners': ('demo_msgs/Cell[4]', None),
        'data': ('int8[]', None),
        'tags': ('string<=8[<=4]', None),
        'offset': ('float64[3]', [0.0, 0.5, 1]),
        'levels': ('uint8[<=3]', [1, 255]),
        'label': ('wstring', ''),
    }
    by_name = {f.name: f for f in grid.structure.fields}
    # a type without package is one of the same service definition
    assert by_name['cells'].type.message == InterfaceRef(
        'demo_msgs', InterfaceKind.MSG, 'Cell')
    assert by_name['origin'].type.message == InterfaceRef(
        'geometry_msgs', InterfaceKind.MSG, 'Pose')
    assert (by_name['cells'].type.array, by_name['cells'].type.array_size) \
        == ('dynamic', None)
    assert (by_name['corners'].type.array,
            by_name['corners'].type.array_size) == ('fixed', 4)
    tags = by_name['tags'].type
    assert (tags.primitive, tags.string_bound, tags.array, tags.array_size) \
        == ('string', 8, 'bounded', 4)
    assert by_name['name'].comment == 'A short name.'
    path = VALID[0].parent / 'service_definition.yaml'
    assert by_name['name'].location.line == _line(path, 'name: {type:')


def test_constants(workspace):
    msgs = _model(workspace, 'demo_msgs', ServiceDefinition)
    grid = msgs.communication_objects[1]
    assert [(c.name, str(c.type), c.value, c.comment)
            for c in grid.structure.constants] == [
        ('FREE', 'int8', 0, 'A free cell.'),
        ('OCCUPIED', 'int8', 100, ''),
        ('FRAME_ID', 'string', 'map', ''),
        ('MAX_RANGE', 'float64', 12.5, ''),
    ]


def test_query_and_action(workspace):
    msgs = _model(workspace, 'demo_msgs', ServiceDefinition)
    query = msgs.queries[0]
    assert query.description == 'Look a cell up.'
    assert _fields(query.request) == {'x': ('int32', None),
                                      'y': ('int32', None)}
    assert [(c.name, c.value) for c in query.request.constants] == [
        ('ANY', -1)]
    assert _fields(query.answer) == {'value': ('int8', -1),
                                     'found': ('bool', None)}
    action = msgs.actions[0]
    assert action.description == 'Explore an area.'
    assert _fields(action.goal) == {'area': ('demo_msgs/Cell[<=16]', None)}
    assert _fields(action.result) == {'map': ('demo_msgs/Grid', None)}
    assert _fields(action.feedback) == {'progress': ('float32', 0.0)}
    event = msgs.events[0]
    assert event.description == 'A cell whose value crosses a threshold.'
    assert _fields(event.activation) == {'threshold': ('int8', None)}
    assert _fields(event.event) == {'cell': ('demo_msgs/Cell', None),
                                    'value': ('int8', None)}


# components ---------------------------------------------------------------

def test_component_package(workspace):
    talker = _model(workspace, 'demo_talker', Component)
    assert talker.name == 'Talker'
    assert talker.language is Language.PYTHON
    assert talker.info.license == 'BSD-3-Clause'
    assert talker.info.version == '0.1.0'
    assert [m.email for m in talker.info.maintainers] == [
        'demo@example.com', 'second@example.org']
    assert talker.info.depends == ('std_msgs',)
    listener = _model(workspace, 'demo_listener', Component)
    assert listener.language is Language.CPP
    # no description: one is made up for package.xml
    assert listener.info.description == \
        'The component demo_listener, generated from a RobMoSys model.'


def test_ports_of_every_pattern_and_role(workspace):
    talker = _model(workspace, 'demo_talker', Component)
    assert [(p.name, p.pattern, p.role, str(p.type)) for p in talker.ports] == [
        ('pGrid', Pattern.PUSH, Role.PROVIDED, 'demo_msgs/msg/Grid'),
        ('rCommand', Pattern.PUSH, Role.REQUIRED, 'std_msgs/msg/String'),
        ('sLog', Pattern.SEND, Role.REQUIRED, 'std_msgs/msg/String'),
        ('sInbox', Pattern.SEND, Role.PROVIDED, 'demo_msgs/msg/Cell'),
        ('qGetCell', Pattern.QUERY, Role.PROVIDED, 'demo_msgs/srv/GetCell'),
        ('qAdd', Pattern.QUERY, Role.REQUIRED,
         'example_interfaces/srv/AddTwoInts'),
        # an event is an action of its service definition
        ('eAlarm', Pattern.EVENT, Role.PROVIDED, 'demo_msgs/action/Alarm'),
        ('eObstacle', Pattern.EVENT, Role.REQUIRED, 'demo_msgs/action/Alarm'),
        ('aExplore', Pattern.ACTION, Role.PROVIDED,
         'demo_msgs/action/Explore'),
        # pkg/Type takes the kind of interface the pattern exchanges
        ('aFibonacci', Pattern.ACTION, Role.REQUIRED,
         'example_interfaces/action/Fibonacci'),
    ]
    assert talker.port('pGrid').description == \
        'The grid, published every period.'
    assert talker.port('nothing') is None


def test_qos_resolved(workspace):
    talker = _model(workspace, 'demo_talker', Component)
    qos = {p.name: resolve_qos(p.qos) for p in talker.ports}
    # a profile, one policy overridden
    assert qos['pGrid'] == ResolvedQoS(
        'keep_last', 3, 'best_effort', 'volatile', None, None, 'automatic',
        None)
    assert qos['rCommand'] == ResolvedQoS(
        'keep_last', 5, 'reliable', 'transient_local', None, None,
        'automatic', None)
    # nothing given: the rclpy default profile
    assert qos['sLog'] == ResolvedQoS(
        'keep_last', 10, 'reliable', 'volatile', None, None, 'automatic',
        None)
    assert (qos['sInbox'].history, qos['sInbox'].deadline,
            qos['sInbox'].lifespan, qos['sInbox'].liveliness,
            qos['sInbox'].liveliness_lease_duration) == (
        'keep_all', 0.5, 2, 'automatic', 1.5)
    assert qos['eObstacle'].adaptive
    assert talker.port('pGrid').qos.profile == 'sensor_data'
    assert talker.port('pGrid').qos.reliability is None


def test_activities(workspace):
    talker = _model(workspace, 'demo_talker', Component)
    assert [(a.name, a.period, a.trigger, a.functions)
            for a in talker.activities] == [
        ('Periodic', 0.1, None, ('fTick', 'fPublish')),
        ('OnCommand', None, 'rCommand', ('fCommand',)),
        ('OnInbox', None, 'sInbox', ('fInbox',)),
        ('OnGetCell', None, 'qGetCell', ('fAnswer',)),
        ('OnObstacle', None, 'eObstacle', ('fObstacle',)),
        ('OnExplore', None, 'aExplore', ('fExplore',)),
        ('OnSum', None, 'qAdd', ('fSum',)),
        ('OnFibonacci', None, 'aFibonacci', ('fFibonacci',)),
    ]
    assert talker.activities[0].description == 'The main loop.'


def test_functions_and_lifecycle(workspace):
    talker = _model(workspace, 'demo_talker', Component)
    functions = {f.name: f for f in talker.functions}
    assert functions['fPublish'].code == (
        'grid = Grid()\n'
        "grid.name = 'demo'\n"
        "if self.get_parameter('verbose').value:\n"
        "    self.get_logger().info('publishing')\n"
        'self.pGrid.publish(grid)\n')
    assert functions['fPublish'].description == 'Publish the grid.'
    assert functions['fConfigure'].code == 'self.count = 0'
    assert functions['fCommand'].description == 'Handle a command.'
    # functions without code are the user's to write
    assert 'fPublish' not in {f.name for f in talker.user_functions}
    assert {'fTick', 'fCommand', 'fInbox'} <= {
        f.name for f in talker.user_functions}
    assert talker.lifecycle == (
        ('on_configure', ('fConfigure',)),
        ('on_activate', ('fActivate', 'fTick')),
        ('on_deactivate', ('fDeactivate',)),
        ('on_cleanup', ('fCleanup',)),
        ('on_shutdown', ('fShutdown',)),
        ('on_error', ('fError',)),
    )
    listener = _model(workspace, 'demo_listener', Component)
    assert listener.lifecycle == ()
    # C++ code is kept as it is written
    assert listener.functions[0].code == (
        'RCLCPP_INFO(get_logger(), "grid %s", commobj.name.c_str());\n')


def test_parameters_of_every_type(workspace):
    talker = _model(workspace, 'demo_talker', Component)
    assert [(p.name, p.type, p.default, p.read_only, p.range)
            for p in talker.parameters] == [
        ('verbose', 'bool', True, False, None),
        ('rate', 'int', 10, False, ParameterRange(1, 100, 1)),
        # a double keeps its values as floats, a range without step has 0
        ('gain', 'double', 1.0, False, ParameterRange(0.0, 2.5, 0)),
        ('frame', 'string', 'map', True, None),
        ('flags', 'bool[]', (True, False), False, None),
        ('ids', 'int[]', (1, 2, 3), False, None),
        ('weights', 'double[]', (0.5, 1.0), False, None),
        ('names', 'string[]', ('a', 'b'), False, None),
        ('key', 'byte[]', (0, 255), False, None),
        ('count', 'int', 0, False, None),
        # an integer default of a double is a float
        ('threshold', 'double', 0.0, False, None),
    ]
    # each has a default: none must be set by a system
    assert not any(p.required for p in talker.parameters)
    assert isinstance(talker.parameters[-1].default, float)
    gain = talker.parameters[2]
    assert isinstance(gain.default, float)
    assert isinstance(talker.parameters[6].default[1], float)
    assert talker.parameters[0].description == 'Log every grid.'


# systems ------------------------------------------------------------------

def test_instances(workspace):
    system = _model(workspace, 'demo_system', System)
    # no name: the package name in CamelCase
    assert system.name == 'DemoSystem'
    assert system.info.description == 'The talker and two listeners.'
    assert [(i.name, i.component, i.namespace, i.activate, i.after)
            for i in system.instances] == [
        ('talker', 'demo_talker', '/robot1', True, ()),
        ('listener', 'demo_listener', '/robot1', True, ('talker',)),
        ('spare', 'demo_listener', '/robot2/arm', False, ()),
    ]
    talker = system.instance('talker')
    assert talker.parameters == (
        ('rate', 20), ('gain', 2), ('frame', 'odom'),
        ('names', ['x', 'y', 'z']), ('verbose', False))
    assert system.instance('spare').parameters == (('retries', 10),)
    assert system.instance('listener').description == \
        'Listens to the talker.'
    path = VALID[0].parent / 'system.yaml'
    line = _line(path, 'parameters: {rate: 20')
    assert [(loc.line, loc.column) for loc in talker.parameter_locations] \
        == [(line, 22), (line, 32), (line, 41), (line, 54), (line, 72)]


def test_connections(workspace):
    system = _model(workspace, 'demo_system', System)
    assert [(str(c.source), str(c.target), c.topic)
            for c in system.connections] == [
        ('talker.pGrid', 'listener.rGrid', None),
        ('listener.pCommand', 'talker.rCommand', '/command'),
        ('talker.sLog', 'listener.sLog', 'log'),
        ('listener.sInbox', 'talker.sInbox', None),
        ('listener.qGetCell', 'talker.qGetCell', None),
        ('talker.qAdd', 'listener.qAdd', None),
        ('talker.eAlarm', 'listener.eAlarm', None),
        ('listener.eObstacle', 'talker.eObstacle', None),
        ('listener.aExplore', 'talker.aExplore', None),
        ('talker.aFibonacci', 'listener.aFibonacci', None),
    ]
    first = system.connections[0]
    path = VALID[0].parent / 'system.yaml'
    line = _line(path, '{from: talker.pGrid')
    assert (first.source.location.line, first.source.location.column,
            first.target.location.column) == (line, 16, 34)


def test_defaults_shared_by_the_models_of_a_file(workspace):
    msgs = _model(workspace, 'demo_multi_msgs', ServiceDefinition)
    node = _model(workspace, 'demo_multi_node', Component)
    system = _model(workspace, 'demo_multi_system', System)
    assert (msgs.info.version, msgs.info.license) == ('2.0.0', 'MIT')
    # a model's own keys win over the defaults
    assert (node.info.version, node.info.license) == ('2.1.0', 'MIT')
    assert (system.info.version, system.info.license) == \
        ('2.0.0', 'Apache-2.0')
    for model in (msgs, node, system):
        assert model.info.maintainers == (
            Maintainer('Multi Team', 'multi@example.com'),)
    assert system.name == 'Loopback'
    assert [(str(c.source), str(c.target)) for c in system.connections] == [
        ('first.pPing', 'second.rPing'), ('second.pPing', 'first.rPing')]
    model_file = next(f for f in workspace.files
                      if f.path.endswith('multi_model.yaml'))
    assert [m.package for m in model_file.models] == [
        'demo_multi_msgs', 'demo_multi_node', 'demo_multi_system']


# the example workspace ----------------------------------------------------

def test_example_workspace(tmp_path):
    result = load_workspace(EXAMPLES, fake_ament_index(tmp_path, EXAMPLE_EXTRA))
    assert result.diagnostics == []
    workspace = result.workspace
    assert sorted(m.package for m in workspace.models) == [
        'add_client', 'add_server', 'cpp_client', 'cpp_dummy_joint_states', 'cpp_dummy_laser',
        'cpp_dummy_map_server', 'cpp_level_sensor', 'cpp_level_watcher', 'cpp_publisher',
        'cpp_receiver', 'cpp_sender', 'cpp_server', 'cpp_subscriber', 'dummy_joint_states',
        'dummy_laser', 'dummy_map_server', 'dummy_robot_bringup', 'dummy_robot_cpp_bringup',
        'dummy_robot_monitor', 'example_msgs', 'examples_system', 'fibonacci_client',
        'fibonacci_server', 'fleet_system', 'handwritten_nodes', 'handwritten_nodes',
        'handwritten_system',
        'level_sensor', 'level_watcher', 'mixed_system', 'mode_arm_system',
        'mode_robot_system', 'mode_sensor', 'publisher', 'pubsub_system',
        'receiver', 'sender', 'simple_msgs', 'subscriber', 'text_relay']

    msgs = _model(workspace, 'simple_msgs', ServiceDefinition)
    ogm, map_ = msgs.communication_objects
    assert _fields(ogm.structure) == {
        'width': ('uint32', None), 'height': ('uint32', None),
        'resolution': ('float32', None), 'data': ('int8[]', None)}
    assert ogm.structure.fields[0].comment == 'Number of cells along x.'
    assert _fields(map_.structure) == {'ogm': ('simple_msgs/OGM', None)}

    publisher = _model(workspace, 'publisher', Component)
    assert publisher.name == 'PeriodicPublisher'
    port = publisher.port('pMap')
    assert (port.pattern, port.role, str(port.type)) == (
        Pattern.PUSH, Role.PROVIDED, 'simple_msgs/msg/Map')
    assert resolve_qos(port.qos) == ResolvedQoS(
        'keep_last', 1, 'reliable', 'volatile', None, None, 'automatic', None)
    assert [(a.name, a.period, a.functions) for a in publisher.activities] \
        == [('Activity1', 0.5, ('fPublishing',))]
    assert publisher.functions[0].code.splitlines()[0] == \
        'transMap = Map()'
    assert [(p.name, p.type, p.default) for p in publisher.parameters] == [
        ('indoor', 'bool', False), ('noOfScans', 'int', 0)]

    subscriber = _model(workspace, 'subscriber', Component)
    rmap = subscriber.port('rMap')
    assert resolve_qos(rmap.qos).reliability == 'best_effort'
    assert resolve_qos(rmap.qos).depth == 100
    assert [(a.trigger, a.functions) for a in subscriber.activities] == [
        ('rMap', ('fListening',))]
    assert [f.name for f in subscriber.user_functions] == ['fListening']

    system = _model(workspace, 'pubsub_system', System)
    assert system.name == 'PubSubSystem'
    assert [(i.name, i.component, i.parameters)
            for i in system.instances] == [
        ('publisher', 'publisher', (('indoor', True), ('noOfScans', 3))),
        ('subscriber', 'subscriber', ())]
    assert [(str(c.source), str(c.target), c.topic)
            for c in system.connections] == [
        ('publisher.pMap', 'subscriber.rMap', None)]


# the documentation ----------------------------------------------------------

def test_documented_models(tmp_path):
    """The complete models of docs/model-format.md load, without a warning."""
    # a model block starts with the schema's modeline (tests/test_schema_strict.py)
    blocks = re.findall(r'^```yaml\n((?:# yaml-language-server: [^\n]*\n)?robmosys: 1\n.*?)^```',
                        DOCS.read_text(), re.MULTILINE | re.DOTALL)
    assert len(blocks) >= 5
    paths = []
    for number, block in enumerate(blocks):
        path = tmp_path / 'src' / f'model{number}' / 'robmosys.yaml'
        path.parent.mkdir(parents=True)
        path.write_text(block)
        paths.append(path)
    result = load_workspace(paths, fake_ament_index(tmp_path / 'prefix'))
    assert [str(d) for d in result.diagnostics] == []
    assert {m.package for m in result.workspace.models} >= {
        'grid_interfaces', 'grid_publisher', 'grid_viewer', 'grid_system',
        'ping_interfaces', 'pinger', 'ping_system'}


# modes ----------------------------------------------------------------------

def test_modes_of_a_system(workspace):
    robot = _model(workspace, 'modes_robot', System)
    path = VALID[0].parent / 'system_modes.yaml'
    assert robot.initial_mode == 'docking'
    assert robot.initial_mode_location.line == _line(path, 'initial: docking')
    assert [m.name for m in robot.modes] == ['docking', 'cruising', 'mapping']
    docking = robot.mode('docking')
    assert docking.active == ('driver',)
    assert [(v.instance, v.values) for v in docking.parameters] == [
        ('driver', (('rate', 2), ('gain', 0.5)))]
    assert docking.subsystems == (('arm', 'stowed'),)
    assert docking.location.line == _line(path, 'docking:')
    assert docking.active_locations[0].line == _line(path, 'active: [driver]')
    assert _model(workspace, 'modes_arm', System).mode('stowed').description == \
        'Only the talker, slowly.'


def test_modes_reach_into_subsystems(workspace):
    """A mode's active instances and values, with those of its subsystems' modes."""
    from colcon_robmosys.model.modes import active_instances, mode_values
    systems = {m.package: m for m in workspace.models if isinstance(m, System)}
    robot = systems['modes_robot']
    assert {m.name: active_instances(robot, m, systems) for m in robot.modes} == {
        'docking': {'driver', 'arm.talker'},
        'cruising': {'driver', 'planner', 'arm.talker'},
        'mapping': {'planner', 'arm.talker', 'arm.listener'}}
    assert mode_values(robot, robot.mode('mapping'), systems) == {
        'planner': {'retries': 0}, 'arm.talker': {'rate': 50, 'names': ['x', 'y']},
        'arm.listener': {'retries': 5}}
