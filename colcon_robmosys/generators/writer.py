# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The one place that writes files: atomic, no-touch, never over user code."""

from __future__ import annotations

import os
from pathlib import Path
import tempfile

from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.mapping.common import GENERATED_BY

#: Every generated file carries this text in its banner.
GENERATED_MARKER = GENERATED_BY.encode('utf-8')

#: How temporary files end: a run killed before it renamed one leaves it,
#: and the next generation removes it (see remove_leftovers).
TEMP_SUFFIX = '.robmosys-tmp'


def is_generated(path: Path) -> bool:
    """Say whether a file carries the banner of a generated file."""
    try:
        with path.open('rb') as stream:
            return GENERATED_MARKER in stream.read(2048)
    except OSError:
        return False


def _write_temp(path: Path, data: bytes, mode: int) -> Path:
    """Write data to a new temporary file beside path; return its path."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, temp = tempfile.mkstemp(prefix=f'.{path.name}.', suffix=TEMP_SUFFIX,
                                dir=path.parent)
    try:
        with os.fdopen(fd, 'wb') as stream:
            stream.write(data)
            stream.flush()
            os.fsync(stream.fileno())
        os.chmod(temp, mode)
    except BaseException:  # noqa: B902 - no temporary file outlives a failure
        os.unlink(temp)
        raise
    return Path(temp)


def _mode(executable: bool) -> int:
    umask = os.umask(0)
    os.umask(umask)
    return (0o777 if executable else 0o666) & ~umask


def write_generated(path: Path, data: bytes, *, executable: bool = False,
                    owned: bool = False) -> bool:
    """Write a generated file unless it already has this content.

    The file is replaced atomically: a reader, or a run killed half-way,
    sees the old content or the new one, never a mix.

    :param owned: the file was written by an earlier generation even if it
      has no banner (a copy of the user's code into the build tree)
    :returns: whether the file was written
    :raises RobmosysError: if a file that is not generated is in the way
    """
    try:
        current = path.read_bytes()
    except FileNotFoundError:
        current = None
    except IsADirectoryError:
        raise RobmosysError.in_file(
            path, 'cannot generate this file: a directory is in the way'
        ) from None
    if current == data:
        if executable and not os.access(path, os.X_OK):
            os.chmod(path, _mode(True))
        return False
    if current is not None and not owned and \
            GENERATED_MARKER not in current[:2048]:
        raise RobmosysError.in_file(
            path, 'refusing to overwrite a file that colcon-robmosys did not '
            'generate; move it away to let the generator write here')
    temp = _write_temp(path, data, _mode(executable))
    os.replace(temp, path)
    return True


def create_user_file(path: Path, data: bytes) -> bool:
    """Create a file for the user to own, only if nothing is there yet.

    :returns: whether the file was created
    """
    if path.exists() or path.is_symlink():
        return False
    # what a run killed before the link below left behind
    for leftover in path.parent.glob(f'.{path.name}.*{TEMP_SUFFIX}'):
        leftover.unlink()
    temp = _write_temp(path, data, _mode(False))
    try:
        # link() refuses to replace an existing file, so a file the user
        # created meanwhile is never clobbered
        os.link(temp, path)
    except FileExistsError:
        return False
    finally:
        os.unlink(temp)
    return True


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


def remove_leftovers(root: Path) -> list[Path]:
    """Remove the temporary files a killed generation left below root.

    :returns: the files removed
    """
    removed = []
    for path in sorted(root.rglob(f'.*{TEMP_SUFFIX}')):
        if path.is_file() and not path.is_symlink():
            path.unlink()
            removed.append(path)
    return removed
