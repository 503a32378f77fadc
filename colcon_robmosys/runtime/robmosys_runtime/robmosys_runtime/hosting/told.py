# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
What the shared processes tell the manager before the manager joins the graph.

Where the shared processes of the manager's host (the Python one, the C++
component container: :func:`tellers`) bring up every managed instance
(:func:`tells_all`), each writes the states it brought them to, one line of
JSON (:func:`robmosys_runtime.hosting.container.bring_up`,
``src/component_container.cpp``): to a pipe of its own that ``bringup`` gave
it (:func:`read_told`), or to a file of its own (:func:`told_file`) that
``<system>.launch.py`` gave it and its manager (:func:`read_told_file`). The
manager reads them before it imports rclpy or makes a DDS participant: one
made while the instances are being made is sent every endpoint of every node
as it appears, and slowed their bring-up by a third (issue 28).
"""

from __future__ import annotations

import json
import os
import select
import sys
import threading
import time
from typing import Any, Dict, Iterable, Iterator, List, Optional, Sequence, Set, Tuple

from robmosys_runtime.hosting.processes import (
    CPP_GROUP, PYTHON_GROUP, shared_arguments, shared_cpp, shared_python, SharedArguments)


def tellers(description: Dict[str, Any], shared: Optional[bool]) -> Dict[str, List[str]]:
    """Return group -> its instances, of the shared processes of the manager's host."""
    groups = {PYTHON_GROUP: shared_python(description, '', shared),
              CPP_GROUP: shared_cpp(description, '', shared)}
    return {group: names for group, names in groups.items() if names}


def tells_all(description: Dict[str, Any], shared: Optional[bool]) -> bool:
    """
    Tell whether the shared processes of this host bring up every managed instance.

    They then tell ``bringup`` what they brought up through pipes, and bringup
    needs no DDS participant of its own to report the bring-up.
    """
    managed = _managed(description)
    telling = {n for names in tellers(description, shared).values() for n in names}
    return bool(managed) and managed <= telling


def _managed(description: Dict[str, Any]) -> Set[str]:
    """Return the managed instances of a system."""
    return {i['instance'] for i in description['instances'] if i['managed']}


def bringing_itself_down(description: Dict[str, Any], shared: Optional[bool]) -> Optional[str]:
    """
    Return the group of the shared process of this host that holds every managed instance.

    It then brings them down itself at SIGINT, in the order ``bringup`` would
    (:func:`robmosys_runtime.hosting.container.bring_down`, the C++ container's own),
    and tells ``bringup`` each step on its pipe (:func:`read_steps`). Where
    other processes or hosts hold managed instances too (None), ``bringup``
    brings every one down through its lifecycle services, in the model's
    order across them.
    """
    managed = _managed(description)
    for group, names in tellers(description, shared).items():
        if managed and managed <= set(names):
            return group
    return None


def read_steps(reading: int, wait: float) -> Iterator[Tuple[str, str]]:
    """
    Yield each step the shared process tells of its bring-down, until it closes its pipe.

    Each comes as (level, text), as :func:`robmosys_runtime.hosting.output.say` takes it.
    Each within wait seconds of the one before (a transition that hangs ends
    the reading: bringup stops the process). The line of the bring-up, not
    read if a signal came first, is skipped.
    """
    pending = b''
    while True:
        ready, _, _ = select.select([reading], [], [], wait)
        chunk = os.read(reading, 65536) if ready else b''
        if not chunk:
            return
        *lines, pending = (pending + chunk).split(b'\n')
        for line in lines:
            text = line.decode('utf-8', 'replace')
            if text.startswith('error: '):
                yield 'error', text[len('error: '):]
            elif text and not text.startswith('{'):
                yield 'info', text


def told_file(path: str, group: str) -> str:
    """Return the file where the shared process of a group tells (``--told-file`` is path)."""
    return path if group == PYTHON_GROUP else f'{path}.cpp'


