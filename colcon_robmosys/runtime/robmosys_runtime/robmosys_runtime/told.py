# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
What the shared process tells the manager before the manager joins the graph.

Where the shared process of the manager's host brings up every managed
instance (:func:`tells_all`), it writes the states it brought them to, one
line of JSON (:func:`robmosys_runtime.container.bring_up`): to a pipe that
``bringup`` gave it (:func:`read_told`), or to a file that
``<system>.launch.py`` gave it and its manager (:func:`read_told_file`). The
manager reads them before it imports rclpy or makes a DDS participant: one
made while the instances are being made is sent every endpoint of every node
as it appears, and slowed their bring-up by a third (issue 28).
"""

from __future__ import annotations

import json
import os
import select
import threading
import time
from typing import Any, Dict, Optional

from robmosys_runtime.processes import shared_python


def tells_all(description: Dict[str, Any], shared: Optional[bool]) -> bool:
    """
    Tell whether the shared process of this host brings up every managed instance.

    It then tells ``bringup`` what it brought up through a pipe, and bringup
    needs no DDS participant of its own to report the bring-up.
    """
    managed = {i['instance'] for i in description['instances'] if i['managed']}
    return bool(managed) and managed <= set(shared_python(description, '', shared))


def read_told(reading: int, timeout: float,
              signalled: threading.Event) -> Optional[Dict[str, str]]:
    """
    Return the states the shared process wrote to a pipe, and close it.

    None if it wrote none: it ended first, or did not write within timeout
    seconds, or a signal came (the manager then learns them as from a launch).
    """
    deadline = time.monotonic() + timeout
    data = b''
    try:
        while not signalled.is_set() and time.monotonic() < deadline:
            ready, _, _ = select.select([reading], [], [], 0.05)
            if not ready:
                continue
            chunk = os.read(reading, 65536)
            if not chunk:
                break
            data += chunk
            if data.endswith(b'\n'):
                break
    finally:
        os.close(reading)
    return told_states(data)


def read_told_file(path: str, timeout: float,
                   signalled: threading.Event) -> Optional[Dict[str, str]]:
    """
    Return the states the shared process wrote to a file (``container --report-file``).

    None if it wrote none: its process ended first (the pid it wrote to
    ``<file>.started`` is gone), or it did not write within timeout seconds,
    or a signal came.
    """
    deadline = time.monotonic() + timeout
    while not signalled.is_set() and time.monotonic() < deadline:
        try:
            with open(path, 'rb') as stream:
                return told_states(stream.read())
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
                return None
        signalled.wait(0.02)
    return None


def told_states(data: bytes) -> Optional[Dict[str, str]]:
    """Return the states of a line of JSON the shared process wrote, None if it is not one."""
    try:
        states = json.loads(data)
    except ValueError:
        return None
    return {str(k): str(v) for k, v in states.items()} if isinstance(states, dict) else None
