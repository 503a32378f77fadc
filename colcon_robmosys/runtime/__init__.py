# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
robmosys_runtime, the ament package generated components use, as package data.

The package (a C++ header library and a Python module, see docs/runtime.md)
sits in the folder :func:`runtime_source`. A workspace of models gets it as one
more package when no prefix provides it already (see :func:`installed_runtime`).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
import importlib
import os
from pathlib import Path
import sys
from types import ModuleType

from colcon_robmosys.check.index import environ_prefixes, search_prefixes
from colcon_robmosys.mapping.common import RUNTIME_PACKAGE


def runtime_source() -> Path:
    """Return the source folder of the runtime package (it holds its package.xml)."""
    return Path(__file__).resolve().parent / RUNTIME_PACKAGE


def package_markers(name: str) -> tuple[Path, Path, Path]:
    """Return what marks a package installed in a prefix, relative to the prefix.

    Its ament index entry, and its CMake config file in both spellings
    find_package() looks for.
    """
    share = Path('share')
    return (share / 'ament_index' / 'resource_index' / 'packages' / name,
            share / name / 'cmake' / f'{name}Config.cmake',
            share / name / 'cmake' / f'{name}-config.cmake')


def installed_runtime(environ: Mapping[str, str] | None = None,
                      ignored: Iterable[Path] = ()) -> Path | None:
    """
    Return the prefix that provides the runtime package, or None.

    A prefix of AMENT_PREFIX_PATH provides it with its ament index entry, one of
    CMAKE_PREFIX_PATH with its CMake config file. Prefixes at or below an
    ignored folder do not count (the install folder of the workspace being
    built: its own earlier build of the runtime is no underlay).
    """
    environ = os.environ if environ is None else environ
    index_entry, cmake_config, _ = package_markers(RUNTIME_PACKAGE)
    for variable, marker in (('AMENT_PREFIX_PATH', index_entry),
                             ('CMAKE_PREFIX_PATH', cmake_config)):
        found = search_prefixes(environ_prefixes(environ, variable), [marker], ignored)
        if found is not None:
            return found
    return None


def runtime_module(name: str) -> ModuleType:
    """
    Import a module of the runtime's Python package from this package data.

    For what the glue runs of the runtime itself (the check of parameter
    files), so that it is the runtime of this colcon-robmosys, not an older
    one of a sourced underlay. The module must not need rclpy.
    """
    source = str(runtime_source())
    loaded = sys.modules.get(RUNTIME_PACKAGE)
    if loaded is not None and not str(getattr(loaded, '__file__', '')).startswith(source):
        for key in [k for k in sys.modules
                    if k == RUNTIME_PACKAGE or k.startswith(f'{RUNTIME_PACKAGE}.')]:
            del sys.modules[key]
    sys.path.insert(0, source)
    try:
        return importlib.import_module(f'{RUNTIME_PACKAGE}.{name}')
    finally:
        sys.path.remove(source)
