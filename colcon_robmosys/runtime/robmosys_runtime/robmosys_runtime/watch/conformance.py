# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The model against the running system: what differs, without rclpy.

A system's description (``bringup.json``) holds every instance, its ports
(the ROS name each is on, its entity and type), its parameter values and where
the model writes each of them. :func:`compare` takes what the ROS graph shows
(:class:`Graph`) and returns each difference from the model, keyed so that a
watch reports it once when it appears and once when it clears
(:mod:`robmosys_runtime.watch.watcher` reads the graph with rclpy).
"""

from __future__ import annotations

from dataclasses import dataclass, field
import difflib
from typing import Any, Callable, Dict, Iterable, List, Optional, Set, Tuple

#: entity of a port -> (kind of name, the end it is on the graph)
ENTITIES = {
    'publisher': ('topic', 'writer'), 'subscription': ('topic', 'reader'),
    'service': ('service', 'server'), 'client': ('service', 'client'),
    'action_server': ('action', 'server'), 'action_client': ('action', 'client'),
    'event_server': ('action', 'server'), 'event_client': ('action', 'client'),
}
#: the end a required port needs on its name
COUNTERPART = {'writer': 'reader', 'reader': 'writer', 'client': 'server', 'server': 'client'}
#: how a message says each end
WORDS = {'writer': 'publisher', 'reader': 'subscription', 'server': 'server',
         'client': 'client'}


@dataclass(frozen=True)
class Endpoint:
    """An end of a name in the ROS graph."""

    #: the fully qualified name of its node
    node: str
    #: writer, reader, server or client
    end: str
    #: pkg/kind/Type
    type: str  # noqa: A003 - the graph's word
    #: the QoS profile of a topic's end (rclpy's QoSProfile), None for a service
    qos: Any = None
    #: the endpoint's GID, if the graph gave one: the QoS of two ends is compared once
    gid: Tuple[int, ...] = ()


@dataclass
class Graph:
    """What the ROS graph shows of the names of a system, and what listens on them."""

    #: fully qualified names of the nodes
    nodes: Set[str] = field(default_factory=set)
    #: name -> its ends
    endpoints: Dict[str, List[Endpoint]] = field(default_factory=dict)
    #: (kind, end, type) -> the names that have such an end; asked only for a hint
    names_with: Optional[Callable[[str, str, str], List[str]]] = None
    #: (node, kind, end) -> [(name, type)] of a node; asked only for a hint
    names_of_node: Optional[Callable[[str, str, str], List[Tuple[str, str]]]] = None
    #: whether the graph names the node of every end (see :mod:`.graph`): a
    #: graph that does not is no ground for a difference
    complete: bool = True


@dataclass(frozen=True)
class Difference:
    """A difference between the model and the running system."""

    #: what it is about, the same from one check to the next
    key: str
    #: where the model states what differs: ``file:line:column``
    location: str
    #: the status it belongs to: ``instance <name>`` or ``connection <index>``
    subject: str
    message: str

    def line(self, severity: str = 'error') -> str:
        """Return the difference as a compiler writes a problem."""
        return f'{self.location}: {severity}: {self.message}'


#: (writer GID, reader GID) -> _qos_problem of the two: an endpoint keeps its QoS
_QOS_PROBLEMS: Dict[Tuple[Tuple[int, ...], Tuple[int, ...]], Optional[str]] = {}


def _qos_problem_of(writer: Endpoint, reader: Endpoint) -> Optional[str]:
    """Return why a writer's QoS cannot reach a reader's, once per pair of endpoints."""
    if not writer.gid or not reader.gid:
        return _qos_problem(writer.qos, reader.qos)
    key = (writer.gid, reader.gid)
    if key not in _QOS_PROBLEMS:
        if len(_QOS_PROBLEMS) > 100000:
            _QOS_PROBLEMS.clear()
        _QOS_PROBLEMS[key] = _qos_problem(writer.qos, reader.qos)
    return _QOS_PROBLEMS[key]


def _qos_problem(writer: Any, reader: Any) -> Optional[str]:
    """Return why a writer's QoS cannot reach a reader's, or None."""
    from rclpy.qos import qos_check_compatible, QoSCompatibility
    try:
        compatibility, reason = qos_check_compatible(writer, reader)
    except Exception:  # noqa: B902 - a profile the graph could not tell in full
        return None
    if compatibility == QoSCompatibility.ERROR:
        return reason.strip().rstrip('.') or 'incompatible QoS'
    return None


@dataclass
class State:
    """What a watch knows beyond the graph: states, parameter values, silences."""

    #: instance -> whether the system is up and the instance should show its ports
    up: Dict[str, bool] = field(default_factory=dict)
    #: instance -> whether its node should be in the graph now
    present: Dict[str, bool] = field(default_factory=dict)
    #: instance -> why it is not in the state the model gives it ('' if it is)
    wrong_state: Dict[str, str] = field(default_factory=dict)
    #: node fqn -> parameter -> value seen at run time
    parameters: Dict[str, Dict[str, Any]] = field(default_factory=dict)
    #: instance.port -> seconds since its name last carried a message, where too long
    silent: Dict[str, float] = field(default_factory=dict)


class Model:
    """A system's description, indexed for :func:`compare`."""

    def __init__(self, description: Dict[str, Any], own_nodes: Iterable[str] = ()) -> None:
        self.package = description['package']
        #: the mode whose values are compared with ('' for a system without modes)
        self.mode = ''
        self.instances = {i['instance']: i for i in description['instances']}
        self.connections = description.get('connections', [])
        #: nodes of the model, and of the system's own tools (the manager, a check)
        self.nodes = {i['fqn'] for i in self.instances.values()} | set(own_nodes)
        #: name -> [(instance, port)]
        self.ports: Dict[str, List[Tuple[str, Dict[str, Any]]]] = {}
        for name, instance in self.instances.items():
            for port in instance.get('ports', ()):
                self.ports.setdefault(port['name'], []).append((name, port))
        #: (instance, port) -> index of its first connection
        self.connection_of: Dict[Tuple[str, str], int] = {}
        #: name -> index of its first connection
        self.connection_on: Dict[str, int] = {}
        for index, connection in enumerate(self.connections):
            self.connection_on.setdefault(connection['name'], index)
            for end in (connection['from'], connection['to']):
                if end:
                    instance, port = end.rsplit('.', 1)
                    self.connection_of.setdefault((instance, port), index)

    def kind(self, name: str) -> str:
        """Return topic, service or action: what a modelled name is."""
        return ENTITIES[self.ports[name][0][1]['entity']][0]

    def subject(self, instance: str, port: str) -> Tuple[str, str]:
        """Return the status and the location of a port: its connection's, or its instance's."""
        index = self.connection_of.get((instance, port))
        if index is None:
            return f'instance {instance}', self.instances[instance].get('location', '')
        return f'connection {index}', self.connections[index].get('location', '')

    def name_subject(self, name: str) -> Tuple[str, str]:
        """Return the status and the location of a name: its first connection's."""
        index = self.connection_on.get(name)
        if index is not None:
            return f'connection {index}', self.connections[index].get('location', '')
        instance, port = self.ports[name][0]
        return self.subject(instance, port['port'])

    def connection_label(self, index: int) -> str:
        """Return how a status names a connection."""
        connection = self.connections[index]
        return f"{connection['from']} -> {connection['to'] or connection['name']}"


