# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The connections of a system: the ROS 2 name each takes, and what carries it."""

from __future__ import annotations

from dataclasses import dataclass

from colcon_robmosys.mapping.names import connection_name, node_name
from colcon_robmosys.mapping.portkinds import port_kind
from colcon_robmosys.model.types import Component, Connection, Instance, PortRef, Role, System


@dataclass(frozen=True)
class SystemConnection:
    """A connection as the smoke test checks it: a ROS 2 name that must carry data."""

    #: the ROS 2 name both ends are remapped to
    name: str
    #: the entity of the provided end (publisher, service, action_server, ...)
    entity: str
    #: pkg/kind/Type of the port
    type: str
    source: str
    #: '' for a connection of one port to a name outside the model
    target: str
    #: where the model states the connection (``file:line:column``)
    location: str = ''


def node_fqn(instance: Instance) -> str:
    """Return the fully qualified node name of an instance."""
    return node_name(instance.namespace, instance.node_name)


def provided_end(connection: Connection, components: dict[str, Component]
                 ) -> PortRef:
    """Return the end of a valid connection whose port is provided.

    A connection of one port to a name outside the model: that port.
    """
    for end in connection.ends:
        port = components[end.instance].port(end.port)
        assert port is not None
        if port.role is Role.PROVIDED or connection.target is None:
            return end
    raise AssertionError(f'no provided end in {connection}')


def connection_topics(system: System, components: dict[str, Component]
                      ) -> dict[tuple[str, str], str]:
    """Return the ROS 2 name every connected port is remapped to.

    The provided end names a connection (see
    :func:`colcon_robmosys.model.names.connection_name`): the publisher of
    a push port, the server of a send, query, action or event port. The
    validation made sure a port takes one name only.
    """
    topics: dict[tuple[str, str], str] = {}
    for connection in system.connections:
        provided = provided_end(connection, components)
        instance = system.instance(provided.instance)
        assert instance is not None
        topic = connection_name(instance.namespace, instance.node_name,
                                provided.port, connection.topic)
        for end in connection.ends:
            topics[(end.instance, end.port)] = topic
    return topics


def system_connections(system: System, components: dict[str, Component],
                       topics: dict[tuple[str, str], str]) -> tuple[SystemConnection, ...]:
    """Return the connections of a system, as its smoke test and its watch check them.

    A connection to a name outside the model has no ``target``: the smoke test
    leaves it out (what is at its other end does not run in the test), the
    system manager's watch checks that something is at that end.
    """
    connections = []
    for connection in system.connections:
        provided = provided_end(connection, components)
        port = components[provided.instance].port(provided.port)
        assert port is not None
        connections.append(SystemConnection(
            topics[(provided.instance, provided.port)], port_kind(port).entity.value,
            str(port.type), str(connection.source),
            '' if connection.target is None else str(connection.target),
            str(connection.location)))
    return tuple(connections)
