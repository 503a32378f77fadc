# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The one place that writes files: atomic, no-touch, never over user code.

A generation's files go out through :func:`write_outputs`, which keeps the
manifest of what it wrote and says what it did (:class:`GenerationReport`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
import itertools
import os
from pathlib import Path
from typing import Iterable, TYPE_CHECKING

from colcon_robmosys.errors import Diagnostic, Location, RobmosysError
from colcon_robmosys.generators.manifest import (
    digest, MANIFEST, Manifest, manifest_bytes, read_manifest, unchanged_since)
from colcon_robmosys.mapping.common import GENERATED_BY

if TYPE_CHECKING:  # the durable batch writes through this module
    from colcon_robmosys.generators.durable import Durable

#: Every generated file carries this text in its banner.
GENERATED_MARKER = GENERATED_BY.encode('utf-8')

#: How temporary files end: a run killed before it renamed one leaves it,
#: and the next generation removes it (see remove_leftovers).
TEMP_SUFFIX = '.robmosys-tmp'


#: Numbers the temporary files of this process.
_counter = itertools.count()


class _Unread:
    """The type of :data:`_UNREAD`: the caller has not read the file."""


_UNREAD = _Unread()


def is_generated(path: Path) -> bool:
    """Say whether a file carries the banner of a generated file."""
    try:
        with path.open('rb') as stream:
            return GENERATED_MARKER in stream.read(2048)
    except OSError:
        return False


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


def _mode(executable: bool) -> int:
    umask = os.umask(0)
    os.umask(umask)
    return (0o777 if executable else 0o666) & ~umask


def write_generated(path: Path, data: bytes, *, executable: bool = False,
                    owned: bool = False,
                    current: bytes | None | _Unread = _UNREAD) -> bool:
    """Write a generated file unless it already has this content.

    The file is replaced atomically: a reader, or a run killed half-way,
    sees the old content or the new one, never a mix. That needs no fsync:
    a killed process leaves its writes in the kernel, and the rename makes
    them visible at once. Only a power cut could then leave a file renamed
    but empty; in the build tree the next generation, which compares every
    file with the manifest, rewrites it (or, without its banner, refuses and
    says so), so the build tree is not synced. Output a user keeps is
    written through a :class:`~colcon_robmosys.generators.durable.Durable`.

    :param owned: the file was written by an earlier generation even if it
      has no banner (a copy of the user's code into the build tree)
    :param current: the content of the file, if the caller read it already
      (None: there is no file)
    :returns: whether the file was written
    :raises RobmosysError: if a file that is not generated is in the way
    """
    if isinstance(current, _Unread):
        current = read_current(path)
    if current == data:
        if executable and not os.access(path, os.X_OK):
            make_executable(path)
        return False
    if current is not None and not owned and \
            GENERATED_MARKER not in current[:2048]:
        raise RobmosysError.in_file(
            path, 'refusing to overwrite a file that colcon-robmosys did not '
            'generate; move it away to let the generator write here')
    temp = write_temp(path, data, executable, sync=False)
    os.replace(temp, path)
    return True


def make_executable(path: Path) -> None:
    """Give a file the mode of an executable (the umask applies)."""
    os.chmod(path, _mode(True))


def read_current(path: Path) -> bytes | None:
    """Return the content of a file about to be generated, None if absent.

    :raises RobmosysError: if a directory is in the way
    """
    try:
        return path.read_bytes()
    except FileNotFoundError:
        return None
    except IsADirectoryError:
        raise RobmosysError.in_file(
            path, 'cannot generate this file: a directory is in the way'
        ) from None


def create_user_file(path: Path, data: bytes) -> bool:
    """Create a file for the user to own, only if nothing is there yet.

    :returns: whether the file was created
    """
    if path.exists() or path.is_symlink():
        return False
    remove_user_leftovers(path)
    # the user's own file from now on: on the disk before it is linked
    temp = write_temp(path, data, False, sync=True)
    try:
        # link() refuses to replace an existing file, so a file the user
        # created meanwhile is never clobbered
        os.link(temp, path)
    except FileExistsError:
        return False
    finally:
        os.unlink(temp)
    return True


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


@dataclass
class GenerationReport:
    """What a generation did."""

    written: list[Path] = field(default_factory=list)
    unchanged: list[Path] = field(default_factory=list)
    removed: list[Path] = field(default_factory=list)
    created_user_files: list[Path] = field(default_factory=list)


def write_tree(files: dict[str, tuple[bytes, bool]], out_dir: Path, *,
               durable: Durable | None = None) -> GenerationReport:
    """Write files that are not rendered (a copy of a package) as generated ones.

    The manifest records them: writing again replaces only what is unchanged
    since, and a file of the user's in the way is refused.

    :param files: path relative to out_dir -> content, and whether it is
      executable
    """
    return write_outputs(dict(files), out_dir, durable=durable)


def write_outputs(outputs: dict[str, tuple[bytes, bool]], out_dir: Path,
                  *, durable: Durable | None = None) -> GenerationReport:
    """Write the outputs of a generation, after checking that each is ours.

    The manifest is written once, before any file, and lists the new content
    of each file and what is there now: a run killed half-way leaves every
    file it wrote, or had not yet replaced, known as generated.

    :param durable: leave the writes to it, to be made durable with the
      others of the run when the caller commits it (the report tells what
      the commit writes)
    """
    report = GenerationReport()
    manifest_path = out_dir / MANIFEST
    # a package generated for the first time: no file to read, none to compare
    fresh = not out_dir.exists()
    previous = {} if fresh else read_manifest(manifest_path)
    if not fresh:
        report.removed += remove_leftovers(out_dir, previous)
    pending: Manifest = {}
    changes: list[tuple[Path, bytes, bool, bool, bytes | None]] = []
    refused: list[Diagnostic] = []
    for relative, (data, executable) in sorted(outputs.items()):
        path = out_dir / relative
        current = None if fresh else read_current(path)
        new = digest(data)
        if current == data:
            pending[relative] = {new}
            if executable and not os.access(path, os.X_OK):
                make_executable(path)
            report.unchanged.append(path)
            continue
        if current is None:
            pending[relative] = {new}
            changes.append((path, data, executable, True, current))
            continue
        old = digest(current)
        owned = relative in previous and (
            previous[relative] is None or old in (previous[relative] or ()))
        if not owned and GENERATED_MARKER not in current[:2048]:
            refused.append(Diagnostic(
                Location(str(path)), 'refusing to overwrite a file that '
                'colcon-robmosys did not generate; move it away to let the '
                'generator write here'))
            continue
        pending[relative] = {new, old}
        changes.append((path, data, executable, owned, current))
    if refused:
        raise RobmosysError(refused)
    stale = []
    for relative in sorted(previous.keys() - outputs.keys()):
        path = out_dir / relative
        if not unchanged_since(path, previous, relative) and \
                not is_generated(path):
            # replaced by a file of the user's since: theirs to keep
            continue
        pending[relative] = previous[relative]
        stale.append(path)
    if fresh and durable is not None:
        # written whole beside it, then renamed into place
        durable.new_package(out_dir, {MANIFEST: (manifest_bytes(pending), False), **{
            relative: outputs[relative] for relative in pending}})
        report.written += [path for path, *_ in changes]
        return report
    if pending != previous:
        if durable is None:
            write_generated(manifest_path, manifest_bytes(pending), owned=True)
        else:
            durable.manifest(manifest_path, manifest_bytes(pending))
    for path, data, executable, owned, current in changes:
        if durable is not None:
            durable.replace(path, data, executable)
        else:
            write_generated(path, data, executable=executable, owned=owned, current=current)
        report.written.append(path)
    for path in stale:
        if durable is not None:
            durable.remove(path, out_dir)
            report.removed.append(path)
        elif remove_generated(path, out_dir):
            report.removed.append(path)
    return report
