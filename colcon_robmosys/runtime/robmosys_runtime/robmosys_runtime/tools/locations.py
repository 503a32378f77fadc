# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Where the system manager's reports point: the installed model files (no rclpy)."""

from __future__ import annotations

import os
from typing import Any, Dict, List, Optional


def resolve_locations(description: Dict[str, Any],
                      prefixes: Optional[List[str]] = None) -> Dict[str, Any]:
    """
    Point the locations of a description at the installed model files; return it.

    ``bringup.json`` names each model file as its installed copy,
    ``share/<package>/robmosys/robmosys.yaml``, relative to the prefix that holds
    it, so that a package holds no path of the machine that built it. Here it
    becomes the file of the first prefix of AMENT_PREFIX_PATH that has it.

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
            found[path] = next((os.path.join(prefix, path) for prefix in prefixes
                                if os.path.isfile(os.path.join(prefix, path))), path)
        return f'{found[path]}:{place}'

    for item in [*description.get('instances', []), *description.get('connections', [])]:
        if 'location' in item:
            item['location'] = resolve(item['location'])
        for parameter in item.get('parameters', []):
            parameter['location'] = resolve(parameter['location'])
    return description
