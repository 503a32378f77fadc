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

A package folder that does not exist yet (a first generation) is written
whole into a hidden folder beside it with no temporary file per file, flushed
with the others in step 2, and renamed into place at once: it appears with
its manifest and every file, or not at all, as ``cp -r`` would write it plus
one rename. A run killed before that rename leaves the hidden folder, which
the next run that writes beside it removes.
"""

from __future__ import annotations

import ctypes
from dataclasses import dataclass, field
import errno
import itertools
import os
from pathlib import Path
import shutil
from typing import Callable, Iterable

from colcon_robmosys.generators.fileops import (
    remove_generated, remove_user_leftovers, write_temp)

#: How the hidden folder a new package is written into ends.
NEW_SUFFIX = '.robmosys-new'

#: Numbers the hidden folders of this process.
_counter = itertools.count()


@dataclass
class _Write:
    """A file to write: replaced (a generated file) or linked (a file of the user's)."""

    path: Path
    data: bytes
    executable: bool = False
    link: bool = False
    temp: Path | None = None


@dataclass
class _Package:
    """A package folder written whole, renamed into place once written."""

    root: Path
    #: path relative to root -> content, and whether it is executable
    files: dict[str, tuple[bytes, bool]]
    staging: Path | None = None


@dataclass
class Durable:
    """The writes of a run, done and made durable together by :meth:`commit`."""

    _manifests: list[_Write] = field(default_factory=list)
    _files: list[_Write] = field(default_factory=list)
    _packages: list[_Package] = field(default_factory=list)
    #: (file, the folder of its package): removed after the writes
    _removals: list[tuple[Path, Path]] = field(default_factory=list)
    #: what to do once everything is in place (record a stamp), and the package
    #: folder it is about (None: the whole run)
    _then: list[tuple[Callable[[], None], Path | None]] = field(default_factory=list)

    def manifest(self, path: Path, data: bytes) -> None:
        """Write a manifest before any other file."""
        self._manifests.append(_Write(path, data))

    def replace(self, path: Path, data: bytes, executable: bool = False) -> None:
        """Write a generated file (checked to be ours by the caller)."""
        self._files.append(_Write(path, data, executable))

    def new_package(self, root: Path, files: dict[str, tuple[bytes, bool]]) -> None:
        """Write a package folder that does not exist yet, its manifest among its files."""
        self._packages.append(_Package(root, files))

    def create(self, path: Path, data: bytes) -> None:
        """Create a file of the user's, unless one is there by then."""
        remove_user_leftovers(path)
        self._files.append(_Write(path, data, link=True))

    def remove(self, path: Path, root: Path) -> None:
        """Remove a file an earlier generation wrote, after the writes."""
        self._removals.append((path, root))

    def then(self, action: Callable[[], None], root: Path | None = None) -> None:
        """Do something once the writes are in place and durable.

        :param root: the package folder the action is about: a new package whose
          folder someone else made meanwhile, and whose files were not all placed,
          skips it (its stamp is not recorded, so the next run looks at every file)
        """
        self._then.append((action, root))

    def commit(self) -> list[Path]:
        """Write everything, durably; return the files of the user's created.

        A file of the user's that appeared since is left as it is, and not
        returned.
        """
        created: list[Path] = []
        #: new packages whose files were not all placed
        partial: set[Path] = set()
        try:
            for group in (self._manifests, self._files):
                for write in group:
                    write.temp = write_temp(write.path, write.data, write.executable,
                                            sync=False)
                flushed = [w.path for w in group]
                if group is self._files:
                    _remove_stale_stagings({p.root.parent for p in self._packages})
                    for package in self._packages:
                        package.staging = _stage(package)
                        flushed.append(package.staging)
                flush_file_systems(flushed)
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
            for package in self._packages:
                staging, package.staging = package.staging, None
                assert staging is not None
                if not _move_in(staging, package.root):
                    partial.add(package.root)
            for path, root in self._removals:
                remove_generated(path, root)
            flush_file_systems([w.path for w in self._manifests + self._files] +
                               [path for path, _ in self._removals] +
                               [p.root for p in self._packages])
        finally:
            # a failure leaves no temporary file of ours (a kill leaves them to
            # the next generation's remove_leftovers)
            for write in self._manifests + self._files:
                if write.temp is not None:
                    os.unlink(write.temp)
                    write.temp = None
            for package in self._packages:
                if package.staging is not None:
                    shutil.rmtree(package.staging, ignore_errors=True)
                    package.staging = None
            self._manifests, self._files, self._removals = [], [], []
            self._packages = []
        then, self._then = self._then, []
        for action, about in then:
            if about not in partial:
                action()
        return created


def _stage(package: _Package) -> Path:
    """Write a new package's files into a hidden folder beside it; return the folder."""
    package.root.parent.mkdir(parents=True, exist_ok=True)
    staging = package.root.parent / \
        f'.{package.root.name}.{os.getpid()}-{next(_counter)}{NEW_SUFFIX}'
    os.mkdir(staging)
    # paths as strings: a Path per file was a tenth of the writing's CPU time
    root = os.fspath(staging)
    made = {root}
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, 'O_CLOEXEC', 0)
    for relative, (data, executable) in package.files.items():
        path = os.path.join(root, relative)
        folder = os.path.dirname(path)
        if folder not in made:
            os.makedirs(folder, exist_ok=True)
            made.add(folder)
        # created with its final mode (the umask applies): no chmod follows
        with os.fdopen(os.open(path, flags, 0o777 if executable else 0o666), 'wb') as stream:
            stream.write(data)
    return staging


def _move_in(staging: Path, root: Path) -> bool:
    """Rename a package's hidden folder into place, or link its files where one appeared.

    A folder made at root since the run looked (by the user, or by another
    run) keeps every file it has: only the files it lacks are linked in.

    :returns: whether every file of the package is in place
    """
    try:
        os.rename(staging, root)  # over nothing, or over an empty folder
        return True
    except OSError as error:
        if error.errno not in (errno.EEXIST, errno.ENOTEMPTY):
            raise
    whole = True
    for path in sorted(staging.rglob('*')):
        if path.is_dir():
            continue
        target = root / path.relative_to(staging)
        target.parent.mkdir(parents=True, exist_ok=True)
        try:
            os.link(path, target)  # never over a file that is there
        except FileExistsError:
            whole = False
    shutil.rmtree(staging)
    return whole


def _remove_stale_stagings(folders: Iterable[Path]) -> None:
    """Remove the hidden folders that runs no longer running left in these folders."""
    for folder in folders:
        try:
            entries = list(os.scandir(folder))
        except (FileNotFoundError, NotADirectoryError):
            continue
        for entry in entries:
            if entry.name.startswith('.') and entry.name.endswith(NEW_SUFFIX) and \
                    entry.is_dir(follow_symlinks=False) and not _running(entry.name):
                shutil.rmtree(entry.path, ignore_errors=True)


def _running(staging_name: str) -> bool:
    """Say whether the process that named a hidden folder still runs."""
    number = staging_name[:-len(NEW_SUFFIX)].rsplit('.', 1)[-1].split('-')[0]
    if not number.isdigit():
        return False
    try:
        os.kill(int(number), 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        pass  # another user's
    return True


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
