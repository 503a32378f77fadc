# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The rules of a parameter beyond its descriptor, and the words of their refusals.

Without rclpy: the nodes' on-set-parameters callback (:mod:`parameters`) and
the offline check of parameter files (:mod:`paramcheck`) say the same.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Optional, Sequence, Tuple

#: A function of the component that validates a value: why it is refused, or '' or None.
Validator = Callable[[Any], Optional[str]]


@dataclass(frozen=True)
class ParameterRule:
    """What a value of one parameter must be, and what runs after it changes."""

    #: the values it may take; of an array, those its elements may take
    one_of: Optional[Tuple[Any, ...]] = None
    #: (min, max) characters of a string or elements of an array; max None: no bound
    size: Optional[Tuple[int, Optional[int]]] = None
    validate: Optional[Validator] = None
    on_change: Sequence[Callable[[], Any]] = ()


def _listed(values: Sequence[Any]) -> str:
    return ', '.join(repr(v) for v in values)


def rule_problem(rule: ParameterRule, value: Any) -> Optional[str]:
    """Return why a value breaks the rule's one_of or size, None if it does not."""
    scalar = isinstance(value, str) or not hasattr(value, '__iter__')
    if not scalar:
        # rclpy gives arrays as array.array, bytes as a list of one-byte bytes
        value = [v[0] if isinstance(v, bytes) else v for v in value]
    if rule.one_of is not None:
        if scalar:
            if value not in rule.one_of:
                return f'{value!r} is not one of {_listed(rule.one_of)}'
        else:
            stray = [v for v in value if v not in rule.one_of]
            if stray:
                return f'element {stray[0]!r} is not one of {_listed(rule.one_of)}'
    if rule.size is not None:
        low, high = rule.size
        unit = 'characters' if isinstance(value, str) else 'elements'
        if len(value) < low:
            return f'{value!r} has {len(value)} {unit}, fewer than {low}'
        if high is not None and len(value) > high:
            return f'{value!r} has {len(value)} {unit}, more than {high}'
    return None
