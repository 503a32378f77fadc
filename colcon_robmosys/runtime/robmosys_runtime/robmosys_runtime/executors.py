# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The executor that spins the nodes of a process: the one its model names, or what they need."""

from __future__ import annotations

import os
from typing import Any, Optional, Sequence

from rclpy.executors import Executor, MultiThreadedExecutor, SingleThreadedExecutor
from rclpy.node import Node


#: the threads a node needs beside the others of its process, when it does not
#: say (a node not generated from a model): threads to spare for blocking calls
DEFAULT_MIN_THREADS = 4


#: the executors a model names, from the cheapest to the most capable
EXECUTORS = ('events', 'single-threaded', 'multi-threaded')


def executor_kind(nodes: Sequence[Node] = (), named: Optional[str] = None) -> str:
    """
    Return the executor a process spins its nodes with: named, or what its nodes need.

    A generated node states its ``executor_name`` (its model's, or the fastest
    that runs its activities correctly); nodes of one process take the most
    capable any of them needs. A node that does not say (not generated from
    a model) is spun as before: by a multi-threaded executor.
    """
    if named is not None:
        if named not in EXECUTORS:
            raise ValueError(f'unknown executor {named!r}: one of {", ".join(EXECUTORS)}')
        return named
    kinds = [getattr(node, 'executor_name', 'multi-threaded') for node in nodes]
    return max(kinds, key=EXECUTORS.index, default='multi-threaded')


def make_executor(kind: str, nodes: Sequence[Node] = ()) -> Executor:
    """Return an executor of a kind (:data:`EXECUTORS`) for the nodes of a process."""
    if kind == 'events':
        from rclpy.experimental import EventsExecutor
        return EventsExecutor()
    if kind == 'single-threaded':
        return SingleThreadedExecutor()
    return ThreadsExecutor(num_threads=executor_threads(nodes))


class ThreadsExecutor(MultiThreadedExecutor):
    """
    rclpy's multi-threaded executor, which skips a timer cancelled after its wait.

    A deactivation cancels a node's activity timers in one of the executor's
    threads while the spinning thread may have found one of them ready. rclpy
    9 (Kilted) then skips the timer (TimerCancelledError); rclpy 7.1 (Jazzy)
    raises 'failed to call timer: timer is canceled' out of spin, which ended
    the component's process (seen in CI), and leaves the timer's callback
    group taken for good: the node's lifecycle and parameter services of that
    group would never be served again. This one skips it too.
    """

    def _take_timer(self, tmr: Any) -> Any:
        try:
            return super()._take_timer(tmr)
        except RuntimeError as error:  # rclpy's RCLError
            if 'timer is canceled' not in str(error):
                raise
            return None


def executor_threads(nodes: Sequence[Node] = ()) -> int:
    """
    Return how many threads the executor of a component's process has.

    A generated node states its ``min_threads``: one per callback group (each
    activity, each client) and one more, so that an activity blocked in a call
    never starves the thread that delivers the answer, nor the lifecycle and
    parameter services. The nodes of one process add up; a process never has
    fewer threads than CPUs, which is what rclpy's MultiThreadedExecutor
    takes by default (and what a hand-written node spins with).
    """
    needed = sum(getattr(node, 'min_threads', DEFAULT_MIN_THREADS) for node in nodes)
    return max(os.cpu_count() or 1, needed or DEFAULT_MIN_THREADS)
