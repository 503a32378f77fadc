# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The model `robmosys-import graph` makes of a graph: from snapshots, without ROS.

tests/test_import_graph.py reads real graphs; here the snapshot is written by
hand, to pin what each kind of node becomes: generated nodes refer to their
component, other nodes become external components (their process tells their
package and own names), ports on one name are connected, names two nodes share
are told apart, and every text stays text.
"""

from __future__ import annotations

from pathlib import Path
import textwrap

import yaml

from colcon_robmosys.check import load_model_file
from colcon_robmosys.importer.graph import import_graph
from colcon_robmosys.importer.graph_read import _visible, Endpoint, GraphNode, GraphParameter
from colcon_robmosys.importer.graph_yaml import Commented, dump
from colcon_robmosys.importer.processes import (
    node_processes, NodeProcess, parse_command_line, process_of)

COMPONENT = textwrap.dedent("""
    robmosys: 1
    components:
      - name: Pub
        package: pub_pkg
        language: python
        license: MIT
        maintainers: [{name: A, email: a@example.com}]
        ports:
          pText: {pattern: push, role: provided, type: std_msgs/msg/String}
          qAsk: {pattern: query, role: required, type: std_srvs/srv/Trigger}
        parameters:
          rate: {type: int, default: 10}
          label: {type: string, default: plain}
          joints: {type: 'string[]', default: [a], read_only: true}
          gain: {type: double, default: 1.0, for_each: joints}
