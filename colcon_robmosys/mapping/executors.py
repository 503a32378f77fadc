# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The executor of each process: the one the model names, or the fastest that is correct.

The events executor (rclpy's and rclcpp's ``EventsExecutor``) runs every callback
on one thread, without rebuilding a wait set per callback: the cheapest per
message. A single thread is correct unless a function waits, inside a callback,
for an answer that the executor itself has to deliver: a blocking ``call`` of a
query client or ``send_goal`` of an action client (``blocking_calls`` of the
port-kind table). Such a component needs the multi-threaded executor; the others
run on their backend's default (``Backend.default_executor``), which the callers
pass in: the backends plan their components with this module, so it cannot ask them.
"""

from __future__ import annotations

from dataclasses import dataclass
import re
from typing import Iterable, Mapping

from colcon_robmosys.mapping.portkinds import port_kind
from colcon_robmosys.model.types import Component, Executor, Function, Language, Port

#: from the cheapest to the most capable: a shared process takes the most
#: capable executor any of its nodes needs
EXECUTOR_ORDER = (Executor.EVENTS, Executor.SINGLE_THREADED, Executor.MULTI_THREADED)


@dataclass(frozen=True)
class BlockingCall:
    """A function that may wait, in a callback, for an answer of a port."""

    port: Port
    #: the function, or None when every function of the user's may (none has code)
    function: Function | None
    method: str


def blocking_calls(component: Component) -> list[BlockingCall]:
    """Return the calls of the component's functions that may block a thread.

    A function with embedded code calls a port blocking when its code says
    ``<port>.call(`` (Python) or ``<port>->call(`` (C++), likewise ``send_goal``;
    a function the user writes in the implementation file may call any.
    """
    found = []
    for port in component.ports:
        methods = port_kind(port).blocking_calls
        if not methods:
            continue
        pattern = re.compile(r'\b%s\s*(?:\.|->)\s*(%s)\s*\(' % (
            re.escape(port.name), '|'.join(map(re.escape, methods))))
        if component.user_functions:
            found.append(BlockingCall(port, None, methods[0]))
        for function in component.functions:
            match = pattern.search(function.code or '')
            if match is not None:
                found.append(BlockingCall(port, function, match.group(1)))
    return found


def component_executor(component: Component, default: Executor) -> Executor:
    """Return the executor of a component's own process: named, or the fastest correct one.

    :param default: its backend's executor of a component that names none and
      blocks no thread (``Backend.default_executor``)
    """
    if component.executor is not None:
        return component.executor
    if blocking_calls(component):
        return Executor.MULTI_THREADED
    return default


def shared_executor(named: Executor | None, components: Iterable[Component],
                    defaults: Mapping[Language, Executor]) -> Executor:
    """Return the executor of a process that several nodes share.

    The one the system names, or the most capable that one of the nodes needs.

    :param defaults: language -> its backend's default (``DEFAULT_EXECUTORS``
      of :mod:`colcon_robmosys.mapping.backends`)
    """
    if named is not None:
        return named
    return max((component_executor(c, defaults[c.language]) for c in components),
               key=EXECUTOR_ORDER.index, default=Executor.EVENTS)


def shared_executors(named: Executor | None, components: Iterable[Component],
                     defaults: Mapping[Language, Executor]) -> tuple[tuple[str, str], ...]:
    """Return, per language of the generated components, the executor of their shared process."""
    by_language: dict[str, list[Component]] = {}
    for component in components:
        if not component.external:
            by_language.setdefault(component.language.value, []).append(component)
    return tuple((language, shared_executor(named, listed, defaults).value)
                 for language, listed in sorted(by_language.items()))
