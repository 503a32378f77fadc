# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Find what is installed outside the workspace, through the ament index.

ament_index_python reads the same index, but not for us: its functions search
the ``AMENT_PREFIX_PATH`` of ``os.environ`` at each call (``search_paths.
get_search_paths``, which raises where it is unset), while an index here is a
list of prefixes given (tests and benchmarks check models against a prefix of
their own, and steering the library through ``os.environ`` would change the
process's environment under colcon's parallel jobs); and its ``get_resources``
gives the first prefix of each name, where the check warns about a package
two underlays install, and so needs them all. So the index is walked here,
the way ament_index_python walks it: ``share/ament_index/resource_index/
<type>/<name>``, a file per resource, dot files and folders not counted.
Generated code, which runs where ROS 2 is sourced, uses ament_index_python
(robmosys_runtime).
"""

from __future__ import annotations

from functools import lru_cache
import os
from pathlib import Path
from typing import Iterable, Mapping, Sequence

from colcon_robmosys.model.types import InterfaceRef

#: ament_index_python.constants.RESOURCE_INDEX_SUBFOLDER
RESOURCE_INDEX = Path('share', 'ament_index', 'resource_index')


def environ_prefixes(environ: Mapping[str, str], variable: str) -> list[str]:
    """Return the prefixes of a path list of the environment, in order."""
    return [entry for entry in environ.get(variable, '').split(os.pathsep) if entry]


def search_prefixes(prefixes: Iterable[Path | str], markers: Iterable[Path],
                    ignored: Iterable[Path] = ()) -> Path | None:
    """
    Return the first prefix that holds one of the markers, resolved, or None.

    The one search of install prefixes: which prefix has a resource of the
    ament index (:class:`InterfaceIndex`), what provides the runtime, and
    which packages a component needs of the prefix no prefix provides
    (package_selection). Not ament_index_python: it reads os.environ's
    AMENT_PREFIX_PATH only, and knows neither CMAKE_PREFIX_PATH, the
    prefixes of a workspace's dependencies nor prefixes that do not count.

    :param ignored: prefixes at or below these folders do not count
    """
    markers = tuple(markers)
    skipped = [Path(p).resolve() for p in ignored]
    for entry in prefixes:
        prefix = Path(entry).resolve()
        if any(prefix == s or s in prefix.parents for s in skipped):
            continue
        if any((prefix / marker).is_file() for marker in markers):
            return prefix
    return None


class InterfaceIndex:
    """The packages, and their resources, installed in a set of ament prefixes."""

    def __init__(self, prefixes: Sequence[Path]):
        # a prefix named twice is one prefix, where it comes first
        kept: dict[Path, Path] = {}
        for prefix in prefixes:
            kept.setdefault(Path(os.path.realpath(prefix)), Path(prefix))
        self.prefixes = tuple(kept.values())
        #: each prefix resolved -> as given
        self._given = kept

    @classmethod
    def from_environment(
            cls, env: Mapping[str, str] | None = None) -> 'InterfaceIndex':
        """Use the prefixes of ``AMENT_PREFIX_PATH``."""
        return cls([Path(p) for p in environ_prefixes(
            os.environ if env is None else env, 'AMENT_PREFIX_PATH')])

    def resources(self, resource_type: str) -> dict[str, list[Path]]:
        """Return the names of a resource type -> the prefixes that have each, in order."""
        found: dict[str, list[Path]] = {}
        for prefix in self.prefixes:
            folder = prefix / RESOURCE_INDEX / resource_type
            if not folder.is_dir():
                continue
            for entry in sorted(folder.iterdir()):
                if not entry.name.startswith('.') and entry.is_file():
                    found.setdefault(entry.name, []).append(prefix)
        return found

    def resource(self, resource_type: str, name: str) -> tuple[str, Path] | None:
        """Return the content of a resource and its prefix, the first that has it."""
        prefix = self.resource_prefix(resource_type, name)
        if prefix is None:
            return None
        path = prefix / RESOURCE_INDEX / resource_type / name
        return path.read_text(encoding='utf-8'), prefix

    @lru_cache(maxsize=None)
    def resource_prefix(self, resource_type: str, name: str) -> Path | None:
        """Return the first prefix that has a resource, or None."""
        found = search_prefixes(self.prefixes, [RESOURCE_INDEX / resource_type / name])
        return None if found is None else self._given[found]

    def package_share(self, package: str) -> Path | None:
        """Return the share directory of an installed package, if any."""
        prefix = self.resource_prefix('packages', package)
        return None if prefix is None else prefix / 'share' / package

    def has_package(self, package: str) -> bool:
        """Tell whether the package is installed."""
        return self.package_share(package) is not None

    def has_interface(self, ref: InterfaceRef) -> bool:
        """Tell whether the interface is installed (as .idl or source)."""
        share = self.package_share(ref.package)
        if share is None:
            return False
        folder = share / ref.kind.value
        return any((folder / f'{ref.name}.{suffix}').is_file()
                   for suffix in ('idl', ref.kind.value))
