# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The models underlays installed: what a workspace builds on, found by package name.

Every generated package installs its model file into ``share/<package>/robmosys/``
and registers the ament index resource ``robmosys_models``. A workspace then refers
to the service definitions, components and systems of its underlays by package
name, as a package.xml does: the workspace's own models first, then each prefix
of ``AMENT_PREFIX_PATH`` in order (the first that has a package wins, as for
packages). A package two underlays install is a warning for each workspace
model that uses it, naming both; one the workspace models itself is not (it
overlays the underlay's, which colcon reports).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.check.results import CheckedFile
from colcon_robmosys.errors import Diagnostic
from colcon_robmosys.model.types import model_key, ModelFile

#: the ament index resource type of installed models
RESOURCE_TYPE = 'robmosys_models'


def installed_model_paths(index: InterfaceIndex, present: set[str]
                          ) -> dict[str, list[Path]]:
    """Return package -> its installed model files, for the packages not in present.

    The first file of a package is the one used; the others are hidden by it.
    """
    found: dict[str, list[Path]] = {}
    for package, prefixes in index.resources(RESOURCE_TYPE).items():
        paths = [prefix / 'share' / package / 'robmosys' / 'robmosys.yaml'
                 for prefix in prefixes]
        paths = [path for path in paths if path.is_file()]
        if package not in present and paths:
            found[package] = paths
    return found


@dataclass
class Underlays:
    """What the underlays installed for a workspace."""

    files: list[ModelFile] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    #: package -> its installed model files, where more than one underlay
    #: installs it: the first is used
    shadowed: dict[str, list[Path]] = field(default_factory=dict)


def installed_models(index: InterfaceIndex, present: set[str],
                     check: Callable[[Path], CheckedFile]) -> Underlays:
    """Return the models of the packages underlays installed, and their problems.

    :param present: the packages (and external components) the workspace models
    :param check: loads and checks one file (through the cache of checked files)
    """
    underlays = Underlays()
    files, diagnostics = underlays.files, underlays.diagnostics
    # an external component is described by the models of the systems that
    # run it (nobody installs it as a package): the first description counts
    described = set(present)
    for package, paths in sorted(installed_model_paths(index, present).items()):
        path = paths[0]
        if len(paths) > 1:
            underlays.shadowed[package] = paths
        checked = check(path)
        diagnostics.extend(checked.diagnostics)
        if checked.model_file is None:
            continue
        loaded = checked.model_file

        def own(models: tuple) -> tuple:  # type: ignore[type-arg]
            # the file may hold the models of other packages too: each installs it
            kept = tuple(m for m in models if m.package == package or (
                getattr(m, 'external', False) and model_key(m) not in described))
            described.update(model_key(m) for m in kept if getattr(m, 'external', False))
            return kept
        files.append(ModelFile(loaded.path, own(loaded.service_definitions),
                               own(loaded.components), own(loaded.systems), installed=True))
    return underlays


def shadow_message(package: str, paths: list[Path]) -> str:
    """Return the warning about a package more than one underlay installs."""
    hidden = ', '.join(f"'{p}'" for p in paths[1:])
    return (f"package '{package}' is installed by more than one underlay: the model "
            f"'{paths[0]}' is used (its prefix comes first in AMENT_PREFIX_PATH), "
            f'{hidden} not')