def read_told(readings: Sequence[int], timeout: float, signalled: threading.Event,
              keep_open: Sequence[int] = ()) -> Optional[Dict[str, str]]:
    """
    Return the states the shared processes wrote to pipes, and close them but keep_open.

    None if none wrote any: each ended first, or did not write within timeout
    seconds, or a signal came (the manager then learns them as from a
    launch). Where only some wrote, the manager asks the others' instances.
    """
    deadline = time.monotonic() + timeout
    data = dict.fromkeys(readings, b'')
    pending = list(readings)
    try:
        while pending and not signalled.is_set() and time.monotonic() < deadline:
            ready, _, _ = select.select(pending, [], [], 0.05)
            for reading in ready:
                chunk = os.read(reading, 65536)
                data[reading] += chunk
                if not chunk or data[reading].endswith(b'\n'):
                    pending.remove(reading)
    finally:
        for reading in readings:
            if reading not in keep_open:
                os.close(reading)
    return _merged(told_states(d) for d in data.values())


def read_told_file(paths: Sequence[str], timeout: float,
                   signalled: threading.Event) -> Optional[Dict[str, str]]:
    """
    Return the states the shared processes wrote to files (``--report-file``).

    None if none wrote any: each process ended first (the pid it wrote to
    ``<file>.started`` is gone), or did not write within timeout seconds, or
    a signal came. Where only some wrote, the manager asks the others' instances.
    """
    deadline = time.monotonic() + timeout
    told: List[Optional[Dict[str, str]]] = []
    pending = list(paths)
    while pending and not signalled.is_set() and time.monotonic() < deadline:
        for path in list(pending):
            try:
                with open(path, 'rb') as stream:
                    told.append(told_states(stream.read()))
                pending.remove(path)
                continue
            except FileNotFoundError:
                pass
            try:
                with open(f'{path}.started', encoding='utf-8') as stream:
                    os.kill(int(stream.read()), 0)
            except (FileNotFoundError, ValueError, PermissionError):
                pass  # not started yet, or being written; or another user's process
            except ProcessLookupError:
                # it ended before it wrote (a process started again writes anew)
                if not os.path.exists(path):
                    pending.remove(path)
        if pending:
            signalled.wait(0.02)
    return _merged(told)


def _merged(told: Iterable[Optional[Dict[str, str]]]) -> Optional[Dict[str, str]]:
    """Return the states of every process that told any, None if none did."""
    merged: Optional[Dict[str, str]] = None
    for states in told:
        if states is not None:
            merged = {**(merged or {}), **states}
    return merged


def told_states(data: bytes) -> Optional[Dict[str, str]]:
    """Return the states of a line of JSON the shared process wrote, None if it is not one."""
    try:
        states = json.loads(data)
    except ValueError:
        return None
    return {str(k): str(v) for k, v in states.items()} if isinstance(states, dict) else None


def write_whole(path: str, text: str) -> None:
    """Write a file that its reader finds whole or not at all (a temporary file renamed)."""
    temporary = f'{path}.{os.getpid()}.tmp'
    try:
        with open(temporary, 'w', encoding='utf-8') as stream:
            stream.write(text)
        os.replace(temporary, path)
    except OSError as error:
        # the manager asks the instances instead
        print(f'{path}: error: {error.strerror}', file=sys.stderr)


def shared_start(argv: List[str], program: str, start: str, language: str
                 ) -> Optional[Tuple[SharedArguments, Dict[str, Any], List[Dict[str, Any]]]]:
    """
    Return a shared process's arguments, the description and its instances, or None.

    None after saying why: not such a command line, or names that are not
    ``language`` instances of the system (``start``: the key that says how a
    process creates an instance's node). With ``--report-file``, the process's
    pid is written to ``<file>.started`` first: the manager waits for the file
    only while that process lives.
    """
    args = shared_arguments(argv)
    if args is None:
        print(f'{program}: error: usage: {program} [--activate [--report-fd FD | '
              '--report-file FILE]] DESCRIPTION PARAMS_FILE INSTANCE...', file=sys.stderr)
        return None
    if args.report_file is not None:
        write_whole(f'{args.report_file}.started', str(os.getpid()))
    with open(args.description_file, encoding='utf-8') as stream:
        description = json.load(stream)
    instances = {i['instance']: i for i in description['instances']}
    unknown = [n for n in args.names if n not in instances or not instances[n].get(start)]
    if unknown:
        which = ', '.join(unknown)
        print(f'{program}: error: not {language} instances of the system: {which}',
              file=sys.stderr)
        return None
    return args, description, [instances[n] for n in args.names]
