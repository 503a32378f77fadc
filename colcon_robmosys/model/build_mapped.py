# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The rules of mapped parameters: a parameter repeated for each entry of a string array.

``gains.p: {type: double, for_each: joints}`` with ``joints: [a, b]`` is
``gains.a.p`` and ``gains.b.p``, as generate_parameter_library's
``gains.__map_joints.p``; typed access is ``gains.joints_map['a'].p``.
"""

from __future__ import annotations

from functools import partial

from colcon_robmosys.model.build_base import BuilderBase
from colcon_robmosys.model.loader import NodePath
from colcon_robmosys.model.parameters import entries_problem
from colcon_robmosys.model.types import Parameter


def map_accessor(array: str) -> str:
    """Return the name of the typed access to the entries of an array (``joints_map``)."""
    return f'{array}_map'


class MappedParameterBuilder(BuilderBase):
    """Check the parameters of a component that are repeated for each entry of an array."""

    def _check_mapped(self, path: NodePath, parameters: tuple[Parameter, ...]) -> None:
        by_name = {p.name: p for p in parameters}
        arrays = sorted(p.name for p in parameters
                        if p.type == 'string[]' and p.for_each is None)
        valid: set[str] = set()
        accessors: set[tuple[str, ...]] = set()
        for parameter in parameters:
            if parameter.for_each is None:
                continue
            problem = _array_problem(by_name.get(parameter.for_each), parameter.for_each,
                                     arrays)
            if problem:
                self.error(path + ('parameters', parameter.name, 'for_each'),
                           f"parameter '{parameter.name}': {problem}")
            else:
                valid.add(parameter.for_each)
                if parameter.path[:-1] + (parameter.for_each,) not in accessors:
                    # once per group and array: they share their typed access
                    accessors.add(parameter.path[:-1] + (parameter.for_each,))
                    self._check_accessor(path, parameter, parameters)
        for array in sorted(valid):
            kept = by_name[array].default
            default = list(kept) if isinstance(kept, tuple) else []
            problem = entries_problem(parameters, array, default)
            if problem:
                self.error_in_list(path + ('parameters', array, 'default'), default, problem,
                                   f"parameter '{array}': {problem}",
                                   partial(entries_problem, parameters, array))

    def _check_accessor(self, path: NodePath, parameter: Parameter,
                        parameters: tuple[Parameter, ...]) -> None:
        """Report a member of the group that has the name of the typed access to the entries."""
        group, accessor = parameter.path[:-1], map_accessor(str(parameter.for_each))
        taken = next((p.name for p in parameters if p.path[:len(group) + 1] ==
                      group + (accessor,) and not (p.for_each and len(p.path) == len(group) + 1)),
                     None)
        if taken is not None:
            full = '.'.join(group + (accessor,))
            self.error(path + ('parameters', parameter.name), f"parameter '{parameter.name}': "
                       f"its typed access '{full}' (one group per entry of "
                       f"'{parameter.for_each}') clashes with the parameter '{taken}'", key=True)


def _array_problem(array: Parameter | None, name: str, arrays: list[str]) -> str | None:
    """Return why a parameter cannot be repeated for each entry of that array."""
    if array is None:
        known = ', '.join(arrays) or 'none'
        return (f"'for_each' names '{name}', which is no parameter of the component "
                f'(its string[] parameters: {known})')
    if array.type != 'string[]':
        return f"'for_each' needs a string[] parameter, '{name}' is {array.type}"
    if array.for_each is not None:
        return f"'{name}' is itself repeated for each entry of '{array.for_each}'"
    if not array.read_only:
        return (f"'{name}' must be read_only: the node declares the parameters of its "
                'entries once, at start')
    return None
