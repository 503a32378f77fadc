# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The context of the Python templates: the spelling of a component, filled by spelling.py."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from colcon_robmosys.mapping.context import (
    ComponentContext, GroupClass, SpelledActivity, SpelledFunction, SpelledParameter, SpelledPort)


@dataclass(frozen=True, kw_only=True)
class PyPort(SpelledPort):
    """A port as the Python node creates it."""

    type_full: str
    #: the QoS profile expression, for ports that use a topic
    qos: str | None
    qos_const: str
    #: the ComponentNode method that creates it
    method: str
    #: what its activity runs: a method, or a list of them
    run: str


@dataclass(frozen=True, kw_only=True)
class PyFunction(SpelledFunction):
    """A function of the model as a method."""

    args: tuple[str, ...]
    default_return: str


@dataclass(frozen=True, kw_only=True)
class PyParameter(SpelledParameter):
    """A parameter: its declaration with a descriptor, and its accessor.

    Its rule is the arguments of its ParameterRule (one_of, size, validate,
    on_change).
    """

    py_type: str
    ros_type: str
    default: Any
    description: str
    read_only: bool


@dataclass(frozen=True, kw_only=True)
class PyActivity(SpelledActivity):
    """A periodic activity and its timer."""

    #: the list of methods it runs
    run: str


@dataclass(frozen=True)
class PyTransition:
    """A lifecycle transition that runs functions of the model."""

    transition: str
    #: the list of methods it runs
    run: str


@dataclass(frozen=True, kw_only=True)
class PyComponent(ComponentContext):
    """Everything the templates of a Python component print: the shared part, and this."""

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
    parameter_groups: tuple[GroupClass, ...]
    #: the lifecycle transitions that run functions, and how
    transitions: tuple[PyTransition, ...]
    #: packages it builds against (its interfaces), and runs with
    depends: tuple[str, ...]
    exec_depends: tuple[str, ...]

    @property
    def port_names(self) -> list[str]:
        """Return the names of the ports (attributes of the node)."""
        return [p.name for p in self.ports]
