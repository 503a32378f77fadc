# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The component generator: the files of a component, from its backend's tables."""

from __future__ import annotations

from pathlib import Path

from colcon_robmosys.errors import Location
from colcon_robmosys.generators.files import (
    files_of, implementation_of, PackageFiles, user_files_of)
from colcon_robmosys.mapping.backends import Backend
from colcon_robmosys.mapping.context import ComponentContext


def component_package(backend: Backend, context: ComponentContext, model_dir: Path,
                      location: Location) -> PackageFiles:
    """Return the files of a component package, spelled by its language's backend."""
    facts = backend.package(context)
    return PackageFiles(
        name=context.package, kind='component', model_dir=model_dir,
        build_depends=facts.build_depends, exec_depends=facts.exec_depends,
        files=files_of(backend.files, context),
        user_files=user_files_of(backend.user_files, context),
        implementation=implementation_of(backend.user_files, context, location,
                                         backend.implements),
        user_folders=context.folders.all,
        merged_folders=facts.merged_folders,
        prefix_requirements=facts.prefix_requirements,
        summary={'executables': [context.cls], 'language': backend.language.value})
