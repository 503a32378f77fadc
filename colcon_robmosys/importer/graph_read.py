# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""What the running ROS 2 graph shows of its nodes, read with rclpy.

A snapshot holds, for every node: its publishers, subscriptions, services,
clients, action servers and action clients with their types (and the QoS of
its topics: reliability, durability, deadline, lifespan, liveliness), its
parameters with their values and descriptors, whether it is a lifecycle node,
and what a node of robmosys_runtime announces of itself (robmosys_runtime's
announce.py). Nothing here decides what a model says: :mod:`.graph` does.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import os
import time
from typing import Any, Callable

#: entities every node has: not ports
_OWN_SERVICES = frozenset((
    'describe_parameters', 'get_parameter_types', 'get_parameters', 'list_parameters',
    'set_parameters', 'set_parameters_atomically', 'get_type_description',
    'change_state', 'get_state', 'get_available_states', 'get_available_transitions',
    'get_transition_graph'))
_OWN_TOPICS = frozenset(('/rosout', '/parameter_events'))
#: parameters rclpy and rclcpp declare on every node
_AUTOMATIC_PARAMETERS = ('use_sim_time', 'start_type_description_service')
#: a duration from this on is DDS's infinity (Fast DDS: 2^31 - 1 s and 2^32 - 1 ns)
_INFINITE_NS = (2 ** 31 - 1) * 10 ** 9

#: ParameterType -> the model's parameter type
PARAMETER_TYPES = {1: 'bool', 2: 'int', 3: 'double', 4: 'string', 5: 'byte[]',
                   6: 'bool[]', 7: 'int[]', 8: 'double[]', 9: 'string[]'}


@dataclass
class Endpoint:
    """One publisher, subscription, server or client of a node."""

    #: publisher, subscription, service, client, action_server, action_client
    kind: str
    name: str
    type: str
    #: the policies the graph shows (topics only): reliability, durability,
    #: deadline, lifespan, liveliness, liveliness_lease_duration
    qos: dict[str, Any] = field(default_factory=dict)


@dataclass
class GraphParameter:
    """A parameter of a node, its current value and its descriptor."""

    name: str
    #: the model's type; '' when it has no value (not set)
    type: str
    value: Any
    description: str = ''
    read_only: bool = False
    #: (from, to, step) of an integer or floating point range
    range: tuple[Any, Any, Any] | None = None


@dataclass
class GraphNode:
    """A node of the graph, as far as the graph shows it."""

    name: str
    namespace: str
    endpoints: list[Endpoint] = field(default_factory=list)
    #: None: the node did not answer the parameter services
    parameters: list[GraphParameter] | None = None
    lifecycle: bool = False
    #: a component container (rclcpp_components): it holds other nodes
    container: bool = False

    @property
    def fqn(self) -> str:
        """Return the fully qualified name of the node."""
        return f"{self.namespace.rstrip('/')}/{self.name}"

    def parameter(self, name: str) -> Any:
        """Return a parameter's value, None if the node has no such parameter."""
        for parameter in self.parameters or ():
            if parameter.name == name:
                return parameter.value
        return None


def read_graph(namespace: str | None, timeout: float, *, settle: float = 3.5,
               expected: Callable[[], set[str]] = set) -> list[GraphNode]:
    """Return the nodes of the graph of the current domain (under a namespace).

    Discovery takes time: the graph is read again until it has not changed for
    ``settle`` seconds (longer than Fast DDS's period of participant
    announcements, 3 s: a participant that missed the first ones is heard
    then), or ``timeout`` seconds have passed. A graph that is steady but
    lacks a node that is known to run (``expected``: fully qualified names,
    asked again every second, since processes start and end) is read on until
    the timeout: on a busy machine a participant can be heard long after the
    others.

    :raises ImportError: if rclpy is not installed
    """
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    context = rclpy.Context()
    rclpy.init(context=context, args=[])
    try:
        node = rclpy.create_node(f'_robmosys_import_{os.getpid()}', context=context,
                                 start_parameter_services=False)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        end = time.monotonic() + timeout
        nodes, stable_since = _snapshot(node, namespace), time.monotonic()
        running, asked = _visible(expected(), namespace), time.monotonic()
        # an empty graph is waited on until the timeout: the system may be starting
        while time.monotonic() < end and (
                not nodes or time.monotonic() - stable_since < settle or
                not running <= {n.fqn for n in nodes}):
            executor.spin_once(timeout_sec=0.1)
            again = _snapshot(node, namespace)
            if again != nodes:
                nodes, stable_since = again, time.monotonic()
            if time.monotonic() - asked >= 1.0:
                running, asked = _visible(expected(), namespace), time.monotonic()
        for graph_node in nodes:
            _read_qos(node, graph_node)
        _read_parameters(node, executor, nodes, max(end - time.monotonic(), 2.0))
        return nodes
    finally:
        rclpy.shutdown(context=context)


