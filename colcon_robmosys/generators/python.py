# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The Python generator: the files of a Python component, from its spelled plan."""

from __future__ import annotations

from pathlib import Path

from colcon_robmosys.errors import Location
from colcon_robmosys.generators.plan import (
    files_of, implementation_of, PackagePlan, Row, user_files_of, UserRow)
from colcon_robmosys.mapping.python_context import PyComponent

_SKEL = 'src-skel/{package}/{cls}_impl_skel.py'

#: template -> output path
FILES = (
    Row('{package}/__init__.py', 'component_python/init.py.jinja'),
    Row('{package}/{cls}.py', 'component_python/node.py.jinja'),
    Row('{package}/{cls}_main.py', 'component_python/main.py.jinja'),
    Row('scripts/{cls}', 'component_python/executable.jinja', executable=True),
    Row('CMakeLists.txt', 'component_python/CMakeLists.txt.jinja'),
    Row('package.xml', 'common/package.xml.jinja', part='package_xml'),
    Row('doc/parameters.md', 'common/parameters.md.jinja', part='parameter_page',
        when='parameter_page'),
    Row(_SKEL, 'component_python/impl.py.jinja', when='has_impl',
        skeleton=True),
)

#: the user's file: created once next to the model, installed from there
USER_FILES = (
    UserRow('src/{package}/{cls}_impl.py', 'component_python/impl.py.jinja', _SKEL,
            when='has_impl',
            required_functions='user_functions', required_class='{cls}_impl'),
)


def python_package(context: PyComponent, model_dir: Path,
                   location: Location) -> PackagePlan:
    """Return the files of a Python component package."""
    return PackagePlan(
        name=context.package, kind='component', model_dir=model_dir,
        build_depends=context.depends, exec_depends=context.exec_depends,
        files=files_of(FILES, context),
        user_files=user_files_of(USER_FILES, context),
        implementation=implementation_of(USER_FILES, context, location),
        user_folders=context.folders.all,
        # the user's modules join the generated ones in one Python package
        merged_folders={context.folders.code: context.package},
        summary={'executables': [context.cls]})