""")


def _generated(name: str, namespace: str, ports: list[str], **values) -> GraphNode:
    parameters = [GraphParameter('robmosys.component', 'string', 'pub_pkg'),
                  GraphParameter('robmosys.ports', 'string[]', ports)]
    parameters += [GraphParameter(k, type(v).__name__, v) for k, v in values.items()]
    return GraphNode(name, namespace, [], parameters, lifecycle=True)


def test_a_snapshot_becomes_instances_components_and_connections(tmp_path: Path):
    (tmp_path / 'robmosys.yaml').write_text(COMPONENT, encoding='utf-8')
    [component] = load_model_file(tmp_path / 'robmosys.yaml').components
    nodes = [
        # generated, twice under one name: told apart, the values it changed kept
        _generated('pub', '/a', ['pText=/a/pub/pText', 'qAsk=/srv/ask'], rate=10,
                   label='a: "b" # c', joints=['a', 'b'], **{'a.gain': 1.0, 'b.gain': 2.0}),
        _generated('pub', '/b', ['pText=/b/pub/pText', 'qAsk=/b/qAsk'], rate=20,
                   label='plain'),
        # nobody's: a server on the name a generated client uses, process unknown
        GraphNode('srv', '/', [Endpoint('service', '/srv/ask', 'std_srvs/srv/Trigger')], []),
        # nobody's, its process known: its own name undone from the remapping
        GraphNode('listener', '/', [Endpoint(
            'subscription', '/a/pub/pText', 'std_msgs/msg/String',
            {'reliability': 'best_effort', 'durability': 'volatile',
             'liveliness': 'automatic'})], [
            GraphParameter('gain', 'double', 0.5, 'Gain\nsecond line', True, (0.0, 1.0, 0.0)),
            GraphParameter('nested.value', 'int', 1), GraphParameter('unset', '', None)]),
        # a manager node is no instance
        GraphNode('sys_bringup', '/', [], [GraphParameter('robmosys.system', 'string', 'sys')]),
    ]
    process = NodeProcess('listeners', 'listener', 'cpp', 'listener', '', {'in': '/a/pub/pText'})
    text = import_graph(
        nodes, 'snap_system', {'pub_pkg': component}, {}, [process],
        lambda package: ('BSD-3-Clause', [('L', 'l@example.com')]), header='Test.')
    model = yaml.safe_load(text)
    instances = model['systems'][0]['instances']
    assert instances == {
        'a_pub': {'component': 'pub_pkg', 'namespace': '/a',
                  # a mapped parameter: for each entry the node runs with
                  'parameters': {'label': 'a: "b" # c', 'joints': ['a', 'b'], 'b.gain': 2.0}},
        'b_pub': {'component': 'pub_pkg', 'namespace': '/b', 'parameters': {'rate': 20}},
        'listener': {'component': 'listeners/listener'},
        'srv': {'component': 'srv/srv'},
    }, text
    assert '# node /a/pub: renamed, another node has its name' in text
    assert '# /sys_bringup brings up the system sys: not an instance' in text
    listener, srv = model['components']
    assert listener['language'] == 'cpp' and listener['license'] == 'BSD-3-Clause', text
    # 'in' is a keyword of Python: the port is named apart from the node's own name
    assert listener['ports'] == {'in_port': {
        'pattern': 'push', 'role': 'required', 'type': 'std_msgs/msg/String', 'name': 'in',
        'qos': {'reliability': 'best_effort', 'durability': 'volatile'}}}, text
    assert listener['parameters'] == {'gain': {
        'type': 'double', 'default': 0.5, 'description': 'Gain\nsecond line', 'read_only': True,
        'range': {'from': 0.0, 'to': 1.0}}}, text
    assert 'parameters not written: nested.value (not a name a model can hold), unset ' \
        '(no value)' in ' '.join(line.strip('# ') for line in text.splitlines())
    # unknown process: the node's name stands for package and executable, and the
    # metadata is the system's (that of its components, most common first)
    assert srv['package'] == 'srv' and srv['external'] == {
        'executable': 'srv', 'lifecycle': False}, text
    assert srv['license'] == model['systems'][0]['license'], text
    # a renamed instance's default names would change: its names are kept as topics;
    # a provided port alone on a name not its own keeps it too
    assert model['systems'][0]['connections'] == [
        {'to': 'b_pub.qAsk', 'topic': '/b/qAsk'},
        {'from': 'a_pub.pText', 'to': 'listener.in_port', 'topic': '/a/pub/pText'},
        {'from': 'b_pub.pText', 'topic': '/b/pub/pText'},
        {'from': 'srv.ask', 'to': 'a_pub.qAsk'},
    ], text


def test_command_lines_tell_package_executable_language_and_remappings(tmp_path: Path):
    script = tmp_path / 'lib' / 'demo_nodes' / 'talker'
    script.parent.mkdir(parents=True)
    script.write_text('#!/usr/bin/env python3\n', encoding='utf-8')
    binary = tmp_path / 'lib' / 'demo_nodes' / 'listener'
    binary.write_bytes(b'\x7fELF\x02\x01')
    talker = parse_command_line(['python3', str(script), '--ros-args', '-r', '__node:=t',
                                 '-r', '__ns:=/robot', '--remap', 'chatter:=/talk',
                                 '-r', 'other:foo:=bar', '--params-file', 'p.yaml'])
    assert talker == NodeProcess('demo_nodes', 'talker', 'python', 't', '/robot',
                                 {'chatter': '/talk'})
    listener = parse_command_line([str(binary)])
    assert listener == NodeProcess('demo_nodes', 'listener', 'cpp')
    assert parse_command_line(['python3', 'script.py']) is None
    assert process_of([talker, listener], 't', '/robot') is talker
    assert process_of([talker, listener], 'listener', '/') is listener
    # the same node twice: the executable is known, remappings that differ are not
    again = NodeProcess('demo_nodes', 'talker', 'python', 't', '/robot', {'chatter': '/x'})
    both = process_of([talker, again], 't', '/robot')
    assert both is not None and both.executable == 'talker' and both.remappings == {}
    assert process_of([talker, NodeProcess('other', 'talker', 'python', 't', '/robot')],
                      't', '/robot') is None
    # the node a command line names is waited for in the graph; one it does not name is not
    assert (talker.named_node, listener.named_node) == ('/robot/t', '')
    assert NodeProcess('p', 'e', 'python', 'n', 'a/b/').named_node == '/a/b/n'
    assert NodeProcess('p', 'e', 'python', 'n').named_node == '/n'


def test_only_nodes_a_snapshot_can_show_are_waited_for():
    running = {'/robot/t', '/robot/arm/j', '/robotics/x', '/robot/_hidden', '/n'}
    assert _visible(running, '/robot') == {'/robot/t', '/robot/arm/j'}
    assert _visible(running, None) == running - {'/robot/_hidden'}
    assert _visible(running, '/') == running - {'/robot/_hidden'}


def test_processes_of_another_ros_domain_are_not_candidates(tmp_path: Path):
    # two systems on one host, each in its own domain, both run a node /listener
    ours = tmp_path / 'lib' / 'listener' / 'listener'
    theirs = tmp_path / 'lib' / 'other_pkg' / 'listener'
    for script in (ours, theirs):
        script.parent.mkdir(parents=True)
        script.write_text('#!/usr/bin/env python3\n', encoding='utf-8')
    proc = tmp_path / 'proc'
    for pid, script, environ in ((11, ours, b'ROS_DOMAIN_ID=7\0HOME=/x\0'),
                                 (12, theirs, b'HOME=/x\0ROS_DOMAIN_ID=8\0'),
                                 (13, theirs, b'HOME=/x\0')):
        (proc / str(pid)).mkdir(parents=True)
        (proc / str(pid) / 'cmdline').write_bytes(b'python3\0' + bytes(script) + b'\0')
        (proc / str(pid) / 'environ').write_bytes(environ)
    # a process whose environment is not readable stays a candidate
    (proc / '14').mkdir()
    (proc / '14' / 'cmdline').write_bytes(b'python3\0' + bytes(ours) + b'\0')
    found = node_processes('7', proc)
    assert [p.package for p in found] == ['listener', 'listener'], found
    assert process_of(found, 'listener', '/') == NodeProcess('listener', 'listener', 'python')
    # unset and empty are domain 0, as ROS 2 reads them
    assert sorted(p.package for p in node_processes('', proc)) == ['listener', 'other_pkg']


def test_hostile_text_reads_back_and_comments_stay_comments():
    hostile = ['a: b', '- c', '#d', '\'e"', 'x\ny', '{f: [g]}', '\\h', 'yes', 'null', '1e3',
               'é ∑ \u2028', '']
    data = {'robmosys': 1, 'values': Commented(
        {f'k{i}': value for i, value in enumerate(hostile)}, ['above\n# not\nmine'],
        'after')}
    text = dump(data, ['first\nsecond'])
    assert yaml.safe_load(text)['values'] == {f'k{i}': v for i, v in enumerate(hostile)}
    comments = [line for line in text.splitlines() if line.lstrip().startswith('#')]
    assert comments[0] == '# first second'
    assert '# above # not mine' in text


DESCRIBED = textwrap.dedent("""
    robmosys: 1
    components:
      - name: Sensor
        package: hand_sensors
        language: python
        license: MIT
        maintainers: [{name: A, email: a@example.com}]
        external: {executable: sensor, lifecycle: false}
        ports:
          pLevel: {pattern: push, role: provided, type: std_msgs/msg/String, name: level}
        parameters:
          rate: {type: int, default: 10}
          gain: {type: double, default: 1.0}
          label: {type: string, default: plain}
          frames: {type: 'string[]', default: [a, b]}
