# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The generated system packages, read and compared with their system models.

Every system of test_workspace is generated (no build needed) and each launch,
activate and parameter file is checked against what the model says, with the
naming rules of docs/model-format.md written out again here, independently of
the generator.
"""

from __future__ import annotations

import ast
import json
from pathlib import Path
import re
import shutil
import sys

import pytest
import yaml

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.generators import generate_package
from colcon_robmosys.generators import plan_package
from colcon_robmosys.mapping.system import json_lines, plan_system
from colcon_robmosys.model.parameters import node_parameters
from colcon_robmosys.model.types import (
    Component, Instance, Pattern, PortRef, Role, System, Workspace)
from conftest import colcon, requires_ros, TEST_WORKSPACE
from harness.launch_files import activate_launch_file, read_activate_after, read_launch_file

#: What the launch files pass besides the node's identity (launch_ros API).
LAUNCH_EXTRA = {'output': 'screen'}


def _load(src: Path) -> Workspace:
    result = load_workspace(find_model_files([src]), InterfaceIndex([Path(sys.prefix)]))
    result.raise_errors()
    return result.workspace


WORKSPACE = _load(TEST_WORKSPACE / 'src')
SYSTEMS = sorted(m.package for m in WORKSPACE.models if isinstance(m, System))


def _system(package: str) -> System:
    system = WORKSPACE.model(package)
    assert isinstance(system, System)
    return system


def _component(system: System, instance: str) -> Component:
    found = system.instance(instance)
    assert found is not None
    component = WORKSPACE.model(found.component)
    assert isinstance(component, Component)
    return component


def expected_remappings(system: System) -> dict[str, set[tuple[str, str]]]:
    """Return instance -> (port, name) remappings, by the documented rules."""
    remappings: dict[str, set[tuple[str, str]]] = {i.name: set() for i in system.instances}
    for connection in system.connections:
        ends = connection.ends
        # a connection of one port to a name outside the model: named from that port
        provided = next((e for e in ends if _component(system, e.instance).port(e.port).role
                         is Role.PROVIDED), ends[0])
        namespace = system.instance(provided.instance).namespace.strip('/')
        prefix = f'/{namespace}' if namespace else ''
        if connection.topic is None:
            name = f'{prefix}/{system.instance(provided.instance).node_name}/{provided.port}'
        elif connection.topic.startswith('/'):
            name = connection.topic
        else:
            name = f'{prefix}/{connection.topic}'
        for end in ends:
            # an external node's port goes by the node's own name for it
            port = _component(system, end.instance).port(end.port)
            remappings[end.instance].add((port.node_name, name))
            # Jazzy remaps an action only through its services and topics
            if port.pattern in (Pattern.ACTION, Pattern.EVENT):
                remappings[end.instance].update(
                    (f'{port.node_name}/_action/{part}', f'{name}/_action/{part}')
                    for part in ('send_goal', 'cancel_goal', 'get_result', 'feedback',
                                 'status'))
    return remappings


@pytest.fixture(scope='module')
def generated(tmp_path_factory) -> Path:
    """Return the generated packages of test_workspace, one folder each."""
    out = tmp_path_factory.mktemp('generated')
    for model in WORKSPACE.generated_models:
        generate_package(plan_package(WORKSPACE, model.package), out / model.package)
    return out


def test_every_example_system_is_checked():
    assert SYSTEMS == ['dummy_robot_bringup', 'dummy_robot_cpp_bringup', 'examples_system',
                       'fleet_system', 'handwritten_system', 'mixed_system', 'mode_arm_system',
                       'mode_robot_system', 'pubsub_system']


def _launch_files(package: str) -> list[str]:
    """Return the launch files of a system package, named as ROS 2 names them."""
    system = _system(package)
    stems = [package] + [f'{package}.{instance.name}' for instance in system.instances]
    return [f'{package}/{stem}{kind}.launch.py' for stem in stems for kind in ('', '.nodes')]


def _aliases(package: str) -> dict[str, str]:
    """Return the launch files under their names of the last release, and what they include."""
    system = _system(package)
    aliases = {'launch.py': f'{package}.nodes.launch.py', 'activate.py': f'{package}.launch.py'}
    for instance in system.instances:
        aliases[f'launch.{instance.name}.py'] = f'{package}.{instance.name}.nodes.launch.py'
        aliases[f'activate.{instance.name}.py'] = f'{package}.{instance.name}.launch.py'
    return aliases


def _fqn(instance: Instance) -> str:
    """Return the full name of an instance's node."""
    return f'{instance.namespace}/{instance.node_name}'


