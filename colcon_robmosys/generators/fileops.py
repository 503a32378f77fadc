# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The file operations under the writer and its durable batch.

A file is written to a temporary file beside its target, then renamed or
linked into place: by :mod:`colcon_robmosys.generators.writer` one at a
time, by :mod:`colcon_robmosys.generators.durable` all of a run's together.
What a killed run leaves of them, and what a generation no longer writes,
is removed here.
"""

from __future__ import annotations

import itertools
import os
from pathlib import Path
from typing import Iterable

#: How temporary files end: a run killed before it renamed one leaves it,
#: and the next generation removes it (see remove_leftovers).
TEMP_SUFFIX = '.robmosys-tmp'


#: Numbers the temporary files of this process.
_counter = itertools.count()


def write_temp(path: Path, data: bytes, executable: bool, *,
               sync: bool) -> Path:
    """Write data to a new temporary file beside path; return its path.

    :param sync: flush the data to the disk before returning, so that a
      rename or link that follows cannot outlive it in a power cut
    """
    # created with its final mode (the umask applies), so that no chmod
    # follows; O_EXCL: a name another process took is tried again
    mode = 0o777 if executable else 0o666
    while True:
        temp = path.parent / \
            f'.{path.name}.{os.getpid()}-{next(_counter)}{TEMP_SUFFIX}'
        try:
            fd = os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_EXCL |
                         getattr(os, 'O_CLOEXEC', 0), mode)
            break
        except FileExistsError:
            continue
        except FileNotFoundError:
            # the folder is new: made once for all its files, not tried
            # before each (a mkdir per file was a third of a first generation)
            if path.parent.is_dir():
                raise
            path.parent.mkdir(parents=True, exist_ok=True)
    try:
        with os.fdopen(fd, 'wb') as stream:
            stream.write(data)
            if sync:
                stream.flush()
                os.fsync(stream.fileno())
    except BaseException:  # noqa: B902 - no temporary file outlives a failure
        os.unlink(temp)
        raise
    return temp


def remove_user_leftovers(path: Path) -> None:
    """Remove what a run killed before it linked a file of the user's left behind."""
    prefix = f'.{path.name}.'
    try:
        names = os.listdir(path.parent)
    except FileNotFoundError:
        names = []
    for name in names:
        if name.startswith(prefix) and name.endswith(TEMP_SUFFIX):
            os.unlink(path.parent / name)


def remove_generated(path: Path, root: Path) -> bool:
    """Remove a file an earlier generation wrote, and emptied folders.

    :param root: the folder of the generated package, which stays
    :returns: whether the file was there
    """
    try:
        path.unlink()
    except FileNotFoundError:
        return False
    parent = path.parent
    while parent != root and root in parent.parents:
        try:
            parent.rmdir()
        except OSError:
            break
        parent = parent.parent
    return True


def remove_leftovers(root: Path, manifest: Iterable[str] = ()) -> list[Path]:
    """Remove the temporary files a killed generation left below root.

    A generation writes its manifest before any other file, so its
    temporary files lie in root or in a folder of a file of the manifest:
    only those folders are looked at, not the whole tree.

    :param manifest: the files (relative to root) of the last manifest
    :returns: the files removed
    """
    folders = {root} | {(root / relative).parent for relative in manifest}
    removed = []
    for folder in sorted(folders):
        try:
            entries = list(os.scandir(folder))
        except (FileNotFoundError, NotADirectoryError):
            continue
        for entry in entries:
            if entry.name.startswith('.') and \
                    entry.name.endswith(TEMP_SUFFIX) and \
                    entry.is_file(follow_symlinks=False):
                os.unlink(entry.path)
                removed.append(Path(entry.path))
    return sorted(removed)
