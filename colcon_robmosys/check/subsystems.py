# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Systems that include other systems: subsystems, expanded.

A system includes another (of the workspace or an underlay) as a subsystem
under a namespace. Its instances and connections join the including system:
instance ``map_server`` of subsystem ``robot1`` becomes the instance
``robot1.map_server``, pushed into the subsystem's namespace (a relative name
of the subsystem moves with it, an absolute one stays, as ROS 2 launch's
``PushRosNamespace`` does). The including system then connects to any port
of them, as ``robot1.map_server.pMap``, and waits for them with ``after``.

Every later stage (the wiring rules, the mapping, the generators) sees the
expanded system only: one set of components deployed as several systems
without copying an instance.
"""

from __future__ import annotations

from dataclasses import replace

from colcon_robmosys.errors import Diagnostic
from colcon_robmosys.model.types import (
    Connection, Instance, model_key, ModelFile, PortRef, Subsystem, System)


def expand_subsystems(files: list[ModelFile], broken: set[str]
                      ) -> tuple[list[ModelFile], list[Diagnostic]]:
    """Return the files with every system's subsystems expanded, and the problems.

    :param broken: packages whose models are too broken to be built: a
      subsystem of one is left out without a word (its errors say enough)
    """
    systems = {model_key(m): m for f in files for m in f.models if isinstance(m, System)}
    packages = {model_key(m) for f in files for m in f.models} | broken
    broken_only = broken - systems.keys()
    expander = _Expander(systems, packages, broken_only)
    expanded = []
    for model_file in files:
        if not any(s.subsystems for s in model_file.systems):
            expanded.append(model_file)
            continue
        expanded.append(replace(model_file, systems=tuple(
            expander.expand(s) for s in model_file.systems)))
    return expanded, expander.diagnostics


class _Expander:
    def __init__(self, systems: dict[str, System], packages: set[str],
                 broken: set[str]) -> None:
        self.systems = systems
        self.packages = packages
        self.broken = broken
        self.diagnostics: list[Diagnostic] = []
        self.done: dict[str, System] = {}

    def expand(self, system: System, including: tuple[str, ...] = ()) -> System:
        """Return a system with the instances and connections of its subsystems."""
        if system.package in self.done:
            return self.done[system.package]
        instances = list(system.instances)
        connections = list(system.connections)
        for subsystem in system.subsystems:
            included = self._included(system, subsystem, including)
            if included is None:
                continue
            inner = self.expand(included, including + (system.package,))
            instances += [_pushed(i, subsystem) for i in inner.instances]
            connections += [_renamed(c, subsystem.name) for c in inner.connections]
        expanded = replace(system, instances=tuple(instances), connections=tuple(connections))
        if not including:
            self.done[system.package] = expanded
        return expanded

    def _included(self, system: System, subsystem: Subsystem,
                  including: tuple[str, ...]) -> System | None:
        """Return the system a subsystem includes, or None after reporting why not."""
        included = self.systems.get(subsystem.system)
        if included is None and subsystem.system in self.broken:
            return None
        if included is None:
            what = 'is not a system' if subsystem.system in self.packages else \
                'is not a system of this workspace or its underlays'
            self._error(subsystem, f"subsystem '{subsystem.name}': package "
                        f"'{subsystem.system}' {what}")
            return None
        if subsystem.system == system.package:
            self._error(subsystem, f"subsystem '{subsystem.name}': package "
                        f"'{subsystem.system}' is this system itself")
            return None
        if subsystem.system in including:
            return None  # a dependency cycle, which the cycle rules report
        return included

    def _error(self, subsystem: Subsystem, message: str) -> None:
        self.diagnostics.append(Diagnostic(subsystem.location, message))


def _pushed(instance: Instance, subsystem: Subsystem) -> Instance:
    """Return an instance of a subsystem as an instance of the including system."""
    namespace = subsystem.namespace + instance.namespace
    # the included system's own host (none named) is where the subsystem runs
    return replace(instance, name=f'{subsystem.name}.{instance.name}', namespace=namespace,
                   after=tuple(f'{subsystem.name}.{a}' for a in instance.after),
                   node=instance.node_name, host=instance.host or subsystem.host)


def _renamed(connection: Connection, subsystem: str) -> Connection:
    """Return a connection of a subsystem, its ends named in the including system."""
    def end(ref: PortRef) -> PortRef:
        return replace(ref, instance=f'{subsystem}.{ref.instance}')
    return replace(connection, source=end(connection.source),
                   target=None if connection.target is None else end(connection.target))
