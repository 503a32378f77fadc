# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Parameters, language-neutral: their groups (dotted names) and their reference page.

``controller.gain`` is the parameter ``gain`` of the group ``controller``: the
ROS 2 parameter keeps the dotted name, typed access nests
(``self.params.controller.gain``, ``params().controller.gain()``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from colcon_robmosys.mapping.common import Banner
from colcon_robmosys.model.types import Component, Parameter

#: Parameters every ROS 2 node declares (rclcpp and rclpy), by name: their type.
NODE_PARAMETERS = {'use_sim_time': 'bool'}


@dataclass(frozen=True)
class ParameterGroup:
    """A group of parameters: those named ``<path>.<name>``, and its subgroups."""

    #: () for the parameters of the node itself
    path: tuple[str, ...]
    #: those declared once (not the mapped ones)
    parameters: tuple[Parameter, ...]
    #: the last part of each subgroup's path
    groups: tuple[str, ...]
    #: the arrays its mapped parameters are repeated for (``gains.p``, ``for_each: joints``)
    mapped: tuple[str, ...] = ()


def parameter_groups(parameters: tuple[Parameter, ...]) -> tuple[ParameterGroup, ...]:
    """Return every group, a subgroup before its group (the root, (), last)."""
    paths: list[tuple[str, ...]] = [()]
    for parameter in parameters:
        for end in range(1, len(parameter.path)):
            if parameter.path[:end] not in paths:
                paths.append(parameter.path[:end])

    def group(path: tuple[str, ...]) -> ParameterGroup:
        members = [p for p in parameters if p.path[:-1] == path]
        return ParameterGroup(
            path, tuple(p for p in members if p.for_each is None),
            tuple(g[-1] for g in paths if len(g) == len(path) + 1 and g[:-1] == path),
            tuple(dict.fromkeys(p.for_each for p in members if p.for_each is not None)))

    groups = [group(path) for path in paths]
    return tuple(sorted(groups, key=lambda g: -len(g.path)))


def camel(path: tuple[str, ...]) -> str:
    """Return a group's path in CamelCase (``controller.pid`` -> ``ControllerPid``)."""
    return ''.join(part[:1].upper() + part[1:] for name in path for part in name.split('_'))


def group_class_names(groups: tuple[ParameterGroup, ...], root: str) -> dict[tuple[str, ...], str]:
    """Name the class of each group after the root's, unique (``a_b`` and ``a.b`` differ)."""
    names: dict[tuple[str, ...], str] = {}
    taken: set[str] = set()
    for group in sorted(groups, key=lambda g: (len(g.path), g.path)):
        name = root + camel(group.path)
        base, index = name, 2
        while name in taken:
            name, index = f'{base}{index}', index + 1
        taken.add(name)
        names[group.path] = name
    return names


def constraints(parameter: Parameter) -> list[str]:
    """Return the rules of a parameter in words, for its documentation."""
    said = []
    if parameter.range is not None:
        bounds = parameter.range
        step = f', step {bounds.step}' if bounds.step else ''
        said.append(f'in [{bounds.start}, {bounds.end}]{step}')
    if parameter.one_of is not None:
        which = 'every element one of' if parameter.type.endswith('[]') else 'one of'
        said.append(f"{which} {', '.join(_shown(v) for v in parameter.one_of)}")
    if parameter.size is not None:
        unit = 'characters' if parameter.type == 'string' else 'elements'
        low, high = parameter.size.min, parameter.size.max
        said.append(f'at least {low} {unit}' if high is None else
                    f'at most {high} {unit}' if not low else f'{low} to {high} {unit}')
    if parameter.validate:
        said.append(f'validated by {parameter.validate}()')
    return said


def _shown(value: Any) -> str:
    """Return a value as the model writes it (YAML flow style)."""
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, tuple):
        return '[' + ', '.join(_shown(v) for v in value) + ']'
    if isinstance(value, str):
        return repr(value)
    return str(value)


def shown_default(parameter: Parameter) -> str:
    """Return the default of a parameter as the model writes it."""
    return _shown(parameter.default)


@dataclass(frozen=True)
class ParameterRow:
    """A parameter on its documentation page; the template escapes the text."""

    name: str
    type: str
    default: str
    read_only: bool
    constraints: tuple[str, ...]
    on_change: tuple[str, ...]
    description: str
    #: no default: a system must set it
    required: bool = False


@dataclass(frozen=True)
class ParameterPage:
    """The page of a component's parameters: share/<package>/doc/parameters.md."""

    banner: Banner
    component: str
    package: str
    rows: tuple[ParameterRow, ...]

    @property
    def has_required(self) -> bool:
        """Tell whether a parameter has no default."""
        return any(r.required for r in self.rows)


def parameter_page(component: Component, banner: Banner) -> ParameterPage | None:
    """Return the documentation page of a component's parameters, None without any."""
    if not component.parameters:
        return None
    return ParameterPage(banner, component.name, component.package, tuple(
        ParameterRow(p.shown_name, p.type, 'none: required' if p.required else shown_default(p),
                     p.read_only,
                     tuple(([f'one per entry of {p.for_each}'] if p.for_each else []) +
                           constraints(p)),
                     p.on_change, p.description, p.required)
        for p in component.parameters))
