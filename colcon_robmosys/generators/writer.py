# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The one place that writes files: atomic, no-touch, never over user code.

A generation's files go out through :func:`write_outputs`, which keeps the
manifest of what it wrote and says what it did (:class:`GenerationReport`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
import os
from pathlib import Path

from colcon_robmosys.errors import Diagnostic, Location, RobmosysError
from colcon_robmosys.generators.durable import Durable
from colcon_robmosys.generators.fileops import (
    remove_generated, remove_leftovers, remove_user_leftovers, write_temp)
from colcon_robmosys.generators.manifest import (
    digest, MANIFEST, Manifest, manifest_bytes, read_manifest, unchanged_since)
from colcon_robmosys.mapping.common import GENERATED_BY

#: Every generated file carries this text in its banner.
GENERATED_MARKER = GENERATED_BY.encode('utf-8')


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
