# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The context of the Python templates: frozen dataclasses, filled by mapping/python.py."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from colcon_robmosys.mapping.common import Banner, PackageXml
from colcon_robmosys.mapping.parameters import ParameterPage
from colcon_robmosys.mapping.userfiles import UserFolders


@dataclass(frozen=True)
class PyPort:
    """A port as the Python node creates it."""

    name: str
    description: str
    entity: str
    type: str
    type_full: str
    #: the QoS profile expression, for ports that use a topic
    qos: str | None
    qos_const: str
    activity: str | None
    functions: tuple[str, ...]
    #: the ComponentNode method that creates it
    method: str
    #: what its activity runs: a method, or a list of them
    run: str


@dataclass(frozen=True)
class PyFunction:
    """A function of the model as a method."""

    name: str
    args: tuple[str, ...]
    code: str | None
    returns: str
    default_return: str
    description: str


@dataclass(frozen=True)
class PyRange:
    """The range of a numeric parameter's descriptor."""

    field: str
    cls: str
    start: str
    end: str
    step: str


@dataclass(frozen=True)
class PyParameter:
    """A parameter: its declaration with a descriptor, and its accessor."""

    name: str
    py_type: str
    ros_type: str
    default: Any
    description: str
    doc: str
    read_only: bool
    range: PyRange | None
    #: the last part of its name: the attribute of its group
    attr: str = ''
    #: the arguments of its ParameterRule (one_of, size, validate, on_change), if any
    rule: tuple[str, ...] = ()


@dataclass(frozen=True)
class PyParameterGroup:
    """The class of a group of parameters: typed access, nested by dotted names."""

    cls: str
    doc: str
    parameters: tuple[PyParameter, ...]
    #: (attribute, class) of each subgroup
    groups: tuple[tuple[str, str], ...]


@dataclass(frozen=True)
class PyActivity:
    """A periodic activity and its timer."""

    name: str
    period: float | None
    functions: tuple[str, ...]
    description: str
    #: the list of methods it runs
    run: str


@dataclass(frozen=True)
class PyTransition:
    """A lifecycle transition that runs functions of the model."""

    transition: str
    #: the list of methods it runs
    run: str


@dataclass(frozen=True)
class PyComponent:
    """Everything the templates of a Python component print."""

    banner: Banner
    package: str
    cls: str
    node_cls: str
    node_module: str
    description: str
    node_imports: tuple[str, ...]
    main_imports: tuple[str, ...]
    impl_imports: tuple[str, ...]
    ports: tuple[PyPort, ...]
    #: the periodic activities
    activities: tuple[PyActivity, ...]
    activity_names: tuple[str, ...]
    functions: tuple[PyFunction, ...]
    user_functions: tuple[PyFunction, ...]
    parameters: tuple[PyParameter, ...]
    #: subgroups first, the class of the node's own parameters last
    parameter_groups: tuple[PyParameterGroup, ...]
    lifecycle: tuple[PyTransition, ...]
    has_impl: bool
    #: the executor threads its process needs at least (ComponentPlan.threads)
    threads: int
    #: packages it builds against (its interfaces), and runs with
    depends: tuple[str, ...]
    exec_depends: tuple[str, ...]
    package_xml: PackageXml
    #: where the user's files are, next to the model
    folders: UserFolders
    #: the page of its parameters (doc/parameters.md), if it has any
    parameter_page: ParameterPage | None = None
    skeleton: bool = False

    @property
    def rules(self) -> tuple[PyParameter, ...]:
        """Return the parameters with rules beyond their descriptors."""
        return tuple(p for p in self.parameters if p.rule)

    @property
    def validates(self) -> bool:
        """Tell whether functions of the component validate values (on configure too)."""
        return any(a.startswith('validate=') for p in self.parameters for a in p.rule)

    @property
    def port_names(self) -> list[str]:
        """Return the names of the ports (attributes of the node)."""
        return [p.name for p in self.ports]

    @property
    def impl_path(self) -> str:
        """Return where the user's implementation lives, next to the model."""
        return f'src/{self.package}/{self.cls}_impl.py'
