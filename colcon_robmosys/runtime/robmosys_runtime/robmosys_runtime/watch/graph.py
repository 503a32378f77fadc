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
from typing import Any, List, Tuple

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


class GraphReader:
    """Reads what the ROS graph shows of the names of a model."""

    def __init__(self, node: Node, model: Model) -> None:
        self._node = node
        self._model = model
        self._names = [(name, model.kind(name)) for name in model.ports]

    def read(self) -> Graph:
        """Return the nodes, and the ends of every modelled name."""
        node = self._node
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
        return graph

    def _topic_ends(self, topic: str, writer: str, reader: str) -> List[Endpoint]:
        node = self._node
        return [Endpoint(_fqn(i.node_namespace, i.node_name), end, i.topic_type, i.qos_profile,
                         tuple(i.endpoint_gid))
                for end, infos in ((writer, node.get_publishers_info_by_topic(topic)),
                                   (reader, node.get_subscriptions_info_by_topic(topic)))
                for i in infos]

    def _service_ends(self, name: str) -> List[Endpoint]:
        # DDS-based middlewares carry a service as two topics: the server writes
        # the replies, its clients read them
        reply = f'rr{name}Reply'
        node = self._node
        return [Endpoint(_fqn(i.node_namespace, i.node_name), end,
                         _service_type(i.topic_type))
                for end, infos in (
                    ('server', node.get_publishers_info_by_topic(reply, no_mangle=True)),
                    ('client', node.get_subscriptions_info_by_topic(reply, no_mangle=True)))
                for i in infos]

    def _names_with(self, kind: str, end: str, type_name: str) -> List[str]:
        """Return the names that have such an end, of that type (for a hint)."""
        node = self._node
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
        node = self._node
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
