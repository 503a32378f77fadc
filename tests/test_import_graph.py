# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""`colcon robmosys-import graph`: models of running systems, on real rclpy nodes.

The round trip: examples_system of test_workspace runs (Python components,
send, query, action and event ports, parameters with ranges, QoS that is not
the default); its graph is imported, the imported system validates clean, is
built and brought up, and imported again: the second import equals the first.
Hand-written nodes become external components, or refer to the description an
installed model gives them; a node nobody described gives its ports, QoS and
parameters (values and descriptors, hostile text included) to the model.
"""

from __future__ import annotations

from pathlib import Path
import shutil
import sys
import textwrap

import pytest
from test_cpp_system import requires_rclcpp
import yaml

from colcon_robmosys.devtools import ros_env
from colcon_robmosys.devtools.ros_env import background, free_domain_id
from colcon_robmosys.devtools.system import wait_until
from conftest import BuiltWorkspace, requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

COLCON = str(Path(sys.prefix) / 'bin' / 'colcon')


def _import(env: dict[str, str], out: Path, *args: str) -> str:
    """Import the graph of env's domain into out; return the model's text."""
    result = ros_env.run([COLCON, 'robmosys-import', 'graph', '--output-dir', str(out),
                          '--timeout', '20', *args], env=env, cwd=out.parent, timeout=120)
    assert result.returncode == 0, result.stdout + result.stderr
    system = args[args.index('--system-package') + 1]
    return (out / system / 'robmosys.yaml').read_text(encoding='utf-8')


def _validate(env: dict[str, str], workspace: Path) -> None:
    result = ros_env.run([COLCON, 'robmosys-generate', '--validate-only'], env=env,
                         cwd=workspace, timeout=120)
    assert result.returncode == 0, result.stdout + result.stderr
    assert 'warning' not in result.stderr and 'error' not in result.stderr, result.stderr


def _bringup(workspace: BuiltWorkspace | Path, system: str, domain_id: int,
             env: dict[str, str] | None = None):
    install = workspace.install if isinstance(workspace, BuiltWorkspace) else workspace
    executable = install / system / 'lib' / system / 'bringup'
    return background([sys.executable, str(executable)],
                      env=env or workspace.env(domain_id), stop_timeout=30)


def test_a_running_system_imports_builds_runs_and_imports_the_same(
        test_workspace_built, tmp_path):
    domain_id = free_domain_id()
    env = test_workspace_built.env(domain_id)
    first_dir = tmp_path / 'imported' / 'src'
    first_dir.mkdir(parents=True)
    with _bringup(test_workspace_built, 'examples_system', domain_id) as bringup:
        assert wait_until(lambda: 'bringup: 8 of 8 managed instances active' in
                          bringup.output(), timeout=120), bringup.output()
        first = _import(env, first_dir, '--system-package', 'imported_examples',
                        '--namespace', '/examples')
    model = yaml.safe_load(first)
    system = model['systems'][0]
    assert 'components' not in model, first  # every node was generated: referred to
    assert system['instances']['sender'] == {
        'component': 'sender', 'namespace': '/examples',
        'parameters': {'greeting': 'hi there', 'scale': 0.5}}, first
    assert system['instances']['level_watcher']['parameters'] == {'threshold': 16}, first
    assert len(system['instances']) == 8, first
    assert system['connections'] == [
        {'from': 'add_server.qAdd', 'to': 'add_client.qAdd'},
        {'from': 'fibonacci_server.aFibonacci', 'to': 'fibonacci_client.aFibonacci'},
        {'from': 'level_sensor.eLevel', 'to': 'level_watcher.eLevel'},
        {'from': 'receiver.sText', 'to': 'sender.sText'}], first
    assert '# The graph does not show: the order of activation (after)' in first
    _validate(env, tmp_path / 'imported')

    # build it, run it instead of the original, and import it again
    result = ros_env.run([COLCON, 'build'], env=env, cwd=tmp_path / 'imported', timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr
    install = tmp_path / 'imported' / 'install'
    imported_env = ros_env.workspace_env(install, env)
    second_dir = tmp_path / 'second'
    second_dir.mkdir()
    with _bringup(install, 'imported_examples', domain_id, imported_env) as bringup:
        assert wait_until(lambda: 'bringup: 8 of 8 managed instances active' in
                          bringup.output(), timeout=120), bringup.output()
        # it behaves as the original: the texts sent arrive, the sum is answered
        assert wait_until(lambda: '[examples.receiver]: received' in bringup.output(),
                          timeout=30), bringup.output()
        second = _import(imported_env, second_dir, '--system-package', 'imported_examples',
                         '--namespace', '/examples')
    assert second == first


def test_hand_written_nodes_refer_to_their_installed_description(test_workspace_built,
                                                                 tmp_path):
    domain_id = free_domain_id()
    env = test_workspace_built.env(domain_id)
    out = tmp_path / 'ws' / 'src'
    out.mkdir(parents=True)
    with _bringup(test_workspace_built, 'handwritten_system', domain_id) as bringup:
        assert wait_until(lambda: 'bringup: 3 of 3 managed instances active' in
                          bringup.output(), timeout=90), bringup.output()
        text = _import(env, out, '--system-package', 'hand_import')
    model = yaml.safe_load(text)
    # handwritten_system's model describes the talker and the listener: referred to,
    # found by the executables their processes run
    assert 'components' not in model, text
    system = model['systems'][0]
    assert system['instances'] == {
        'echo': {'component': 'text_relay', 'namespace': '/outside'},
        'listener': {'component': 'handwritten_nodes/lifecycle_listener'},
        'relay': {'component': 'text_relay'},
        'talker': {'component': 'handwritten_nodes/talker'}}, text
    assert system['connections'] == [
        {'to': 'echo.rIn', 'topic': '/outside/words'},
        {'from': 'echo.pOut', 'topic': '/outside/echoes'},
        {'from': 'relay.pOut', 'to': 'listener.rHeard'},
        {'from': 'talker.pChatter', 'to': 'relay.rIn'}], text
    assert '/handwritten_system_bringup brings up the system handwritten_system' in text
    _validate(env, tmp_path / 'ws')


#: a hand-written node with parameters, as an ordinary ament package installs it
TUNED_NODE = textwrap.dedent("""\
    #!/usr/bin/env python3
    \"\"\"A hand-written node with parameters, which a system sets.\"\"\"
    import rclpy
    from rclpy.executors import ExternalShutdownException
    from std_msgs.msg import String

    rclpy.init()
    node = rclpy.create_node('tuned_node')
    node.declare_parameter('rate', 10)
    node.declare_parameter('gain', 1.0)
    node.declare_parameter('label', 'plain')
    node.declare_parameter('frames', ['a', 'b'])
    node.create_publisher(String, 'level', 10)
    node.get_logger().info('tuned up')
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
""")

TUNED_PACKAGE = {
    'CMakeLists.txt': textwrap.dedent("""\
        cmake_minimum_required(VERSION 3.8)
        project(hand_tuned NONE)
        find_package(ament_cmake REQUIRED)
        install(PROGRAMS tuned_node DESTINATION lib/${PROJECT_NAME})
        ament_package()
    """),
    'package.xml': textwrap.dedent("""\
        <?xml version="1.0"?>
        <package format="3">
          <name>hand_tuned</name>
          <version>0.1.0</version>
          <description>A hand-written node with parameters.</description>
          <maintainer email="lab@example.com">Lab Team</maintainer>
          <license>Apache-2.0</license>
          <buildtool_depend>ament_cmake</buildtool_depend>
          <exec_depend>rclpy</exec_depend>
          <exec_depend>std_msgs</exec_depend>
          <export><build_type>ament_cmake</build_type></export>
        </package>
    """),
    'tuned_node': TUNED_NODE,
}

#: the values the system sets: all but gain, text that is YAML's and Python's syntax
TUNED_VALUES = {'rate': 25, 'label': 'Rate: "quoted" # no comment {x: [y]} \\ \'done\'',
                'frames': ['map', "- not: 'a list item'"]}
TUNED_DEFAULTS = {'rate': 10, 'gain': 1.0, 'label': 'plain', 'frames': ['a', 'b']}


def _tuned_system() -> str:
    """Return a model that describes the hand-written node and runs it twice."""
    return textwrap.dedent("""\
        robmosys: 1
        defaults:
          license: Apache-2.0
          maintainers: [{name: Lab Team, email: lab@example.com}]
        components:
          - name: Tuned
            package: hand_tuned
            language: python
            external: {executable: tuned_node, lifecycle: false}
            ports:
              pLevel: {pattern: push, role: provided, type: std_msgs/msg/String, name: level}
            parameters:
              rate: {type: int, default: 10}
              gain: {type: double, default: 1.0}
              label: {type: string, default: plain}
              frames: {type: 'string[]', default: [a, b]}
        systems:
          - package: tuned_system
            instances:
              tuned: {component: hand_tuned/tuned_node, parameters: %s}
              untouched: {component: hand_tuned/tuned_node, namespace: spare}
    """) % yaml.safe_dump(TUNED_VALUES, default_flow_style=True, width=2 ** 31).strip()


def test_a_described_node_runs_with_its_values_in_a_system_built_from_the_import(
        test_workspace_built, tmp_path, domain_id):
    """The values a system gives a node that an external component describes are kept."""
    from colcon_robmosys.devtools.system import LifecycleDriver
    env = test_workspace_built.env(domain_id)
    source = tmp_path / 'hand' / 'src'
    for name, text in TUNED_PACKAGE.items():
        (source / 'hand_tuned' / name).parent.mkdir(parents=True, exist_ok=True)
        (source / 'hand_tuned' / name).write_text(text, encoding='utf-8')
    (source / 'hand_tuned' / 'tuned_node').chmod(0o755)
    (source / 'tuned_system').mkdir()
    (source / 'tuned_system' / 'robmosys.yaml').write_text(_tuned_system(), encoding='utf-8')
    result = ros_env.run([COLCON, 'build'], env=env, cwd=source.parent, timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr
    hand_env = ros_env.workspace_env(source.parent / 'install', env)
    out = tmp_path / 'imported' / 'src'
    out.mkdir(parents=True)
    names = sorted(TUNED_DEFAULTS)
    with _bringup(source.parent / 'install', 'tuned_system', domain_id, hand_env) as bringup:
        assert wait_until(lambda: bringup.output().count('tuned up') == 2, timeout=90), \
            bringup.output()
        # the driver is gone before the import: no node of the graph but the system's
        with LifecycleDriver(domain_id) as driver:
            assert driver.parameters('/tuned', names) == {**TUNED_DEFAULTS, **TUNED_VALUES}
        text = _import(hand_env, out, '--system-package', 'tuned_import')
    model = yaml.safe_load(text)
    assert 'components' not in model, text  # the installed description is referred to
    assert model['systems'][0]['instances'] == {
        'tuned': {'component': 'hand_tuned/tuned_node', 'parameters': TUNED_VALUES},
        'untouched': {'component': 'hand_tuned/tuned_node', 'namespace': '/spare'}}, text
    _validate(hand_env, tmp_path / 'imported')

    # what matters: the system built from the import runs the node with those values
    result = ros_env.run([COLCON, 'build'], env=hand_env, cwd=out.parent, timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr
    install = out.parent / 'install'
    imported_env = ros_env.workspace_env(install, hand_env)
    with _bringup(install, 'tuned_import', domain_id, imported_env) as bringup, \
            LifecycleDriver(domain_id) as driver:
        assert wait_until(lambda: bringup.output().count('tuned up') == 2, timeout=90), \
            bringup.output()
        assert driver.parameters('/tuned', names) == {**TUNED_DEFAULTS, **TUNED_VALUES}
        assert driver.parameters('/spare/untouched', names) == TUNED_DEFAULTS


#: a node nobody modelled: QoS that is not the default, parameters with descriptors
PROBE = textwrap.dedent("""
    import sys
    import rclpy
    from rclpy.duration import Duration
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from rcl_interfaces.msg import (
        FloatingPointRange, IntegerRange, ParameterDescriptor)
    from std_msgs.msg import String
    from std_srvs.srv import Trigger

    rclpy.init()
    node = rclpy.create_node('graph_probe', namespace='/lab')
    node.declare_parameter('rate', 20, ParameterDescriptor(
        description=sys.argv[1], integer_range=[IntegerRange(
            from_value=1, to_value=100, step=1)]))
    node.declare_parameter('gain', 0.25, ParameterDescriptor(
        floating_point_range=[FloatingPointRange(from_value=0.0, to_value=1.0)]))
    node.declare_parameter('frame', sys.argv[2], ParameterDescriptor(read_only=True))
    node.declare_parameter('layers', ['static', 'dynamic'])
    qos = QoSProfile(depth=3, reliability=ReliabilityPolicy.BEST_EFFORT,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL,
                     deadline=Duration(seconds=0.5))
    node.create_publisher(String, 'status', qos)
    node.create_subscription(String, '/commands', lambda message: None, 10)
    node.create_service(Trigger, 'reset', lambda request, response: response)
    from example_msgs.action import Fibonacci
    from rclpy.action import ActionClient, ActionServer
    ActionServer(node, Fibonacci, 'count', lambda goal: Fibonacci.Result())
    ActionClient(node, Fibonacci, '/planner/plan')
    print('probe up', flush=True)
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
""")

HOSTILE = 'Rate in Hz: "quoted" # not a comment\n- not a list item {x: [y]} \\ done'


def test_a_node_nobody_modelled_becomes_an_external_component(test_workspace_built,
                                                              tmp_path):
    domain_id = free_domain_id()
    env = test_workspace_built.env(domain_id)
    script = tmp_path / 'probe.py'
    script.write_text(PROBE, encoding='utf-8')
    out = tmp_path / 'ws' / 'src'
    out.mkdir(parents=True)
    with background([sys.executable, str(script), HOSTILE, "map: {a: 'b'}"],
                    env=env) as probe:
        assert wait_until(lambda: 'probe up' in probe.output(), timeout=30), probe.output()
        text = _import(env, out, '--system-package', 'lab_import', '--namespace', 'lab',
                       '--license', 'BSD-3-Clause',
                       '--maintainer', 'Lab Team <lab@example.com>')
    model = yaml.safe_load(text)
    [component] = model['components']
    assert component['package'] == 'graph_probe', text
    assert component['external'] == {'executable': 'graph_probe', 'lifecycle': False}, text
    assert component['ports'] == {
        'status': {'pattern': 'push', 'role': 'provided', 'type': 'std_msgs/msg/String',
                   'qos': {'reliability': 'best_effort', 'durability': 'transient_local',
                           'deadline': 0.5}},
        'commands': {'pattern': 'push', 'role': 'required', 'type': 'std_msgs/msg/String',
                     'name': '/commands',
                     'qos': {'reliability': 'reliable', 'durability': 'volatile'}},
        'reset': {'pattern': 'query', 'role': 'provided', 'type': 'std_srvs/srv/Trigger'},
        'count': {'pattern': 'action', 'role': 'provided',
                  'type': 'example_msgs/action/Fibonacci'},
        'plan': {'pattern': 'action', 'role': 'required', 'type': 'example_msgs/action/Fibonacci',
                 'name': '/planner/plan'},
    }, text
    # hostile text is read back as it was
    assert component['parameters'] == {
        'frame': {'type': 'string', 'default': "map: {a: 'b'}", 'read_only': True},
        'gain': {'type': 'double', 'default': 0.25, 'range': {'from': 0.0, 'to': 1.0}},
        'layers': {'type': 'string[]', 'default': ['static', 'dynamic']},
        'rate': {'type': 'int', 'default': 20, 'description': HOSTILE,
                 'range': {'from': 1, 'to': 100, 'step': 1}},
    }, text
    assert '# node /lab/graph_probe: no process of this host runs it' in text
    assert 'history and depth of its topics are not visible in the graph' in text
    system = model['systems'][0]
    assert system['license'] == 'BSD-3-Clause', text
    assert system['maintainers'] == [{'name': 'Lab Team', 'email': 'lab@example.com'}], text
    assert system['instances'] == {
        'graph_probe': {'component': 'graph_probe/graph_probe', 'namespace': '/lab'}}, text
    # its ports keep their names: /lab/status is the port's own; the subscription
    # listens on a name outside the model
    assert system['connections'] == [{'to': 'graph_probe.commands', 'topic': '/commands'},
                                     {'to': 'graph_probe.plan', 'topic': '/planner/plan'}]
    _validate(env, tmp_path / 'ws')


#: a node nobody spins: its parameter services never answer
SILENT = textwrap.dedent("""
    import time
    import rclpy

    rclpy.init()
    node = rclpy.create_node('silent', namespace='/lab')
    print('silent up', flush=True)
    try:
        time.sleep(300)
    except KeyboardInterrupt:
        pass
