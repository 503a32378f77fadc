# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The check stage: every rule over every model file of a workspace, at once."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable

from colcon_robmosys.check.activities import activity_problems
from colcon_robmosys.check.cycles import CycleRules
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.check.types import TypeRules
from colcon_robmosys.check.wiring import WiringRules
from colcon_robmosys.errors import Diagnostic, RobmosysError
from colcon_robmosys.model.build import FileBuilder
from colcon_robmosys.model.files import find_model_files, packages_of
from colcon_robmosys.model.loader import load_file, LoadedFile
from colcon_robmosys.model.schema import check_structure
from colcon_robmosys.model.types import (
    Component, ModelFile, ServiceDefinition, Workspace)

__all__ = ['check_model_file', 'find_model_files', 'load_model_file',
           'load_workspace', 'LoadResult', 'WorkspaceChecker']


@dataclass
class LoadResult:
    """The valid part of a workspace and every problem found in it."""

    workspace: Workspace
    diagnostics: list[Diagnostic] = field(default_factory=list)
    #: model files whose own content is broken -> the packages, with their
    #: kinds, that each seems to declare
    broken_files: dict[str, list[tuple[str, str]]] = field(
        default_factory=dict)

    @property
    def errors(self) -> list[Diagnostic]:
        """Return the diagnostics of severity error."""
        return [d for d in self.diagnostics if d.severity == 'error']

    def errors_of(self, model_file: str) -> list[Diagnostic]:
        """Return the errors located in one model file."""
        return [d for d in self.errors if d.location.path == model_file]

    #: package -> the warnings about its model
    package_warnings: dict[str, list[Diagnostic]] = field(
        default_factory=dict)

    def warnings_of(self, package: str) -> list[Diagnostic]:
        """Return the warnings about the model of one package."""
        return self.package_warnings.get(package, [])

    def raise_errors(self) -> None:
        """Raise every error at once, if there is any."""
        if self.errors:
            raise RobmosysError(self.errors)


def load_model_file(path: Path) -> ModelFile:
    """Load and check a single file on its own.

    :raises RobmosysError: with every problem of the file
    """
    return check_model_file(load_file(path))


def check_model_file(loaded: LoadedFile) -> ModelFile:
    """Check a loaded file on its own.

    :raises RobmosysError: with every problem of the file
    """
    problems = check_structure(loaded)
    if problems:
        raise RobmosysError(problems)
    builder = FileBuilder(loaded)
    model_file = builder.build()
    problems = list(builder.diagnostics)
    if not problems:
        for component in model_file.components:
            problems += activity_problems(component)
    if problems:
        raise RobmosysError(problems)
    return model_file


def load_workspace(paths: Iterable[Path],
                   index: InterfaceIndex | None = None) -> LoadResult:
    """Load the model files and check them together.

    Every file is loaded even when others are broken, so that one run
    reports every problem of the workspace.
    """
    files: list[ModelFile] = []
    diagnostics: list[Diagnostic] = []
    broken: dict[str, list[tuple[str, str]]] = {}
    for path in sorted(set(paths)):
        try:
            loaded = load_file(path)
        except RobmosysError as exc:
            diagnostics.extend(exc.diagnostics)
            broken[str(path)] = []
            continue
        try:
            files.append(check_model_file(loaded))
        except RobmosysError as exc:
            diagnostics.extend(exc.diagnostics)
            # read once: a large file is slow to parse
            broken[str(path)] = packages_of(loaded.data)
    checker = WorkspaceChecker(
        files, index or InterfaceIndex.from_environment(),
        (name for declared in broken.values() for name, _ in declared))
    checker.check()
    diagnostics.extend(checker.diagnostics)
    return LoadResult(Workspace(tuple(files)), sorted(set(diagnostics)),
                      broken, {package: sorted(set(warnings)) for package,
                               warnings in checker.package_warnings.items()})


class WorkspaceChecker(TypeRules, WiringRules, CycleRules):
    """Run every rule that needs more than one model."""

    def check(self) -> None:
        """Check the models of every file together."""
        for model_file in self.files:
            for model in model_file.models:
                other = self.models.get(model.package)
                if other is not None:
                    self.error(model.info.location,
                               f"package '{model.package}' is already "
                               f'generated by the model at '
                               f'{other.info.location}')
                    continue
                self.models[model.package] = model
                if isinstance(model, ServiceDefinition):
                    self.definitions[model.package] = model
                elif isinstance(model, Component):
                    self.components[model.package] = model
        for model in self.models.values():
            if isinstance(model, ServiceDefinition):
                self._check_definition(model)
            elif isinstance(model, Component):
                self._check_component(model)
            else:
                self._check_system(model)
        self._check_cycles()
