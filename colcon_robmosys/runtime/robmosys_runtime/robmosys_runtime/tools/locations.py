# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
Where the system manager's reports point: the model file the user wrote, or its copy.

``bringup.json`` names each model file as its installed copy,
``share/<package>/robmosys/robmosys.yaml``, relative to the prefix that holds
it: a package holds no path of the machine that built it. The copy is the model
file's text as it is (its lines are the model file's), and ``source.yaml``
beside it says where the model file was when the package was built, relative
to the copy's folder (CMake wrote it at the build: the package's generated
sources hold no path either). Here each location becomes that model file where
it is there with the text the system was built from (the workspace it was
built in), else the copy (an installed robot, an install moved, a model edited
since). No rclpy, no yaml: bringup starts the instances right after.
"""

from __future__ import annotations

import os
from typing import Any, Dict, List, Optional

#: beside the installed copy: where its model file was built from
SOURCE_FILE = 'source.yaml'
_SOURCE_KEY = "source: '"


def resolve_locations(description: Dict[str, Any],
                      prefixes: Optional[List[str]] = None) -> Dict[str, Any]:
    """
    Point the locations of a description at the model files; return it.

    Each installed copy is the file of the first prefix of AMENT_PREFIX_PATH that
    has it, then the model file it was made from where that is there with the
    same text (:func:`model_file`); a path below the current folder is shown
    relative to it, as a compiler shows the files it was given.

    :param prefixes: the prefixes to search (default: AMENT_PREFIX_PATH's)
    """
    if prefixes is None:
        prefixes = [p for p in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep) if p]
    found: Dict[str, str] = {}

    def resolve(location: str) -> str:
        path, sep, place = location.partition(':')
        if not sep or not path.startswith('share/'):
            return location
        if path not in found:
            copy = next((os.path.join(prefix, path) for prefix in prefixes
                         if os.path.isfile(os.path.join(prefix, path))), None)
            found[path] = shown(model_file(copy)) if copy is not None else path
        return f'{found[path]}:{place}'

    for item in [*description.get('instances', []), *description.get('connections', [])]:
        if 'location' in item:
            item['location'] = resolve(item['location'])
        for parameter in item.get('parameters', []):
            parameter['location'] = resolve(parameter['location'])
    return description


def model_file(copy: str) -> str:
    """
    Return the model file an installed copy was made from, if it is there unchanged; else the copy.

    Unchanged: the same text, so that every line the description gives is the
    line of that file. A model edited since the build has other lines: the
    copy's are the system's.
    """
    source = _source_of(copy)
    if not source:
        return copy
    text = _text(copy)
    if text is None:
        return copy
    folder = os.path.dirname(copy)
    # the path is relative to the folder as the build named the prefix; a prefix
    # reached through a symbolic link leads there from the folder's real path
    for base in dict.fromkeys((folder, os.path.realpath(folder))):
        candidate = os.path.normpath(os.path.join(base, source))
        if os.path.isfile(candidate) and _text(candidate) == text:
            return candidate
    return copy


def shown(path: str) -> str:
    """Return a path relative to the current folder if it lies below it, else as it is."""
    try:
        here = os.getcwd()
    except OSError:
        return path
    absolute = os.path.abspath(path)
    if here != os.sep and absolute.startswith(here.rstrip(os.sep) + os.sep):
        return os.path.relpath(absolute, here)
    return path


def _source_of(copy: str) -> str:
    """Return what source.yaml beside a copy says ('' where nothing, or no such file)."""
    text = _text(os.path.join(os.path.dirname(copy), SOURCE_FILE))
    for line in (text or '').splitlines():
        if line.startswith(_SOURCE_KEY) and line.endswith("'") and len(line) > len(_SOURCE_KEY):
            return line[len(_SOURCE_KEY):-1].replace("''", "'")
    return ''


def _text(path: str) -> Optional[str]:
    try:
        with open(path, encoding='utf-8') as stream:
            return stream.read()
    except (OSError, UnicodeDecodeError):
        return None
