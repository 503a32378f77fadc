# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The model against a graph: each kind of difference, and none when they agree."""

from rclpy.qos import QoSProfile, ReliabilityPolicy
from robmosys_runtime.tools.locations import resolve_locations
from robmosys_runtime.watch.conformance import compare, Endpoint, Graph, Model, same_value, State

RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
BEST_EFFORT = QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT)


def _port(port, entity, name, type_name, required, period=None):
    return {'port': port, 'entity': entity, 'name': name, 'type': type_name,
            'required': required, 'connected': True, 'period': period,
            'unconnected': False, 'quiet': False}


DESCRIPTION = {
    'package': 'demo_system',
    'instances': [
        {'instance': 'talker', 'fqn': '/talker', 'managed': True, 'location': 'm.yaml:5:7',
         'ports': [_port('pText', 'publisher', '/text', 'std_msgs/msg/String', False, 0.1)],
         'parameters': [{'name': 'rate', 'value': 10.0, 'location': 'm.yaml:6:20'}]},
        {'instance': 'listener', 'fqn': '/listener', 'managed': True,
         'location': 'm.yaml:7:7',
         'ports': [_port('rText', 'subscription', '/text', 'std_msgs/msg/String', True),
                   _port('qAdd', 'client', '/camera/add', 'demo/srv/Add', True)],
         'parameters': []},
    ],
    'connections': [
        {'name': '/text', 'entity': 'publisher', 'type': 'std_msgs/msg/String',
         'from': 'talker.pText', 'to': 'listener.rText', 'location': 'm.yaml:9:9'},
        {'name': '/camera/add', 'entity': 'client', 'type': 'demo/srv/Add',
         'from': 'listener.qAdd', 'to': '', 'location': 'm.yaml:10:9'},
    ],
}


def _graph(**extra):
    endpoints = {
        '/text': [Endpoint('/talker', 'writer', 'std_msgs/msg/String', RELIABLE),
                  Endpoint('/listener', 'reader', 'std_msgs/msg/String', RELIABLE)],
        '/camera/add': [Endpoint('/listener', 'client', 'demo/srv/Add'),
                        Endpoint('/camera', 'server', 'demo/srv/Add')],
    }
    for name, ends in extra.items():
        endpoints[name.replace('_', '/')] = endpoints.get(name.replace('_', '/'), []) + ends
    return Graph(nodes={'/talker', '/listener', '/camera'}, endpoints=endpoints)


def _compare(graph, **state):
    model = Model(DESCRIPTION, own_nodes=['/demo_system_bringup'])
    return {d.key: d for d in compare(model, graph, State(
        up={'talker': True, 'listener': True}, **state)).values()}


def test_a_system_as_its_model_has_no_difference():
    assert _compare(_graph()) == {}


def test_a_foreign_type_a_second_server_and_a_second_writer_are_differences():
    found = _compare(_graph(
        _text=[Endpoint('/intruder', 'writer', 'std_msgs/msg/Int32', RELIABLE),
               Endpoint('/copy', 'writer', 'std_msgs/msg/String', RELIABLE),
               Endpoint('/echo', 'reader', 'std_msgs/msg/String', RELIABLE)],
        _camera_add=[Endpoint('/another', 'server', 'demo/srv/Add')]))
    messages = sorted((d.location, d.message) for d in found.values())
    assert messages == [
        ('m.yaml:10:9', '/camera/add has 2 servers, nodes /another, /camera (the model '
         'expects one)'),
        ('m.yaml:9:9', '/text has a publisher the model does not have: node /copy'),
        ('m.yaml:9:9', '/text: node /intruder has a publisher of type std_msgs/msg/Int32, '
         "the model's is std_msgs/msg/String"),
    ]


def test_qos_that_cannot_match_is_a_difference():
    graph = _graph()
    graph.endpoints['/text'][0] = Endpoint('/talker', 'writer', 'std_msgs/msg/String',
                                           BEST_EFFORT)
    (difference,) = _compare(graph).values()
    assert difference.location == 'm.yaml:9:9'
    assert difference.message.startswith(
        '/text: the QoS of the publisher of node /talker and the subscription of node '
        '/listener cannot match: ')


