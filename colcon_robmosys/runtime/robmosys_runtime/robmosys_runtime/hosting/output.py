# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""What bringup prints: one line at a time, errors on stderr (no rclpy needed)."""

from __future__ import annotations

import sys
import threading

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
