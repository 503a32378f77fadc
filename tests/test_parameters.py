# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Parameters on real ROS 2: rules, validators, change callbacks, groups, mapped parameters.

System-wide values too; a mapped parameter is repeated for each entry of a string array.

A Python component with every kind of rule runs twice, as two instances of a
system (started as its launch files start them); a probe node sets and reads
their parameters through the parameter services, as ``ros2 param`` does.
"""

from __future__ import annotations

import contextlib
import re
import sys
from typing import Iterator

import pytest

from colcon_robmosys.devtools.ros_env import Background, background, free_domain_id, run
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from conftest import build_workspace, BuiltWorkspace, requires_ros
from harness.launch_files import NodeLaunch, nodes_launch_file, read_launch_file

pytestmark = [pytest.mark.integration, requires_ros]

MODEL = """\
robmosys: 1
defaults:
  license: Apache-2.0
  maintainers: [{name: A, email: a@example.com}]
components:
  - name: Tuner
    package: tuner
    language: python
    functions:
      vLabel:
        description: Refuse labels with spaces (written in Tuner_impl.py).
      vLayers:
        code: |
          return 'layers must differ' if len(set(value)) != len(value) else None
      fGainChanged:
        code: |
          self.get_logger().info(f'gain is now {self.params.controller.gain}')
      fKpChanged:
        code: |
          self.get_logger().info(f'kp is now {self.params.controller.pid.kp}')
          raise RuntimeError('a failing on_change is logged')
      fJointGain:
        code: |
          gains = sorted((j, e.gain) for j, e in self.params.joints_map.items())
          self.get_logger().info(f'joint gains {gains}')
    parameters:
      mode: {type: string, default: slow, one_of: [slow, fast], description: 'Speed | pace.'}
      label: {type: string, default: abc, size: {min: 1, max: 8}, validate: vLabel}
      layers: {type: 'string[]', default: [a], one_of: [a, b, c], size: {max: 2},
               validate: vLayers}
      controller.gain: {type: double, default: 0.5, range: {from: 0.0, to: 1.0},
                        on_change: fGainChanged}
      controller.pid.kp: {type: int, default: 3, one_of: [1, 2, 3], on_change: [fKpChanged]}
      joints: {type: 'string[]', default: [a], read_only: true}
      gain: {type: double, default: 1.0, range: {from: 0.0, to: 5.0}, for_each: joints,
             on_change: fJointGain}
      limits.mode: {type: string, default: soft, one_of: [soft, hard], for_each: joints}
      # no default: required, set by the system
      port: {type: string, description: The device it talks to.}
systems:
  - package: tuner_system
    parameters: {mode: fast, port: /dev/null}
    instances:
      first: {component: tuner, parameters: {mode: slow, controller.gain: 0.7, joints: [a, b],
                                             b.gain: 2.5}}
      second: {component: tuner, parameters: {use_sim_time: true}}
"""

IMPL = '''\
"""The user's code of Tuner."""

from tuner.Tuner import Tuner


class Tuner_impl(Tuner):
    """Tuner, with its validator."""

    def vLabel(self, value: str) -> str:
        """Refuse labels with spaces."""
        return 'no spaces, please' if ' ' in value else ''
