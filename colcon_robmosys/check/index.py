# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Find interfaces installed outside the workspace, through the ament index."""

from __future__ import annotations

from functools import lru_cache
import os
from pathlib import Path
from typing import Mapping, Sequence

from colcon_robmosys.model.types import InterfaceRef


class InterfaceIndex:
    """The interface packages installed in a set of ament prefixes."""

    def __init__(self, prefixes: Sequence[Path]):
        self.prefixes = tuple(prefixes)

    @classmethod
    def from_environment(
            cls, env: Mapping[str, str] | None = None) -> 'InterfaceIndex':
        """Use the prefixes of ``AMENT_PREFIX_PATH``."""
        value = (os.environ if env is None else env).get(
            'AMENT_PREFIX_PATH', '')
        return cls([Path(p) for p in value.split(os.pathsep) if p])

    @lru_cache(maxsize=None)
    def package_share(self, package: str) -> Path | None:
        """Return the share directory of an installed package, if any."""
        for prefix in self.prefixes:
            marker = prefix / 'share' / 'ament_index' / 'resource_index' / \
                'packages' / package
            if marker.is_file():
                return prefix / 'share' / package
        return None

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
