# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
When each publisher of a component last sent: its own count, no copy of the data.

The watch of a system asks how long ago each periodic port carried a
message. A subscription would answer at the price of a copy of every
message; a component knows when it publishes. Where the ``bringup`` that
started its process names a directory in :data:`SENDS` (on the host's
shared memory), each lifecycle publisher of the component keeps there a file
of eight bytes: the ``CLOCK_MONOTONIC`` time, in nanoseconds, of its last
send, written at each publish (a store into a mapped page). The ``bringup``
reads the files of a topic (:class:`Sends`) once per check period. Without
the variable (a node started by hand or by a launch file) nothing is kept.

The C++ components keep the same files (``robmosys_runtime/sends.hpp``): a
file is named ``<key>-<pid>-<n>``, key the FNV-1a hash of the topic's name
(:func:`topic_key`), so that a reader finds every publisher of a topic
without knowing the nodes.
"""

from __future__ import annotations

import itertools
import mmap
import os
from pathlib import Path
import shutil
import struct
import time
from typing import Any, Dict, Iterable, Optional

#: the environment variable that names the directory of the send files
SENDS = 'ROBMOSYS_SENDS'
_STAMP = struct.Struct('=q')
_numbers = itertools.count()
_PREFIX = 'robmosys-sends-'


def send_directory() -> Path:
    """
    Make the directory of a bringup's send files; remove those of bringups that ended.

    On the host's shared memory (``/dev/shm``) where there is one: the files
    are never written to a disk. A bringup removes its own when it ends; one
    killed leaves it, for the next to remove.
    """
    import tempfile  # once, at the start of a bringup, after its instances
    base = Path('/dev/shm')
    if not os.access(base, os.W_OK):
        base = Path(tempfile.gettempdir())
    for left in base.glob(f'{_PREFIX}*-*'):
        pid = left.name[len(_PREFIX):].split('-', 1)[0]
        if pid.isdigit() and not Path(f'/proc/{pid}').exists():
            shutil.rmtree(left, ignore_errors=True)
    return Path(tempfile.mkdtemp(prefix=f'{_PREFIX}{os.getpid()}-', dir=base))


def topic_key(topic: str) -> str:
    """Return the key of a topic's files: FNV-1a (64 bits) of its name, in hex."""
    value = 0xcbf29ce484222325
    for byte in topic.encode():
        value = ((value ^ byte) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
    return f'{value:016x}'


def count_sends(publisher: Any) -> None:
    """
    Make a lifecycle publisher keep the time of its last send, where bringup asks.

    Only a send while the publisher is activated counts: a lifecycle
    publisher drops the others.
    """
    directory = os.environ.get(SENDS)
    if not directory:
        return
    try:
        stamp = _stamp_file(Path(directory), publisher.topic_name)
    except OSError:
        return  # the bringup that asked has gone: the watch ends with it
    publish = publisher.publish
    clock = time.monotonic_ns

    def counted(msg: Any) -> None:
        publish(msg)
        if publisher.is_activated:
            _STAMP.pack_into(stamp, 0, clock())

    publisher.publish = counted


def _stamp_file(directory: Path, topic: str) -> mmap.mmap:
    path = directory / f'{topic_key(topic)}-{os.getpid()}-{next(_numbers)}'
    descriptor = os.open(path, os.O_RDWR | os.O_CREAT | os.O_TRUNC | os.O_CLOEXEC, 0o600)
    try:
        os.ftruncate(descriptor, _STAMP.size)
        return mmap.mmap(descriptor, _STAMP.size)
    finally:
        os.close(descriptor)


class Sends:
    """
    The bringup's side: when the publishers of a topic, on its host, last sent.

    :param directory: the directory named in :data:`SENDS`
    """

    def __init__(self, directory: Path) -> None:
        self.directory = directory
        #: file name -> its mapping, once opened
        self._open: Dict[str, mmap.mmap] = {}

    def latest(self, topics: Iterable[str]) -> Dict[str, Optional[float]]:
        """
        Return, for each topic whose publishers keep a file, the time of the last send.

        The time as ``time.monotonic()`` gives it (the same clock), None if none
        sent yet; a topic with no file is left out.
        """
        keys = {topic_key(t): t for t in topics}
        latest: Dict[str, int] = {}
        try:
            names = [e.name for e in os.scandir(self.directory)]
        except OSError:
            return {}
        for name in names:
            topic = keys.get(name.split('-', 1)[0])
            if topic is None:
                continue
            mapping = self._open.get(name) or self._map(name)
            if mapping is not None:
                latest[topic] = max(latest.get(topic, 0), _STAMP.unpack_from(mapping, 0)[0])
        return {t: n / 1e9 if n else None for t, n in latest.items()}

    def _map(self, name: str) -> Optional[mmap.mmap]:
        try:
            with open(self.directory / name, 'rb') as file:
                self._open[name] = mmap.mmap(file.fileno(), _STAMP.size, access=mmap.ACCESS_READ)
        except (OSError, ValueError):
            return None  # made and not yet sized: read at the next period
        return self._open[name]

    def close(self) -> None:
        """Release the mappings."""
        for mapping in self._open.values():
            mapping.close()
        self._open.clear()
