# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""C++ components built by colcon and run on real ROS 2, next to Python ones.

Where rclcpp, rclcpp_lifecycle and rclcpp_components are not in the ROS prefix
(PyPI has no rclcpp), colcon skips the C++ packages and says why: the first
test checks exactly that, the others skip with the reason. Where they are (a
ROS 2 Jazzy or Kilted install sourced before ``make test``), the examples of
test_workspace are built with the rest and run as mixed_system's launch file
would start them.
"""

from __future__ import annotations

import contextlib
import json
import os
from pathlib import Path
import re
import signal
import sys

import pytest

from colcon_robmosys.devtools import ros_env
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from colcon_robmosys.mapping.backends.cpp.spelling import CPP_CLIENT_PACKAGES
from colcon_robmosys.package_selection.robmosys import missing_prefix_packages
from conftest import assert_no_traceback, requires_ros
from harness.launch_files import activate_launch_file, nodes_launch_file, read_launch_file

pytestmark = [pytest.mark.integration, requires_ros]

CPP_PACKAGES = ('cpp_client', 'cpp_dummy_joint_states', 'cpp_dummy_laser',
                'cpp_dummy_map_server', 'cpp_level_sensor', 'cpp_level_watcher',
                'cpp_publisher', 'cpp_receiver', 'cpp_sender', 'cpp_server', 'cpp_subscriber')
SYSTEM = 'mixed_system'


def rclcpp_missing_reason() -> str | None:
    """Return why C++ components cannot be built here, or None."""
    missing = missing_prefix_packages(CPP_CLIENT_PACKAGES, [],
                                      environ=ros_env.loopback_env(1))
    if not missing:
        return None
    return (f'{", ".join(missing)} not found in AMENT_PREFIX_PATH/CMAKE_PREFIX_PATH '
            '(not on PyPI): colcon skips the C++ components here')


requires_rclcpp = pytest.mark.skipif(rclcpp_missing_reason() is not None,
                                     reason=rclcpp_missing_reason() or '')


def test_cpp_packages_are_built_or_skipped_with_the_reason(test_workspace_built):
    """Without rclcpp the build skips them, says why, and builds the system."""
    install, output = test_workspace_built.install, test_workspace_built.build_output
    share = test_workspace_built.share(SYSTEM)
    assert activate_launch_file(share).is_file()
    # one warning for each set of what is missing, naming every package skipped for it
    warnings = re.findall(r"^.*WARNING:.*Skipping ('.*'): (?:it|they) needs? rclcpp.*$",
                          output, re.MULTILINE)
    named = {name for line in warnings for name in re.findall(r"'([^']+)'", line)}
    if rclcpp_missing_reason():
        assert len(warnings) <= 2, warnings  # rclcpp_action is missing for some only
    for package in CPP_PACKAGES:
        executable = install / package / 'lib' / package
        if rclcpp_missing_reason():
            # skipped, as colcon skips unselected packages: never started,
            # so never reported as finished
            assert package in named, output
            assert f'Starting >>> {package}\n' not in output
            assert f'Finished <<< {package} ' not in output
            assert not executable.exists()
        else:
            assert package not in named
            registered = install / package / 'share' / 'ament_index' / 'resource_index' / \
                'rclcpp_components' / package
            assert registered.read_text().startswith(f'{package}::'), package


@contextlib.contextmanager
def _system(built, domain_id: int, names: list[str]):
    """Start some instances of mixed_system as its launch.py would."""
    share = built.share(SYSTEM)
    nodes = {n.name: n for n in read_launch_file(nodes_launch_file(share), share)}
    env = built.env(domain_id)
    with contextlib.ExitStack() as stack:
        processes = {name: stack.enter_context(
            ros_env.background(nodes[name].command(built.install), env=env))
            for name in names}
        driver = stack.enter_context(LifecycleDriver(domain_id))
        yield {name: nodes[name].fqn for name in names}, processes, driver


def _bring_up(driver: LifecycleDriver, fqns: list[str]) -> None:
    for transition in ('configure', 'activate'):
        for fqn in fqns:
            assert driver.transition(fqn, transition), f'{transition} {fqn}'


MAPS = re.compile(r'got map data: width (\d+), height (\d+)')


@requires_rclcpp
def test_cpp_and_python_publish_to_each_other(test_workspace_built, domain_id):
    """C++ publisher -> Python subscriber, Python publisher -> C++ subscriber."""
    with _system(test_workspace_built, domain_id,
                 ['cpp_pub', 'py_sub', 'py_pub', 'cpp_sub']) as (fqn, out, driver):
        assert driver.state(fqn['cpp_pub']) == 'unconfigured'
        assert driver.parameters(fqn['cpp_pub'], ['indoor', 'noOfScans']) == \
            {'indoor': True, 'noOfScans': 0}
        for name in fqn:
            assert driver.transition(fqn[name], 'configure')
        assert driver.state(fqn['cpp_pub']) == 'inactive'
        wait_until(lambda: False, timeout=1.5)
        assert 'Publishing map' not in out['cpp_pub'].output()
        assert not MAPS.search(out['py_sub'].output())

        for name in fqn:
            assert driver.transition(fqn[name], 'activate')
        for subscriber in ('py_sub', 'cpp_sub'):
            assert wait_until(lambda: len(MAPS.findall(out[subscriber].output())) >= 2,
                              timeout=20), out[subscriber].output()
            assert set(MAPS.findall(out[subscriber].output())) == {('16', '16')}
        assert 'resolution 0.10' in out['cpp_sub'].output()

        # deactivated, the C++ timer stops; cleaned up and configured again, it restarts
        assert driver.transition(fqn['cpp_pub'], 'deactivate')
        wait_until(lambda: False, timeout=0.6)
        published = out['cpp_pub'].output().count('Publishing map')
        wait_until(lambda: False, timeout=1.5)
        assert out['cpp_pub'].output().count('Publishing map') == published
        assert driver.transition(fqn['cpp_pub'], 'cleanup')
        assert driver.state(fqn['cpp_pub']) == 'unconfigured'
        _bring_up(driver, [fqn['cpp_pub']])
        assert wait_until(
            lambda: out['cpp_pub'].output().count('Publishing map') > published + 1, timeout=10)

        # SIGTERM ends the C++ process cleanly
        process = out['cpp_sub'].proc
        process.send_signal(signal.SIGTERM)
        assert process.wait(timeout=15) == 0, out['cpp_sub'].output()


PYTHON_CALL = """
import sys
import rclpy
from example_msgs.srv import AddTwoInts
from colcon_robmosys.devtools.system import answered
rclpy.init()
node = rclpy.create_node('python_call')
client = node.create_client(AddTwoInts, sys.argv[1])
assert client.wait_for_service(timeout_sec=20), 'no service'
print('sum', answered(client, AddTwoInts.Request(a=int(sys.argv[2]), b=int(sys.argv[3])),
                      node).sum)