def test_a_missing_end_and_an_outside_name_with_nothing_there_are_differences():
    graph = _graph()
    graph.endpoints['/camera/add'] = [Endpoint('/listener', 'client', 'demo/srv/Add')]
    graph.names_with = lambda kind, end, type_name: ['/camera/ad', '/elsewhere/else']
    graph.endpoints['/text'] = graph.endpoints['/text'][1:]
    messages = sorted(d.line() for d in _compare(graph).values())
    assert messages == [
        'm.yaml:10:9: error: /camera/add has no server; /camera/ad has one, of the same type',
        'm.yaml:9:9: error: port talker.pText: node /talker has no publisher on /text',
    ]


def test_states_parameters_and_silence_are_differences():
    graph = _graph()
    graph.nodes.discard('/talker')
    found = _compare(graph, present={'talker': True},
                     wrong_state={'listener': 'is inactive, not active'},
                     parameters={'/talker': {'rate': 2.5}}, silent={'talker.pText': 1.5})
    messages = sorted(d.line() for d in found.values())
    assert messages == [
        'm.yaml:5:7: error: instance talker: node /talker is not in the ROS graph',
        'm.yaml:6:20: error: parameter rate of instance talker is 2.5, the model gives 10.0',
        'm.yaml:7:7: error: instance listener is inactive, not active',
        'm.yaml:9:9: error: port talker.pText has sent nothing on /text for 1.5 s (its '
        'activities run every 0.1 s) while the instance is active',
    ]


def test_values_compare_as_parameters_do():
    assert same_value(10, 10.0) and same_value([1, 2], (1, 2)) and same_value('a', 'a')
    assert not same_value(True, 1) and not same_value([1], [1, 2]) and not same_value('a', 'b')


def test_a_port_the_model_leaves_unconnected_is_no_difference():
    graph = _graph()
    graph.endpoints['/camera/add'] = [Endpoint('/listener', 'client', 'demo/srv/Add')]
    description = {**DESCRIPTION, 'connections': DESCRIPTION['connections'][:1]}
    description['instances'] = [dict(i) for i in DESCRIPTION['instances']]
    listener = description['instances'][1]
    listener['ports'] = [dict(listener['ports'][0]), dict(
        listener['ports'][1], connected=False, name='/listener/qAdd')]
    graph.endpoints['/listener/qAdd'] = graph.endpoints.pop('/camera/add')
    model = Model(description)
    state = State(up={'talker': True, 'listener': True})
    (difference,) = compare(model, graph, state).values()
    assert difference.line() == 'm.yaml:7:7: error: /listener/qAdd has no server (required ' \
        'port listener.qAdd is not connected in the model)'
    listener['ports'][1]['unconnected'] = True
    assert compare(Model(description), graph, state) == {}


def test_locations_point_at_the_installed_model_of_the_first_prefix_that_has_it(tmp_path):
    # bringup.json names the installed copy relative to its prefix: no path of the
    # machine that built it; the manager reports the file of this machine's prefix
    underlay, overlay = tmp_path / 'underlay', tmp_path / 'overlay'
    model = 'share/a_system/robmosys/robmosys.yaml'
    for prefix in (underlay, overlay):
        (prefix / model).parent.mkdir(parents=True)
        (prefix / model).write_text('robmosys: 1\n')
    description = {
        'instances': [{'location': f'{model}:7:5',
                       'parameters': [{'name': 'rate', 'location': f'{model}:9:20'}]}],
        'connections': [{'location': 'share/gone/robmosys/robmosys.yaml:3:7'},
                        {'location': '/elsewhere/robmosys.yaml:4:1'}]}
    resolve_locations(description, [str(overlay), str(underlay)])
    assert description['instances'][0]['location'] == f'{overlay / model}:7:5'
    assert description['instances'][0]['parameters'][0]['location'] == \
        f'{overlay / model}:9:20'
    # a file no prefix has, and a path of another form, stay as they are
    assert [c['location'] for c in description['connections']] == [
        'share/gone/robmosys/robmosys.yaml:3:7', '/elsewhere/robmosys.yaml:4:1']
