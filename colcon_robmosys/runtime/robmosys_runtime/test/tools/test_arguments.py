# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The launch arguments of a system, as launch files and bringup apply them."""

import pytest
from robmosys_runtime.tools.arguments import (
    ArgumentError, log_level, matches, moved, moved_description, node_values,
    normalized_namespace, parameters_file, sim_time)
import yaml


def test_a_namespace_is_normalized_and_a_wrong_one_refused():
    assert normalized_namespace('') == ''
    assert normalized_namespace('/') == ''
    assert normalized_namespace('robot1') == '/robot1'
    assert normalized_namespace('/fleet/robot1/') == '/fleet/robot1'
    with pytest.raises(ArgumentError, match="'1robot' is not a name of a ROS 2 namespace"):
        normalized_namespace('fleet/1robot')


def test_use_sim_time_and_log_level_take_what_ros_users_type():
    assert sim_time('') is None
    assert sim_time('True') is True
    assert sim_time('false') is False
    with pytest.raises(ArgumentError, match='it is true or false'):
        sim_time('yes please')
    assert log_level('DEBUG') == 'debug'
    assert log_level(None) == ''
    with pytest.raises(ArgumentError, match='it is one of debug, info, warn, error, fatal'):
        log_level('verbose')


def test_a_namespace_moves_every_name_of_the_description():
    description = {'package': 's', 'instances': [{
        'instance': 'laser', 'namespace': '', 'fqn': '/laser',
        'remappings': [['scan', '/laser/scan']],
        'ports': [{'port': 'scan', 'name': '/laser/scan'}],
        'parameters': [{'name': 'qos_overrides./laser/scan.publisher.depth', 'value': 5},
                       {'name': 'frame', 'value': 'laser'}]}, {
        'instance': 'viewer', 'namespace': '/ops', 'fqn': '/ops/viewer', 'remappings': []}],
        'connections': [{'name': '/laser/scan'}]}
    assert moved_description(description, '') is description
    result = moved_description(description, '/robot1')
    laser, viewer = result['instances']
    assert (laser['namespace'], laser['fqn']) == ('/robot1', '/robot1/laser')
    assert laser['remappings'] == [['scan', '/robot1/laser/scan']]
    assert laser['ports'][0]['name'] == '/robot1/laser/scan'
    assert [p['name'] for p in laser['parameters']] == [
        'qos_overrides./robot1/laser/scan.publisher.depth', 'frame']
    assert (viewer['namespace'], viewer['fqn']) == ('/robot1/ops', '/robot1/ops/viewer')
    assert result['connections'] == [{'name': '/robot1/laser/scan'}]
    assert result['namespace'] == '/robot1'
    # the description given is left as it was
    assert description['instances'][0]['fqn'] == '/laser'
    assert moved('/robot1', 'relative') == 'relative'


@pytest.mark.parametrize('key, fqn, expected', [
    ('/**', '/a', True), ('/**', '/x/y/a', True), ('a', '/a', True), ('/a', '/x/a', False),
    ('/x/*', '/x/a', True), ('/x/*', '/x/y/a', False), ('/**/a', '/x/y/a', True),
    ('/**/a', '/a', True), ('/x/**', '/x/a', True), ('/x/**', '/y/a', False)])
def test_entries_match_nodes_as_ros2_matches_them(key, fqn, expected):
    assert matches(key, fqn) is expected


def _write(path, document):
    path.write_text(yaml.safe_dump(document))
    return str(path)


def test_the_operators_file_wins_over_the_system_and_the_simulated_time_between(tmp_path):
    system = _write(tmp_path / 'params.yaml', {
        '/**': {'ros__parameters': {'use_sim_time': True, 'frame': 'odom'}},
        '/laser': {'ros__parameters': {'frame': 'laser', 'limits': {'max': 4.0},
                                       'qos_overrides./laser/scan.publisher.depth': 5}},
        '/viewer': {'ros__parameters': {'use_sim_time': True}}})
    operator = _write(tmp_path / 'mine.yaml', {
        '/robot1/laser': {'ros__parameters': {'limits.max': 8.0}},
        '/**': {'ros__parameters': {'frame': 'base'}}})
    values = node_values(['/robot1/laser', '/robot1/viewer'], system, '/robot1', False,
                         operator)
    assert values == {
        '/robot1/laser': {'use_sim_time': False, 'frame': 'base', 'limits.max': 8.0,
                          'qos_overrides./robot1/laser/scan.publisher.depth': 5},
        '/robot1/viewer': {'use_sim_time': False, 'frame': 'base'}}
    # without argument, the system's own file serves
    assert parameters_file(['/laser'], system) == system
    made = parameters_file(['/laser'], system, use_sim_time=False)
    assert yaml.safe_load(open(made)) == {'/laser': {'ros__parameters': {
        'use_sim_time': False, 'frame': 'laser', 'limits.max': 4.0,
        'qos_overrides./laser/scan.publisher.depth': 5}}}


def test_a_file_that_is_no_parameter_file_is_refused_with_its_name(tmp_path):
    system = _write(tmp_path / 'params.yaml', {'/**': {'ros__parameters': {}}})
    broken = tmp_path / 'broken.yaml'
    broken.write_text('/laser: {frame: laser}\n')
    with pytest.raises(ArgumentError, match="entry '/laser' has no ros__parameters"):
        node_values(['/laser'], system, operator_file=str(broken))
    with pytest.raises(ArgumentError, match='No such file'):
        node_values(['/laser'], system, operator_file=str(tmp_path / 'none.yaml'))


def test_the_keys_above_ros_parameters_make_the_nodes_name(tmp_path):
    # as rcl reads a file: robot2: {publisher: {ros__parameters}} is /robot2/publisher
    system = _write(tmp_path / 'params.yaml', {'/**': {'ros__parameters': {}}})
    operator = tmp_path / 'mine.yaml'
    operator.write_text('robot2:\n  publisher:\n    ros__parameters: {indoor: false}\n'
                        '  ros__parameters: {rate: 2.0}\n'
                        '/robot1/:\n  publisher:\n    ros__parameters:\n')
    values = node_values(['/robot1/publisher', '/robot2/publisher', '/robot2'], system,
                         operator_file=str(operator))
    assert values == {'/robot1/publisher': {}, '/robot2/publisher': {'indoor': False},
                      '/robot2': {'rate': 2.0}}
