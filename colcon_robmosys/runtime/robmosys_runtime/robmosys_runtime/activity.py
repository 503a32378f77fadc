# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""An activity of a component: its callback group and its lock."""

from __future__ import annotations

import threading
from typing import Any, Callable, Sequence

from rclpy.callback_groups import MutuallyExclusiveCallbackGroup

Function = Callable[..., Any]


def call_each(functions: Sequence[Function], *received: Any) -> None:
    """Call the functions of an activity, in order, with what its trigger delivered."""
    for function in functions:
        function(*received)


class Activity:
    """An activity: its callback group, and the lock its functions run under."""

    def __init__(self, name: str) -> None:
        self.name = name
        self.callback_group = MutuallyExclusiveCallbackGroup()
        # the group serialises the callbacks of the executor; the lock also
        # covers calls from other threads (an event condition tested in fire())
        self.lock = threading.Lock()
