# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Stamps: what the last complete generation of a package was made from.

A generation with nothing changed renders every file to find each one the
same. A stamp lets it stop sooner: it records the fingerprint of what the
generation was made from (the model files the package depends on, found
by content, and the code of colcon-robmosys), the user's files it copied,
and the file system's identity of each file it left (inode, size, times,
mode). The same fingerprint, the same user files and every file as it was
left: the generation would write nothing, and is skipped.

Each write of the writer is an atomic replace, which makes a new inode, so
a file rewritten since (by a generation killed half-way, or by hand) is
never taken for the one recorded. The stamp of a package is removed before
a generation writes anything, and written after it completed.
"""

from __future__ import annotations

from dataclasses import dataclass
import hashlib
import os
from pathlib import Path
import pickle
import tempfile

#: What a stamp records of a file: inode, size, mtime, ctime (ns), mode.
FileState = tuple[int, int, int, int, int]


def file_state(path: Path) -> FileState | None:
    """Return what a stamp records of a file, None if it is not there."""
    try:
        st = os.lstat(path)
    except OSError:
        return None
    return (st.st_ino, st.st_size, st.st_mtime_ns, st.st_ctime_ns, st.st_mode)


def content_digest(path: Path) -> str | None:
    """Return the digest of a user's file, None if it cannot be read."""
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return None


@dataclass(frozen=True)
class Stamp:
    """The record of one complete generation of a package."""

    fingerprint: str
    #: file written (relative to the package's folder) -> its state then
    files: dict[str, FileState]
    #: the user's files it copied -> their digests then
    user_files: dict[str, str]


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
        for source, digest in stamp.user_files.items():
            if content_digest(Path(source)) != digest:
                return None
        for relative, state in stamp.files.items():
            if file_state(out_dir / relative) != state:
                return None
        return [out_dir / relative for relative in sorted(stamp.files)]

    def forget(self, out_dir: Path) -> None:
        """Remove the stamp of a package, before its files change."""
        try:
            os.unlink(self._path(out_dir))
        except FileNotFoundError:
            pass

    def record(self, out_dir: Path, fingerprint: str, files: list[str],
               user_files: dict[str, str]) -> None:
        """Record a complete generation of the package.

        :param files: every file it left, relative to out_dir
        :param user_files: the user's files it copied -> the digests of
          the contents it copied
        """
        states = {}
        for relative in files:
            state = file_state(out_dir / relative)
            if state is None:
                return  # gone already: no stamp, the next run checks all
            states[relative] = state
        digests = dict(user_files)
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            fd, temp = tempfile.mkstemp(dir=self.folder, prefix='.', suffix='.tmp')
            try:
                with os.fdopen(fd, 'wb') as stream:
                    pickle.dump(Stamp(fingerprint, states, digests), stream,
                                protocol=pickle.HIGHEST_PROTOCOL)
                os.replace(temp, self._path(out_dir))
            except BaseException:  # noqa: B902 - leave no temporary file
                os.unlink(temp)
                raise
        except OSError:
            pass  # no stamp: the next generation only takes longer
