# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""What bringup prints: one line at a time, errors on stderr, a failure once (no rclpy)."""

from __future__ import annotations

import functools
import sys
import threading
import traceback
from typing import Any, Callable, TypeVar

#: one line at a time: the instances of a level are brought up in parallel threads
_OUTPUT = threading.Lock()


def say(level: str, text: str) -> None:
    """Print a line of the bring-up: errors on stderr, the rest on stdout."""
    # The line and its end go in one write, under a lock: print() writes them
    # apart, and lines of parallel transitions ran into each other.
    line = (f'bringup: {level}: {text}' if level == 'error' else f'bringup: {text}') + '\n'
    stream = sys.stderr if level == 'error' else sys.stdout
    with _OUTPUT:
        stream.write(line)
        stream.flush()


def failure_text(error: BaseException) -> str:
    """Return one line of an exception: what it is, and where it was raised."""
    frames = traceback.extract_tb(error.__traceback__)
    where = f' (at {frames[-1].filename}:{frames[-1].lineno})' if frames else ''
    return f'{type(error).__name__}: {error}{where}'


Callback = TypeVar('Callback', bound=Callable[..., Any])


def guarded(what: str, callback: Callback) -> Callback:
    """
    Wrap a callback of the manager: an exception is reported, not raised.

    rclpy raises a callback's exception out of ``spin``, and the thread that spun the
    manager ended with it: every service went unanswered and every instance 'did not tell
    its state'. A service (std_srvs/Trigger) answers with ``success`` false and the
    exception as its message; any other callback reports each distinct failure once.
    """
    told = set()

    @functools.wraps(callback)
    def call(*args: Any) -> Any:
        try:
            return callback(*args)
        except Exception as error:  # noqa: B902 - the manager serves on
            text = f'{what} failed: {failure_text(error)}'
            if text not in told:
                told.add(text)
                say('error', text)
            if len(args) == 2 and hasattr(args[1], 'success'):
                response = args[1]
                response.success = False
                response.message = text
                return response
            return None
    return call  # type: ignore[return-value]
