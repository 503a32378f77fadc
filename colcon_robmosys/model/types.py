# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The RobMoSys model, in RobMoSys terms: frozen, typed and validated."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from typing import Any, Union

from colcon_robmosys.errors import Location


class Pattern(str, Enum):
    """Communication patterns of RobMoSys, plus ROS 2 actions."""

    PUSH = 'push'
    SEND = 'send'
    QUERY = 'query'
    EVENT = 'event'
    ACTION = 'action'


class Role(str, Enum):
    """Which side of a communication pattern a port is."""

    PROVIDED = 'provided'
    REQUIRED = 'required'


class Language(str, Enum):
    """The programming language of a component's implementation."""

    PYTHON = 'python'
    CPP = 'cpp'


class InterfaceKind(str, Enum):
    """The kind of a ROS 2 interface file."""

    MSG = 'msg'
    SRV = 'srv'
    ACTION = 'action'


#: The interface kind each pattern exchanges.
PATTERN_INTERFACE = {
    Pattern.PUSH: InterfaceKind.MSG,
    Pattern.SEND: InterfaceKind.MSG,
    Pattern.EVENT: InterfaceKind.ACTION,
    Pattern.QUERY: InterfaceKind.SRV,
    Pattern.ACTION: InterfaceKind.ACTION,
}

PRIMITIVE_TYPES = frozenset({
    'bool', 'byte', 'char', 'float32', 'float64', 'int8', 'uint8', 'int16',
    'uint16', 'int32', 'uint32', 'int64', 'uint64', 'string', 'wstring',
})

LIFECYCLE_TRANSITIONS = (
    'on_configure', 'on_activate', 'on_deactivate', 'on_cleanup',
    'on_shutdown', 'on_error',
)


@dataclass(frozen=True)
class Maintainer:
    """A person responsible for a package."""

    name: str
    email: str


@dataclass(frozen=True)
class PackageInfo:
    """Metadata shared by every model that becomes a ROS 2 package."""

    name: str
    description: str
    version: str
    license: str
    maintainers: tuple[Maintainer, ...]
    depends: tuple[str, ...]
    #: the model file this package comes from
    model_file: str
    location: Location


@dataclass(frozen=True)
class InterfaceRef:
    """A reference to a ROS 2 interface: ``package/kind/Name``."""

    package: str
    kind: InterfaceKind
    name: str

    def __str__(self) -> str:
        return f'{self.package}/{self.kind.value}/{self.name}'


@dataclass(frozen=True)
class FieldType:
    """The type of a field or constant of a communication object."""

    #: a primitive type name, or None for a reference to a message
    primitive: str | None = None
    message: InterfaceRef | None = None
    #: upper bound of a string type (``string<=N``)
    string_bound: int | None = None
    #: None: not an array; 'dynamic', 'fixed' or 'bounded'
    array: str | None = None
    array_size: int | None = None

    @property
    def base_name(self) -> str:
        """Return the element type in .msg syntax."""
        if self.message is not None:
            return f'{self.message.package}/{self.message.name}'
        assert self.primitive is not None
        if self.string_bound is not None:
            return f'{self.primitive}<={self.string_bound}'
        return self.primitive

    def __str__(self) -> str:
        suffix = {
            None: '', 'dynamic': '[]', 'fixed': f'[{self.array_size}]',
            'bounded': f'[<={self.array_size}]',
        }[self.array]
        return self.base_name + suffix


@dataclass(frozen=True)
class Field:
    """A field of a communication object."""

    name: str
    type: FieldType
    default: Any
    comment: str
    location: Location


@dataclass(frozen=True)
class Constant:
    """A constant of a communication object."""

    name: str
    type: FieldType
    value: Any
    comment: str
    location: Location


@dataclass(frozen=True)
class Structure:
    """Fields and constants: a message, or one part of a query or action."""

    description: str
    fields: tuple[Field, ...]
    constants: tuple[Constant, ...]


@dataclass(frozen=True)
class CommunicationObject:
    """A communication object: becomes a ``.msg`` file."""

    name: str
    structure: Structure
    location: Location


@dataclass(frozen=True)
class Query:
    """A query request/answer pair: becomes a ``.srv`` file."""

    name: str
    description: str
    request: Structure
    answer: Structure
    location: Location


@dataclass(frozen=True)
class Action:
    """A goal/result/feedback triple: becomes an ``.action`` file."""

    name: str
    description: str
    goal: Structure
    result: Structure
    feedback: Structure
    location: Location


@dataclass(frozen=True)
class Event:
    """An event: activation and event structures; becomes an ``.action`` file.

    The goal is the activation, the result and the feedback are the event.
    """

    name: str
    description: str
    activation: Structure
    event: Structure
    location: Location


@dataclass(frozen=True)
class ServiceDefinition:
    """A service definition: one interface package."""

    info: PackageInfo
    communication_objects: tuple[CommunicationObject, ...]
    queries: tuple[Query, ...]
    actions: tuple[Action, ...]
    events: tuple[Event, ...] = ()

    @property
    def package(self) -> str:
        """Return the name of the generated package."""
        return self.info.name


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


ParameterValue = Union[bool, int, float, str, tuple, None]


@dataclass(frozen=True)
class ParameterRange:
    """The range a numeric parameter may take."""

    start: float
    end: float
    step: float


@dataclass(frozen=True)
class Parameter:
    """A parameter of a component."""

    name: str
    type: str
    default: ParameterValue
    description: str
    read_only: bool
    range: ParameterRange | None
    location: Location


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
    """A connection between two ports of two instances."""

    source: PortRef
    target: PortRef
    topic: str | None
    location: Location


@dataclass(frozen=True)
class System:
    """A system: component instances wired together."""

    info: PackageInfo
    name: str
    instances: tuple[Instance, ...]
    connections: tuple[Connection, ...]
    location: Location

    @property
    def package(self) -> str:
        """Return the name of the generated package."""
        return self.info.name

    def instance(self, name: str) -> Instance | None:
        """Return the instance of that name, if any."""
        return next((i for i in self.instances if i.name == name), None)


Model = Union[ServiceDefinition, Component, System]


@dataclass(frozen=True)
class ModelFile:
    """The models of one robmosys.yaml file."""

    path: str
    service_definitions: tuple[ServiceDefinition, ...] = ()
    components: tuple[Component, ...] = ()
    systems: tuple[System, ...] = ()

    @property
    def models(self) -> tuple[Model, ...]:
        """Return every model of the file, in file order per kind."""
        return (
            *self.service_definitions, *self.components, *self.systems)


@dataclass(frozen=True)
class Workspace:
    """Every model of a workspace, validated together."""

    files: tuple[ModelFile, ...] = field(default=())
    #: every model of every file, in file order
    models: tuple[Model, ...] = field(init=False, repr=False, compare=False)
    # package -> its model; built once, as colcon plans and builds the
    # packages one by one: a scan per lookup made that quadratic
    _by_package: dict[str, Model] = field(
        init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        models = tuple(m for f in self.files for m in f.models)
        by_package: dict[str, Model] = {}
        for model in models:
            # a package claimed twice is an error of the workspace; until
            # it is fixed, the first model keeps it
            by_package.setdefault(model.package, model)
        object.__setattr__(self, 'models', models)
        object.__setattr__(self, '_by_package', by_package)

    def model(self, package: str) -> Model | None:
        """Return the model that generates the named package, if any."""
        return self._by_package.get(package)
