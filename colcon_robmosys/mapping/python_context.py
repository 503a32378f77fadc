# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The context of the Python templates: frozen dataclasses, filled by mapping/python.py."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

from colcon_robmosys.mapping.common import Banner, PackageXml


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
    callback: str
    functions: tuple[str, ...]
    #: the node method that destroys it, if it has no destroy() of its own
    destroy: str | None


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


@dataclass(frozen=True)
class PyActivity:
    """A periodic activity and its timer."""

    name: str
    period: float | None
    functions: tuple[str, ...]
    description: str


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
    #: the helper classes the node module defines
    helpers: tuple[str, ...]
    functions: tuple[PyFunction, ...]
    user_functions: tuple[PyFunction, ...]
    parameters: tuple[PyParameter, ...]
    lifecycle: Mapping[str, tuple[str, ...]]
    has_impl: bool
    #: packages it builds against (its interfaces), and runs with
    depends: tuple[str, ...]
    exec_depends: tuple[str, ...]
    package_xml: PackageXml
    skeleton: bool = False

    @property
    def impl_path(self) -> str:
        """Return where the user's implementation lives, next to the model."""
        return f'src/{self.package}/{self.cls}_impl.py'