def _instance_of(name: str) -> str | None:
    """Return the instance a launch file is for, or None for the whole system."""
    # <system>.<instance>[.nodes].launch.py; an instance of a subsystem is sub.instance
    parts = name.removesuffix('.launch.py').removesuffix('.nodes').split('.')
    return '.'.join(parts[1:]) or None


LAUNCH_FILES = [f for package in SYSTEMS for f in _launch_files(package)]


def test_the_launch_folder_holds_exactly_these_files(generated):
    for package in SYSTEMS:
        found = {f'{package}/{p.name}' for p in (generated / package / 'launch').iterdir()}
        assert found == set(_launch_files(package)) | {
            f'{package}/{alias}' for alias in _aliases(package)}


def test_the_names_of_the_last_release_include_the_new_files(generated):
    for package in SYSTEMS:
        for alias, target in _aliases(package).items():
            tree = ast.parse((generated / package / 'launch' / alias).read_text())
            strings = {n.value for n in ast.walk(tree) if isinstance(n, ast.Constant)}
            assert target in strings, alias
            assert f'{alias} is deprecated: use ' in strings


@pytest.mark.parametrize('launch_file', LAUNCH_FILES)
def test_launch_file_follows_the_system_model(generated, launch_file):
    package, name = launch_file.split('/')
    system = _system(package)
    share = generated / package
    nodes = read_launch_file(share / 'launch' / name, share)
    instance = _instance_of(name)
    wanted = [i for i in system.instances if instance in (None, i.name)]
    # nodes are told apart by their full names: a subsystem's keep their own names
    by_fqn = {_fqn(i): i for i in system.instances}
    assert sorted(n.fqn for n in nodes) == sorted(_fqn(i) for i in wanted)
    remappings = expected_remappings(system)
    for node in nodes:
        model = by_fqn[node.fqn]
        assert node.name == model.node_name
        component = _component(system, model.name)
        # an external component is package/executable
        assert node.package == model.component.split('/')[0]
        assert node.executable == component.executable_name
        assert node.namespace == model.namespace
        assert set(node.remappings) == remappings[model.name]
        assert len(node.remappings) == len(remappings[model.name]), 'a port remapped twice'
        assert node.params_files == (share / 'cfg' / 'params.yaml',)
        assert node.extra == {**LAUNCH_EXTRA, **({'respawn': True} if model.respawn else {})}


@pytest.mark.parametrize('launch_file', [f for f in LAUNCH_FILES if '.nodes.' not in f])
def test_activate_file_follows_the_activation_model(generated, launch_file):
    """<system>[.<instance>].launch.py manages the instances with activate: true, in order."""
    package, name = launch_file.split('/')
    system = _system(package)
    instance = _instance_of(name)
    if instance is None:
        # the system's own file: the system manager brings it up, from bringup.json
        source = (generated / package / 'launch' / name).read_text()
        assert "cmd=[arguments.bringup, '--attach', *arguments.manager]," in source
        description = json.loads((generated / package / 'bringup.json').read_text())
        activate_after = {i['instance']: i['after'] for i in description['instances']
                          if i['managed']}
    else:
        activate_after = read_activate_after(generated / package / 'launch' / name)
    # a plain external node cannot be managed: started only
    managed = [i for i in system.instances if i.activate and instance in (None, i.name)
               and _component(system, i.name).lifecycle_node]
    in_file = {i.name for i in managed}
    # a file waits only for the instances it activates itself
    assert activate_after == {i.name: [a for a in i.after if a in in_file] for i in managed}
    # the nodes are created in an order that respects 'after'
    by_fqn = {_fqn(i): i.name for i in system.instances}
    nodes = [by_fqn[n.fqn] for n in read_launch_file(generated / package / 'launch' / name,
                                                     generated / package)]
    for i in managed:
        assert all(nodes.index(a) < nodes.index(i.name) for a in activate_after[i.name])