node.destroy_node()
rclpy.shutdown()
"""


@requires_rclcpp
def test_cpp_server_answers_python_and_cpp_clients(test_workspace_built, domain_id):
    """rclpy, the generated Python client and the C++ client query the C++ server."""
    env = test_workspace_built.env(domain_id)
    with _system(test_workspace_built, domain_id,
                 ['server', 'client', 'py_client']) as (fqn, out, driver):
        assert driver.transition(fqn['server'], 'configure')

        def call(a: int, b: int) -> str:
            result = ros_env.run([sys.executable, '-c', PYTHON_CALL, '/server/qAdd', str(a),
                                  str(b)], env=env, timeout=60)
            assert result.returncode == 0, result.stderr
            return result.stdout.strip()

        # inactive: the server answers the default response and warns
        assert call(3, 4) == 'sum 0'
        assert 'while inactive' in out['server'].output()
        assert driver.transition(fqn['server'], 'activate')
        assert call(3, 4) == 'sum 7'

        # the blocking call from a C++ activity does not deadlock the executor
        _bring_up(driver, [fqn['client'], fqn['py_client']])
        for client in ('client', 'py_client'):
            assert wait_until(lambda: 'callback answer: 2002' in out[client].output(),
                              timeout=20), out[client].output()
            assert 'blocking answer: 1 + 1000 = 1001' in out[client].output()
            assert 'no answer' not in out[client].output()


EVENTS = re.compile(r'event: level (\d+)')


@requires_rclcpp
def test_events_between_cpp_and_python(test_workspace_built, domain_id):
    """C++ sensor -> Python watcher and Python sensor -> C++ watcher, conditions held."""
    with _system(test_workspace_built, domain_id,
                 ['cpp_sensor', 'py_watcher', 'py_sensor', 'cpp_watcher']) as (fqn, out, driver):
        _bring_up(driver, [fqn['cpp_sensor'], fqn['py_sensor']])
        _bring_up(driver, [fqn['py_watcher'], fqn['cpp_watcher']])
        for watcher, threshold in (('py_watcher', 16), ('cpp_watcher', 17)):
            assert wait_until(lambda: len(EVENTS.findall(out[watcher].output())) >= 6,
                              timeout=30), out[watcher].output()
            levels = {int(level) for level in EVENTS.findall(out[watcher].output())}
            assert levels and min(levels) >= threshold, (watcher, levels)
            # the single activation ended with its one event
            assert wait_until(lambda: re.search(
                r'single activation: 1 event\(s\), ended: (True|true)',
                out[watcher].output()) is not None, timeout=10), out[watcher].output()
        assert re.search(r'level \d+ notified to [12]', out['cpp_sensor'].output())


@requires_rclcpp
def test_cpp_sender_sends_to_cpp_receiver_with_checked_parameters(
        test_workspace_built, domain_id):
    """Send pattern, parameter override, and ROS 2 itself refusing bad values."""
    from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
    from rcl_interfaces.srv import SetParameters
    with _system(test_workspace_built, domain_id, ['sender', 'receiver']) as (fqn, out, driver):
        assert driver.parameters(fqn['sender'], ['width', 'height', 'frame']) == \
            {'width': 5, 'height': 4, 'frame': 'map'}

        def set_parameter(name: str, value: ParameterValue) -> bool:
            request = SetParameters.Request(parameters=[Parameter(name=name, value=value)])
            answer = driver._call(SetParameters, f'{fqn["sender"]}/set_parameters',
                                  request, 20)
            return answer.results[0].successful

        integer = ParameterType.PARAMETER_INTEGER
        assert not set_parameter('width', ParameterValue(type=integer, integer_value=0))
        assert not set_parameter('width', ParameterValue(
            type=ParameterType.PARAMETER_STRING, string_value='wide'))
        assert not set_parameter('frame', ParameterValue(
            type=ParameterType.PARAMETER_STRING, string_value='odom'))
        assert set_parameter('height', ParameterValue(type=integer, integer_value=6))
        # the rules beyond the descriptor refuse with their reason; on_change runs after
        sender = fqn['sender']
        assert driver.set_parameters(sender, {'shape.kind': 'circle'})['shape.kind'] == (
            False, "parameter 'shape.kind': 'circle' is not one of 'rectangle', 'square'")
        assert driver.set_parameters(sender, {'shape.max_cells': 29}) == {'shape.max_cells': (
            False, "parameter 'shape.max_cells': fewer than width x height cells")}
        assert driver.set_parameters(sender, {'frame': ''})['frame'][0] is False
        assert driver.set_parameters(sender, {'shape.kind': 'square'})['shape.kind'][0]
        assert wait_until(lambda: 'shape is now square' in out['sender'].output(), 10)
        assert driver.parameters(sender, ['shape.kind']) == {'shape.kind': 'square'}

        _bring_up(driver, [fqn['receiver'], fqn['sender']])
        assert wait_until(lambda: 'received map: width 5, height 6' in out['receiver'].output(),
                          timeout=20), out['receiver'].output()


@requires_rclcpp
def test_a_cpp_node_without_its_required_parameter_does_not_configure(
        test_workspace_built, domain_id):
    """cpp_receiver's station has no default: without a value, configure fails and names it."""
    share = test_workspace_built.share(SYSTEM)
    receiver = {n.name: n for n in read_launch_file(nodes_launch_file(share), share)}['receiver']
    # its executable, without the system's parameter file
    command = [*receiver.command(test_workspace_built.install)[:1], '--ros-args', '-r',
               '__node:=lonely_receiver']
    with ros_env.background(command, env=test_workspace_built.env(domain_id)) as process, \
            LifecycleDriver(domain_id) as driver:
        assert driver.state('/lonely_receiver') == 'unconfigured', process.output()
        assert not driver.transition('/lonely_receiver', 'configure')
        assert wait_until(lambda: "configure failed: parameter 'station' has no value" in
                          process.output(), 10), process.output()
        assert driver.set_parameters('/lonely_receiver', {'station': 'dock'}) == {
            'station': (True, '')}
        assert driver.transition('/lonely_receiver', 'configure'), process.output()


