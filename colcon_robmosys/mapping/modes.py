# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The modes of a system as its manager reads them: whole, its subsystems' expanded.

A mode of the model names what differs; the system manager is given, for
each mode, every instance active in it and the value each parameter that any
mode sets holds in it (the mode's, else the system's), so that a switch and the
watch compare two tables and need no rule of the model.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterable

from colcon_robmosys.mapping.conformance import WatchedInstance
from colcon_robmosys.mapping.parameters import NODE_PARAMETERS
from colcon_robmosys.model.modes import active_instances, mode_values
from colcon_robmosys.model.parameters import freeze_parameter_value, node_parameters
from colcon_robmosys.model.types import Component, System, Workspace


@dataclass(frozen=True)
class ModePlan:
    """A mode of a system, whole: what is active, what every moded parameter holds."""

    name: str
    description: str
    #: the instances active in the mode, in activation order
    active: tuple[str, ...]
    #: instance -> ((parameter, value), ...): every parameter any mode sets, in model order
    values: tuple[tuple[str, tuple[tuple[str, Any], ...]], ...]
    #: where the model writes the mode
    location: str

    def value(self, instance: str, name: str) -> Any:
        """Return the value a parameter of an instance holds in the mode."""
        return dict(dict(self.values).get(instance, ()))[name]

    def as_json(self) -> dict[str, Any]:
        """Return it as bringup.json holds it."""
        return {'name': self.name, 'description': self.description,
                'active': list(self.active), 'location': self.location,
                'values': {i: dict(v) for i, v in self.values}}


def plan_modes(system: System, workspace: Workspace, components: dict[str, Component],
               order: Iterable[str], watched: Iterable[WatchedInstance]) -> tuple[ModePlan, ...]:
    """Return the modes of a system, whole (none for a system without modes).

    :param order: the instances in activation order
    :param watched: what the watch expects of each instance: the system's values
    """
    if not system.modes:
        return ()
    systems = {m.package: m for m in workspace.models if isinstance(m, System)}
    order = list(order)
    given = {m.name: mode_values(system, m, systems) for m in system.modes}
    # every parameter some mode sets, per instance, in the order modes name them
    moded: dict[str, list[str]] = {}
    for values in given.values():
        for instance, pairs in values.items():
            names = moded.setdefault(instance, [])
            names += [n for n in pairs if n not in names]
    base = {w.instance: {n: v for n, v, _ in w.parameters} for w in watched}
    plans = []
    for mode in system.modes:
        active = active_instances(system, mode, systems)
        table = []
        for instance in (i for i in order if i in moded):
            types = _types(system, instance, components[instance])
            table.append((instance, tuple(
                (name, _plain(freeze_parameter_value(
                    types.get(name, ''), given[mode.name].get(instance, {})[name]))
                 if name in given[mode.name].get(instance, {})
                 else base[instance].get(name))
                for name in moded[instance])))
        plans.append(ModePlan(mode.name, mode.description,
                              tuple(i for i in order if i in active), tuple(table),
                              str(mode.location)))
    return tuple(plans)


def _types(system: System, name: str, component: Component) -> dict[str, str]:
    """Return the type of each parameter an instance's node declares."""
    instance = system.instance(name)
    assert instance is not None
    declared = node_parameters(component.parameters, {
        **dict(system.parameters), **dict(instance.parameters)})
    types = dict(NODE_PARAMETERS)
    types.update((n, p.type) for n, p in declared.items())
    return types


def _plain(value: Any) -> Any:
    """Return a parameter value as JSON holds it (lists for tuples)."""
    return [_plain(v) for v in value] if isinstance(value, tuple) else value