""")


def test_a_node_that_does_not_answer_costs_the_others_nothing(
        test_workspace_built, tmp_path, domain_id):
    """The parameters of the nodes that answer are read, whichever node does not."""
    env = test_workspace_built.env(domain_id)
    (tmp_path / 'probe.py').write_text(PROBE, encoding='utf-8')
    (tmp_path / 'silent.py').write_text(SILENT, encoding='utf-8')
    out = tmp_path / 'ws' / 'src'
    out.mkdir(parents=True)
    with background([sys.executable, str(tmp_path / 'probe.py'), 'Rate.', 'map'],
                    env=env) as probe, \
            background([sys.executable, str(tmp_path / 'silent.py')], env=env) as silent:
        assert wait_until(lambda: 'probe up' in probe.output() and
                          'silent up' in silent.output(), timeout=30), \
            probe.output() + silent.output()
        text = _import(env, out, '--system-package', 'lab_import', '--namespace', 'lab',
                       '--license', 'BSD-3-Clause',
                       '--maintainer', 'Lab Team <lab@example.com>')
    components = {c['package']: c for c in yaml.safe_load(text)['components']}
    assert components['graph_probe']['parameters']['rate']['default'] == 20, text
    assert 'parameters' not in components['silent'], text
    assert '# node /lab/silent: parameters: the node did not answer' in text
    assert '# node /lab/graph_probe: parameters: the node did not answer' not in text


#: a node that joins the graph a while after its process starts, as on a busy machine
LATE = textwrap.dedent("""
    import sys
    import time
    import rclpy

    time.sleep(float(sys.argv[1]))
    rclpy.init(args=sys.argv)
    node = rclpy.create_node('unnamed')
    print(f'{node.get_fully_qualified_name()} up', flush=True)
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
""")


def test_a_node_this_host_runs_is_waited_for_until_it_is_in_the_graph(
        test_workspace_built, tmp_path, domain_id):
    """A steady graph without a node a process of this host names is not the whole graph."""
    env = test_workspace_built.env(domain_id)
    script = tmp_path / 'lib' / 'late_pkg' / 'late_node'
    script.parent.mkdir(parents=True)
    script.write_text(LATE, encoding='utf-8')
    out = tmp_path / 'ws' / 'src'
    out.mkdir(parents=True)

    def node(name: str, delay: float):
        return background([sys.executable, str(script), str(delay), '--ros-args',
                           '-r', f'__node:={name}', '-r', '__ns:=/lab'], env=env)
    with node('early', 0) as early, node('late', 10) as late:
        assert wait_until(lambda: '/lab/early up' in early.output(), timeout=30), \
            early.output()
        # the graph is steady, with early alone, for longer than the import's settling
        text = _import(env, out, '--system-package', 'lab_import', '--namespace', 'lab',
                       '--license', 'BSD-3-Clause',
                       '--maintainer', 'Lab Team <lab@example.com>')
        assert '/lab/late up' in late.output()
    model = yaml.safe_load(text)
    assert model['systems'][0]['instances'] == {
        'early': {'component': 'late_pkg/late_node', 'namespace': '/lab'},
        'late': {'component': 'late_pkg/late_node', 'namespace': '/lab'}}, text


def test_an_existing_model_is_never_replaced_and_no_graph_is_an_error(test_workspace_built,
                                                                      tmp_path):
    env = test_workspace_built.env(free_domain_id())
    model = tmp_path / 'out' / 'mine' / 'robmosys.yaml'
    model.parent.mkdir(parents=True)
    model.write_text('my own model\n', encoding='utf-8')
    result = ros_env.run([COLCON, 'robmosys-import', 'graph', '--output-dir',
                          str(tmp_path / 'out'), '--system-package', 'mine'],
                         env=env, cwd=tmp_path, timeout=60)
    assert result.returncode == 1
    assert 'error: the file exists' in result.stderr
    assert model.read_text(encoding='utf-8') == 'my own model\n'
    # nothing runs in this domain: a clear error, within the timeout, nothing written
    result = ros_env.run([COLCON, 'robmosys-import', 'graph', '--output-dir',
                          str(tmp_path / 'out'), '--system-package', 'nothing',
                          '--namespace', '/nobody', '--timeout', '2'],
                         env=env, cwd=tmp_path, timeout=60)
    assert result.returncode == 1
    assert result.stderr.count('error: no node found under the namespace /nobody') == 1, \
        result.stderr
    assert not (tmp_path / 'out' / 'nothing').exists()
    shutil.rmtree(tmp_path / 'out')


@requires_rclcpp
def test_generated_cpp_nodes_announce_themselves(test_workspace_built, tmp_path):
    """C++ components announce their package and ports as Python ones do (prefix only)."""
    domain_id = free_domain_id()
    env = test_workspace_built.env(domain_id)
    out = tmp_path / 'ws' / 'src'
    out.mkdir(parents=True)
    with _bringup(test_workspace_built, 'dummy_robot_cpp_bringup', domain_id) as bringup:
        assert wait_until(lambda: 'bringup: 6 of 6 managed instances active' in
                          bringup.output(), timeout=120), bringup.output()
        text = _import(env, out, '--system-package', 'cpp_import')
    model = yaml.safe_load(text)
    assert 'components' not in model, text
    system = model['systems'][0]
    assert {name: i['component'] for name, i in system['instances'].items()} == {
        'map_server': 'cpp_dummy_map_server', 'joints': 'cpp_dummy_joint_states',
        'laser_front': 'cpp_dummy_laser', 'laser_rear': 'cpp_dummy_laser',
        'laser_spare': 'cpp_dummy_laser', 'monitor': 'dummy_robot_monitor',
        'monitor_ops': 'dummy_robot_monitor'}, text
    assert system['instances']['laser_rear']['parameters'] == {
        'frame_id': 'laser_rear', 'samples': 180}, text
    scan = [c for c in system['connections'] if c.get('topic') == '/cpp_robot/scan']
    assert sorted((c['from'], c['to']) for c in scan) == [
        ('laser_front.scan', 'monitor.scan'), ('laser_front.scan', 'monitor_ops.scan'),
        ('laser_rear.scan', 'monitor.scan'), ('laser_rear.scan', 'monitor_ops.scan')], text
    assert {'from': 'map_server.map', 'to': 'monitor_ops.map'} in system['connections'], text
    _validate(env, tmp_path / 'ws')
