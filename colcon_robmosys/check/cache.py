# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Model files loaded and checked by an earlier run, kept in the build tree.

Loading and checking a model file depends on nothing but its content, its
path (every location names it) and the code of colcon-robmosys: an entry is
found by a digest of the three, so that a changed file, a moved one or
another colcon-robmosys (even one of the same version number, as during its
development) finds no entry and checks the file anew. An entry that cannot
be read back, for whatever reason, counts as none. Beside the entries, the
schema compiled to bytecode, for the files that are not in the cache.
"""

from __future__ import annotations

from contextlib import suppress
from functools import lru_cache
import hashlib
import marshal
import os
from pathlib import Path
import pickle
import sys
import tempfile

import colcon_robmosys
from colcon_robmosys.check.results import CheckedFile
from colcon_robmosys.model import rosidl, schema

#: The folder of the cache, in the build base (``build/`` of colcon).
CACHE_DIR = '.robmosys-cache'

#: What each entry ends with, so that nothing else in the folder is read.
_SUFFIX = '.model'

#: What the entry of the compiled schema ends with (one: see use_compiled_schema).
_SCHEMA_SUFFIX = '.schema-code'

#: The parts of colcon-robmosys whose code or data a check depends on.
_CODE_SUFFIXES = ('.py', '.json', '.jinja')


@lru_cache(maxsize=1)
def code_digest() -> str:
    """Return a digest of the installed colcon-robmosys (code, schema, templates), and rosidl's.

    The version number alone would not do: during development it stays the
    same while the code changes.
    """
    root = Path(colcon_robmosys.__file__).parent
    digest = hashlib.sha256(f'{colcon_robmosys.__version__} {sys.version}'.encode())
    for path in sorted(root.rglob('*')):
        if path.suffix in _CODE_SUFFIXES and path.is_file():
            digest.update(str(path.relative_to(root)).encode() + b'\0')
            digest.update(path.read_bytes() + b'\0')
    # types and names are rosidl_adapter's to judge: the rosidl of another
    # ROS 2 (another distribution sourced) may judge otherwise
    digest.update(rosidl.parser_source())
    return digest.hexdigest()


def file_key(path: Path, raw: bytes) -> str:
    """Return the key of a model file: its path and content, and the code."""
    digest = hashlib.sha256(code_digest().encode())
    digest.update(str(path).encode('utf-8', 'surrogateescape') + b'\0')
    digest.update(raw)
    return digest.hexdigest()


class ModelCache:
    """A folder of checked model files, one entry per key.

    :param writable: store new entries (a build does; ``colcon list`` and
      ``colcon graph`` write nothing)
    """

    def __init__(self, folder: Path, *, writable: bool = True):
        self.folder = Path(folder)
        self.writable = writable
        self.hits = 0
        self.misses = 0
        self._schema_given = False

    def _entry(self, key: str) -> Path:
        return self.folder / f'{key}{_SUFFIX}'

    def use_compiled_schema(self) -> None:
        """Give the schema check the compiled schema kept here; compile and keep it if none.

        Compiling it takes some 0.3 to 0.4 s, which every colcon process that
        checks a model file paid; read back, some 10 ms. Called before
        the first file that is not in the cache is checked. The entry of
        another schema, fastjsonschema or Python is replaced.
        """
        if self._schema_given or schema.fast_check_ready():
            return
        self._schema_given = True
        key = schema.compiled_key()
        if key is None:
            return
        entry = self.folder / f'{key}{_SCHEMA_SUFFIX}'
        try:
            schema.use_fast_check(marshal.loads(entry.read_bytes()))
            return
        except Exception:  # noqa: B902 - missing, truncated, from other code
            pass
        code = schema.compile_fast_check()
        if code is None:
            return
        schema.use_fast_check(code)
        if self._store(entry, marshal.dumps(code)):
            for other in self.folder.glob(f'*{_SCHEMA_SUFFIX}'):
                if other != entry:
                    with suppress(OSError):
                        other.unlink()

    def has(self, key: str) -> bool:
        """Say whether there is an entry for a key (:meth:`get` reads it)."""
        return self._entry(key).is_file()

    def get(self, key: str) -> CheckedFile | None:
        """Return the entry of a key, None if there is none that reads back."""
        try:
            with open(self._entry(key), 'rb') as stream:
                entry = pickle.load(stream)
        except Exception:  # noqa: B902 - missing, truncated, from other code
            self.misses += 1
            return None
        if not isinstance(entry, CheckedFile):
            self.misses += 1
            return None
        self.hits += 1
        return entry

    def put(self, key: str, entry: CheckedFile) -> None:
        """Store an entry; a folder that cannot be written only slows the next run."""
        self._store(self._entry(key),
                    pickle.dumps(entry, protocol=pickle.HIGHEST_PROTOCOL))

    def _store(self, path: Path, data: bytes) -> bool:
        """Write a file of the cache atomically, if writable; return whether it was written."""
        if not self.writable:
            return False
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            fd, temp = tempfile.mkstemp(dir=self.folder, prefix='.', suffix='.tmp')
            try:
                with os.fdopen(fd, 'wb') as stream:
                    stream.write(data)
                # atomic: a reader sees a whole entry or none (no fsync: an
                # entry lost in a power cut is only checked again)
                os.replace(temp, path)
            except BaseException:  # noqa: B902 - leave no temporary file
                os.unlink(temp)
                raise
        except OSError:
            return False
        return True

    def prune(self, used: set[str]) -> None:
        """Remove the entries of files that no longer are, once they are many."""
        if not self.writable:
            return
        try:
            names = [n for n in os.listdir(self.folder) if n.endswith(_SUFFIX)]
        except OSError:
            return
        if len(names) <= 2 * len(used) + 100:
            return
        for name in names:
            if name[:-len(_SUFFIX)] not in used:
                try:
                    os.unlink(self.folder / name)
                except OSError:
                    pass