def compare(model: Model, graph: Graph, state: State) -> Dict[str, Difference]:
    """Return every difference between the model and the graph, by key."""
    found: Dict[str, Difference] = {}

    def add(key: str, subject: str, location: str, message: str) -> None:
        found.setdefault(key, Difference(key, location, subject, message))

    for name, instance in model.instances.items():
        where = instance.get('location', '')
        if name in state.wrong_state:
            add(f'state {name}', f'instance {name}', where,
                f'instance {name} {state.wrong_state[name]}')
        elif state.present.get(name, False) and instance['fqn'] not in graph.nodes:
            add(f'node {name}', f'instance {name}', where,
                f"instance {name}: node {instance['fqn']} is not in the ROS graph")
    for name in model.ports:
        _compare_name(model, graph, state, name, add)
    for key, subject, where, message in _parameters(model, state):
        add(key, subject, where, message)
    for which, seconds in state.silent.items():
        instance, port = which.split('.', 1)
        entry = next(p for p in model.instances[instance]['ports'] if p['port'] == port)
        subject, where = model.subject(instance, port)
        add(f'silent {which}', subject, where,
            f"port {which} has sent nothing on {entry['name']} for {seconds:.1f} s "
            f"(its activities run every {entry['period']:g} s) while the instance is active")
    return found


