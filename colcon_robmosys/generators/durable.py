# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Writes made durable together: two or three flushes of the disk for a whole run.

Output a user keeps (``colcon robmosys-generate --output-dir``, ``--export``,
the implementation files it creates) must survive a power cut whole: each
file old or new, never renamed into place before its content is on the
disk. An fsync per file did that at the price of a flush of the file
system's journal per file: some 80 s for the 17,000 files of 1000
components, where copying them takes a second (docs/performance.md).

A :class:`Durable` keeps the writes of a run and does them at
:meth:`Durable.commit`, in the order that keeps the writer's promises:

1. the manifest of each package (:mod:`colcon_robmosys.generators.manifest`)
   to temporary files, one flush of the file system, then renamed into place:
   a run killed from here on leaves every file it writes known as generated,
   and its temporary files in folders the manifest names;
2. every other file to a temporary file beside it, one flush, then each
   renamed into place (or, for a file of the user's, linked: a file the user
   made meanwhile is never replaced); then the files no longer generated are
   removed;
3. one last flush, for the renames and removals.
"""

from __future__ import annotations

import ctypes
from dataclasses import dataclass, field
import os
from pathlib import Path
from typing import Callable, Iterable

from colcon_robmosys.generators.writer import (
    remove_generated, remove_user_leftovers, write_temp)


@dataclass
class _Write:
    """A file to write: replaced (a generated file) or linked (a file of the user's)."""

    path: Path
    data: bytes
    executable: bool = False
    link: bool = False
    temp: Path | None = None


@dataclass
class Durable:
    """The writes of a run, done and made durable together by :meth:`commit`."""

    _manifests: list[_Write] = field(default_factory=list)
    _files: list[_Write] = field(default_factory=list)
    #: (file, the folder of its package): removed after the writes
    _removals: list[tuple[Path, Path]] = field(default_factory=list)
    #: what to do once everything is in place (record a stamp)
    _then: list[Callable[[], None]] = field(default_factory=list)

    def manifest(self, path: Path, data: bytes) -> None:
        """Write a manifest before any other file."""
        self._manifests.append(_Write(path, data))

    def replace(self, path: Path, data: bytes, executable: bool = False) -> None:
        """Write a generated file (checked to be ours by the caller)."""
        self._files.append(_Write(path, data, executable))

    def create(self, path: Path, data: bytes) -> None:
        """Create a file of the user's, unless one is there by then."""
        remove_user_leftovers(path)
        self._files.append(_Write(path, data, link=True))

    def remove(self, path: Path, root: Path) -> None:
        """Remove a file an earlier generation wrote, after the writes."""
        self._removals.append((path, root))

    def then(self, action: Callable[[], None]) -> None:
        """Do something once the writes are in place and durable."""
        self._then.append(action)

    def commit(self) -> list[Path]:
        """Write everything, durably; return the files of the user's created.

        A file of the user's that appeared since is left as it is, and not
        returned.
        """
        created: list[Path] = []
        try:
            for group in (self._manifests, self._files):
                for write in group:
                    write.temp = write_temp(write.path, write.data, write.executable,
                                            sync=False)
                flush_file_systems(w.path for w in group)
                for write in group:
                    temp, write.temp = write.temp, None
                    assert temp is not None
                    if not write.link:
                        os.replace(temp, write.path)
                        continue
                    try:
                        # link() refuses to replace a file: the user's is never clobbered
                        os.link(temp, write.path)
                        created.append(write.path)
                    except FileExistsError:
                        pass
                    finally:
                        os.unlink(temp)
            for path, root in self._removals:
                remove_generated(path, root)
            flush_file_systems([w.path for w in self._manifests + self._files] +
                               [path for path, _ in self._removals])
        finally:
            # a failure leaves no temporary file of ours (a kill leaves them to
            # the next generation's remove_leftovers)
            for write in self._manifests + self._files:
                if write.temp is not None:
                    os.unlink(write.temp)
                    write.temp = None
            self._manifests, self._files, self._removals = [], [], []
        then, self._then = self._then, []
        for action in then:
            action()
        return created


def _syncfs() -> Callable[[int], int] | None:
    """Return Linux's syncfs(2), None where the C library has none."""
    try:
        function = ctypes.CDLL(None, use_errno=True).syncfs
    except (AttributeError, OSError):
        return None
    function.argtypes = [ctypes.c_int]
    function.restype = ctypes.c_int
    return function


_SYNCFS = _syncfs()


def flush_file_systems(paths: Iterable[Path]) -> None:
    """Flush to the disk what was written to the file systems of these paths.

    Once per file system (its device), with syncfs(2); where there is no
    syncfs, sync(2) flushes every file system.
    """
    devices: dict[int, Path] = {}
    for folder in {path.parent for path in paths}:
        try:
            devices.setdefault(os.stat(folder).st_dev, folder)
        except OSError:
            continue  # removed meanwhile: nothing of ours left to flush there
    for folder in devices.values():
        if _SYNCFS is None:
            os.sync()
            return
        fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
        try:
            if _SYNCFS(fd) != 0:
                error = ctypes.get_errno()
                raise OSError(error, os.strerror(error), str(folder))
        finally:
            os.close(fd)
