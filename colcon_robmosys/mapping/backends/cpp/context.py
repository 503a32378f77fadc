# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The context of the C++ templates: the spelling of a component, filled by spelling.py."""

from __future__ import annotations

from dataclasses import dataclass

from colcon_robmosys.mapping.context import (
    ComponentContext, GroupClass, SpelledActivity, SpelledFunction, SpelledParameter, SpelledPort)


@dataclass(frozen=True, kw_only=True)
class CppPort(SpelledPort):
    """A port as the C++ node declares and creates it."""

    member_type: str
    #: the fragment of create_ports that creates it
    template: str
    #: the parameters of the functions it runs (PARAMETERS), if it runs any
    params: tuple[str, ...]
    #: statements that set each QoS policy (topics and events)
    qos: tuple[str, ...]
    own_group: bool
    call_args: str


@dataclass(frozen=True, kw_only=True)
class CppFunction(SpelledFunction):
    """A function of the model as a virtual member function."""

    params: tuple[str, ...]
    #: what the skeleton does not use yet
    param_names: tuple[str, ...]
    #: one parameter a line, when one line would be too long for cpplint
    wrap: bool


@dataclass(frozen=True, kw_only=True)
class CppParameter(SpelledParameter):
    """A parameter: its declaration with a descriptor, and its accessor.

    Its rule is the statements that fill its ParameterRule.
    """

    cpp_type: str
    accessor: str
    default_lines: tuple[str, ...]
    description_lines: tuple[str, ...]
    read_only: str
    #: its rclcpp::ParameterType, declared without a value when it is required
    parameter_type: str = ''


@dataclass(frozen=True)
class CppParameterGroup(GroupClass):
    """The class of a group of parameters, named in Parameters ('' for Parameters itself)."""

    @property
    def initializers(self) -> list[str]:
        """Return the member initializers of its constructor: subgroups, then the node."""
        return [f'{member}(node)' for member, _ in self.groups] + ['node_(node)']


@dataclass(frozen=True, kw_only=True)
class CppActivity(SpelledActivity):
    """An activity: its callback group, lock and, if periodic, its timer."""

    period_ns: int | None


@dataclass(frozen=True)
class CppIncludes:
    """The includes of the generated header."""

    system: tuple[str, ...]
    ros: tuple[str, ...]


@dataclass(frozen=True, kw_only=True)
class CppComponent(ComponentContext):
    """Everything the templates of a C++ component print: the shared part, and this."""

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
    find_packages: tuple[str, ...]
    link_targets: tuple[str, ...]
    interface_packages: tuple[str, ...]
    sources: tuple[str, ...]
    prefix_requirements: tuple[str, ...]