COMPONENT_LOADER = """
import sys
import rclpy
from composition_interfaces.srv import LoadNode
rclpy.init()
node = rclpy.create_node('component_loader')
client = node.create_client(LoadNode, '/ComponentManager/_container/load_node')
assert client.wait_for_service(timeout_sec=20), 'no container'
request = LoadNode.Request(package_name=sys.argv[1], plugin_name=sys.argv[2],
                           node_name=sys.argv[3])
future = client.call_async(request)
rclpy.spin_until_future_complete(node, future, timeout_sec=30)
print('loaded', future.result().success, future.result().full_node_name)
node.destroy_node()
rclpy.shutdown()
"""


@requires_rclcpp
def test_cpp_component_runs_in_a_container(test_workspace_built, domain_id):
    """rclcpp_components loads the registered component into a container process."""
    from colcon_robmosys.devtools.ros_env import background, run
    env = test_workspace_built.env(domain_id)
    container = None
    for prefix in env['AMENT_PREFIX_PATH'].split(os.pathsep):
        candidate = f'{prefix}/lib/rclcpp_components/component_container_mt'
        if prefix and os.path.exists(candidate):
            container = candidate
            break
    if container is None:
        pytest.skip('component_container_mt of rclcpp_components is not installed')
    with background([container, '--ros-args', '-r', '__node:=ComponentManager'],
                    env=env) as process, LifecycleDriver(domain_id) as driver:
        result = run([sys.executable, '-c', COMPONENT_LOADER, 'cpp_publisher',
                      'cpp_publisher::PeriodicPublisher', 'contained'], env=env, timeout=90)
        assert result.stdout.strip() == 'loaded True /contained', result.stderr
        _bring_up(driver, ['/contained'])
        assert wait_until(lambda: 'Publishing map' in process.output(), timeout=20), \
            process.output()


