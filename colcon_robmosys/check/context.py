# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""What every rule of the workspace is given (check.rules): the models, and the findings."""

from __future__ import annotations

from typing import Iterable, Sequence

from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.errors import Diagnostic, Location
from colcon_robmosys.model.types import (
    Component, Model, ModelFile, ServiceDefinition)


class CheckContext:
    """The models of a workspace, and the diagnostics found in them."""

    def __init__(self, files: Sequence[ModelFile], index: InterfaceIndex,
                 broken_packages: Iterable[str] = ()):
        self.files = files
        self.index = index
        # packages of files with errors of their own: what refers to them
        # is not checked, rather than reported as unknown
        self.broken_packages = frozenset(broken_packages)
        self.diagnostics: list[Diagnostic] = []
        self.package_warnings: dict[str, list[Diagnostic]] = {}
        self.models: dict[str, Model] = {}
        self.definitions: dict[str, ServiceDefinition] = {}
        self.components: dict[str, Component] = {}
        #: ports whose type is already reported: what follows from it is not
        self.mistyped: set[Location] = set()

    def error(self, location: Location, message: str) -> None:
        """Record an error."""
        self.diagnostics.append(Diagnostic(location, message))

    def warning(self, package: str, location: Location, message: str
                ) -> None:
        """Record a warning about the model of a package."""
        diagnostic = Diagnostic(location, message, 'warning')
        self.diagnostics.append(diagnostic)
        self.package_warnings.setdefault(package, []).append(diagnostic)
