# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The manifest of a generated package: which files a generation wrote."""

from __future__ import annotations

import hashlib
from pathlib import Path

from colcon_robmosys.generators.durable import Durable
from colcon_robmosys.generators.writer import write_generated
from colcon_robmosys.mapping.common import GENERATED_BY

#: Lists, inside a generated package, the files the generation wrote.
MANIFEST = '.robmosys-generated'

#: The files of a generation -> the digests of the contents it may have
#: written there; None for a manifest written before digests were recorded.
Manifest = dict[str, set[str] | None]


def read_manifest(path: Path) -> Manifest:
    """Return the files a generation wrote, with the digests of each."""
    try:
        lines = path.read_text(encoding='utf-8').split('\n')
    except FileNotFoundError:
        return {}
    files: Manifest = {}
    for line in lines:
        if not line or line.startswith('#'):
            continue
        value, sep, relative = line.partition('  ')
        if sep and len(value) == 64:
            files[relative] = (files.get(relative) or set()) | {value}
        else:
            files[line] = None
    return files


def write_manifest(path: Path, files: Manifest, durable: Durable | None = None) -> None:
    """Write the manifest of a generation, or leave it to a durable batch of writes."""
    data = (f'# {GENERATED_NOTE}\n' + ''.join(
        f'{value}  {relative}\n' for relative in sorted(files)
        for value in sorted(files[relative] or ())
    )).encode('utf-8')
    if durable is None:
        write_generated(path, data, owned=True)
    else:
        durable.manifest(path, data)


def digest(data: bytes) -> str:
    """Return the digest the manifest records of a content."""
    return hashlib.sha256(data).hexdigest()


def unchanged_since(path: Path, previous: Manifest, relative: str) -> bool:
    """Say whether a file still holds what a generation wrote there."""
    if relative not in previous:
        return False
    digests = previous[relative]
    if digests is None:
        return True  # an old manifest: trust it as before
    try:
        return digest(path.read_bytes()) in digests
    except OSError:
        return False


GENERATED_NOTE = f'{GENERATED_BY}: the files of the last generation'