@requires_rclcpp
def test_cpp_mapped_parameters_are_declared_checked_and_read_per_entry(
        test_workspace_built, domain_id):
    """dummy_robot_cpp_bringup's joints: an amplitude per joint, its range, typed access."""
    from sensor_msgs.msg import JointState
    share = test_workspace_built.share('dummy_robot_cpp_bringup')
    node = {n.name: n for n in read_launch_file(nodes_launch_file(share), share)}['joints']
    env = test_workspace_built.env(domain_id)
    with ros_env.background(node.command(test_workspace_built.install), env=env) as process, \
            LifecycleDriver(domain_id) as driver:
        names = ['shoulder.amplitude', 'elbow.amplitude']
        assert driver.parameters(node.fqn, names) == {
            'shoulder.amplitude': 1.0, 'elbow.amplitude': 0.5}, process.output()
        # the descriptor's range holds for each entry
        assert not driver.set_parameters(node.fqn, {'elbow.amplitude': 5.0})['elbow.amplitude'][0]
        assert driver.parameters(node.fqn, ['joint1.amplitude']) == {}
        # fInit reads joint_names_map(): each joint swings with its own amplitude
        states: list[JointState] = []
        driver.node.create_subscription(JointState, f'{node.fqn.rsplit("/", 1)[0]}/joint_states',
                                        states.append, 10)
        _bring_up(driver, [node.fqn])

        def swinging() -> bool:
            driver.spin(0.1)
            return any(abs(s.position[0]) > 0.01 for s in states)

        assert wait_until(swinging, 20), process.output()
        moving = next(s for s in states if abs(s.position[0]) > 0.01)
        assert list(moving.name) == ['shoulder', 'elbow']
        assert moving.position[1] == pytest.approx(moving.position[0] * 0.5)
    bad = ros_env.run([*node.command(test_workspace_built.install), '-p',
                       'joint_names:=[shoulder, shoulder]'], env=env, timeout=60)
    assert bad.returncode != 0
    assert "parameter 'joint_names': entry 'shoulder' is listed twice" in \
        bad.stdout + bad.stderr, bad.stdout + bad.stderr


