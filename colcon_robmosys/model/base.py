# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The words every model shares: patterns, roles, interfaces, package metadata."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

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


class Executor(str, Enum):
    """What runs the callbacks of a process: one thread on events, one on a wait set, or many."""

    EVENTS = 'events'
    SINGLE_THREADED = 'single-threaded'
    MULTI_THREADED = 'multi-threaded'


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
    #: where the model names each of ``depends``
    depends_locations: tuple[Location, ...] = ()
    #: rosdep keys of system dependencies (components): for package.xml only
    system_depends: tuple[str, ...] = ()


@dataclass(frozen=True)
class InterfaceRef:
    """A reference to a ROS 2 interface: ``package/kind/Name``."""

    package: str
    kind: InterfaceKind
    name: str

    def __str__(self) -> str:
        return f'{self.package}/{self.kind.value}/{self.name}'
