# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Rules on activities and signatures: what runs a function, and with what.

A function has one signature in C++ and one way of being called in Python,
so every activity that runs it must hand it the same thing.
"""

from __future__ import annotations

from colcon_robmosys.errors import Diagnostic
from colcon_robmosys.mapping.executors import blocking_calls, BlockingCall
from colcon_robmosys.mapping.portkinds import port_kind, PORT_KINDS
from colcon_robmosys.model.types import Component, Executor, Pattern, System

#: the order patterns are named in
_PATTERN_ORDER = [p.value for p in Pattern]


def port_problems(component: Component) -> list[Diagnostic]:
    """Return the ports that set what their ROS 2 entity has no use for."""
    problems = []
    for port in component.ports:
        if port.qos_location is not None and not port_kind(port).topic_qos:
            with_qos = sorted({k.pattern.value for k in PORT_KINDS.values()
                               if k.topic_qos}, key=_PATTERN_ORDER.index)
            problems.append(Diagnostic(
                port.qos_location, f"port '{port.name}': {port.pattern.value} "
                'ports use the QoS of ROS 2 services and actions; '
                f"'qos' applies to {', '.join(with_qos[:-1])} and {with_qos[-1]} "
                'ports'))
    return problems


def activity_problems(component: Component) -> list[Diagnostic]:
    """Return what is wrong with the triggers and functions of activities."""
    problems: list[Diagnostic] = []
    triggered_by: dict[str, str] = {}
    for activity in component.activities:
        port = component.port(activity.trigger) if activity.trigger else None
        if port is None:
            continue
        where = activity.trigger_location or activity.location
        kind = port_kind(port)
        if not kind.triggers:
            problems.append(Diagnostic(
                where, f'a {port.role.value} {port.pattern.value} port '
                f"('{port.name}') delivers nothing that could trigger an "
                'activity'))
        elif port.name in triggered_by:
            problems.append(Diagnostic(
                where, f"port '{port.name}' already triggers activity "
                f"'{triggered_by[port.name]}'"))
        else:
            triggered_by[port.name] = activity.name
            if kind.one_function and len(activity.functions) != 1:
                problems.append(Diagnostic(
                    activity.functions_location or activity.location,
                    f"activity '{activity.name}' answers port "
                    f"'{port.name}', so it must have exactly one function: "
                    'the one that returns the answer'))
    for port in component.ports:
        if port_kind(port).needs_handler and port.name not in triggered_by:
            problems.append(Diagnostic(
                port.location, f'provided {port.pattern.value} port '
                f"'{port.name}' needs an activity triggered by it to answer"))
    if not problems:
        problems += signature_problems(component) + executor_problems(component)
    return problems


def signature_problems(component: Component) -> list[Diagnostic]:
    """Return the functions that two triggers would call differently.

    A function listed in several activities is called by each; the ports
    that trigger them must deliver the same thing (in both languages: a C++
    function has one signature, and a Python function called with other
    arguments fails at run time). Periodic activities and lifecycle
    transitions call a function with nothing.
    """
    #: function -> (what it receives, said in words) per caller
    callers: dict[str, list[tuple[object, str]]] = {}
    for activity in component.activities:
        port = component.port(activity.trigger) if activity.trigger else None
        if port is not None:
            kind = port_kind(port)
            what: object = (kind.delivers, port.type)
            said = f"the port '{port.name}' ({kind.delivers_text}, {port.type})"
        else:
            what, said = None, f"the periodic activity '{activity.name}'"
        for name in activity.functions:
            callers.setdefault(name, []).append((what, said))
    for transition, names in component.lifecycle:
        for name in names:
            callers.setdefault(name, []).append(
                (None, f"the lifecycle transition '{transition}'"))
    for parameter in component.parameters:
        for name in parameter.on_change:
            callers.setdefault(name, []).append(
                (None, f"a change of the parameter '{parameter.name}'"))
        if parameter.validate is not None:
            callers.setdefault(parameter.validate, []).append((
                ('value', parameter.type),
                f"the validation of the parameter '{parameter.name}' (a {parameter.type} value)"))
    problems = []
    for function in component.functions:
        calls = callers.get(function.name, [])
        first = calls[0] if calls else None
        other = next((c for c in calls if c[0] != first[0]), None) \
            if first else None
        if first is not None and other is not None:
            problems.append(Diagnostic(
                function.location,
                f"function '{function.name}' is run by {first[1]} and by "
                f'{other[1]}, which deliver different things; a function '
                'has one signature: give each its own function'))
    return problems


def _blocking_words(call: BlockingCall) -> str:
    kind = port_kind(call.port)
    who = (f"function '{call.function.name}' calls" if call.function is not None
           else 'functions written in the implementation file may call')
    return (f"{who} {call.method}() of port '{call.port.name}' "
            f'({kind.role.value} {kind.pattern.value}), which waits for an answer '
            'that another thread of the executor delivers')


def executor_problems(component: Component) -> list[Diagnostic]:
    """Return the executor the model names if the component cannot run on it.

    The events and the single-threaded executor run every callback on one
    thread: a function that blocks in a call from a callback would wait for
    an answer that nothing takes (see mapping/executors.py).
    """
    if component.executor in (None, Executor.MULTI_THREADED):
        return []
    calls = blocking_calls(component)
    if not calls:
        return []
    assert component.executor is not None and component.executor_location is not None
    return [Diagnostic(
        component.executor_location,
        f"component '{component.name}' cannot run on the {component.executor.value} "
        f'executor: {_blocking_words(calls[0])}; it needs executor: multi-threaded '
        '(or only the asynchronous calls call_async and send_goal_async)')]


def system_executor_problems(system: System, components: dict[str, Component]
                             ) -> list[Diagnostic]:
    """Return the executor a system names for its shared processes if an instance cannot run on it.

    :param components: instance name -> its component
    """
    if system.executor in (None, Executor.MULTI_THREADED):
        return []
    assert system.executor is not None and system.executor_location is not None
    for instance, component in components.items():
        calls = [] if component.external else blocking_calls(component)
        if calls:
            return [Diagnostic(
                system.executor_location,
                f"the shared processes of system '{system.name}' cannot run on the "
                f"{system.executor.value} executor: in instance '{instance}' (component "
                f"'{component.name}'), {_blocking_words(calls[0])}; they need executor: "
                'multi-threaded')]
    return []
