# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Rules on the parameter values a system sets: per instance, and for every instance.

A value must fit the parameter's type and its range, ``one_of`` and ``size``;
the functions of a component that validate values (``validate``) are the
user's code and run in the node only (on every change, and on configure).
"""

from __future__ import annotations

from functools import partial
from typing import Any, Callable, Iterable, Mapping, Sequence

from colcon_robmosys.errors import Diagnostic, Location
from colcon_robmosys.mapping.parameters import NODE_PARAMETERS
from colcon_robmosys.model.build_base import entry_at_fault
from colcon_robmosys.model.parameters import (
    entries_problem, node_parameters, parameter_value_problem, rule_problem)
from colcon_robmosys.model.types import Component, Instance, Parameter, System


def _value_problem(parameter: Parameter, value: Any,
                   parameters: Sequence[Parameter] = ()) -> str | None:
    """Return why a value does not fit; of an array with mapped parameters, its entries too."""
    return parameter_value_problem(parameter.type, value) or \
        rule_problem(parameter, value) or \
        entries_problem(parameters, parameter.name, value)


def _declared(component: Component, instance: Instance,
              shared: Mapping[str, Any]) -> dict[str, Parameter]:
    """Return the parameters of an instance's node by name, with the values a system sets."""
    return node_parameters(component.parameters, {**shared, **dict(instance.parameters)})


def override_problems(instance: Instance, component: Component,
                      shared: Mapping[str, Any] | None = None) -> list[Diagnostic]:
    """Return what is wrong with the values a system gives an instance.

    :param shared: the values the system sets for every instance (the arrays
      of mapped parameters among them)
    """
    problems = []
    parameters = _declared(component, instance, shared or {})
    locations = instance.parameter_locations or \
        (instance.location,) * len(instance.parameters)
    entries = instance.parameter_entry_locations or ((),) * len(instance.parameters)
    for (name, value), location, at in zip(instance.parameters, locations, entries):
        parameter = parameters.get(name)
        if parameter is None:
            if name in NODE_PARAMETERS:
                check = partial(parameter_value_problem, NODE_PARAMETERS[name])
                problem = check(value)
                if problem:
                    problems.append(Diagnostic(
                        _at_entry(location, at, value, problem, check),
                        f"instance '{instance.name}', parameter '{name}': {problem}"))
                continue
            known = ', '.join(sorted(parameters)) or 'none'
            problems.append(Diagnostic(
                location, f"instance '{instance.name}': component '{component.name}' has "
                f"no parameter '{name}' (its parameters: {known})"))
            continue
        problem_of = partial(_value_problem, parameter, parameters=component.parameters)
        problem = problem_of(value)
        if problem:
            problems.append(Diagnostic(
                _at_entry(location, at, value, problem, problem_of),
                f"instance '{instance.name}', parameter '{name}': {problem}"))
    return problems


def unset_problems(system: System, instance: Instance, component: Component
                   ) -> list[Diagnostic]:
    """Return the parameters without default that a system leaves unset for an instance.

    The node would not configure without a value (it names the parameter);
    the system sets it for the instance, or for every instance.
    """
    given = {name for name, _ in instance.parameters} | {name for name, _ in system.parameters}
    return [Diagnostic(instance.location, f"instance '{instance.name}': parameter "
                       f"'{parameter.name}' of component '{component.name}' has no default, "
                       "and the system does not set it (in the instance's parameters, or "
                       "the system's)")
            for parameter in component.parameters
            if parameter.required and parameter.name not in given]


def _at_entry(location: Location, entries: tuple[Location, ...], value: Any, problem: str,
              problem_of: Callable[[Any], str | None]) -> Location:
    """Return where a value's problem stands: at its entry, if it is one entry's."""
    index = entry_at_fault(value, problem, problem_of)
    return location if index is None or index >= len(entries) else entries[index]


def everywhere_problems(system: System, components: Iterable[tuple[Instance, Component]]
                        ) -> list[Diagnostic]:
    """Return what is wrong with the values a system sets for every instance.

    A value goes to every node of the system (the ``/**`` entry of its
    parameter file); nodes that do not declare the parameter ignore it, as
    ROS 2 does. At least one instance must have it, with a fitting value.
    """
    problems = []
    pairs = list(components)
    shared = dict(system.parameters)
    locations = system.parameter_locations or (system.location,) * len(system.parameters)
    entries = system.parameter_entry_locations or ((),) * len(system.parameters)
    for (name, value), location, at in zip(system.parameters, locations, entries):
        types = {NODE_PARAMETERS[name]: 'every ROS 2 node'} if name in NODE_PARAMETERS else {}
        check: Callable[[Any], str | None] = partial(
            parameter_value_problem, NODE_PARAMETERS.get(name, ''))
        problem, whose = check(value) if types else None, ''
        for instance, component in pairs:
            parameter = _declared(component, instance, shared).get(name)
            if parameter is None or problem:
                continue
            types.setdefault(parameter.type, f"instance '{instance.name}'")
            check = partial(_value_problem, parameter, parameters=component.parameters)
            problem, whose = check(value), f" (for instance '{instance.name}')"
        if problem:
            problems.append(_everywhere(_at_entry(location, at, value, problem, check),
                                        name, problem + whose))
        elif len(types) > 1:
            # one value in the file: ROS 2 refuses an int for a double and the reverse
            problems.append(_everywhere(location, name, 'its types differ: ' + ', '.join(
                f'{type_} in {where}' for type_, where in types.items())))
        elif not types:
            problems.append(_everywhere(
                location, name, 'no instance of the system has it (nor is it a parameter '
                'of every ROS 2 node)'))
    return problems


def _everywhere(location: Location, name: str, problem: str) -> Diagnostic:
    return Diagnostic(location, f"parameter '{name}' for every instance: {problem}")
