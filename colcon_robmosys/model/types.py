# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The RobMoSys model, in RobMoSys terms: frozen, typed and validated.

The concepts live in base, definitions, components and systems; this module
names them all, and holds what spans them (a file, a workspace).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Union

from colcon_robmosys.model.base import (
    Executor, InterfaceKind, InterfaceRef, Language, LIFECYCLE_TRANSITIONS, Maintainer,
    PackageInfo, Pattern, PATTERN_INTERFACE, Role)
from colcon_robmosys.model.components import (
    Activity, Component, Function, Parameter, ParameterRange, ParameterSize,
    ParameterValue, Port, QoS)
from colcon_robmosys.model.definitions import (
    Action, CommunicationObject, Constant, Event, Field, FieldType, Query,
    ServiceDefinition, Structure)
from colcon_robmosys.model.systems import (
    Connection, Instance, Mode, ModeValues, PortRef, QoSOverride, Subsystem, System)

__all__ = [
    'Action', 'Activity', 'CommunicationObject', 'Component', 'Connection',
    'Constant', 'Event', 'Field', 'FieldType', 'Function', 'Instance',
    'Executor', 'InterfaceKind', 'InterfaceRef', 'Language', 'LIFECYCLE_TRANSITIONS',
    'Maintainer', 'Mode', 'Model', 'model_key', 'ModeValues', 'ModelFile', 'PackageInfo',
    'Parameter', 'ParameterRange', 'ParameterSize', 'ParameterValue', 'Pattern',
    'PATTERN_INTERFACE',
    'Port', 'PortRef', 'QoS', 'QoSOverride', 'Query', 'Role',
    'ServiceDefinition', 'Structure', 'Subsystem', 'System', 'Workspace',
]

Model = Union[ServiceDefinition, Component, System]


@dataclass(frozen=True)
class ModelFile:
    """The models of one robmosys.yaml file."""

    path: str
    service_definitions: tuple[ServiceDefinition, ...] = ()
    components: tuple[Component, ...] = ()
    systems: tuple[System, ...] = ()
    #: a model installed by an underlay (share/<package>/robmosys/): built already
    installed: bool = False

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
    # model file -> how many components of it generate a package
    _components_per_file: dict[str, int] = field(
        init=False, repr=False, compare=False)
    # the models that generate a package, asked for by every system's plan
    _generated: tuple[Model, ...] = field(init=False, repr=False, compare=False)
    # model file -> the first package by name generated from it
    _first_package: dict[str, str] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        of_files = [(f, f.models) for f in self.files]
        models = tuple(m for _, of_file in of_files for m in of_file)
        by_package: dict[str, Model] = {}
        for model in models:
            # a package claimed twice is an error of the workspace; until
            # it is fixed, the first model keeps it
            by_package.setdefault(model_key(model), model)
        per_file: dict[str, int] = {}
        for model in models:
            if isinstance(model, Component) and not model.external:
                per_file[model.info.model_file] = per_file.get(model.info.model_file, 0) + 1
        object.__setattr__(self, 'models', models)
        object.__setattr__(self, '_by_package', by_package)
        object.__setattr__(self, '_components_per_file', per_file)
        object.__setattr__(self, '_generated', tuple(
            m for f, of_file in of_files if not f.installed for m in of_file
            if not (isinstance(m, (Component, ServiceDefinition)) and m.external)))
        first: dict[str, str] = {}
        for model in self._generated:
            path = model.info.model_file
            if path not in first or model.package < first[path]:
                first[path] = model.package
        object.__setattr__(self, '_first_package', first)

    @property
    def generated_models(self) -> tuple[Model, ...]:
        """Return the models that generate a package of this workspace.

        Not external components (a hand-written package) nor external service
        definitions (an installed interface package), nor the models an
        underlay installed (built there).
        """
        return self._generated

    def first_package_of(self, model_file: str) -> str | None:
        """Return the first package by name generated from a model file, None if none is."""
        return self._first_package.get(model_file)

    def components_in_file(self, model_file: str) -> int:
        """Return how many components of a model file generate a package."""
        return self._components_per_file.get(model_file, 0)

    def model(self, package: str) -> Model | None:
        """Return the model of a package, or of an external component (package/executable)."""
        return self._by_package.get(package)


def model_key(model: Model) -> str:
    """Return what names a model: its package; package/executable for an external component.

    A hand-written package may hold several nodes: each external component
    of it is named by its executable too (an instance's ``component``).
    """
    if isinstance(model, Component) and model.external:
        return f'{model.package}/{model.executable}'
    return model.package
