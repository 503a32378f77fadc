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
import os
from pathlib import Path

#: The name of the runtime package.
RUNTIME_PACKAGE = 'robmosys_runtime'


def runtime_source() -> Path:
    """Return the source folder of the runtime package (it holds its package.xml)."""
    return Path(__file__).resolve().parent / RUNTIME_PACKAGE


def installed_runtime(environ: Mapping[str, str] | None = None,
                      ignored: Iterable[Path] = ()) -> Path | None:
    """
    Return the prefix that provides the runtime package, or None.

    A prefix of AMENT_PREFIX_PATH provides it with its ament index entry, one of
    CMAKE_PREFIX_PATH with its CMake config file. Prefixes at or below an
    ignored folder do not count (the install folder of the workspace being
    built: its own earlier build of the runtime is no underlay).
    """
    # not ament_index_python: it reads os.environ's AMENT_PREFIX_PATH only, and
    # knows neither CMAKE_PREFIX_PATH nor prefixes that do not count
    environ = os.environ if environ is None else environ
    skipped = [Path(p).resolve() for p in ignored]
    candidates = {
        'AMENT_PREFIX_PATH': Path('share', 'ament_index', 'resource_index', 'packages',
                                  RUNTIME_PACKAGE),
        'CMAKE_PREFIX_PATH': Path('share', RUNTIME_PACKAGE, 'cmake',
                                  f'{RUNTIME_PACKAGE}Config.cmake'),
    }
    for variable, marker in candidates.items():
        for entry in environ.get(variable, '').split(os.pathsep):
            if not entry:
                continue
            prefix = Path(entry).resolve()
            if any(prefix == s or s in prefix.parents for s in skipped):
                continue
            if (prefix / marker).is_file():
                return prefix
    return None