#: what a quiet shutdown never prints
NOISE = re.compile(r'Traceback|terminate called|\[ERROR\]|exception|Segmentation')

#: C++ instance of mixed_system -> its peer, and what one of them prints while working
CPP_WORKING = {
    'cpp_pub': ('py_sub', r'got map data'),
    'sender': ('receiver', r'received'),
    'cpp_sensor': ('py_watcher', r'event: level'),
    'cpp_watcher': ('py_sensor', r'notified to'),
}


@requires_rclcpp
@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM], ids=['SIGINT', 'SIGTERM'])
@pytest.mark.parametrize('name', sorted(CPP_WORKING))
def test_a_signal_while_working_ends_a_cpp_node_quietly(test_workspace_built, name, signum):
    """As tests/test_shutdown.py for Python: exit 0, nothing on the console."""
    peer, working = CPP_WORKING[name]
    with _system(test_workspace_built, ros_env.free_domain_id(), [name, peer]) as (
            fqn, out, driver):
        # servers before clients: the sensors before the watchers
        order = [peer, name] if name.endswith('watcher') else [name, peer]
        _bring_up(driver, [fqn[n] for n in order])
        assert wait_until(lambda: re.search(working, out[name].output() + out[peer].output())
                          is not None, timeout=30), out[name].output() + out[peer].output()
        process = out[name].proc
        process.send_signal(signum)
        assert process.wait(timeout=15) == 0, out[name].output()
        assert not NOISE.search(out[name].output()), out[name].output()


@requires_rclcpp
def test_a_second_signal_ends_a_cpp_node_promptly(test_workspace_built):
    with _system(test_workspace_built, ros_env.free_domain_id(), ['cpp_pub', 'py_sub']) as (
            fqn, out, driver):
        _bring_up(driver, [fqn['cpp_pub'], fqn['py_sub']])
        assert wait_until(lambda: MAPS.search(out['py_sub'].output()) is not None, timeout=30)
        process = out['cpp_pub'].proc
        process.send_signal(signal.SIGINT)
        process.send_signal(signal.SIGINT)
        process.wait(timeout=10)
        assert 'terminate called' not in out['cpp_pub'].output()


