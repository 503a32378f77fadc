# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The system generator: launch files, parameters and a diagram."""

from __future__ import annotations

from pathlib import Path

from colcon_robmosys.generators.files import files_of, FileSpec, PackageFiles
from colcon_robmosys.mapping.launch import PARAMS_FILE
from colcon_robmosys.mapping.system import SystemPackage
from colcon_robmosys.mapping.tables import Row

#: template -> output path, once per launch file (all instances, then each)
LAUNCH_FILES = (
    Row('launch/{nodes_file}', 'system/launch.py.jinja'),
    Row('launch/{activate_file}', 'system/activate.py.jinja', when='activates_itself'),
    Row('launch/{activate_file}', 'system/manage.launch.py.jinja', when='has_manager'),
    # the names of the last release, kept for one more
    Row('launch/launch{suffix}.py', 'system/alias.launch.py.jinja', part='nodes_alias',
        when='has_aliases'),
    Row('launch/activate{suffix}.py', 'system/alias.launch.py.jinja',
        part='activate_alias', when='has_aliases'),
)

#: template -> output path
FILES = (
    Row(PARAMS_FILE, 'system/params.yaml.jinja'),
    Row('{diagram}', 'system/diagram.dot.jinja'),
    Row('doc/modes.md', 'system/modes.md.jinja', when='has_modes'),
    Row('{svg}', 'system/diagram.svg.jinja'),
    Row('bringup.json', 'system/bringup.json.jinja'),
    Row('bringup', 'system/bringup.jinja', executable=True),
    Row('check_params', 'system/check_params.jinja', executable=True),
    Row('test/test_smoke.py', 'system/test_smoke.py.jinja'),
    Row('CMakeLists.txt', 'system/CMakeLists.txt.jinja'),
    Row('package.xml', 'common/package.xml.jinja', part='package_xml'),
)


def system_package(context: SystemPackage, model_dir: Path) -> PackageFiles:
    """Return the files of a system package."""
    files: tuple[FileSpec, ...] = ()
    for launch in context.launch_files:
        files += files_of(LAUNCH_FILES, launch)
    return PackageFiles(
        name=context.package, kind='system', model_dir=model_dir,
        build_depends=context.depends, exec_depends=context.exec_depends,
        files=files + files_of(FILES, context),
        summary={'nodes': context.nodes})
