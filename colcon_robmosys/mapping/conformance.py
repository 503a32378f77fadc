# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""What the system manager's conformance watch expects of each instance in the ROS graph."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from colcon_robmosys.mapping.names import connection_name
from colcon_robmosys.mapping.parameters import NODE_PARAMETERS
from colcon_robmosys.mapping.portkinds import port_kind
from colcon_robmosys.model.parameters import freeze_parameter_value, node_parameters
from colcon_robmosys.model.types import Component, Role, System


@dataclass(frozen=True)
class WatchedPort:
    """A port of an instance as the system manager's watch expects it in the ROS graph."""

    port: str
    #: the entity it becomes (portkinds' Entity value)
    entity: str
    #: the ROS 2 name it is on: remapped by a connection, or its own in the node's namespace
    name: str
    #: pkg/kind/Type
    type: str
    required: bool
    connected: bool
    #: seconds between two messages at most: the longest period of the activities of a
    #: component whose activities are all periodic (a push port it provides); else None
    period: float | None = None
    #: the model says it may stay unconnected (instance key ``unconnected``)
    unconnected: bool = False
    #: the model says it may stay silent (instance key ``quiet``)
    quiet: bool = False


@dataclass(frozen=True)
class WatchedInstance:
    """What the watch compares of an instance: where it is written, its ports and values."""

    instance: str
    location: str
    ports: tuple[WatchedPort, ...]
    #: (name, value, where the model gives the value) of every parameter the model sets
    parameters: tuple[tuple[str, Any, str], ...]


def watched_instances(system: System, components: dict[str, Component],
                      topics: dict[tuple[str, str], str]) -> tuple[WatchedInstance, ...]:
    """Return what the system manager's watch expects of every instance."""
    watched = []
    for instance in system.instances:
        component = components[instance.name]
        periods = [a.period for a in component.activities if a.period is not None]
        # a component with a triggered activity may publish from it: no period promised
        period = max(periods) if periods and len(periods) == len(component.activities) and \
            not component.external else None
        ports = []
        for port in component.ports:
            kind = port_kind(port)
            connected = (instance.name, port.name) in topics
            name = topics.get((instance.name, port.name)) or connection_name(
                instance.namespace, instance.node_name, port.name, port.node_name)
            ports.append(WatchedPort(
                port.name, kind.entity.value, name, str(port.type),
                port.role is Role.REQUIRED, connected,
                period if kind.entity.value == 'publisher' and port.role is Role.PROVIDED
                else None,
                port.name in instance.unconnected, port.name in instance.quiet))
        values: dict[str, tuple[Any, str]] = {}
        # by ROS 2 name: a mapped parameter once per entry of its array
        declared = node_parameters(component.parameters, {
            **dict(system.parameters), **dict(instance.parameters)})
        for name, parameter in declared.items():
            if parameter.default is not None:
                values[name] = (parameter.default, str(instance.location))
        for (name, value), at in zip(system.parameters, system.parameter_locations):
            if name in values or name == 'use_sim_time':
                values[name] = (value, str(at))
        for (name, value), at in zip(instance.parameters, instance.parameter_locations):
            values[name] = (value, str(at))
        types = {n: p.type for n, p in declared.items()}
        types.update(NODE_PARAMETERS)
        watched.append(WatchedInstance(
            instance.name, str(instance.location), tuple(ports),
            tuple((name, _plain(freeze_parameter_value(types[name], value)), at)
                  for name, (value, at) in values.items())))
    return tuple(watched)


def _plain(value: Any) -> Any:
    """Return a parameter value as JSON holds it (lists for tuples)."""
    return [_plain(v) for v in value] if isinstance(value, tuple) else value
