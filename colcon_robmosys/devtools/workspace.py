# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
Where a workspace is built with each distribution's venv: colcon's base folders.

``make demo`` and the tests build test_workspace in place, into the same folders, so
that the tests' build after the demo's is an incremental one that finds nothing to do.
Kilted's folders are colcon's defaults (where README's own ``colcon build`` puts them);
Jazzy's stand beside them, so that neither distribution reuses the other's CMake caches.
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import metadata

DISTRIBUTIONS = ('kilted', 'jazzy')
#: the venv of each distribution in the repository (the Makefile's VENV)
DEFAULT_VENVS = {'kilted': '.venv', 'jazzy': '.venv-jazzy'}


def venv_distribution() -> str:
    """Return the ROS 2 distribution of the running venv's ``ros-*`` wheels."""
    try:
        metadata.distribution('ros-jazzy-rclpy')
    except metadata.PackageNotFoundError:
        return 'kilted'
    return 'jazzy'


@dataclass(frozen=True)
class Bases:
    """The build, install and log folders of a workspace, relative to its root."""

    build: str = 'build'
    install: str = 'install'
    log: str = 'log'

    def command(self, verb: str, *args: str) -> list[str]:
        """Return the arguments of colcon (without the executable) for ``verb`` here.

        colcon's defaults are left out, so that a default build reads as users type it.
        """
        default = Bases()
        before = ['--log-base', self.log] if self.log != default.log else []
        after = []
        if verb in ('build', 'test') and self.build != default.build:
            after += ['--build-base', self.build]
        if verb in ('build', 'test') and self.install != default.install:
            after += ['--install-base', self.install]
        return [*before, verb, *after, *args]


def bases_of(distribution: str) -> Bases:
    """Return the folders a distribution's venv builds test_workspace into."""
    if distribution == DISTRIBUTIONS[0]:
        return Bases()
    return Bases(f'build-{distribution}', f'install-{distribution}', f'log-{distribution}')