@pytest.mark.parametrize('package', SYSTEMS)
def test_params_file_holds_the_overrides_by_node_name(generated, package):
    system = _system(package)
    params = yaml.safe_load((generated / package / 'cfg' / 'params.yaml').read_text())
    expected = {}
    for instance in system.instances:
        if instance.parameters:
            # by ROS 2 name: a mapped parameter once per entry of its array
            types = {n: p.type for n, p in node_parameters(
                _component(system, instance.name).parameters,
                dict(instance.parameters)).items()}
            values = {n: float(v) if types[n] == 'double' else
                      list(v) if isinstance(v, (list, tuple)) else v
                      for n, v in instance.parameters}
            expected[_fqn(instance)] = {'ros__parameters': values}
    # a system that sets none says so, in a file rcl still reads
    assert params == (expected or {'/**': {'ros__parameters': {}}})


@pytest.mark.parametrize('package', SYSTEMS)
def test_package_depends_on_every_component_it_launches(generated, package):
    from catkin_pkg.package import parse_package
    system = _system(package)
    xml = parse_package(generated / package / 'package.xml')
    exec_depends = {d.name for d in xml.exec_depends}
    components = {i.component.split('/')[0] for i in system.instances}
    assert components | {'launch', 'launch_ros', 'lifecycle_msgs', 'ament_index_python'} \
        <= exec_depends
    cmake = (generated / package / 'CMakeLists.txt').read_text()
    assert 'install(DIRECTORY launch cfg doc' in cmake


@pytest.mark.parametrize('package', SYSTEMS)
def test_diagram_shows_instances_ports_and_typed_connections(generated, package):
    system = _system(package)
    dot = (generated / package / 'doc' / f'{package}.dot').read_text()
    assert dot.count('{') == dot.count('}')
    for instance in system.instances:
        component = _component(system, instance.name)
        line = next(x for x in dot.splitlines() if x.startswith(f'  "{instance.name}" ['))
        assert _fqn(instance) in line
        for port in component.ports:
            assert f'<{port.name}> {port.name} ({port.role.value} {port.pattern.value})' in line
        assert ('style=dashed' in line) is (not instance.activate)
    # a name outside the model is a node of its own, without ports; an instance of a
    # subsystem is subsystem.instance
    edge = (r'^  "([\w/.]+)"(?::(\w+))? -> "([\w/.]+)"(?::(\w+))? '
            r'\[label="(\w+) ([\w/]+)\\n([\w/]+)"\];$')
    edges = re.findall(edge, dot, re.MULTILINE)
    assert len(edges) == len(system.connections)
    remappings = expected_remappings(system)
    for connection in system.connections:
        ends = connection.ends
        port = _component(system, ends[0].instance).port(ends[0].port)
        by_role = {_component(system, e.instance).port(e.port).role: e for e in ends}
        if connection.target is None:
            name = dict(remappings[ends[0].instance])[port.node_name]
            assert f'  "{name}" [shape=plaintext, label="{name}"];' in dot
            other = Role.REQUIRED if port.role is Role.PROVIDED else Role.PROVIDED
            by_role[other] = PortRef(name, '', connection.location)
        # arrows follow the data: to the server of send, query and action
        if port.pattern in (Pattern.SEND, Pattern.QUERY, Pattern.ACTION):
            source, target = by_role[Role.REQUIRED], by_role[Role.PROVIDED]
        else:
            source, target = by_role[Role.PROVIDED], by_role[Role.REQUIRED]
        named = source if source.port else target
        named_port = _component(system, named.instance).port(named.port)
        name = dict(remappings[named.instance])[named_port.node_name]
        assert (source.instance, source.port, target.instance, target.port,
                port.pattern.value, str(port.type), name) in edges


