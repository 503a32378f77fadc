# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Systems: component instances wired together."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

from colcon_robmosys.errors import Location
from colcon_robmosys.model.base import Executor, PackageInfo
from colcon_robmosys.model.components import QoS


@dataclass(frozen=True)
class QoSOverride:
    """New values of QoS policies of one port, for one instance."""

    port: str
    #: policy -> value, as a port's ``qos`` spells them (no ``profile``)
    policies: tuple[tuple[str, Any], ...]
    #: where the instance names the port
    location: Location

    def applied_to(self, qos: QoS) -> QoS:
        """Return a port's QoS with these policies in place of its own."""
        policies = dict(self.policies)
        if policies.get('history') == 'keep_all':
            policies.setdefault('depth', None)
        return replace(qos, **policies)


@dataclass(frozen=True)
class Instance:
    """A component instance in a system."""

    name: str
    component: str
    namespace: str
    parameters: tuple[tuple[str, Any], ...]
    activate: bool
    after: tuple[str, ...]
    description: str
    location: Location
    #: where the key of each entry of ``parameters`` stands
    parameter_locations: tuple[Location, ...] = ()
    #: started again when its process ends
    respawn: bool = False
    #: seconds for each lifecycle transition; None: the bring-up's default
    timeout: float | None = None
    #: the host it runs on; '' for the manager's
    host: str = ''
    #: the node's name where it differs from the instance's: an instance of a
    #: subsystem (``robot1.map_server``) is the node ``map_server``
    node: str = ''
    #: the QoS the instance gives its ports in place of the component's
    qos: tuple[QoSOverride, ...] = ()
    #: where each entry of ``after`` stands
    after_locations: tuple[Location, ...] = ()
    #: where each element of each value of ``parameters`` stands (none for a scalar)
    parameter_entry_locations: tuple[tuple[Location, ...], ...] = ()
    #: required ports meant to stay unconnected: no warning, nothing for the watch to report
    unconnected: tuple[str, ...] = ()
    #: push ports that may stay silent while the instance is active (the watch does not
    #: report their silence)
    quiet: tuple[str, ...] = ()
    #: where the instance lists each of ``unconnected``, then of ``quiet``
    watch_locations: tuple[Location, ...] = ()

    @property
    def node_name(self) -> str:
        """Return the name of the instance's node (in its namespace)."""
        return self.node or self.name

    def after_location(self, name: str) -> Location:
        """Return where the instance names another in ``after``: the entry, else the instance."""
        for entry, location in zip(self.after, self.after_locations):
            if entry == name:
                return location
        return self.location

    def qos_of(self, port: str, qos: QoS) -> QoS:
        """Return the QoS a port of the instance has: the component's, overridden."""
        override = self.qos_override(port)
        return qos if override is None else override.applied_to(qos)

    def qos_override(self, port: str) -> QoSOverride | None:
        """Return the instance's override of a port's QoS, if any."""
        return next((o for o in self.qos if o.port == port), None)


@dataclass(frozen=True)
class PortRef:
    """``instance.port`` in a connection."""

    instance: str
    port: str
    location: Location

    def __str__(self) -> str:
        return f'{self.instance}.{self.port}'


@dataclass(frozen=True)
class Connection:
    """A connection between two ports of two instances, or of one port to a name.

    A connection with one port (``target`` None) joins it to a ROS 2 name outside
    the model (``topic``): a topic, service or action of a node nobody modelled.
    """

    source: PortRef
    target: PortRef | None
    topic: str | None
    location: Location

    @property
    def ends(self) -> tuple[PortRef, ...]:
        """Return the ports of the connection: two, or one."""
        return (self.source,) if self.target is None else (self.source, self.target)


@dataclass(frozen=True)
class Subsystem:
    """Another system included in a system, under a namespace."""

    name: str
    #: the package of the included system
    system: str
    #: absolute, without a trailing slash; '' for the root namespace
    namespace: str
    location: Location
    #: the host of its instances that name none; '' for the manager's
    host: str = ''


@dataclass(frozen=True)
class ModeValues:
    """The values a mode gives the parameters of one instance."""

    instance: str
    values: tuple[tuple[str, Any], ...]
    #: where the mode names the instance
    location: Location
    #: where the key of each value stands
    value_locations: tuple[Location, ...] = ()
    #: where each element of each list value stands (none for a scalar)
    entry_locations: tuple[tuple[Location, ...], ...] = ()


@dataclass(frozen=True)
class Mode:
    """A mode of a system: its active instances, its values, its subsystems' modes."""

    name: str
    #: the managed instances of the system (not of its subsystems) active in the mode
    active: tuple[str, ...]
    parameters: tuple[ModeValues, ...]
    #: subsystem -> its mode in this mode (a subsystem not named: its initial mode)
    subsystems: tuple[tuple[str, str], ...]
    location: Location
    #: where each entry of ``active`` stands
    active_locations: tuple[Location, ...] = ()
    #: where each entry of ``subsystems`` stands (its value)
    subsystem_locations: tuple[Location, ...] = ()
    description: str = ''

    def active_location(self, name: str) -> Location:
        """Return where the mode lists an instance as active, else where the mode is."""
        for entry, location in zip(self.active, self.active_locations):
            if entry == name:
                return location
        return self.location


@dataclass(frozen=True)
class System:
    """A system: component instances wired together.

    A system with subsystems holds, once the workspace is checked, their
    instances and connections too (``subsystem.instance``): see
    :mod:`colcon_robmosys.check.subsystems`.
    """

    info: PackageInfo
    name: str
    instances: tuple[Instance, ...]
    connections: tuple[Connection, ...]
    location: Location
    #: 'per_instance', 'shared' (the Python instances of a host in one process), or ''
    #: where the model does not say (the mapping decides by size: process_layout)
    processes: str = ''
    subsystems: tuple[Subsystem, ...] = ()
    #: values for every instance (the /** entry of the parameter file), and where each stands
    parameters: tuple[tuple[str, Any], ...] = ()
    parameter_locations: tuple[Location, ...] = ()
    #: where each element of each of those values stands (none for a scalar)
    parameter_entry_locations: tuple[tuple[Location, ...], ...] = ()
    #: the executor of its shared processes the model names (None: the mapping's default)
    executor: Executor | None = None
    executor_location: Location | None = None
    #: its modes, in the model's order (none: one set of instances, as ever)
    modes: tuple[Mode, ...] = ()
    #: the mode the system starts in, and where the model names it
    initial_mode: str = ''
    initial_mode_location: Location | None = None

    @property
    def package(self) -> str:
        """Return the name of the generated package."""
        return self.info.name

    def mode(self, name: str) -> Mode | None:
        """Return the mode of that name, if any."""
        return next((m for m in self.modes if m.name == name), None)

    def instance(self, name: str) -> Instance | None:
        """Return the instance of that name, if any."""
        return next((i for i in self.instances if i.name == name), None)
