# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The diagram of a system package: its instances, their ports, the data's way."""

from __future__ import annotations

from dataclasses import dataclass

from colcon_robmosys.mapping.connections import node_fqn, provided_end
from colcon_robmosys.mapping.portkinds import port_kind
from colcon_robmosys.model.types import Component, PortRef, Role, System


@dataclass(frozen=True)
class DiagramPort:
    """A port in the diagram."""

    name: str
    role: str
    pattern: str


@dataclass(frozen=True)
class DiagramInstance:
    """An instance in the diagram."""

    name: str
    fqn: str
    component: str
    package: str
    managed: bool
    ports: tuple[DiagramPort, ...]


@dataclass(frozen=True)
class DiagramEdge:
    """A connection in the diagram, drawn the way the data flows."""

    source: str
    source_port: str
    target: str
    target_port: str
    label: str


def diagram_instances(system: System, components: dict[str, Component]
                      ) -> tuple[DiagramInstance, ...]:
    """Return the instances of a system with their ports, in the model's order."""
    return tuple(
        DiagramInstance(
            name=i.name, fqn=node_fqn(i), component=components[i.name].name,
            package=components[i.name].package, managed=i.activate,
            ports=tuple(DiagramPort(p.name, p.role.value, p.pattern.value)
                        for p in components[i.name].ports))
        for i in system.instances)


def diagram_edges(system: System, components: dict[str, Component],
                  topics: dict[tuple[str, str], str]) -> tuple[DiagramEdge, ...]:
    """Return the connections of a system, each from where its data comes."""
    edges = []
    for connection in system.connections:
        source = provided_end(connection, components)
        port = components[source.instance].port(source.port)
        assert port is not None
        name = topics[(source.instance, source.port)]
        if connection.target is None:
            # a name outside the model: a plain node of the diagram, named so
            target = PortRef(name, '', source.location)
        else:
            target = (connection.target if source == connection.source
                      else connection.source)
        # arrows follow the data: from the publisher of push and event, to
        # the server of send, query and action (the other end of a
        # connection of one port is its peer: publisher or server when the
        # port is required)
        if port_kind(port).data_to_provider != (port.role is Role.REQUIRED):
            source, target = target, source
        edges.append(DiagramEdge(
            source.instance, source.port, target.instance, target.port,
            f'{port.pattern.value} {port.type}\\n{name}'))
    return tuple(edges)