@pytest.mark.parametrize('package', SYSTEMS)
def test_svg_draws_every_instance_and_connection_in_their_host_and_subsystem(generated, package):
    """The drawing the manager's page shows too: laid out by the generator, no Graphviz."""
    import xml.etree.ElementTree as ElementTree
    system = _system(package)
    ns = {'svg': 'http://www.w3.org/2000/svg'}
    svg = ElementTree.parse(generated / package / 'doc' / f'{package}.svg').getroot()
    drawn = {g.get('data-instance'): g for g in svg.iterfind('svg:g[@class]', ns)
             if g.get('data-instance')}
    assert list(drawn) == [i.name for i in system.instances]
    for instance in system.instances:
        texts = [t.text for t in drawn[instance.name].iterfind('svg:text', ns)]
        assert texts[0] == _fqn(instance)
        ports = _component(system, instance.name).ports
        assert texts[2:] == [f'{p.name} ({p.role.value} {p.pattern.value})' for p in ports]
    lines = [g for g in svg.iterfind('svg:g', ns) if g.get('data-connection')]
    assert [int(g.get('data-connection')) for g in lines] == \
        list(range(len(system.connections)))
    description = json.loads((generated / package / 'bringup.json').read_text())
    for g, connection in zip(lines, description['connections']):
        assert g.get('data-name') == connection['name']
        assert g.find('svg:path', ns).get('d').startswith('M')
    groups = [g.find('svg:text', ns).text for g in svg.iterfind('svg:g', ns)
              if (g.get('class') or '').startswith('group ')]
    hosts = {i.host for i in system.instances}
    assert groups[0] == "the manager's host" if '' in hosts else groups[0].startswith('host ')
    assert {f'host {h}' for h in hosts if h} <= set(groups)
    assert {i.name.rpartition('.')[0] for i in system.instances} - {''} <= set(groups)


def test_activate_file_drives_the_managed_instances_by_their_node_names(generated):
    """An instance's launch file hands SystemActivation the instance and its order.

    What SystemActivation does with them (levels, failures reported with what
    they hold back, timeouts) is tested on rclpy with the runtime
    (robmosys_runtime/test/test_activation.py); the system's own file runs the
    manager, tested in tests/test_bringup.py.
    """
    source = activate_launch_file(generated / 'dummy_robot_bringup', 'monitor').read_text()
    tree = ast.parse(source)
    tables = {ast.unparse(n.targets[0]): ast.literal_eval(n.value) for n in tree.body
              if isinstance(n, ast.Assign)}
    system = _system('dummy_robot_bringup')
    managed = [i for i in system.instances if i.activate and i.name == 'monitor']
    assert tables['NODES'] == {i.name: _fqn(i) for i in managed}
    assert set(tables['ACTIVATE_AFTER']) == set(tables['NODES'])
    # moved into the namespace argument, if one is given
    assert 'SystemActivation(get_ros_node(context),\n' \
        '                                  SystemArguments.moved_nodes(context, NODES),\n' \
        '                                  ACTIVATE_AFTER' in source


# warnings -------------------------------------------------------------------

@pytest.fixture
def unwired(tmp_path) -> Path:
    """Return test_workspace with the dummy robot's ops monitor lacking its map."""
    shutil.copytree(TEST_WORKSPACE / 'src', tmp_path / 'src',
                    ignore=shutil.ignore_patterns('__pycache__'))
    model = tmp_path / 'src' / 'dummy_robot_bringup' / 'robmosys.yaml'
    text = model.read_text()
    assert '      - {from: map_server.map, to: monitor_ops.map}\n' in text
    model.write_text(text.replace('      - {from: map_server.map, to: monitor_ops.map}\n', ''))
    return tmp_path


