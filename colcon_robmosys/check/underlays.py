# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The models underlays installed: what a workspace builds on, found by package name.

Every generated package installs its model file into ``share/<package>/robmosys/``
and registers the ament index resource ``robmosys_models``. A workspace then refers
to the service definitions, components and systems of its underlays by package
name, as a package.xml does: the workspace's own models first, then each prefix
of ``AMENT_PREFIX_PATH`` in order (the first that has a package wins, as for
packages).
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

from colcon_robmosys.check.cache import CheckedFile
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.errors import Diagnostic
from colcon_robmosys.model.types import ModelFile

#: the ament index resource type of installed models
RESOURCE_TYPE = 'robmosys_models'


def installed_model_paths(index: InterfaceIndex, present: set[str]) -> dict[str, Path]:
    """Return package -> its installed model file, for the packages not in present."""
    found: dict[str, Path] = {}
    for prefix in index.prefixes:
        folder = prefix / 'share' / 'ament_index' / 'resource_index' / RESOURCE_TYPE
        if not folder.is_dir():
            continue
        for marker in sorted(folder.iterdir()):
            path = prefix / 'share' / marker.name / 'robmosys' / 'robmosys.yaml'
            if marker.name not in present and marker.name not in found and path.is_file():
                found[marker.name] = path
    return found


def installed_models(index: InterfaceIndex, present: set[str],
                     check: Callable[[Path], CheckedFile]
                     ) -> tuple[list[ModelFile], list[Diagnostic]]:
    """Return the models of the packages underlays installed, and their problems.

    :param present: the packages (and external components) the workspace models
    :param check: loads and checks one file (through the cache of checked files)
    """
    files: list[ModelFile] = []
    diagnostics: list[Diagnostic] = []
    for package, path in sorted(installed_model_paths(index, present).items()):
        checked = check(path)
        diagnostics.extend(checked.diagnostics)
        if checked.model_file is None:
            continue
        loaded = checked.model_file

        def own(models: tuple) -> tuple:  # type: ignore[type-arg]
            # the file may hold the models of other packages too: each installs it
            return tuple(m for m in models if m.package == package)
        files.append(ModelFile(loaded.path, own(loaded.service_definitions),
                               own(loaded.components), own(loaded.systems), installed=True))
    return files, diagnostics
