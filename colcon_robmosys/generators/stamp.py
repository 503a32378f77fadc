# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Stamps: what the last complete generation of a package was made from.

A generation with nothing changed renders every file to find each one the
same. A stamp lets it stop sooner, before the package is even planned: it
records the fingerprint of what the generation read (:func:`fingerprint`),
the user's files it read or copied, by content, the files in the user's
folders (a file added there may be copied, take a generated name, or be the
implementation of a component renamed), and the file system's identity of
each file it left (inode, size, times, mode). The same fingerprint, the same
user files and every file as it was left: the generation would write
nothing, and is skipped.

Each write of the writer is an atomic replace, which makes a new inode, so
a file rewritten since (by a generation killed half-way, or by hand) is
never taken for the one recorded. The stamp of a package is removed before
a generation writes anything, and written after it completed.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
import hashlib
import os
from pathlib import Path
import pickle
import tempfile

import jinja2

from colcon_robmosys.check import LoadResult
from colcon_robmosys.check.cache import code_digest
from colcon_robmosys.generators.files import PackageFiles
from colcon_robmosys.generators.render import templates_dir
from colcon_robmosys.generators.usercode import implementation_files, user_files_below
from colcon_robmosys.model.files import model_dependencies
from colcon_robmosys.model.types import System

#: What a stamp records of a file: inode, size, mtime, ctime (ns), mode.
FileState = tuple[int, int, int, int, int]
#: The files in the user's folders (see :meth:`WatchedFolders.listing`).
Listing = tuple[tuple[object, ...], ...]


def fingerprint(result: LoadResult, package: str, *, standalone: bool) -> str:
    """Return a digest of everything the generation of a package reads but the user's files.

    The model files of the package and of every model it depends on, found
    by content (an underlay's installed models too, and the external
    components a system starts), which also digests colcon-robmosys's
    code and rosidl's (see :func:`colcon_robmosys.check.cache.file_key`);
    the templates (wherever they are read from) and Jinja's version; and
    how the package is generated (``standalone``, with copies of the user's
    files, or for the build tree).
    """
    files: set[str] = set()
    seen: set[str] = set()
    todo = [package]
    while todo:
        name = todo.pop()
        model = result.workspace.model(name)
        if name in seen or model is None:
            continue
        seen.add(name)
        files.add(model.info.model_file)
        todo.extend(model_dependencies(model))
        if isinstance(model, System):
            # an external component is named package/executable
            todo.extend(i.component for i in model.instances)
    digest = hashlib.sha256(
        f'{package}\0{standalone}\0{code_digest()}\0{templates_digest()}\0'
        f'{jinja2.__version__}\0'.encode('utf-8', 'surrogateescape'))
    for path in sorted(files):
        key = result.file_keys.get(path) or content_digest(Path(path))
        digest.update(f'{path}\0{key}\0'.encode('utf-8', 'surrogateescape'))
    return digest.hexdigest()


@lru_cache(maxsize=1)
def templates_digest() -> str:
    """Return a digest of the templates the renderer reads (their paths and contents)."""
    root = templates_dir()
    digest = hashlib.sha256()
    for path in sorted(root.rglob('*')):
        if path.is_file() and '__pycache__' not in path.parts:
            digest.update(path.relative_to(root).as_posix().encode() + b'\0')
            digest.update(path.read_bytes() + b'\0')
    return digest.hexdigest()


def file_state(path: Path | str) -> FileState | None:
    """Return what a stamp records of a file, None if it is not there."""
    try:
        st = os.lstat(path)
    except OSError:
        return None
    return (st.st_ino, st.st_size, st.st_mtime_ns, st.st_ctime_ns, st.st_mode)


def content_digest(path: Path) -> str | None:
    """Return the digest of a user's file and whether it is executable, None if unreadable."""
    try:
        return user_digest(path.read_bytes(), os.access(path, os.X_OK))
    except OSError:
        return None


def user_digest(data: bytes, executable: bool) -> str:
    """Return what a stamp records of a user's file: its content, and its mode (copied)."""
    return hashlib.sha256(data).hexdigest() + ('+x' if executable else '')