def _warning_line(workspace: Path) -> str:
    model = workspace / 'src' / 'dummy_robot_bringup' / 'robmosys.yaml'
    line = model.read_text().splitlines().index('      monitor_ops:') + 1
    return f"{model}:{line}:7: warning: required port 'monitor_ops.map' is not connected"


def test_unconnected_required_port_is_a_warning_only(unwired):
    result = load_workspace(find_model_files([unwired / 'src']),
                            InterfaceIndex([Path(sys.prefix)]))
    assert result.errors == []
    assert [str(d) for d in result.diagnostics] == [_warning_line(unwired)]
    assert [str(d) for d in result.warnings_of('dummy_robot_bringup')] == \
        [_warning_line(unwired)]
    # an unconnected provided port (laser_spare.scan) is no warning; the
    # system is generated, the port left under its own name
    plan = plan_package(result.workspace, 'dummy_robot_bringup')
    nodes = {n.instance: n for n in plan.summary['nodes']}
    assert nodes['laser_spare'].remappings == ()
    assert ('map', '/dummy_robot/map_server/map') not in nodes['monitor_ops'].remappings


@requires_ros
def test_warnings_are_told_by_the_verb_and_the_build_without_failing(
        unwired, test_workspace_built):
    result = colcon(['robmosys-generate', '--validate-only'], cwd=unwired)
    assert result.returncode == 0, result.stderr
    assert result.stderr.splitlines().count(_warning_line(unwired)) == 1
    # the components it launches, built once for the session, and the runtime they use
    for package in {i.component for i in _system('dummy_robot_bringup').instances} | {
            'robmosys_runtime'}:
        shutil.copytree(test_workspace_built.install / package, unwired / 'install' / package,
                        symlinks=True)
    # like a compiler's warning: in the package's stderr, the build goes on
    result = colcon(['build', '--packages-select', 'dummy_robot_bringup',
                     '--event-handlers', 'console_cohesion+'], cwd=unwired, timeout=300)
    output = result.stdout + result.stderr
    assert result.returncode == 0, output
    assert f'--- stderr: dummy_robot_bringup\n{_warning_line(unwired)}\n---\n' in output
    assert '1 package had stderr output: dummy_robot_bringup' in output
    share = unwired / 'install' / 'dummy_robot_bringup' / 'share' / 'dummy_robot_bringup'
    assert activate_launch_file(share).is_file()
    assert (share / 'doc' / 'dummy_robot_bringup.dot').is_file()
    # laid out by the generator: no Graphviz needed
    assert (share / 'doc' / 'dummy_robot_bringup.svg').is_file()


# what the system manager reads ---------------------------------------------

def test_respawn_and_timeouts_of_the_model_reach_the_manager_and_the_launch_file(tmp_path):
    shutil.copytree(TEST_WORKSPACE / 'src' / 'examples_system', tmp_path / 'src' / 'system')
    for name in ('send_example', 'example_msgs'):
        shutil.copytree(TEST_WORKSPACE / 'src' / name, tmp_path / 'src' / name)
    model = tmp_path / 'src' / 'system' / 'robmosys.yaml'
    raw = yaml.safe_load(model.read_text())
    system = raw['systems'][0]
    system['instances'] = {
        'sender': {'component': 'sender', 'respawn': True},
        'receiver': {'component': 'receiver', 'timeout': 2.5}}
    system['connections'] = [c for c in system['connections'] if c['from'] == 'receiver.sText']
    model.write_text(yaml.safe_dump(raw))
    workspace = _load(tmp_path / 'src')
    out = tmp_path / 'out'
    generate_package(plan_package(workspace, 'examples_system'), out)
    description = json.loads((out / 'bringup.json').read_text())
    instances = {i['instance']: i for i in description['instances']}
    assert instances['sender']['respawn'] is True and instances['sender']['timeout'] is None
    assert instances['receiver']['respawn'] is False and instances['receiver']['timeout'] == 2.5
    # the smoke test's connections: the provided end names it; the watch names its line
    line = next(n for n, text in enumerate(model.read_text().splitlines(), 1)
                if 'from: receiver.sText' in text)
    # in the model's installed copy, at the model's own line: no path of this machine
    assert description['connections'] == [{
        'name': '/receiver/sText', 'entity': 'subscription',
        'type': 'example_msgs/msg/Text', 'from': 'receiver.sText', 'to': 'sender.sText',
        'location': f'share/examples_system/robmosys/robmosys.yaml:{line}:5'}]
    nodes = {n.name: n for n in read_launch_file(
        out / 'launch' / 'examples_system.nodes.launch.py', out)}
    assert nodes['sender'].extra == {**LAUNCH_EXTRA, 'respawn': True}
    assert nodes['receiver'].extra == LAUNCH_EXTRA


