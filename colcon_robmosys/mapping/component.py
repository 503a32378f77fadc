# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The language-neutral plan of a component: what its lifecycle node holds.

Every decision about what a component becomes in ROS 2 is taken here, from
the port-kind table (:mod:`colcon_robmosys.mapping.portkinds`), once for every
language; the language backends (:mod:`colcon_robmosys.mapping.backends`) only
spell the plan.
"""

from __future__ import annotations

from dataclasses import dataclass

from colcon_robmosys.errors import Location, RobmosysError
from colcon_robmosys.mapping.executors import component_executor
from colcon_robmosys.mapping.portkinds import (
    Delivery, Entity, PORT_KINDS, PortKind, Returns)
from colcon_robmosys.model.files import model_dependencies
from colcon_robmosys.model.types import (
    Component, Executor, Function, InterfaceRef, Language, Parameter, PATTERN_INTERFACE,
    QoS)


@dataclass(frozen=True)
class PortPlan:
    """A port and the ROS 2 entity it becomes."""

    name: str
    kind: PortKind
    type: InterfaceRef
    qos: QoS
    description: str
    #: the activity it triggers, and that activity's functions
    activity: str | None
    functions: tuple[str, ...]

    @property
    def entity(self) -> str:
        """Return the name of the entity, which names its template fragment."""
        return self.kind.entity.value


@dataclass(frozen=True)
class FunctionPlan:
    """A function of the model and how its callers call it."""

    name: str
    arguments: tuple[str, ...]
    returns: Returns
    #: the port whose data it receives, if a port runs it
    port: PortPlan | None
    #: the embedded code, if the model gives it; otherwise the user writes it
    code: str | None
    description: str
    location: Location
    #: the type of the parameter values it validates, if it is a validator
    validates: str | None = None


@dataclass(frozen=True)
class ActivityPlan:
    """An activity: a callback group, a lock and, if periodic, a timer."""

    name: str
    period: float | None
    functions: tuple[str, ...]
    description: str
    trigger: str | None

    @property
    def period_ns(self) -> int | None:
        """Return the period of its timer in nanoseconds, if periodic."""
        return round(self.period * 1e9) if self.period is not None else None


@dataclass(frozen=True)
class ComponentPlan:
    """What the lifecycle node of a component holds, in ROS 2 terms."""

    package: str
    cls: str
    language: Language
    description: str
    ports: tuple[PortPlan, ...]
    activities: tuple[ActivityPlan, ...]
    functions: tuple[FunctionPlan, ...]
    #: parameters with their descriptors (range, read-only, description)
    parameters: tuple[Parameter, ...]
    #: lifecycle hooks: transition -> functions run on it, in order
    lifecycle: tuple[tuple[str, tuple[str, ...]], ...]
    #: interface packages and others the model depends on
    depends: tuple[str, ...]
    #: what spins the node in a process of its own (mapping/executors.py)
    executor: Executor = Executor.MULTI_THREADED

    @property
    def entities(self) -> frozenset[Entity]:
        """Return the kinds of entity the node holds."""
        return frozenset(p.kind.entity for p in self.ports)

    @property
    def uses_actions(self) -> bool:
        """Tell whether a port is made of ROS 2 actions."""
        return any(p.kind.uses_actions for p in self.ports)

    @property
    def user_functions(self) -> tuple[FunctionPlan, ...]:
        """Return the functions whose body the user writes."""
        return tuple(f for f in self.functions if f.code is None)

    @property
    def has_impl(self) -> bool:
        """Tell whether the user implements functions in a class of theirs."""
        return bool(self.user_functions)

    @property
    def node_cls(self) -> str:
        """Return the class the executable instantiates."""
        return f'{self.cls}_impl' if self.has_impl else self.cls

    @property
    def node_module(self) -> str:
        """Return the module of :attr:`node_cls`, in the package (Python)."""
        return self.node_cls

    @property
    def callback_groups(self) -> int:
        """Return the callback groups: one per activity and per client."""
        return len(self.activities) + sum(1 for p in self.ports
                                          if p.kind.own_group)

    @property
    def threads(self) -> int:
        """Return the executor threads that keep every callback group served.

        One thread more than groups means that activities blocked in calls
        never starve the threads that deliver the answers, nor the lifecycle
        and parameter services.
        """
        return self.callback_groups + 1

    def hook(self, transition: str) -> tuple[str, ...]:
        """Return the functions run on a lifecycle transition."""
        return dict(self.lifecycle).get(transition, ())


def plan_component(component: Component, default_executor: Executor) -> ComponentPlan:
    """Map a checked component to its plan.

    :param default_executor: its backend's executor of a component that names
      none and blocks no thread (``Backend.default_executor``)
    :raises RobmosysError: an internal error, if the check let through a
      model this cannot map (a function two ports would call differently)
    """
    by_trigger = {a.trigger: a for a in component.activities if a.trigger}
    ports = []
    for port in component.ports:
        kind = PORT_KINDS.get((port.pattern, port.role))
        if kind is None or port.type.kind is not PATTERN_INTERFACE[port.pattern]:
            # the schema and the file builder refuse these
            raise RobmosysError.at(
                port.location, f"internal error: port '{port.name}' "
                f'({port.role.value} {port.pattern.value}, {port.type}) has no '
                'ROS 2 mapping; the check should have refused it')
        activity = by_trigger.get(port.name)
        ports.append(PortPlan(
            port.name, kind, port.type, port.qos,
            port.description or f'{port.role.value.capitalize()} '
            f'{port.pattern.value} port ({port.type}).',
            activity.name if activity else None,
            activity.functions if activity else ()))
    return ComponentPlan(
        package=component.package, cls=component.name,
        language=component.language,
        description=component.info.description,
        ports=tuple(ports),
        activities=tuple(ActivityPlan(a.name, a.period, a.functions,
                                      a.description, a.trigger)
                         for a in component.activities),
        functions=tuple(_function(f, ports, component.parameters)
                        for f in component.functions),
        parameters=component.parameters,
        lifecycle=component.lifecycle,
        depends=tuple(model_dependencies(component)),
        executor=component_executor(component, default_executor))


def _function(function: Function, ports: list[PortPlan],
              parameters: tuple[Parameter, ...]) -> FunctionPlan:
    """Return how a function is called, from the port or parameter that runs it."""
    validated = next((p for p in parameters if p.validate == function.name), None)
    if validated is not None:
        # check/activities.py makes it a validator only
        return FunctionPlan(function.name, ('value',), Returns.PROBLEM, None, function.code,
                            function.description, function.location, validated.type)
    runners = [p for p in ports if function.name in p.functions]
    delivered = {(p.kind.delivers, p.type) for p in runners}
    if len(delivered) > 1:
        # the check (check/activities.py) refuses this with the model's line
        raise RobmosysError.at(
            function.location, f"internal error: function '{function.name}' "
            'is run by ports that deliver different things; the check should '
            'have refused it')
    port = runners[0] if runners else None
    return FunctionPlan(
        function.name, port.kind.arguments if port else (),
        port.kind.returns if port else Returns.NOTHING, port,
        function.code, function.description, function.location)


__all__ = ['ActivityPlan', 'ComponentPlan', 'Delivery', 'FunctionPlan',
           'plan_component', 'PortPlan']