""")


def test_a_described_node_keeps_the_values_it_runs_with(tmp_path: Path):
    """An external component's instance sets its values as a generated one does.

    Only values other than the defaults: an array at its default is none.
    """
    (tmp_path / 'robmosys.yaml').write_text(DESCRIBED, encoding='utf-8')
    [component] = load_model_file(tmp_path / 'robmosys.yaml').components
    hostile = 'a: "b" # c\n- d'
    nodes = [GraphNode(name, '/', [Endpoint('publisher', f'/{name}/level',
                                            'std_msgs/msg/String')], parameters)
             for name, parameters in (
                 ('moved', [GraphParameter('rate', 'int', 25),
                            GraphParameter('gain', 'double', 1.0),
                            GraphParameter('label', 'string', hostile),
                            GraphParameter('frames', 'string[]', ['a', 'b'])]),
                 ('as_modelled', [GraphParameter('rate', 'int', 10),
                                  GraphParameter('frames', 'string[]', ['a', 'b'])]))]
    processes = [NodeProcess('hand_sensors', 'sensor', 'python', name, '',
                             {'level': f'/{name}/level'}) for name in ('moved', 'as_modelled')]
    text = import_graph(nodes, 'snap_system', {}, {'hand_sensors/sensor': component},
                        processes, lambda package: None, header='Test.')
    model = yaml.safe_load(text)
    assert 'components' not in model, text  # referred to, not made again
    assert model['systems'][0]['instances'] == {
        'as_modelled': {'component': 'hand_sensors/sensor'},
        'moved': {'component': 'hand_sensors/sensor',
                  'parameters': {'rate': 25, 'label': hostile}},
    }, text
