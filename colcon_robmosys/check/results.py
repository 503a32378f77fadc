# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""What the check stage returns: of one model file, and of a workspace."""

from __future__ import annotations

from dataclasses import dataclass, field

from colcon_robmosys.errors import Diagnostic, RobmosysError
from colcon_robmosys.model.types import ModelFile, Workspace


@dataclass(frozen=True)
class CheckedFile:
    """What loading and checking one model file on its own gave.

    The check cache keeps these (see check.cache), one per file content.
    """

    #: the models that passed its own rules, whole (None: the file cannot be read)
    model_file: ModelFile | None
    #: its problems, if any
    diagnostics: tuple[Diagnostic, ...] = ()
    #: the packages, with their kinds, of its models that did not pass
    broken: tuple[tuple[str, str], ...] = ()


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