def _visible(fqns: set[str], namespace: str | None) -> set[str]:
    """Return those of these node names that a snapshot under namespace can show."""
    shown = set()
    for fqn in fqns:
        node_namespace, _, name = fqn.rpartition('/')
        if not name.startswith('_') and _under(node_namespace or '/', namespace):
            shown.add(fqn)
    return shown


def _under(namespace: str, prefix: str | None) -> bool:
    if prefix is None or prefix.rstrip('/') == '':
        return True
    prefix = '/' + prefix.strip('/')
    return namespace == prefix or namespace.startswith(prefix + '/')


def _snapshot(node: Any, namespace: str | None) -> list[GraphNode]:
    from rclpy.action import graph as action_graph
    found = []
    for name, node_namespace in sorted(node.get_node_names_and_namespaces(),
                                       key=lambda n: (n[1], n[0])):
        if name.startswith('_') or not _under(node_namespace, namespace):
            continue  # hidden nodes (this one, ros2cli's daemon) and other namespaces
        graph_node = GraphNode(name, node_namespace)
        lists = (
            ('publisher', node.get_publisher_names_and_types_by_node),
            ('subscription', node.get_subscriber_names_and_types_by_node),
            ('service', node.get_service_names_and_types_by_node),
            ('client', node.get_client_names_and_types_by_node),
            ('action_server', lambda n, ns: action_graph.get_action_server_names_and_types_by_node(
                node, n, ns)),
            ('action_client', lambda n, ns: action_graph.get_action_client_names_and_types_by_node(
                node, n, ns)),
        )
        try:
            for kind, names_and_types in lists:
                for topic, types in names_and_types(name, node_namespace):
                    graph_node.endpoints.append(Endpoint(kind, topic, types[0] if types else ''))
        except Exception:  # noqa: B902 - the node went away while it was read
            continue
        graph_node.lifecycle = any(e.kind == 'service' and e.name == f'{graph_node.fqn}/get_state'
                                   for e in graph_node.endpoints)
        graph_node.container = any(e.kind == 'service' and
                                   e.name == f'{graph_node.fqn}/_container/load_node'
                                   for e in graph_node.endpoints)
        graph_node.endpoints = sorted(
            (e for e in graph_node.endpoints if not _infrastructure(e, graph_node.fqn)),
            key=lambda e: (e.name, e.kind))
        found.append(graph_node)
    return found


def _infrastructure(endpoint: Endpoint, fqn: str) -> bool:
    """Return whether an endpoint is one every node (or every action) has."""
    name = endpoint.name
    if name in _OWN_TOPICS or '/_action/' in name:
        return True
    if name.startswith(fqn + '/'):
        rest = name[len(fqn) + 1:]
        if rest in _OWN_SERVICES or rest == 'transition_event' or rest.startswith('_'):
            return True
    # a hidden name (a segment starting with _) is nobody's port
    return any(segment.startswith('_') for segment in name.split('/'))


def _read_qos(node: Any, graph_node: GraphNode) -> None:
    """Read the QoS of a node's topics."""
    for endpoint in graph_node.endpoints:
        if endpoint.kind == 'publisher':
            infos = node.get_publishers_info_by_topic(endpoint.name)
        elif endpoint.kind == 'subscription':
            infos = node.get_subscriptions_info_by_topic(endpoint.name)
        else:
            continue
        for info in infos:
            if (info.node_name, info.node_namespace) == (graph_node.name, graph_node.namespace):
                endpoint.qos = _qos(info.qos_profile)
                break


