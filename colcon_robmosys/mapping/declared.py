# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The parameters each node of a system declares: what a parameter file may set.

A system's ``bringup.json`` carries them per instance (``declared``), so that
an operator's parameter file is checked against the system offline, on a
robot without colcon-robmosys (``ros2 run <system> check_params FILE``,
robmosys_runtime.tools.paramcheck), and in the workspace (``colcon robmosys-check
params``) from the same description.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

from colcon_robmosys.mapping.names import connection_name
from colcon_robmosys.mapping.parameters import NODE_PARAMETERS
from colcon_robmosys.mapping.portkinds import Entity, port_kind
from colcon_robmosys.model.parameters import node_parameters
from colcon_robmosys.model.types import Component, Instance, Parameter

#: ROS 2's QoS overrides of a publisher or a subscription, as the runtime's ports
#: declare them (read-only, ``qos_overrides.<topic>.<entity>.<policy>``): policy ->
#: type and the values rclcpp and rclpy read (durations: integer nanoseconds)
QOS_POLICIES: dict[str, tuple[str, tuple[str, ...] | None]] = {
    'history': ('string', ('keep_last', 'keep_all', 'system_default')),
    'depth': ('int', None),
    'reliability': ('string', ('reliable', 'best_effort', 'system_default', 'best_available')),
    'durability': ('string', ('volatile', 'transient_local', 'system_default',
                              'best_available')),
    'deadline': ('int', None),
    'lifespan': ('int', None),
    'liveliness': ('string', ('automatic', 'manual_by_topic', 'system_default',
                              'best_available')),
    'liveliness_lease_duration': ('int', None),
}

#: What rclcpp and rclpy (Iron and later) declare besides NODE_PARAMETERS, read-only: in
#: every dump of a node (``ros2 param dump``), so in files made from one
READ_ONLY_NODE_PARAMETERS = {'start_type_description_service': 'bool'}

#: What a generated node announces of itself (robmosys_runtime's announce): read-only,
#: declared ignoring overrides, so that a parameter file never changes them
ANNOUNCED = {'robmosys.component': 'string', 'robmosys.ports': 'string[]'}


@dataclass(frozen=True)
class DeclaredParameter:
    """A parameter a node declares, with what ROS 2 and the node hold its values to."""

    name: str
    type: str
    #: 'model' (the component's), 'node' (every ROS 2 node's), 'qos' (a port's QoS
    #: override), 'announced' (what the node says of itself: never from a file) or
    #: 'mapped' (a mapped parameter's template: ``for_each``)
    origin: str
    read_only: bool = False
    #: (from, to, step)
    range: tuple[float, float, float] | None = None
    one_of: tuple[Any, ...] | None = None
    #: (min, max): max None for no bound
    size: tuple[int, int | None] | None = None
    #: of a mapped parameter (one per entry) and of its template (origin 'mapped', named
    #: as in the model): the string array whose entries it is repeated for
    for_each: str | None = None

    def as_json(self) -> dict[str, Any]:
        """Return it as bringup.json holds it."""
        held = {'name': self.name, 'type': self.type, 'origin': self.origin,
                'read_only': self.read_only,
                'range': list(self.range) if self.range is not None else None,
                'one_of': list(self.one_of) if self.one_of is not None else None,
                'size': list(self.size) if self.size is not None else None}
        if self.for_each is not None:
            held['for_each'] = self.for_each
        return held


def declared_parameters(instance: Instance, component: Component,
                        topics: dict[tuple[str, str], str],
                        shared: Mapping[str, Any] | None = None) -> tuple[DeclaredParameter, ...]:
    """Return every parameter the node of an instance declares, the model's first.

    A mapped parameter comes once per entry of its array, as the system sets
    the array (``shared``: its values for every instance; the instance's own win).
    """
    values = {**(shared or {}), **dict(instance.parameters)}
    declared = [_declared(name, p, 'model')
                for name, p in node_parameters(component.parameters, values).items()]
    # and each mapped parameter once more, as a template: a parameter file that sets
    # its array names other entries than the system does (robmosys_runtime.tools.paramcheck)
    declared += [_declared(p.name, p, 'mapped') for p in component.parameters
                 if p.for_each is not None]
    declared += [DeclaredParameter(name, type_, 'node')
                 for name, type_ in NODE_PARAMETERS.items()]
    declared += [DeclaredParameter(name, type_, 'node', True)
                 for name, type_ in READ_ONLY_NODE_PARAMETERS.items()]
    if component.external:
        # a hand-written node declares what its model says, and what every node does
        return tuple(declared)
    for port in component.ports:
        entity = port_kind(port).entity
        if entity not in (Entity.PUBLISHER, Entity.SUBSCRIPTION):
            continue
        topic = topics.get((instance.name, port.name)) or connection_name(
            instance.namespace, instance.node_name, port.name, port.node_name)
        declared += [DeclaredParameter(f'qos_overrides.{topic}.{entity.value}.{policy}', type_,
                                       'qos', True, one_of=values)
                     for policy, (type_, values) in QOS_POLICIES.items()]
    declared += [DeclaredParameter(name, type_, 'announced', True)
                 for name, type_ in ANNOUNCED.items()
                 if name != 'robmosys.ports' or component.ports]
    return tuple(declared)


def _declared(name: str, parameter: Parameter, origin: str) -> DeclaredParameter:
    return DeclaredParameter(
        name, parameter.type, origin, parameter.read_only,
        (parameter.range.start, parameter.range.end, parameter.range.step)
        if parameter.range is not None else None,
        parameter.one_of,
        (parameter.size.min, parameter.size.max) if parameter.size is not None else None,
        parameter.for_each)