def test_a_system_on_two_hosts_has_launch_files_per_host(tmp_path):
    (tmp_path / 'src' / 'hosted').mkdir(parents=True)
    shutil.copy(Path(__file__).parent / 'models' / 'valid' / 'system_on_two_hosts.yaml',
                tmp_path / 'src' / 'hosted' / 'robmosys.yaml')
    workspace = _load(tmp_path / 'src')
    out = tmp_path / 'out'
    generate_package(plan_package(workspace, 'hosted_system'), out)
    launch = out / 'launch'
    names = {p.name for p in launch.iterdir()}
    assert {'hosted_system.on_robot.nodes.launch.py', 'hosted_system.on_robot.launch.py'} <= names
    # the files of hosts are new: no alias under the names of the last release
    assert not {n for n in names if 'on_robot' in n and not n.startswith('hosted_system.')}
    # the manager's files start the instances of no host, and activate every one; its
    # one Python instance in the shared process, as bringup runs it
    nodes_file = launch / 'hosted_system.nodes.launch.py'
    assert read_launch_file(nodes_file, out) == []
    assert re.search(r"'robmosys_runtime\.hosting\.container',\s+arguments\.description, "
                     r"arguments\.params_file,\s+'planner',", nodes_file.read_text())
    assert "cmd=[arguments.bringup, '--attach'," in \
        (launch / 'hosted_system.launch.py').read_text()
    assert read_activate_after(launch / 'hosted_system.on_robot.launch.py') == {'arm': []}
    assert [n.name for n in read_launch_file(
        launch / 'hosted_system.on_robot.nodes.launch.py', out)] == ['arm']
    description = json.loads((out / 'bringup.json').read_text())
    assert description['processes'] == 'shared'
    instances = {i['instance']: i for i in description['instances']}
    assert instances['arm']['host'] == 'robot' and instances['planner']['host'] == ''
    assert instances['arm']['python_class'] == 'single_component.Single:Single'


def test_the_description_holds_what_the_conformance_watch_compares(tmp_path):
    # every port of every instance on its ROS name, the values the model gives (with
    # their lines), the period a push port of periodic activities promises, and the
    # connections to names outside the model
    for name in ('handwritten_system', 'handwritten_nodes'):
        shutil.copytree(TEST_WORKSPACE / 'src' / name, tmp_path / 'src' / name)
    model = tmp_path / 'src' / 'handwritten_system' / 'robmosys.yaml'
    text = model.read_text()
    out = tmp_path / 'out'
    generate_package(plan_package(_load(tmp_path / 'src'), 'handwritten_system'), out)
    description = json.loads((out / 'bringup.json').read_text())
    lines = text.splitlines()

    def at(fragment: str, column: int) -> str:
        line = next(n for n, t in enumerate(lines, 1) if fragment in t)
        # in the installed copy of the model, whose lines are the model's
        return f'share/handwritten_system/robmosys/robmosys.yaml:{line}:{column}'
    instances = {i['instance']: i for i in description['instances']}
    assert instances['echo']['location'] == at('echo: {component', 7)
    assert instances['talker']['lifecycle'] is False
    assert instances['talker']['ports'] == [{
        'port': 'pChatter', 'entity': 'publisher', 'name': '/talker/pChatter',
        'type': 'std_msgs/msg/String', 'required': False, 'connected': True, 'period': None,
        'unconnected': False, 'quiet': False}]
    assert {p['port']: p['name'] for p in instances['echo']['ports']} == {
        'rIn': '/outside/words', 'pOut': '/outside/echoes'}
    outside = [c for c in description['connections'] if not c['to']]
    assert outside == [
        {'name': '/outside/words', 'entity': 'subscription', 'type': 'std_msgs/msg/String',
         'from': 'echo.rIn', 'to': '', 'location': at('{to: echo.rIn', 9)},
        {'name': '/outside/echoes', 'entity': 'publisher', 'type': 'std_msgs/msg/String',
         'from': 'echo.pOut', 'to': '', 'location': at('{from: echo.pOut', 9)}]