def _qos(profile: Any) -> dict[str, Any]:
    qos: dict[str, Any] = {
        'reliability': profile.reliability.name.lower(),
        'durability': profile.durability.name.lower(),
    }
    for policy in ('deadline', 'lifespan', 'liveliness_lease_duration'):
        nanoseconds = getattr(profile, policy).nanoseconds
        if 0 < nanoseconds < _INFINITE_NS:
            qos[policy] = nanoseconds / 1e9
    qos['liveliness'] = profile.liveliness.name.lower()
    return qos


#: the services that tell a node's parameters, asked one after the other
_PARAMETER_SERVICES = ('list_parameters', 'describe_parameters', 'get_parameters')


def _read_parameters(node: Any, executor: Any, nodes: list[GraphNode], timeout: float) -> None:
    """Read the parameters of every node: their names, descriptors and values.

    Each node is asked its next question as soon as it answers the one before:
    a node that does not answer (a busy executor, a node nobody spins) costs
    the others nothing, where questions asked of all nodes at once, in three
    rounds, left every node's parameters unread behind it.
    """
    from rcl_interfaces.srv import DescribeParameters, GetParameters, ListParameters
    types = dict(zip(_PARAMETER_SERVICES, (ListParameters, DescribeParameters, GetParameters)))
    end = time.monotonic() + timeout
    answers: dict[str, list[Any]] = {n.fqn: [] for n in nodes}
    #: fqn -> the client of its current question, and the future of its answer
    asking: dict[str, tuple[Any, Any]] = {}

    def request(fqn: str, service: str) -> Any:
        if service == 'list_parameters':
            return ListParameters.Request()
        return types[service].Request(names=_names(answers[fqn][0]))
    try:
        while time.monotonic() < end and any(len(a) < 3 for a in answers.values()):
            for fqn, answered in answers.items():
                client, future = asking.get(fqn, (None, None))
                if future is not None:
                    if not future.done():
                        continue
                    answer = future.result()
                    answered.append(answer)
                    if answer is None:
                        answered[:] = [None] * 3  # no answer to build the next question on
                    node.destroy_client(client)
                    del asking[fqn]
                    client = None
                if len(answered) == 3:
                    continue
                service = _PARAMETER_SERVICES[len(answered)]
                if client is None:
                    client = node.create_client(types[service], f'{fqn}/{service}')
                    asking[fqn] = (client, None)
                if client.service_is_ready():
                    asking[fqn] = (client, client.call_async(request(fqn, service)))
            executor.spin_once(timeout_sec=0.05)
    finally:
        for client, _ in asking.values():
            node.destroy_client(client)
    for graph_node in nodes:
        answered = answers[graph_node.fqn]
        if len(answered) < 3 or None in answered:
            continue  # it did not answer: parameters stay None
        listed, descriptors, values = answered
        graph_node.parameters = [
            _parameter(name, descriptor, value) for name, descriptor, value in zip(
                _names(listed), descriptors.descriptors, values.values)]


def _names(listed: Any) -> list[str]:
    """Return the names of a node's parameters that are its own."""
    return sorted(n for n in listed.result.names if n not in _AUTOMATIC_PARAMETERS and
                  not n.startswith('qos_overrides.'))


def _parameter(name: str, descriptor: Any, value: Any) -> GraphParameter:
    parameter = GraphParameter(name, PARAMETER_TYPES.get(value.type, ''), _value(value),
                               descriptor.description, descriptor.read_only)
    for ranges in (descriptor.integer_range, descriptor.floating_point_range):
        if ranges:
            parameter.range = (ranges[0].from_value, ranges[0].to_value, ranges[0].step)
    return parameter


def _value(value: Any) -> Any:
    fields = {1: 'bool_value', 2: 'integer_value', 3: 'double_value', 4: 'string_value',
              5: 'byte_array_value', 6: 'bool_array_value', 7: 'integer_array_value',
              8: 'double_array_value', 9: 'string_array_value'}
    if value.type not in fields:
        return None
    read = getattr(value, fields[value.type])
    if value.type == 5:
        return [b if isinstance(b, int) else ord(b) for b in read]
    return list(read) if value.type > 5 else read