'''


@pytest.fixture(scope='module')
def built(tmp_path_factory) -> BuiltWorkspace:
    src = tmp_path_factory.mktemp('params_src')
    (src / 'tuner' / 'src' / 'tuner').mkdir(parents=True)
    (src / 'tuner' / 'robmosys.yaml').write_text(MODEL)
    (src / 'tuner' / 'src' / 'tuner' / 'Tuner_impl.py').write_text(IMPL)
    return build_workspace(src, tmp_path_factory.mktemp('params_ws'))


def _launched(built: BuiltWorkspace) -> dict[str, NodeLaunch]:
    """Return the nodes of tuner_system's launch files, by instance."""
    share = built.share('tuner_system')
    return {n.name: n for n in read_launch_file(nodes_launch_file(share), share)}


@pytest.fixture(scope='module')
def running(built) -> Iterator[tuple[dict[str, NodeLaunch], dict[str, Background],
                                     LifecycleDriver]]:
    nodes = _launched(built)
    domain_id = free_domain_id()
    with contextlib.ExitStack() as stack:
        env = built.env(domain_id)
        processes = {name: stack.enter_context(background(node.command(built.install), env=env))
                     for name, node in nodes.items()}
        driver = stack.enter_context(LifecycleDriver(domain_id))
        for node in nodes.values():
            assert driver.state(node.fqn) == 'unconfigured'
        yield nodes, processes, driver


def test_system_wide_and_own_values_are_read_back_nested(running):
    nodes, _, driver = running
    names = ['use_sim_time', 'mode', 'controller.gain', 'controller.pid.kp', 'port']
    assert driver.parameters(nodes['first'].fqn, names) == {
        'use_sim_time': False, 'mode': 'slow', 'controller.gain': 0.7, 'controller.pid.kp': 3,
        'port': '/dev/null'}
    assert driver.parameters(nodes['second'].fqn, names) == {
        'use_sim_time': True, 'mode': 'fast', 'controller.gain': 0.5, 'controller.pid.kp': 3,
        'port': '/dev/null'}


def test_values_that_break_a_rule_are_refused_with_the_reason(running):
    nodes, _, driver = running
    fqn = nodes['second'].fqn
    refused = {
        'mode': ('medium', "parameter 'mode': 'medium' is not one of 'slow', 'fast'"),
        'label': ('much too long', "parameter 'label': 'much too long' has 13 characters, "
                  'more than 8'),
        'layers': (['a', 'd'], "parameter 'layers': element 'd' is not one of 'a', 'b', 'c'"),
    }
    for name, (value, reason) in refused.items():
        assert driver.set_parameters(fqn, {name: value})[name] == (False, reason)
    # the user's validator (Tuner_impl.py) and one embedded in the model
    assert driver.set_parameters(fqn, {'label': 'a b'})['label'] == (
        False, "parameter 'label': no spaces, please")
    assert driver.set_parameters(fqn, {'layers': ['b', 'b']})['layers'] == (
        False, "parameter 'layers': layers must differ")
    assert driver.set_parameters(fqn, {'layers': ['a', 'b', 'c']})['layers'] == (
        False, "parameter 'layers': ['a', 'b', 'c'] has 3 elements, more than 2")
    assert driver.set_parameters(fqn, {'mode': 'slow', 'label': 'ok', 'layers': ['c', 'a']}) == {
        'mode': (True, ''), 'label': (True, ''), 'layers': (True, '')}
    assert driver.parameters(fqn, ['mode', 'label', 'layers']) == {
        'mode': 'slow', 'label': 'ok', 'layers': ['c', 'a']}


def test_on_change_runs_after_an_accepted_change_and_sees_the_new_value(running):
    nodes, processes, driver = running
    fqn, process = nodes['first'].fqn, processes['first']
    assert driver.set_parameters(fqn, {'controller.gain': 0.25})['controller.gain'][0]
    assert wait_until(lambda: 'gain is now 0.25' in process.output(), 10), process.output()
    # refused (out of the range): nothing runs
    assert not driver.set_parameters(fqn, {'controller.gain': 2.0})['controller.gain'][0]
    assert driver.set_parameters(fqn, {'controller.pid.kp': 1})['controller.pid.kp'][0]
    assert wait_until(lambda: 'on_change of controller.pid.kp failed' in process.output(), 10)
    assert 'kp is now 1' in process.output()
    assert 'gain is now 2.0' not in process.output()
    assert driver.parameters(fqn, ['controller.gain', 'controller.pid.kp']) == {
        'controller.gain': 0.25, 'controller.pid.kp': 1}


def test_mapped_parameters_are_declared_per_entry_and_keep_their_rules(running):
    nodes, processes, driver = running
    first, second = nodes['first'].fqn, nodes['second'].fqn
    names = ['a.gain', 'b.gain', 'limits.a.mode', 'limits.b.mode']
    assert driver.parameters(first, names) == {
        'a.gain': 1.0, 'b.gain': 2.5, 'limits.a.mode': 'soft', 'limits.b.mode': 'soft'}
    # the second keeps the default entries, [a]: nothing is declared for b (rclpy
    # answers no value at all for a name it does not have)
    assert driver.parameters(second, names[::2]) == {'a.gain': 1.0, 'limits.a.mode': 'soft'}
    assert driver.parameters(second, ['b.gain']) == {}
    # the range of the descriptor and the rules hold for each entry
    assert not driver.set_parameters(first, {'b.gain': 7.0})['b.gain'][0]
    assert driver.set_parameters(first, {'limits.b.mode': 'firm'})['limits.b.mode'] == (
        False, "parameter 'limits.b.mode': 'firm' is not one of 'soft', 'hard'")
    assert driver.set_parameters(first, {'a.gain': 0.5}) == {'a.gain': (True, '')}
    # on_change runs, and the typed access reads each entry's values
    process = processes['first']
    assert wait_until(lambda: "joint gains [('a', 0.5), ('b', 2.5)]" in process.output(),
                      10), process.output()
    assert driver.parameters(first, ['a.gain', 'b.gain']) == {'a.gain': 0.5, 'b.gain': 2.5}


def test_the_node_still_configures_with_valid_values(running):
    nodes, processes, driver = running
    assert driver.transition(nodes['second'].fqn, 'configure'), processes['second'].output()


def test_a_start_value_that_breaks_a_rule_stops_the_node(built):
    node = _launched(built)['second']
    result = run([*node.command(built.install), '-p', 'mode:=medium'],
                 env=built.env(free_domain_id()), timeout=60)
    assert result.returncode != 0
    output = result.stdout + result.stderr
    assert "parameter 'mode': 'medium' is not one of 'slow', 'fast'" in output, output


def test_entries_of_a_mapped_array_that_break_its_rules_stop_the_node(built):
    node = _launched(built)['second']
    result = run([*node.command(built.install), '-p', 'joints:=[a, b, a]'],
                 env=built.env(free_domain_id()), timeout=60)
    assert result.returncode != 0
    output = result.stdout + result.stderr
    assert "parameter 'joints': entry 'a' is listed twice" in output, output


def test_a_validator_refuses_the_value_of_the_moment_on_configure(built):
    node = _launched(built)['second']
    domain_id = free_domain_id()
    # a start value is checked by the rules of the model, the user's validators
    # run from configure on: this one refuses it there
    with background([*node.command(built.install), '-p', 'label:=a b'],
                    env=built.env(domain_id)) as process, LifecycleDriver(domain_id) as driver:
        assert driver.state(node.fqn) == 'unconfigured', process.output()
        assert not driver.transition(node.fqn, 'configure')
        assert wait_until(lambda: re.search(
            r"configure failed:.*parameter 'label': no spaces, please", process.output(),
            re.DOTALL), 10), process.output()


def test_the_parameter_page_is_installed(built):
    page = (built.share('tuner') / 'doc' / 'parameters.md').read_text()
    assert '| `controller.pid.kp` | int | 3 | no | one of 1, 2, 3 | fKpChanged |  |' in page
    # model text is escaped: the pipe of the description does not end its cell
    assert "| one of 'slow', 'fast' |  | Speed \\| pace. |" in page
    assert "| 'abc' | no | 1 to 8 characters; validated by vLabel\\(\\) |" in page
    assert '| `<joints>.gain` | double | 1.0 | no | one per entry of joints; in \\[0.0, 5.0\\] ' \
        '| fJointGain |  |' in page
    assert '| `port` | string | none: required | no |  |  | The device it talks to. |' in page
    assert 'A parameter without default is required' in page


def test_a_required_parameter_left_unset_fails_configure_with_its_name(built):
    node = _launched(built)['second']
    domain_id = free_domain_id()
    # started without the system's parameter file: port has no value
    command = [*node.command(built.install)[:1], '--ros-args', '-r', '__node:=lonely']
    with background(command, env=built.env(domain_id)) as process, \
            LifecycleDriver(domain_id) as driver:
        assert driver.state('/lonely') == 'unconfigured', process.output()
        assert not driver.transition('/lonely', 'configure')
        assert wait_until(lambda: "configure failed: parameter 'port' has no value (it has no "
                          'default: set it in a parameter file, or with -p port:=<value>)'
                          in process.output(), 10), process.output()
        assert driver.state('/lonely') == 'unconfigured'
        # given a value, it configures
        assert driver.set_parameters('/lonely', {'port': '/dev/ttyS0'}) == {'port': (True, '')}
        assert driver.transition('/lonely', 'configure'), process.output()


def test_bringup_applies_the_launch_arguments_to_every_node(built, tmp_path):
    """--use-sim-time, --log-level, --namespace and --params-file reach the nodes."""
    operator = tmp_path / 'operator.yaml'
    # the operator's file names the nodes as they run, in the namespace; its
    # values win over the system's (first: mode slow, second: port /dev/null)
    operator.write_text('/robot1/first:\n  ros__parameters:\n    mode: fast\n'
                        '/**:\n  ros__parameters:\n    port: /dev/ttyUSB0\n')
    domain_id = free_domain_id()
    executable = built.install / 'tuner_system' / 'lib' / 'tuner_system' / 'bringup'
    with background([sys.executable, str(executable), '--use-sim-time', '--log-level', 'debug',
                     '--namespace', 'robot1', '--params-file', str(operator),
                     '--check-period', '0'], env=built.env(domain_id)) as process, \
            LifecycleDriver(domain_id) as driver:
        # bringup says so once every managed instance is active
        assert wait_until(lambda: 'bringup: 2 of 2 managed instances active' in
                          process.output(), 90), process.output()
        names = ['use_sim_time', 'mode', 'port', 'controller.gain']
        assert driver.parameters('/robot1/first', names) == {
            'use_sim_time': True, 'mode': 'fast', 'port': '/dev/ttyUSB0',
            'controller.gain': 0.7}
        assert driver.parameters('/robot1/second', names) == {
            'use_sim_time': True, 'mode': 'fast', 'port': '/dev/ttyUSB0',
            'controller.gain': 0.5}
        # the manager moved with its system; nothing is left at the root
        assert wait_until(lambda: ('tuner_system_bringup', '/robot1') in
                          driver.node.get_node_names_and_namespaces(), 10)
        assert not {('first', '/'), ('second', '/')} & set(
            driver.node.get_node_names_and_namespaces())
        # debug messages of the nodes' processes: rcl's, at node creation
        assert wait_until(lambda: re.search(r'\[DEBUG\].*first', process.output()), 10)
