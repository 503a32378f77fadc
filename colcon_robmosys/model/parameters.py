# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Parameter values: which fit a parameter type, and how the model keeps them."""

from __future__ import annotations

import math
import re
from typing import Any, Callable, Mapping, Sequence

from colcon_robmosys.model.components import Parameter


PARAMETER_KINDS: dict[str, Callable[[Any], bool]] = {
    'bool': lambda v: isinstance(v, bool),
    'int': lambda v: isinstance(v, int) and not isinstance(v, bool),
    'double': lambda v: isinstance(v, (int, float)) and
    not isinstance(v, bool) and math.isfinite(v),
    'string': lambda v: isinstance(v, str),
}

PARAMETER_ZERO = {
    'bool': False, 'int': 0, 'double': 0.0, 'string': '',
    'bool[]': (), 'int[]': (), 'double[]': (), 'string[]': (), 'byte[]': (),
}


def parameter_value_problem(type_name: str, value: Any) -> str | None:
    """Return why a value cannot be given to a parameter of the type."""
    if type_name == 'byte[]':
        if not isinstance(value, list):
            return f'{value!r} is not a list of bytes (integers 0..255)'
        stray = next((v for v in value if not (
            PARAMETER_KINDS['int'](v) and 0 <= v <= 255)), _NONE)
        if stray is not _NONE:
            return f'element {stray!r} is not a byte (an integer 0..255)'
        return None
    if type_name.endswith('[]'):
        check = PARAMETER_KINDS[type_name[:-2]]
        if not isinstance(value, list):
            return f'{value!r} is not a list of {type_name[:-2]} values'
        stray = next((v for v in value if not check(v)), _NONE)
        if stray is not _NONE:
            # said of the element, so that it is reported where it stands
            return f'element {stray!r} is not {_article(type_name[:-2])} value'
        return None
    if not PARAMETER_KINDS[type_name](value):
        return f'{value!r} is not {_article(type_name)} value'
    return None


#: what no element of a list is: a None of the list is an element
_NONE = object()


def _article(type_name: str) -> str:
    return f"{'an' if type_name == 'int' else 'a'} {type_name}"


def freeze_parameter_value(type_name: str, value: Any) -> Any:
    """Return the value in the form the model keeps (tuples, floats)."""
    if isinstance(value, list):
        return tuple(freeze_parameter_value(type_name[:-2], v) for v in value)
    if type_name.startswith('double') and isinstance(value, int):
        return float(value)
    return value


def _listed(values: Any) -> str:
    return ', '.join(repr(v) for v in values)


def rule_problem(parameter: Parameter, value: Any) -> str | None:
    """Return why a value of the parameter's type breaks its range, one_of or size.

    The generated nodes refuse such a value with the same words at run time
    (robmosys_runtime's parameters module and parameters.hpp).
    """
    bounds = parameter.range
    if bounds is not None and not parameter.type.endswith('[]') and \
            not bounds.start <= value <= bounds.end:
        return f'{value} is out of the range [{bounds.start}, {bounds.end}]'
    if parameter.one_of is not None:
        if not parameter.type.endswith('[]'):
            if value not in parameter.one_of:
                return f'{value!r} is not one of {_listed(parameter.one_of)}'
        else:
            stray = next((v for v in value if v not in parameter.one_of), None)
            if stray is not None:
                return f'element {stray!r} is not one of {_listed(parameter.one_of)}'
    size = parameter.size
    if size is not None:
        unit = 'characters' if parameter.type == 'string' else 'elements'
        if len(value) < size.min:
            return f'{value!r} has {len(value)} {unit}, fewer than {size.min}'
        if size.max is not None and len(value) > size.max:
            return f'{value!r} has {len(value)} {unit}, more than {size.max}'
    return None


#: an entry of an array that parameters are repeated for: one part of a parameter name
_ENTRY = re.compile(r'(?!.*__)[A-Za-z][A-Za-z0-9_]*\Z')


def entries_problem(parameters: Sequence[Parameter], array: str,
                    entries: Sequence[Any]) -> str | None:
    """Return why the entries of an array cannot each have the parameters mapped over it.

    Each entry is one part of a parameter name, listed once, and none of the
    names it gives is a parameter the node has already. The generated nodes
    refuse such a value at start with the same words (robmosys_runtime's
    ``map_entries``).
    """
    mapped = [p for p in parameters if p.for_each == array]
    if not mapped:
        return None
    fixed = {p.name for p in parameters if p.for_each is None}
    seen: set[str] = set()
    for entry in entries:
        if not isinstance(entry, str) or not _ENTRY.match(entry):
            return (f'entry {entry!r} is not a parameter name part (a letter, then '
                    'letters, digits and single underscores)')
        if entry in seen:
            return f'entry {entry!r} is listed twice'
        seen.add(entry)
        clash = next((p.ros_name(entry) for p in mapped if p.ros_name(entry) in fixed), None)
        if clash is not None:
            return f"entry {entry!r} gives the parameter '{clash}', which the component has"
    return None


def array_entries(parameters: Sequence[Parameter], array: str,
                  values: Mapping[str, Any] | None = None) -> tuple[str, ...]:
    """Return the entries of an array: its value in ``values`` if they fit, else its default."""
    value = (values or {}).get(array)
    if isinstance(value, (list, tuple)) and not entries_problem(parameters, array, value):
        return tuple(value)
    default = next((p.default for p in parameters if p.name == array), ())
    return tuple(default) if isinstance(default, tuple) else ()


def node_parameters(parameters: Sequence[Parameter],
                    values: Mapping[str, Any] | None = None) -> dict[str, Parameter]:
    """Return every parameter a node of the component declares, by its ROS 2 name.

    A mapped parameter (``for_each``) comes once per entry of its array: the
    array's value in ``values`` (parameter name -> value, as a system or a
    parameter file sets them), else its default. ``Parameter.for_each`` tells
    a mapped parameter, ``Parameter.ros_name(entry)`` its name for an entry.
    """
    named: dict[str, Parameter] = {}
    for parameter in parameters:
        if parameter.for_each is None:
            named[parameter.name] = parameter
            continue
        for entry in array_entries(parameters, parameter.for_each, values):
            named.setdefault(parameter.ros_name(entry), parameter)
    return named
