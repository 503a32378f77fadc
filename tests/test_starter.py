# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Starting models (colcon robmosys-new): commented, valid, built and run.

A workspace made by robmosys-new alone (a service definition, a Python
component that uses it, a system of it) validates without a diagnostic, is
generated and built by colcon, and its node publishes and receives through
the system's connection.
"""

from __future__ import annotations

import contextlib
from pathlib import Path
import re
import sys

import pytest
from test_cpp_system import requires_rclcpp
import yaml

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.devtools.ros_env import background
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from colcon_robmosys.generators.starter import (
    class_name, Maintainer, name_problems, render_starter, starter_component,
    starter_system, StarterDefinition, StarterInfo)
from colcon_robmosys.model.types import Component, Language
from conftest import colcon, requires_ros, TEST_WORKSPACE
from harness.launch_files import nodes_launch_file, read_launch_file

INFO = StarterInfo('demo_msgs', 'Apache-2.0', (Maintainer('Jane "J" Roe', 'jane@example.com'),))
MAINTAINER = ['--maintainer', 'Jane Roe <jane.roe@example.com>']


def _info(package: str) -> StarterInfo:
    return StarterInfo(package, INFO.license, INFO.maintainers)


def _write(root: Path, package: str, text: str) -> Path:
    path = root / package / 'robmosys.yaml'
    path.parent.mkdir(parents=True)
    path.write_text(text, encoding='utf-8')
    return path


def _check(root: Path):
    return load_workspace(find_model_files([root]), InterfaceIndex([Path(sys.prefix)]))


@requires_ros
@pytest.mark.parametrize('language', ['python', 'cpp'])
@pytest.mark.parametrize('own_interfaces', [True, False], ids=['own', 'std_msgs'])
def test_starting_models_are_valid_without_a_warning(tmp_path, language, own_interfaces):
    _write(tmp_path, 'demo_msgs', render_starter(StarterDefinition(INFO)))
    component = starter_component(_info('demo_node'), Language(language),
                                  'demo_msgs' if own_interfaces else None)
    _write(tmp_path, 'demo_node', render_starter(component))
    first = _check(tmp_path)
    assert first.diagnostics == []
    node = first.workspace.model('demo_node')
    assert isinstance(node, Component)
    assert node.name == 'DemoNode' and node.language.value == language
    assert {str(p.type) for p in node.ports} == {
        'demo_msgs/msg/Sample' if own_interfaces else 'std_msgs/msg/String'}
    assert first.workspace.model('demo_msgs').info.maintainers[0].name == 'Jane "J" Roe'
    system = starter_system(_info('demo_system'), [node, node])
    _write(tmp_path, 'demo_system', render_starter(system))
    result = _check(tmp_path)
    assert result.diagnostics == []
    model = result.workspace.model('demo_system')
    assert [(i.name, i.component) for i in model.instances] == [
        ('demo_node', 'demo_node'), ('demo_node_2', 'demo_node')]
    # each receives from the other instance, not from itself
    assert sorted((c.ends[0].instance, c.ends[1].instance) for c in model.connections) == [
        ('demo_node', 'demo_node_2'), ('demo_node_2', 'demo_node')]


#: mappings whose keys are names the user chooses, not keys of the format
NAME_MAPS = {'communication_objects', 'queries', 'fields', 'constants', 'ports', 'activities',
             'functions', 'parameters', 'instances'}


def _format_keys(value: object, parent: str = '') -> set[str]:
    keys: set[str] = set()
    if isinstance(value, dict):
        for key, item in value.items():
            if parent not in NAME_MAPS:
                keys.add(key)
            keys |= _format_keys(item, key)
    elif isinstance(value, list):
        for item in value:
            keys |= _format_keys(item, parent)
    return keys


@pytest.mark.parametrize('language', ['python', 'cpp'])
def test_every_key_is_explained(language):
    """Each key of the format that a starting model uses is named in one of its comments."""
    system = starter_system(_info('demo_system'), [_check(TEST_WORKSPACE / 'src').workspace.model(
        'publisher')])
    for starter in (StarterDefinition(INFO), system,
                    starter_component(_info('demo_node'), Language(language), None)):
        text = render_starter(starter)
        comments = ' '.join(line.split('#', 1)[1] for line in text.splitlines() if '#' in line)
        words = set(re.findall(r'[a-z_]+', comments)) | set(re.findall(
            r'^[ -]*(\w+):[^#\n]*#', text, re.MULTILINE))
        keys = _format_keys(yaml.safe_load(text))
        assert keys and keys <= words, keys - words


def test_names_follow_the_rules_of_the_checks():
    assert name_problems('component', 'my_node') == []
    assert class_name('my_node2_x') == 'MyNode2X'
    assert 'is not a valid ROS 2 package name' in name_problems('definition', 'My-Msgs')[0]
    assert 'keyword' in name_problems('system', 'class')[0]
    assert name_problems('component', 'none') == [
        "the class name 'None' made of 'none' is a Python keyword"]


def test_a_system_of_existing_components_is_wired_by_pattern_and_type():
    result = _check(TEST_WORKSPACE / 'src')
    components = [result.workspace.model(p) for p in ('publisher', 'subscriber', 'sender')]
    system = starter_system(_info('wired'), components)
    assert system.connections == (('publisher.pMap', 'subscriber.rMap'),)
    # sender's required send port has no server among the instances
    assert system.unconnected == ('sender.sText',)
    text = render_starter(system)
    assert '# sender.sText is not connected' in text
    assert '#   indoor: false   # bool' in text
    assert yaml.safe_load(text)['systems'][0]['connections'] == [
        {'from': 'publisher.pMap', 'to': 'subscriber.rMap'}]


# the verb -----------------------------------------------------------------

def _new(args: list[str], cwd: Path):
    return colcon(['robmosys-new', *args, '--path', 'src', *MAINTAINER], cwd=cwd)


@requires_ros
def test_the_verb_never_replaces_a_file_and_refuses_bad_names(tmp_path):
    model = tmp_path / 'src' / 'demo_msgs' / 'robmosys.yaml'
    model.parent.mkdir(parents=True)
    model.write_text('# mine\n')
    result = _new(['definition', 'demo_msgs'], tmp_path)
    assert result.returncode == 1
    assert 'src/demo_msgs/robmosys.yaml: error: the file exists' in result.stderr
    assert model.read_text() == '# mine\n'
    result = _new(['component', 'Demo-Node', '--interfaces', 'x'], tmp_path)
    assert result.returncode == 1
    assert result.stderr.splitlines() == [
        "error: 'Demo-Node' is not a valid ROS 2 package name: lower case letters, digits and "
        'single underscores, starting with a letter, at least two characters, not ending '
        'with an underscore',
        "error: --interfaces: 'x' is not a valid ROS 2 package name: lower case letters, "
        'digits and single underscores, starting with a letter, at least two characters, '
        'not ending with an underscore']
    result = _new(['system', 'demo_system', '--components', 'nowhere'], tmp_path)
    assert result.returncode == 1
    assert "error: --components: 'nowhere': no component of the workspace" in result.stderr
    assert not (tmp_path / 'src' / 'demo_system').exists()


@requires_ros
@pytest.mark.integration
def test_a_workspace_of_starting_models_builds_and_runs(tmp_path, domain_id):
    for args in (['definition', 'demo_msgs'],
                 ['component', 'demo_node', '--interfaces', 'demo_msgs'],
                 ['component', 'demo_cpp', '--language', 'cpp'],
                 ['system', 'demo_system', '--components', 'demo_node']):
        result = _new(args, tmp_path)
        assert result.returncode == 0, result.stderr
        assert result.stdout.startswith(f'created src/{args[1]}/robmosys.yaml: ')
    result = colcon(['robmosys-generate', '--validate-only'], cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stderr == ''
    assert '4 package(s) valid: demo_cpp, demo_msgs, demo_node, demo_system' in result.stdout
    result = colcon(['robmosys-generate'], cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert (tmp_path / 'src' / 'demo_node' / 'src' / 'demo_node' / 'DemoNode_impl.py').is_file()
    assert (tmp_path / 'src' / 'demo_cpp' / 'src' / 'demo_cpp' / 'DemoCpp_impl.cpp').is_file()
    result = colcon(['build', '--packages-up-to', 'demo_system'], cwd=tmp_path, timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr

    install = tmp_path / 'install'
    share = install / 'demo_system' / 'share' / 'demo_system'
    (node,) = read_launch_file(nodes_launch_file(share), share)
    from colcon_robmosys.devtools import ros_env
    env = ros_env.workspace_env(install, ros_env.loopback_env(domain_id))
    with contextlib.ExitStack() as stack:
        process = stack.enter_context(background(node.command(install), env=env))
        driver = stack.enter_context(LifecycleDriver(domain_id))
        assert driver.transition(node.fqn, 'configure')
        assert "configured with text 'hello'" in process.output()
        assert driver.transition(node.fqn, 'activate')
        # it publishes, and receives what it publishes through the system's connection
        assert wait_until(lambda: 'fReceive is not implemented yet' in process.output(),
                          timeout=20), process.output()
        assert 'publishing: hello' in process.output()
        assert driver.transition(node.fqn, 'deactivate')


@requires_ros
@pytest.mark.integration
@requires_rclcpp
def test_the_cpp_starting_component_builds_and_runs(tmp_path, domain_id):
    result = _new(['component', 'demo_cpp', '--language', 'cpp'], tmp_path)
    assert result.returncode == 0, result.stderr
    result = colcon(['robmosys-generate'], cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    result = colcon(['build', '--packages-up-to', 'demo_cpp'], cwd=tmp_path, timeout=900)
    assert result.returncode == 0, result.stdout + result.stderr
    # its functions' code is the model's: nothing for the user to fill to run it
    install = tmp_path / 'install'
    executable = install / 'demo_cpp' / 'lib' / 'demo_cpp' / 'DemoCpp'
    from colcon_robmosys.devtools import ros_env
    env = ros_env.workspace_env(install, ros_env.loopback_env(domain_id))
    command = [str(executable), '--ros-args', '-r', '__node:=starter']
    with contextlib.ExitStack() as stack:
        process = stack.enter_context(background(command, env=env))
        driver = stack.enter_context(LifecycleDriver(domain_id))
        assert driver.transition('/starter', 'configure'), process.output()
        assert "configured with text 'hello'" in process.output()
        assert driver.transition('/starter', 'activate')
        assert wait_until(lambda: 'publishing: hello' in process.output(), timeout=20), \
            process.output()
        assert driver.transition('/starter', 'deactivate')


def test_a_starting_system_with_two_modes(tmp_path):
    """``robmosys-new system --modes``: running (every managed instance) and idle (none)."""
    _write(tmp_path, 'demo_node', render_starter(
        starter_component(_info('demo_node'), Language('python'), None)))
    node = _check(tmp_path).workspace.model('demo_node')
    text = render_starter(starter_system(_info('demo_system'), [node, node], modes=True))
    _write(tmp_path, 'demo_system', text)
    result = _check(tmp_path)
    assert result.diagnostics == []
    model = result.workspace.model('demo_system')
    assert model.initial_mode == 'running'
    assert [(m.name, m.active) for m in model.modes] == [
        ('running', ('demo_node', 'demo_node_2')), ('idle', ())]
    comments = ' '.join(line.split('#', 1)[1] for line in text.splitlines() if '#' in line)
    assert {'modes', 'initial', 'active', 'parameters'} <= set(re.findall(r'[a-z_]+', comments))