def _compare_name(model: Model, graph: Graph, state: State, name: str,
                  add: Callable[[str, str, str, str], None]) -> None:
    """Compare the ends of one modelled name with the model."""
    ports = model.ports[name]
    kind = model.kind(name)
    ends = graph.endpoints.get(name, [])
    modelled_type = ports[0][1]['type']
    up = {i for i, _ in ports if state.up.get(i, False)}
    # each port of an instance that is up is there, of its type
    for instance, port in ports:
        if instance not in up:
            continue
        fqn = model.instances[instance]['fqn']
        end = ENTITIES[port['entity']][1]
        mine = [e for e in ends if e.node == fqn and e.end == end]
        subject, where = model.subject(instance, port['port'])
        which = f"{instance}.{port['port']}"
        if not mine:
            add(f'missing {which}', subject, where,
                f'port {which}: node {fqn} has no {WORDS[end]} on {name}' +
                _elsewhere(graph, fqn, kind, end, port['type'], name))
        elif all(e.type != port['type'] for e in mine):
            add(f'type {which}', subject, where,
                f'port {which}: the {WORDS[end]} of node {fqn} on {name} is of type '
                f"{mine[0].type}, the model's is {port['type']}")
    # a required port has its counterpart, unless a modelled one is down (reported so)
    for instance, port in ports:
        end = ENTITIES[port['entity']][1]
        if instance not in up or not port['required'] or port.get('unconnected'):
            continue
        wanted = COUNTERPART[end]
        if any(not p['required'] for _, p in ports):
            continue  # a modelled provider: its own port is reported if it is not there
        if not any(e.end == wanted for e in ends):
            which = f"{instance}.{port['port']}"
            subject, where = model.subject(instance, port['port'])
            hint = _near(graph, kind, wanted, port['type'], name)
            # another hint, another difference: reported again
            add(f'alone {which}{hint}', subject, where,
                f'{name} has no {WORDS[wanted]}' + (hint or (
                    '' if port['connected'] else
                    f' (required port {which} is not connected in the model)')))
    subject, where = model.name_subject(name)
    # ends the model does not have
    servers = [e for e in ends if e.end == 'server']
    modelled_servers = sorted(e.node for e in servers if e.node in model.nodes)
    if len(servers) > 1 and not modelled_servers:
        # a name outside the model: one server is what the model's client expects
        add(f"servers {name} {' '.join(sorted(e.node for e in servers))}", subject, where,
            f'{name} has {len(servers)} servers, nodes '
            f"{', '.join(sorted(e.node for e in servers))} (the model expects one)")
    writers_modelled = any(not p['required'] and ENTITIES[p['entity']][1] == 'writer'
                           for _, p in ports)
    for e in ends:
        if e.node in model.nodes:
            continue
        if e.type != modelled_type:
            add(f'foreign type {name} {e.node} {e.end}', subject, where,
                f'{name}: node {e.node} has a {WORDS[e.end]} of type {e.type}, '
                f"the model's is {modelled_type}")
        elif e.end == 'server' and len(servers) > 1 and modelled_servers:
            add(f'second server {name} {e.node}', subject, where,
                f"{name} has a second server, node {e.node} (the model's: "
                f"{', '.join(modelled_servers)})")
        elif e.end == 'writer' and kind == 'topic' and writers_modelled:
            add(f'second writer {name} {e.node}', subject, where,
                f'{name} has a publisher the model does not have: node {e.node}')
    # QoS between the ends that are there
    topic_ends = ends if kind == 'topic' else graph.endpoints.get(f'{name}/_action/feedback', [])
    writers = [e for e in topic_ends if e.end in ('writer', 'server') and e.qos is not None]
    readers = [e for e in topic_ends if e.end in ('reader', 'client') and e.qos is not None]
    for w in writers:
        for r in readers:
            problem = _qos_problem_of(w, r)
            if problem:
                add(f'qos {name} {w.node} {r.node}', subject, where,
                    f'{name}: the QoS of the {WORDS[w.end]} of node {w.node} and the '
                    f'{WORDS[r.end]} of node {r.node} cannot match: {problem}')


def _near(graph: Graph, kind: str, end: str, type_name: str, name: str) -> str:
    """Return a hint: a name like ``name`` with such an end, of the same type."""
    if graph.names_with is None:
        return ''
    candidates = [n for n in graph.names_with(kind, end, type_name) if n != name]
    close = difflib.get_close_matches(name, candidates, n=1, cutoff=0.8)
    if not close:
        return ''
    return f'; {close[0]} has one, of the same type'


def _elsewhere(graph: Graph, fqn: str, kind: str, end: str, type_name: str,
               name: str) -> str:
    """Return a hint: where the node has such an end, or a name like ``name`` has one."""
    if graph.names_of_node is not None:
        other = [n for n, t in graph.names_of_node(fqn, kind, end) if t == type_name]
        if other:
            return f'; it has one of that type on {other[0]}'
    return _near(graph, kind, end, type_name, name)


def same_value(seen: Any, expected: Any) -> bool:
    """Tell whether a parameter value seen at run time is the model's."""
    if isinstance(expected, list) or isinstance(seen, (list, tuple)):
        seen_list = list(seen) if isinstance(seen, (list, tuple, bytes)) else None
        expected_list = list(expected) if isinstance(expected, (list, tuple)) else None
        return seen_list is not None and expected_list is not None and \
            len(seen_list) == len(expected_list) and \
            all(same_value(s, e) for s, e in zip(seen_list, expected_list))
    if isinstance(expected, bool) or isinstance(seen, bool):
        return seen is expected or seen == expected and type(seen) is type(expected)
    if isinstance(expected, (int, float)) and isinstance(seen, (int, float)):
        return abs(float(seen) - float(expected)) <= 1e-9 * max(1.0, abs(float(expected)))
    return bool(seen == expected)


def _parameters(model: Model, state: State) -> List[Tuple[str, str, str, str]]:
    found = []
    for name, instance in model.instances.items():
        seen = state.parameters.get(instance['fqn'], {})
        for parameter in instance.get('parameters', ()):
            if parameter['name'] not in seen:
                continue
            value = seen[parameter['name']]
            if not same_value(value, parameter['value']):
                found.append((
                    f"parameter {name} {parameter['name']}", f'instance {name}',
                    parameter['location'],
                    f"parameter {parameter['name']} of instance {name} is {value!r}, "
                    f"{f'mode {model.mode}' if model.mode else 'the model'} gives "
                    f"{parameter['value']!r}"))
    return found
