# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The interfaces generator: .msg, .srv and .action files, and their package."""

from __future__ import annotations

from pathlib import Path

from colcon_robmosys.generators.files import files_of, FileSpec, PackageFiles
from colcon_robmosys.mapping.interfaces import InterfacePackage
from colcon_robmosys.mapping.tables import Row

#: the template of every interface file (at the path the plan gives)
INTERFACE_TEMPLATE = 'interfaces/interface.jinja'

#: template -> output path
FILES = (
    Row('CMakeLists.txt', 'interfaces/CMakeLists.txt.jinja'),
    Row('package.xml', 'common/package.xml.jinja', part='package_xml'),
)


def interfaces_package(context: InterfacePackage,
                       model_dir: Path) -> PackageFiles:
    """Return the files of an interface package."""
    files = tuple(FileSpec(f.path, INTERFACE_TEMPLATE, f)
                  for f in context.files)
    return PackageFiles(
        name=context.package, kind='interfaces', model_dir=model_dir,
        build_depends=context.depends, exec_depends=context.depends,
        files=files + files_of(FILES, context),
        summary={'interfaces': list(context.interface_files)})