@requires_rclcpp
def test_a_shared_system_runs_its_cpp_instances_in_one_container(
        test_workspace_built, domain_id):
    """With bringup --shared, the C++ instances run in one component container.

    The Python ones share one process; parameters of the system's file reach
    the nodes the container makes. The container is robmosys_runtime's, built
    by the system package: it brought its instances up itself, and serves
    rclcpp_components' services.
    """
    from colcon_robmosys.devtools.ros_env import background
    instances = [i.name for i in _model_system().instances]
    executable = test_workspace_built.install / SYSTEM / 'lib' / SYSTEM / 'bringup'
    with background([sys.executable, str(executable), '--shared'],
                    env=test_workspace_built.env(domain_id), stop_timeout=30) as bringup, \
            LifecycleDriver(domain_id) as driver:
        done = f'bringup: {len(instances)} of {len(instances)} managed instances active'
        assert wait_until(lambda: done in bringup.output(), timeout=120), bringup.output()
        # C++ -> Python and Python -> C++, across the two shared processes
        assert wait_until(lambda: len(MAPS.findall(bringup.output())) >= 2, timeout=30), \
            bringup.output()
        # each shared process brought up what it could by itself (the container's
        # client after its server too); the manager only those that come after an
        # instance of the other process
        assert set(re.findall(r'instance (\w+) is active', bringup.output())) == {
            'cpp_watcher', 'py_watcher', 'py_client'}, bringup.output()
        assert driver.parameters('/sender', ['width']) == {'width': 5}
        containers = [p for p in Path('/proc').iterdir() if p.name.isdigit() and
                      b'__node:=mixed_system_container' in _cmdline(p)]
        assert len(containers) == 1, containers
        assert f'{SYSTEM}/component_container'.encode() in _cmdline(containers[0])
        # no process of its own: the container's command line is the only one naming it
        assert [p for p in Path('/proc').iterdir() if p.name.isdigit() and
                b'__node:=cpp_pub' in _cmdline(p)] == containers
        from composition_interfaces.srv import ListNodes
        listed = driver.call(ListNodes, '/mixed_system_container/_container/list_nodes',
                             ListNodes.Request())
        description = json.loads((test_workspace_built.install / SYSTEM / 'share' / SYSTEM /
                                  'bringup.json').read_text())
        cpp = {i['fqn'] for i in description['instances'] if i['plugin']}
        assert len(cpp) == 8 and sorted(listed.full_node_names) == sorted(cpp), listed
        bringup.proc.send_signal(signal.SIGINT)
        assert bringup.proc.wait(timeout=60) == 0, bringup.output()
        assert_no_traceback(bringup.output())


#: start the container as bringup does (--activate, --report-fd), read what it tells
#: with bringup's own readers, SIGINT it: print the states, the steps and its exit code
#: as JSON (argv: the description, the parameter file, the instances); in the
#: workspace's environment, where robmosys_runtime is
CONTAINER_TELLING = """
import json, os, signal, subprocess, sys, threading
from robmosys_runtime.hosting.told import read_steps, read_told
reading, writing = os.pipe()
container = subprocess.Popen(
    [sys.executable, '-m', 'robmosys_runtime.hosting.cpp_container', '--activate', '--report-fd',
     str(writing), *sys.argv[1:]], pass_fds=[writing], stdout=sys.stderr)
os.close(writing)
try:
    states = read_told([reading], 60.0, threading.Event(), keep_open=[reading])
    container.send_signal(signal.SIGINT)
    steps = [text if level == 'info' else f'{level}: {text}'
             for level, text in read_steps(reading, wait=30.0)]
    code = container.wait(timeout=30)
finally:
    if container.poll() is None:
        container.kill()
        container.wait()
    os.close(reading)
print(json.dumps({'states': states, 'steps': steps, 'code': code}))
"""


@requires_rclcpp
def test_the_container_brings_its_instances_down_itself_and_tells_each_step(
        test_workspace_built, domain_id):
    """At SIGINT the container deactivates and cleans up what it brought up, the last first.

    As the shared Python process does: bringup reads each step on the pipe it
    told the bring-up on, instead of finding 50 nodes' lifecycle services
    then (4.4 s at 50 instances, where the container takes 0.5 s).
    """
    share = test_workspace_built.share(SYSTEM)
    description = json.loads((share / 'bringup.json').read_text(encoding='utf-8'))
    cpp = [i['instance'] for i in description['instances'] if i['plugin']]
    result = ros_env.run([sys.executable, '-c', CONTAINER_TELLING, str(share / 'bringup.json'),
                          str(share / description['params_file']), *cpp],
                         env=test_workspace_built.env(domain_id), timeout=150)
    assert result.returncode == 0, result.stdout + result.stderr
    told = json.loads(result.stdout.splitlines()[-1])
    active = [name for name in cpp if (told['states'] or {}).get(name) == 'active']
    assert active, told
    assert told['steps'] == [f'{verb} {name}' for name in reversed(active)
                             for verb in ('deactivate', 'cleanup')], told
    assert told['code'] == 0, result.stderr
    assert_no_traceback(result.stderr)


def _cmdline(proc: Path) -> bytes:
    try:
        return (proc / 'cmdline').read_bytes()
    except OSError:
        return b''


