# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The C++ generator: the files of a C++ component, from its spelled plan."""

from __future__ import annotations

from pathlib import Path

from colcon_robmosys.errors import Location
from colcon_robmosys.generators.plan import (
    files_of, implementation_of, PackagePlan, Row, user_files_of, UserRow)
from colcon_robmosys.mapping.cpp_context import CppComponent

_SRC = 'src-gen/{package}'
_SKEL = 'src-skel/{package}/{cls}_impl'

#: template -> output path
FILES = (
    Row(f'{_SRC}/{{cls}}.hpp', 'component_cpp/node.hpp.jinja'),
    Row(f'{_SRC}/{{cls}}.cpp', 'component_cpp/node.cpp.jinja'),
    Row(f'{_SRC}/{{cls}}_main.cpp', 'component_cpp/main.cpp.jinja'),
    Row('CMakeLists.txt', 'component_cpp/CMakeLists.txt.jinja'),
    Row('package.xml', 'common/package.xml.jinja', part='package_xml'),
    Row('doc/parameters.md', 'common/parameters.md.jinja', part='parameter_page',
        when='parameter_page'),
    Row(f'{_SKEL}.hpp', 'component_cpp/impl.hpp.jinja', when='has_impl',
        skeleton=True),
    Row(f'{_SKEL}.cpp', 'component_cpp/impl.cpp.jinja', when='has_impl',
        skeleton=True),
)

#: the user's files: created once next to the model, compiled from there
USER_FILES = (
    UserRow('src/{package}/{cls}_impl.hpp', 'component_cpp/impl.hpp.jinja',
            f'{_SKEL}.hpp', when='has_impl',
            required_functions='user_functions', required_class='{cls}_impl'),
    UserRow('src/{package}/{cls}_impl.cpp', 'component_cpp/impl.cpp.jinja',
            f'{_SKEL}.cpp', when='has_impl'),
)


def cpp_package(context: CppComponent, model_dir: Path,
                location: Location) -> PackagePlan:
    """Return the files of a C++ component package."""
    return PackagePlan(
        name=context.package, kind='component', model_dir=model_dir,
        build_depends=context.find_packages,
        exec_depends=context.find_packages,
        files=files_of(FILES, context),
        user_files=user_files_of(USER_FILES, context),
        implementation=implementation_of(USER_FILES, context, location),
        user_folders=context.folders.all,
        prefix_requirements=context.prefix_requirements,
        summary={'executables': [context.cls], 'language': 'cpp'})
