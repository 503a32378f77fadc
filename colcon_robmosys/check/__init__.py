# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The check stage: every rule over every model file of a workspace, at once."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable

from colcon_robmosys.check.activities import activity_problems, port_problems
from colcon_robmosys.check.cycles import CycleRules
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.check.types import TypeRules
from colcon_robmosys.check.wiring import WiringRules
from colcon_robmosys.errors import Diagnostic, RobmosysError
from colcon_robmosys.model.build import FileBuilder
from colcon_robmosys.model.build_base import MODEL_SECTIONS
from colcon_robmosys.model.files import find_model_files, packages_of
from colcon_robmosys.model.loader import load_file, LoadedFile
from colcon_robmosys.model.schema import structure_problems
from colcon_robmosys.model.types import (
    Component, ModelFile, ServiceDefinition, System, Workspace)

__all__ = ['check_model_file', 'FileCheck', 'find_model_files', 'load_model_file',
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


@dataclass(frozen=True)
class FileCheck:
    """What the rules of a single file found in it."""

    #: the models that passed, whole
    model_file: ModelFile
    diagnostics: tuple[Diagnostic, ...]
    #: the packages, with their kinds, of the models that did not pass
    broken: tuple[tuple[str, str], ...]


def load_model_file(path: Path) -> ModelFile:
    """Load and check a single file on its own.

    :raises RobmosysError: with every problem of the file
    """
    checked = check_model_file(load_file(path))
    if checked.diagnostics:
        raise RobmosysError(checked.diagnostics)
    return checked.model_file


def check_model_file(loaded: LoadedFile) -> FileCheck:
    """Run the rules of a single file: the schema, then each model's own.

    A model whose part of the file breaks a rule is left out; the others
    are kept for the rules of the workspace, so that an error in one model
    hides no error of another.
    """
    located = structure_problems(loaded)
    diagnostics = [d for _, d in located]
    everything = packages_of(loaded.data)
    if any(len(p) < 2 or p[0] not in MODEL_SECTIONS for p, _ in located):
        # the file as a whole (its version, its defaults) is broken
        return FileCheck(ModelFile(str(loaded.path)), tuple(diagnostics),
                         tuple(everything))
    skip = frozenset((str(p[0]), int(p[1])) for p, _ in located)
    builder = FileBuilder(loaded)
    models = builder.build_models(skip)
    diagnostics += builder.diagnostics
    broken = set(skip) | builder.broken_models
    for key, model in models:
        if isinstance(model, Component):
            problems = port_problems(model) + activity_problems(model)
            diagnostics += problems
            if problems:
                broken.add(key)
    kept = [m for key, m in models if key not in broken]
    kept_packages = {m.package for m in kept}
    return FileCheck(
        ModelFile(
            str(loaded.path),
            tuple(m for m in kept if isinstance(m, ServiceDefinition)),
            tuple(m for m in kept if isinstance(m, Component)),
            tuple(m for m in kept if isinstance(m, System))),
        tuple(diagnostics),
        tuple(p for p in everything if p[0] not in kept_packages))


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
        checked = check_model_file(loaded)
        files.append(checked.model_file)
        if checked.diagnostics:
            diagnostics.extend(checked.diagnostics)
            broken[str(path)] = list(checked.broken)
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