def _model_system():
    from colcon_robmosys.check import find_model_files, load_workspace
    from colcon_robmosys.check.index import InterfaceIndex
    from conftest import TEST_WORKSPACE
    result = load_workspace(find_model_files([TEST_WORKSPACE / 'src']),
                            InterfaceIndex([Path(sys.prefix)]))
    return result.workspace.model(SYSTEM)


#: a system of C++ components with two modes, built on test_workspace's install
CPP_MODES = """\
robmosys: 1
systems:
  - package: cpp_mode_system
    license: Apache-2.0
    maintainers: [{name: RobMoSys Example Team, email: robmosys-examples@example.com}]
    description: A C++ sender that sends in one of two modes, its maps' size set per mode.
    instances:
      receiver: {component: cpp_receiver, parameters: {station: dock}}
      sender: {component: cpp_sender, after: [receiver], parameters: {width: 5}}
    connections:
      - {from: receiver.sMap, to: sender.sMap}
    modes:
      initial: idle
      idle: {active: [receiver], parameters: {sender: {width: 2}}}
      sending: {active: [receiver, sender], parameters: {sender: {width: 7, height: 3}}}
"""


@requires_rclcpp
def test_a_cpp_system_is_switched_between_its_modes(test_workspace_built, domain_id,
                                                    tmp_path):
    """The manager switches C++ lifecycle nodes; their own rules take the mode's values."""
    from std_srvs.srv import Trigger
    root = tmp_path / 'modes_ws'
    (root / 'src' / 'cpp_mode_system').mkdir(parents=True)
    (root / 'src' / 'cpp_mode_system' / 'robmosys.yaml').write_text(CPP_MODES)
    env = test_workspace_built.env(domain_id)
    built = ros_env.run([str(Path(sys.prefix) / 'bin' / 'colcon'), 'build'], env=env,
                        cwd=root, timeout=900)
    assert built.returncode == 0, built.stdout + built.stderr
    env = ros_env.workspace_env(root / 'install', env)
    bringup = root / 'install' / 'cpp_mode_system' / 'lib' / 'cpp_mode_system' / 'bringup'
    manager = '/cpp_mode_system_bringup'

    with ros_env.background([sys.executable, str(bringup), '--check-period', '0.5'],
                            env=env, stop_timeout=30) as system, \
            LifecycleDriver(domain_id) as driver:
        def switch(mode: str) -> list[str]:
            answer = driver.call(Trigger, f'{manager}/set_mode/{mode}', Trigger.Request(),
                                 timeout=30.0, attempt=10.0)
            assert answer.success, answer.message + system.output()
            return answer.message.splitlines()

        def in_mode(active: str, values: dict) -> bool:
            return driver.state('/sender') == active and \
                driver.state('/receiver') == 'active' and \
                driver.parameters('/sender', list(values)) == values

        assert wait_until(lambda: 'bringup: 1 of 1 managed instances active' in
                          system.output(), timeout=90), system.output()
        # the instance the mode leaves out is configured with the mode's values
        assert in_mode('inactive', {'width': 2, 'height': 4}), system.output()
        assert switch('sending') == ['set sender: height, width', 'activate sender',
                                     'mode: sending']
        assert in_mode('active', {'width': 7, 'height': 3})
        mark = len(system.output())
        assert wait_until(lambda: 'received map: width 7, height 3' in
                          system.output()[mark:], timeout=20), system.output()
        # back: the sender goes first, then the system's values come back
        assert switch('idle') == ['deactivate sender', 'set sender: height, width',
                                  'mode: idle']
        assert in_mode('inactive', {'width': 2, 'height': 4})
        report = driver.call(Trigger, f'{manager}/report', Trigger.Request(), timeout=30.0)
        assert report.message.splitlines()[0] == 'mode: idle', report.message
        assert wait_until(lambda: driver.call(Trigger, f'{manager}/conformance',
                                              Trigger.Request(), timeout=30.0).success, 20)
        system.proc.send_signal(signal.SIGINT)
        assert system.proc.wait(timeout=60) == 0, system.output()
        assert_no_traceback(system.output())
