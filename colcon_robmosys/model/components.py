# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Components: ports, activities, functions, parameters, lifecycle hooks."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Union

from colcon_robmosys.errors import Location
from colcon_robmosys.model.base import (
    Executor, InterfaceRef, Language, PackageInfo, Pattern, Role)


@dataclass(frozen=True)
class QoS:
    """Quality of service of a port, as written in the model."""

    profile: str = 'default'
    history: str | None = None
    depth: int | None = None
    reliability: str | None = None
    durability: str | None = None
    deadline: float | None = None
    lifespan: float | None = None
    liveliness: str | None = None
    liveliness_lease_duration: float | None = None


@dataclass(frozen=True)
class Port:
    """A port of a component."""

    name: str
    pattern: Pattern
    role: Role
    type: InterfaceRef
    qos: QoS
    description: str
    location: Location
    #: where the model sets its QoS, if it does
    qos_location: Location | None = None
    #: where the model names its type
    type_location: Location | None = None
    #: the name the node itself gives it (an external component's); None: the port's name
    ros_name: str | None = None

    @property
    def node_name(self) -> str:
        """Return the name the node uses for the port, what a system remaps."""
        return self.ros_name or self.name


@dataclass(frozen=True)
class Activity:
    """An activity: functions run periodically or when a port delivers."""

    name: str
    functions: tuple[str, ...]
    period: float | None
    trigger: str | None
    description: str
    location: Location
    #: where the trigger and the list of functions stand
    trigger_location: Location | None = None
    functions_location: Location | None = None


@dataclass(frozen=True)
class Function:
    """A function of a component, with its body or left to the user."""

    name: str
    code: str | None
    description: str
    location: Location


ParameterValue = Union[bool, int, float, str, tuple[Any, ...], None]


@dataclass(frozen=True)
class ParameterRange:
    """The range a numeric parameter may take."""

    start: float
    end: float
    step: float


@dataclass(frozen=True)
class ParameterSize:
    """How many characters (string) or elements (array) a parameter may hold."""

    min: int
    max: int | None


@dataclass(frozen=True)
class Parameter:
    """A parameter of a component; a dotted name is a parameter of a group."""

    name: str
    type: str
    default: ParameterValue
    description: str
    read_only: bool
    range: ParameterRange | None
    location: Location
    #: the values it may take (of an array: its elements)
    one_of: tuple[Any, ...] | None = None
    size: ParameterSize | None = None
    #: the function that validates a new value: it returns why it is refused, or nothing
    validate: str | None = None
    #: the functions run after a change of its value
    on_change: tuple[str, ...] = ()
    #: where ``validate`` and ``on_change`` stand
    validate_location: Location | None = None
    on_change_location: Location | None = None
    #: the string array it is repeated for: one parameter per entry (a mapped parameter)
    for_each: str | None = None
    for_each_location: Location | None = None
    #: no default: a system must set it, and a node without a value does not configure
    required: bool = False

    @property
    def path(self) -> tuple[str, ...]:
        """Return the groups of the name, then its last part."""
        return tuple(self.name.split('.'))

    def ros_name(self, entry: str = '') -> str:
        """Return the ROS 2 name: of a mapped parameter, the one of an entry of its array.

        ``gains.p`` repeated for each entry of ``joints`` is ``gains.<entry>.p``,
        ``gain`` is ``<entry>.gain`` (generate_parameter_library's
        ``gains.__map_joints.p``).
        """
        if self.for_each is None:
            return self.name
        return '.'.join(self.path[:-1] + (entry, self.path[-1]))

    @property
    def shown_name(self) -> str:
        """Return the name as its documentation writes it (``gains.<joints>.p``)."""
        return self.ros_name(f'<{self.for_each}>')


@dataclass(frozen=True)
class Component:
    """A component: one lifecycle node package."""

    info: PackageInfo
    name: str
    language: Language
    ports: tuple[Port, ...]
    activities: tuple[Activity, ...]
    functions: tuple[Function, ...]
    parameters: tuple[Parameter, ...]
    #: transition name -> functions run on it, in order
    lifecycle: tuple[tuple[str, tuple[str, ...]], ...]
    location: Location
    #: the executable of a node nobody generates (``external``); '' for a generated one
    executable: str = ''
    #: whether the node is a lifecycle node (always, for a generated one)
    lifecycle_node: bool = True
    #: the executor the model names for its process (None: the mapping's default)
    executor: Executor | None = None
    executor_location: Location | None = None

    @property
    def external(self) -> bool:
        """Tell whether the node is hand-written: nothing is generated for it."""
        return bool(self.executable)

    @property
    def executable_name(self) -> str:
        """Return the executable that runs the node, in lib/<package>/."""
        return self.executable or self.name

    @property
    def package(self) -> str:
        """Return the name of the generated package."""
        return self.info.name

    def port(self, name: str) -> Port | None:
        """Return the port of that name, if any."""
        return next((p for p in self.ports if p.name == name), None)

    @property
    def user_functions(self) -> tuple[Function, ...]:
        """Return the functions whose body the user writes."""
        return tuple(f for f in self.functions if f.code is None)
