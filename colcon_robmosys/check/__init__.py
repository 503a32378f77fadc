# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The check stage: every rule over every model file of a workspace, at once."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable

from colcon_robmosys.check.activities import activity_problems, port_problems
from colcon_robmosys.check.cache import CheckedFile, file_key, ModelCache
from colcon_robmosys.check.cycles import CycleRules
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.check.subsystems import expand_subsystems
from colcon_robmosys.check.types import TypeRules
from colcon_robmosys.check.underlays import installed_models, shadow_message
from colcon_robmosys.check.wiring import WiringRules
from colcon_robmosys.errors import Diagnostic, RobmosysError
from colcon_robmosys.model import rosidl
from colcon_robmosys.model.build import FileBuilder
from colcon_robmosys.model.build_base import MODEL_SECTIONS
from colcon_robmosys.model.files import (
    external_components_of, find_model_files, model_dependencies, packages_of)
from colcon_robmosys.model.loader import (
    load_bytes, load_file, LoadedFile, read_model_bytes)
from colcon_robmosys.model.schema import structure_problems
from colcon_robmosys.model.types import (
    Component, model_key, ModelFile, ServiceDefinition, System, Workspace)

__all__ = ['check_file', 'check_model_file', 'FileCheck', 'find_model_files',
           'load_model_file', 'load_workspace', 'LoadResult', 'ModelCache',
           'WorkspaceChecker']


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

    #: model file -> the key of its content (see check.cache.file_key)
    file_keys: dict[str, str] = field(default_factory=dict)

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
            # an external node answers its ports with code nobody generates
            problems = port_problems(model) + (
                [] if model.external else activity_problems(model))
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


def check_file(path: Path, raw: bytes) -> CheckedFile:
    """Load and check the content of one model file on its own."""
    try:
        loaded = load_bytes(raw, path)
    except RobmosysError as exc:
        return CheckedFile(None, exc.diagnostics)
    checked = check_model_file(loaded)
    return CheckedFile(checked.model_file, checked.diagnostics, checked.broken)


def load_workspace(paths: Iterable[Path],
                   index: InterfaceIndex | None = None,
                   cache: ModelCache | None = None) -> LoadResult:
    """Load the model files and check them together.

    Every file is loaded even when others are broken, so that one run
    reports every problem of the workspace.

    :param cache: where files checked by an earlier run are kept, by content
    """
    if rosidl.MISSING is not None:
        # nothing can be checked without it: one error, and every file broken,
        # so that the build of its packages fails
        return LoadResult(Workspace(()), [Diagnostic(rosidl.MISSING_LOCATION, rosidl.MISSING)],
                          {str(path): [] for path in sorted(set(paths))})
    files: list[ModelFile] = []
    diagnostics: list[Diagnostic] = []
    broken: dict[str, list[tuple[str, str]]] = {}
    keys: dict[str, str] = {}
    # external components of broken files: no "unknown component" for their instances
    broken_external: set[str] = set()

    def checked_file(path: Path, raw: bytes) -> CheckedFile:
        key = keys[str(path)] = file_key(path, raw)
        checked = cache.get(key) if cache is not None else None
        if checked is None:
            if cache is not None:
                cache.use_compiled_schema()
            checked = check_file(path, raw)
            if cache is not None:
                cache.put(key, checked)
        return checked

    for path in sorted(set(paths)):
        try:
            raw = read_model_bytes(path)
        except RobmosysError as exc:
            diagnostics.extend(exc.diagnostics)
            broken[str(path)] = []
            continue
        checked = checked_file(path, raw)
        if checked.model_file is not None:
            # the models that passed: the rules of the workspace check them
            files.append(checked.model_file)
        if checked.diagnostics:
            diagnostics.extend(checked.diagnostics)
            broken[str(path)] = list(checked.declared)
            broken_external.update(_broken_external(path, checked.model_file))
    index = index or InterfaceIndex.from_environment()
    # then what the underlays installed, for the packages the workspace lacks
    present = {model_key(m) for f in files for m in f.models} | {
        name for declared in broken.values() for name, _ in declared}
    underlays = installed_models(
        index, present, lambda path: checked_file(path, path.read_bytes()))
    files += underlays.files
    diagnostics += underlays.diagnostics
    # the rules below see every system with the instances of its subsystems
    files, problems = expand_subsystems(
        files, {name for declared in broken.values() for name, _ in declared})
    diagnostics += problems
    if cache is not None:
        cache.prune(set(keys.values()))
    checker = WorkspaceChecker(
        files, index,
        [name for declared in broken.values() for name, _ in declared] +
        sorted(broken_external))
    checker.check()
    for model_file in files:
        for model in () if model_file.installed else model_file.models:
            for package in model_dependencies(model):
                if package in underlays.shadowed:
                    checker.warning(model.package, model.info.location, shadow_message(
                        package, underlays.shadowed[package]))
    diagnostics.extend(checker.diagnostics)
    return LoadResult(Workspace(tuple(files)), sorted(set(diagnostics)),
                      broken, {package: sorted(set(warnings)) for package,
                               warnings in checker.package_warnings.items()},
                      keys)


def _broken_external(path: Path, kept: ModelFile | None) -> set[str]:
    """Return the external components of a broken file that did not pass."""
    try:
        described = external_components_of(load_file(path).data)
    except RobmosysError:
        return set()
    return set(described) - {model_key(c) for c in kept.components} if kept else set(described)


class WorkspaceChecker(TypeRules, WiringRules, CycleRules):
    """Run every rule that needs more than one model."""

    def check(self) -> None:
        """Check the models of every file together."""
        for model_file in self.files:
            for model in model_file.models:
                key = model_key(model)
                other = self.models.get(key)
                if other is not None:
                    self.error(model.info.location,
                               f"package '{key}' is already "
                               f'generated by the model at '
                               f'{other.info.location}')
                    continue
                self.models[key] = model
                if isinstance(model, ServiceDefinition):
                    self.definitions[key] = model
                elif isinstance(model, Component):
                    self.components[key] = model
        # components before systems: a system's rules skip what follows
        # from a component's error
        for model in self.definitions.values():
            self._check_definition(model)
        for model in self.components.values():
            self._check_component(model)
        # an installed system was checked when its workspace built it; a
        # workspace system that includes it is checked with its instances
        installed = {model_key(m) for f in self.files if f.installed for m in f.systems}
        for key, model in self.models.items():
            if isinstance(model, System) and key not in installed:
                self._check_system(model)
        self._check_cycles()
