# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The context of the C++ templates: frozen dataclasses, filled by mapping/cpp.py."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from colcon_robmosys.mapping.common import Banner, PackageXml
from colcon_robmosys.mapping.parameters import ParameterPage
from colcon_robmosys.mapping.userfiles import UserFolders


@dataclass(frozen=True)
class CppPort:
    """A port as the C++ node declares and creates it."""

    name: str
    entity: str
    type: str
    member_type: str
    description: str
    #: statements that set each QoS policy (topics and events)
    qos: tuple[str, ...]
    activity: str | None
    functions: tuple[str, ...]
    own_group: bool
    call_args: str


@dataclass(frozen=True)
class CppFunction:
    """A function of the model as a virtual member function."""

    name: str
    returns: str
    params: tuple[str, ...]
    #: what the skeleton does not use yet
    param_names: tuple[str, ...]
    #: one parameter a line, when one line would be too long for cpplint
    wrap: bool
    code: str | None
    description: str


@dataclass(frozen=True)
class CppRange:
    """The range of a numeric parameter's descriptor."""

    field: str
    cls: str
    start: str
    end: str
    step: str


@dataclass(frozen=True)
class CppParameter:
    """A parameter: its declaration with a descriptor, and its accessor."""

    name: str
    cpp_type: str
    accessor: str
    default_lines: tuple[str, ...]
    description_lines: tuple[str, ...]
    doc: str
    read_only: str
    range: CppRange | None
    #: the last part of its name: the accessor of its group
    attr: str = ''
    #: the statements that fill its ParameterRule, if it has rules
    rule_lines: tuple[str, ...] = ()


@dataclass(frozen=True)
class CppParameterGroup:
    """The class of a group of parameters: typed access, nested by dotted names."""

    #: its name in Parameters ('' for Parameters itself)
    cls: str
    doc: str
    parameters: tuple[CppParameter, ...]
    #: (member, class) of each subgroup
    groups: tuple[tuple[str, str], ...]

    @property
    def initializers(self) -> list[str]:
        """Return the member initializers of its constructor: subgroups, then the node."""
        return [f'{member}(node)' for member, _ in self.groups] + ['node_(node)']


@dataclass(frozen=True)
class CppActivity:
    """An activity: its callback group, lock and, if periodic, its timer."""

    name: str
    period: float | None
    period_ns: int | None
    functions: tuple[str, ...]
    description: str


@dataclass(frozen=True)
class CppIncludes:
    """The includes of the generated header."""

    system: tuple[str, ...]
    ros: tuple[str, ...]


@dataclass(frozen=True)
class CppComponent:
    """Everything the templates of a C++ component print."""

    banner: Banner
    package: str
    cls: str
    node_cls: str
    node_header: str
    description: str
    includes: CppIncludes
    ports: tuple[CppPort, ...]
    #: the ports by entity, so that templates need not compare names
    publishers: tuple[CppPort, ...]
    action_servers: tuple[CppPort, ...]
    activities: tuple[CppActivity, ...]
    periodic: tuple[CppActivity, ...]
    functions: tuple[CppFunction, ...]
    user_functions: tuple[CppFunction, ...]
    parameters: tuple[CppParameter, ...]
    #: the groups of Parameters, a subgroup first; then Parameters itself
    parameter_groups: tuple[CppParameterGroup, ...]
    #: transition -> functions run on it (the transitions that run any)
    lifecycle: Mapping[str, tuple[str, ...]]
    threads: int
    has_impl: bool
    find_packages: tuple[str, ...]
    link_targets: tuple[str, ...]
    interface_packages: tuple[str, ...]
    sources: tuple[str, ...]
    prefix_requirements: tuple[str, ...]
    package_xml: PackageXml
    #: where the user's files are, next to the model
    folders: UserFolders
    #: the page of its parameters (doc/parameters.md), if it has any
    parameter_page: ParameterPage | None = None
    #: the skeleton or the user's file (impl templates)
    skeleton: bool = False

    @property
    def rules(self) -> tuple[CppParameter, ...]:
        """Return the parameters with rules beyond their descriptors."""
        return tuple(p for p in self.parameters if p.rule_lines)

    @property
    def validates(self) -> bool:
        """Tell whether functions of the component validate values (on configure too)."""
        return any(line.startswith('rule.validate') for p in self.rules for line in p.rule_lines)

    @property
    def impl_paths(self) -> tuple[str, str]:
        """Return where the user's header and source live, next to the model."""
        stem = f'src/{self.package}/{self.cls}_impl'
        return f'{stem}.hpp', f'{stem}.cpp'