def test_the_description_is_json_with_an_instance_per_line():
    workspace = _load(TEST_WORKSPACE / 'src')
    plan = plan_system(_system('dummy_robot_bringup'), workspace)
    text = plan.bringup_description
    description = json.loads(text)
    # what json's own indented form holds, each instance and connection on a line
    assert json.loads(json.dumps(description, indent=2)) == description
    lines = text.splitlines()
    for key in ('instances', 'connections'):
        assert len(description[key]) > 1
        for item in description[key]:
            line = json.dumps(item, sort_keys=True)
            assert f'    {line},' in lines or f'    {line}' in lines
    weird = {'b': [], 'a': ['x\n"y"', {'z': 1, 'k': [1, 2]}], 'c': {'\u00e9': None}}
    assert json.loads(json_lines(weird)) == weird
    assert json_lines(weird).startswith('{\n  "a": [\n    "x\\n\\"y\\"",\n')


def test_the_description_holds_the_values_and_periods_of_the_model():
    workspace = _load(TEST_WORKSPACE / 'src')
    plan = plan_system(_system('dummy_robot_bringup'), workspace)
    description = json.loads(plan.bringup_description)
    instances = {i['instance']: i for i in description['instances']}
    values = {p['name']: p['value'] for p in instances['laser_rear']['parameters']}
    # the instance's values over the component's defaults
    assert values == {'frame_id': 'laser_rear', 'samples': 180, 'range_max': 10.0}
    where = {p['name']: p['location'] for p in instances['laser_rear']['parameters']}
    assert where['samples'] != where['range_max'] == instances['laser_rear']['location']
    (scan,) = instances['laser_rear']['ports']
    # a laser scans every 0.1 s: its scans are watched for silence
    assert (scan['name'], scan['period'], scan['required']) == ('/dummy_robot/scan', 0.1, False)
    assert all(p['period'] is None for p in instances['monitor']['ports'])


def test_bringup_json_declares_a_mapped_parameter_per_entry(generated):
    """The offline check of parameter files sees elbow.amplitude, not amplitude.

    And amplitude once more as a template (origin ``mapped``), for a file that
    sets joint_names itself.
    """
    description = json.loads((generated / 'dummy_robot_bringup' / 'bringup.json').read_text())
    [joints] = [i for i in description['instances'] if i['instance'] == 'joints']
    declared = {d['name']: d for d in joints['declared'] if d['origin'] != 'mapped'}
    assert 'amplitude' not in declared
    assert declared['shoulder.amplitude']['range'] == [0.0, 3.0, 0.0]
    assert declared['elbow.amplitude']['type'] == 'double'
    assert declared['elbow.amplitude']['for_each'] == 'joint_names'
    [template] = [d for d in joints['declared'] if d['origin'] == 'mapped']
    assert (template['name'], template['for_each'], template['range']) == \
        ('amplitude', 'joint_names', [0.0, 3.0, 0.0])
