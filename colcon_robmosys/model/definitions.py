# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Service definitions: communication objects, queries, actions, events."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from colcon_robmosys.errors import Location
from colcon_robmosys.model.base import InterfaceRef, PackageInfo


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
    #: describes an installed interface package: nothing is generated
    external: bool = False

    @property
    def package(self) -> str:
        """Return the name of the generated package."""
        return self.info.name
