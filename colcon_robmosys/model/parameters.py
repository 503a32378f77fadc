# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Parameter values: which fit a parameter type, and how the model keeps them."""

from __future__ import annotations

import math
from typing import Any, Callable


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
        if not isinstance(value, list) or not all(
                PARAMETER_KINDS['int'](v) and 0 <= v <= 255 for v in value):
            return f'{value!r} is not a list of bytes (integers 0..255)'
        return None
    if type_name.endswith('[]'):
        check = PARAMETER_KINDS[type_name[:-2]]
        if not isinstance(value, list) or not all(check(v) for v in value):
            return f'{value!r} is not a list of {type_name[:-2]} values'
        return None
    if not PARAMETER_KINDS[type_name](value):
        article = 'an' if type_name == 'int' else 'a'
        return f'{value!r} is not {article} {type_name} value'
    return None


def freeze_parameter_value(type_name: str, value: Any) -> Any:
    """Return the value in the form the model keeps (tuples, floats)."""
    if isinstance(value, list):
        return tuple(freeze_parameter_value(type_name[:-2], v) for v in value)
    if type_name.startswith('double') and isinstance(value, int):
        return float(value)
    return value
