# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
What the ROS graph shows of the names of a system's model.

:class:`GraphReader` asks rclpy for the ends of every name of the model
(each end's node, type and QoS) once per call, and, only when a hint is
wanted, which other names have such an end.
"""

from __future__ import annotations

import importlib
import time
from typing import Any, Dict, List, Optional, Set, Tuple

from rclpy.node import Node
from robmosys_runtime.watch.conformance import Endpoint, Graph, Model


def interface(name: str) -> Any:
    """Return the Python class of an interface named ``pkg/kind/Type``."""
    package, kind, type_name = name.split('/')
    return getattr(importlib.import_module(f'{package}.{kind}'), type_name)


def _fqn(namespace: str, name: str) -> str:
    return f"{namespace.rstrip('/')}/{name}"


def _service_type(dds: str) -> str:
    """Return pkg/srv/Name of a service's reply topic type (``pkg::srv::dds_::Name_Response_``)."""
    parts = [p for p in dds.replace('::', '/').split('/') if p and p != 'dds_']
    if len(parts) < 3:
        return dds
    name = parts[-1].rstrip('_')
    for suffix in ('_Response', '_Request'):
        if name.endswith(suffix):
            name = name[:-len(suffix)]
    return f'{parts[0]}/{parts[1]}/{name}'


_FEEDBACK = '/_action/feedback'

#: the node the graph gives an end whose participant's node names it does not
#: have (rmw_dds_common's placeholders)
UNKNOWN_NODE = '_NODE_NAMESPACE_UNKNOWN_/_NODE_NAME_UNKNOWN_'
#: a topic every ROS node publishes on: its writers name every node
_EVERY_NODE = '/parameter_events'
#: seconds an end stays without its node's name before the reader reads
#: through a participant made anew: a participant just made (a tool started on
#: the manager's host) shows its ends a moment before its names, and one made
#: anew for it would be one more participant in the manager for good, which
#: discovers the whole site again (half as much again on the base station's link
#: of the fleet test, and its CPU)
RENEW_AFTER = 4.0


class GraphReader:
    """
    Reads what the ROS graph shows of the names of a model.

    A participant forgets the node names of another one with its lease (a
    link down for longer than that), and does not get them back when the two
    meet again: rmw_fastrtps sends the names once, as a ParticipantEntitiesInfo
    sample, and the reader, which has had that sample, takes no copy of it
    again; the names come back only with the next change of the other's
    nodes. Meanwhile the graph shows the other's ends with no node's name
    (:data:`UNKNOWN_NODE`) and leaves its nodes out; a participant made afresh
    sees them all. A read with such ends is *incomplete* (``Graph.complete``,
    no ground for a difference); once an end stayed so for :data:`RENEW_AFTER`
    seconds the reader reads through a participant of its own, made anew (one
    more on its host, from then on), whose reads are incomplete for ``settle``
    seconds, while it discovers the graph. An end that it cannot name either
    (the writer of a DDS application that is no ROS node) is taken as it is.
    """

    def __init__(self, node: Node, model: Model, settle: float = 3.0) -> None:
        self._node = node
        #: the node whose participant reads the graph: node's, or one of its own
        self._reading = node
        self._own: Optional[Node] = None
        self._settle = settle
        #: when the reader's own participant was made, until a read after its settle
        self._fresh: Optional[float] = None
        #: GID -> when it was first read without its node's name
        self._unnamed_since: Dict[Tuple[int, ...], float] = {}
        #: the ends a participant made afresh could not name either
        self._nameless: Set[Tuple[int, ...]] = set()
        self._model = model
        self._names = [(name, model.kind(name)) for name in model.ports]
        node.context.on_shutdown(self.close)

    def read(self) -> Graph:
        """Return the nodes, and the ends of every modelled name."""
        node = self._reading
        graph = Graph(nodes=set(node.get_fully_qualified_node_names()),
                      names_with=self._names_with, names_of_node=self._names_of_node)
        for name, kind in self._names:
            if kind == 'topic':
                graph.endpoints[name] = self._topic_ends(name, 'writer', 'reader')
            elif kind == 'service':
                graph.endpoints[name] = self._service_ends(name)
            else:
                ends = self._topic_ends(name + _FEEDBACK, 'server', 'client')
                graph.endpoints[name + _FEEDBACK] = ends
                graph.endpoints[name] = [
                    Endpoint(e.node, e.end, e.type[:-len('_FeedbackMessage')]
                             if e.type.endswith('_FeedbackMessage') else e.type, None)
                    for e in ends]
        graph.complete = self._named(graph)
        return graph

    def _named(self, graph: Graph) -> bool:
        """Tell whether the graph names the node of each end; renew the reader if not."""
        now = time.monotonic()
        if self._fresh is not None and now - self._fresh < self._settle:
            return False
        settled, self._fresh = self._fresh is not None, None
        ends = [*(e for ends in graph.endpoints.values() for e in ends),
                *self._topic_ends(_EVERY_NODE, 'writer', 'reader')]
        unnamed = {e.gid for e in ends if e.node == UNKNOWN_NODE} - self._nameless
        self._unnamed_since = {g: self._unnamed_since.get(g, now) for g in unnamed}
        if not unnamed:
            return True
        if settled:
            # a participant that discovered the graph afresh cannot name them either
            self._nameless |= unnamed
            self._unnamed_since.clear()
            return True
        if now - min(self._unnamed_since.values()) >= RENEW_AFTER:
            self._unnamed_since.clear()
            self._renew(now)
        return False

    def _renew(self, now: float) -> None:
        """Read through a participant of the reader's own, made anew."""
        import rclpy
        self.close()
        context = rclpy.Context()
        rclpy.init(context=context, args=['--ros-args', '--disable-rosout-logs'])
        self._own = rclpy.create_node(
            f'_{self._node.get_name()}_graph', namespace=self._node.get_namespace(),
            context=context, start_parameter_services=False, enable_rosout=False)
        self._reading = self._own
        self._fresh = now
        self._nameless.clear()

    def close(self) -> None:
        """End the reader's own participant, if it made one."""
        own, self._own, self._reading = self._own, None, self._node
        if own is not None:
            context = own.context
            own.destroy_node()
            context.try_shutdown()

    def _topic_ends(self, topic: str, writer: str, reader: str) -> List[Endpoint]:
        node = self._reading
        return [Endpoint(_fqn(i.node_namespace, i.node_name), end, i.topic_type, i.qos_profile,
                         tuple(i.endpoint_gid))
                for end, infos in ((writer, node.get_publishers_info_by_topic(topic)),
                                   (reader, node.get_subscriptions_info_by_topic(topic)))
                for i in infos]

    def _service_ends(self, name: str) -> List[Endpoint]:
        # DDS-based middlewares carry a service as two topics: the server writes
        # the replies, its clients read them
        reply = f'rr{name}Reply'
        node = self._reading
        return [Endpoint(_fqn(i.node_namespace, i.node_name), end,
                         _service_type(i.topic_type), None, tuple(i.endpoint_gid))
                for end, infos in (
                    ('server', node.get_publishers_info_by_topic(reply, no_mangle=True)),
                    ('client', node.get_subscriptions_info_by_topic(reply, no_mangle=True)))
                for i in infos]

    def _names_with(self, kind: str, end: str, type_name: str) -> List[str]:
        """Return the names that have such an end, of that type (for a hint)."""
        node = self._reading
        if kind == 'service':
            names = [n for n, types in node.get_service_names_and_types()
                     if type_name in types]
            return [n for n in names if any(e.end == end for e in self._service_ends(n))]
        if kind == 'action':
            feedback = f'{type_name}_FeedbackMessage'
            names = [n[:-len(_FEEDBACK)] for n, types in node.get_topic_names_and_types()
                     if n.endswith(_FEEDBACK) and feedback in types]
            pick = 'server' if end == 'server' else 'client'
            return [n for n in names if any(
                e.end == pick for e in self._topic_ends(n + _FEEDBACK, 'server', 'client'))]
        names = [n for n, types in node.get_topic_names_and_types() if type_name in types]
        return [n for n in names if any(
            e.end == end for e in self._topic_ends(n, 'writer', 'reader'))]

    def _names_of_node(self, fqn: str, kind: str, end: str) -> List[Tuple[str, str]]:
        """Return (name, type) of the ends of a kind a node has (for a hint)."""
        namespace, _, name = fqn.rpartition('/')
        node = self._reading
        ask: Any
        try:
            if kind == 'topic':
                ask = node.get_publisher_names_and_types_by_node if end == 'writer' else \
                    node.get_subscriber_names_and_types_by_node
                return [(n, t) for n, types in ask(name, namespace or '/') for t in types]
            if kind == 'service':
                ask = node.get_service_names_and_types_by_node if end == 'server' else \
                    node.get_client_names_and_types_by_node
                return [(n, t) for n, types in ask(name, namespace or '/') for t in types]
        except Exception:  # noqa: B902 - the node went away meanwhile: no hint
            return []
        return []