@dataclass(frozen=True)
class WatchedFolders:
    """The user's folders of a package, as a generation found them."""

    #: the directory of the model
    root: str
    #: folders (relative to root) whose files are copied or must not take a
    #: generated name
    trees: tuple[str, ...]
    #: the folder of the implementation files, and their suffixes
    implementation: str = ''
    suffixes: tuple[str, ...] = ()

    @staticmethod
    def of(package: PackageFiles) -> WatchedFolders:
        """Return the user's folders of a package."""
        impl = package.implementation
        return WatchedFolders(str(package.model_dir), package.user_folders,
                              impl.folder if impl else '', impl.suffixes if impl else ())

    def listing(self) -> Listing:
        """Return the files in the folders now."""
        root = Path(self.root)
        found: list[tuple[object, ...]] = [
            tuple(str(p) for p in user_files_below(root / folder)) for folder in self.trees]
        if self.implementation:
            found.append(tuple(implementation_files(root / self.implementation, self.suffixes)))
        return tuple(found)


@dataclass(frozen=True)
class Stamp:
    """The record of one complete generation of a package."""

    fingerprint: str
    #: file written (relative to the package's folder) -> its state then
    files: dict[str, FileState]
    #: the user's files it read or copied -> their digests then (user_digest)
    user_files: dict[str, str]
    #: the user's folders, and the files in them then
    folders: WatchedFolders
    listing: Listing


class StampStore:
    """The stamps of the generated packages, in a folder of the build tree."""

    def __init__(self, folder: Path):
        self.folder = Path(folder)

    def _path(self, out_dir: Path) -> Path:
        name = hashlib.sha256(str(Path(out_dir).absolute()).encode(
            'utf-8', 'surrogateescape')).hexdigest()
        return self.folder / f'{name}.stamp'

    def unchanged(self, out_dir: Path, fingerprint: str) -> list[Path] | None:
        """Return the files of the package if a generation would change nothing.

        :returns: the files of the last generation, None if the package has
          to be generated
        """
        try:
            with open(self._path(out_dir), 'rb') as stream:
                stamp = pickle.load(stream)
        except Exception:  # noqa: B902 - none, truncated, from other code
            return None
        if not isinstance(stamp, Stamp) or stamp.fingerprint != fingerprint:
            return None
        base = os.fspath(out_dir)
        for relative, state in stamp.files.items():
            if file_state(os.path.join(base, relative)) != state:
                return None
        for source, digest in stamp.user_files.items():
            if content_digest(Path(source)) != digest:
                return None
        if stamp.folders.listing() != stamp.listing:
            return None
        return [out_dir / relative for relative in sorted(stamp.files)]

    def forget(self, out_dir: Path) -> None:
        """Remove the stamp of a package, before its files change."""
        try:
            os.unlink(self._path(out_dir))
        except FileNotFoundError:
            pass

    def record(self, out_dir: Path, fingerprint: str, files: list[str],
               user_files: dict[str, str], folders: WatchedFolders,
               listing: Listing) -> None:
        """Record a complete generation of the package.

        :param files: every file it left, relative to out_dir
        :param user_files: the user's files it read or copied -> the
          digests (:func:`user_digest`) of what it read
        :param listing: the files in the user's folders before it read any
        """
        states = {}
        base = os.fspath(out_dir)
        for relative in files:
            state = file_state(os.path.join(base, relative))
            if state is None:
                return  # gone already: no stamp, the next run checks all
            states[relative] = state
        stamp = Stamp(fingerprint, states, dict(user_files), folders, listing)
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            fd, temp = tempfile.mkstemp(dir=self.folder, prefix='.', suffix='.tmp')
            try:
                with os.fdopen(fd, 'wb') as stream:
                    pickle.dump(stamp, stream, protocol=pickle.HIGHEST_PROTOCOL)
                os.replace(temp, self._path(out_dir))
            except BaseException:  # noqa: B902 - leave no temporary file
                os.unlink(temp)
                raise
        except OSError:
            pass  # no stamp: the next generation only takes longer
