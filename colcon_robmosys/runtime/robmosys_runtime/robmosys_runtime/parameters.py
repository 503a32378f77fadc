# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The rules of a component's parameters beyond their descriptors, and what runs on a change.

ROS 2 checks a parameter's type, range and read-only flag itself (the
ParameterDescriptor); a parameter's other rules are checked here, in the
node's on-set-parameters callback: the values it may take (``one_of``), its
size (characters of a string, elements of an array), and the function of the
component that validates it. A value that breaks one is refused with the
reason (SetParametersResult successful=false), at start too: a parameter
file's value that breaks a rule stops the node. The component's functions run
after an accepted change (``on_change``) see the new value.

The words of the reasons are those of colcon-robmosys's own checks of models.
"""

from __future__ import annotations

import re
import traceback
from typing import Any, Dict, List, Optional, Sequence

from rcl_interfaces.msg import SetParametersResult
from rclpy.node import Node
from rclpy.parameter import Parameter
from robmosys_runtime.rules import ParameterRule, rule_problem, Validator

__all__ = ['map_entries', 'ParameterRule', 'ParameterRules', 'rule_problem', 'Validator']


class ParameterRules:
    """
    The rules of a node's parameters, checked in its on-set-parameters callback.

    Create it before the parameters are declared, so that a value given at
    start breaks no rule either, and call :meth:`start` once they are. The
    component's validators run from then on (they are methods of the user's
    class, which may need what its constructor sets up), and again on
    configure over the values of the moment (:meth:`check_current`).
    """

    def __init__(self, node: Node, rules: Dict[str, ParameterRule]) -> None:
        self._node = node
        self._rules = dict(rules)
        self._started = False
        node.add_on_set_parameters_callback(self._on_set)

    def start(self) -> None:
        """Run the validators on every change from now on, and the on_change functions."""
        self._started = True
        self._node.add_post_set_parameters_callback(self._after_set)

    def add(self, name: str, rule: ParameterRule) -> None:
        """Add the rule of a parameter declared later (one of a mapped group's)."""
        self._rules[name] = rule

    def problem(self, name: str, value: Any) -> Optional[str]:
        """Return why a parameter may not take a value: its rules, then its validator."""
        rule = self._rules.get(name)
        if rule is None:
            return None
        try:
            problem = rule_problem(rule, value)
        except TypeError:
            return None  # a value of another type: the descriptor refuses it
        if problem is None and rule.validate is not None and self._started:
            problem = rule.validate(value) or None
        return None if problem is None else f"parameter '{name}': {problem}"

    def check_current(self) -> None:
        """Raise ValueError if a current value is refused (on configure)."""
        for name in self._rules:
            problem = self.problem(name, self._node.get_parameter(name).value)
            if problem is not None:
                raise ValueError(problem)

    def _on_set(self, parameters: List[Parameter]) -> SetParametersResult:
        for parameter in parameters:
            try:
                problem = self.problem(parameter.name, parameter.value)
            except Exception as error:  # noqa: B902 - a failing validator refuses the value
                problem = f"parameter '{parameter.name}': its validator failed: {error!r}"
            if problem is not None:
                return SetParametersResult(successful=False, reason=problem)
        return SetParametersResult(successful=True)

    def _after_set(self, parameters: List[Parameter]) -> None:
        for parameter in parameters:
            rule = self._rules.get(parameter.name)
            for function in rule.on_change if rule is not None else ():
                try:
                    function()
                except Exception:  # noqa: B902 - a failing function must not stop the node
                    self._node.get_logger().error(
                        f'on_change of {parameter.name} failed:\n' + traceback.format_exc())


#: an entry of an array that parameters are repeated for: one part of a parameter name
_ENTRY = re.compile(r'(?!.*__)[A-Za-z][A-Za-z0-9_]*\Z')


def map_entries(node: Node, array: str, patterns: Sequence[str]) -> List[str]:
    """
    Return the entries of an array parameter that mapped parameters are repeated for.

    Each entry is one part of a parameter name, listed once, and none of the
    names it gives (``patterns``, ``{}`` for the entry) is a parameter the node
    has already; ValueError says which is not, in colcon-robmosys's words.
    """
    entries: List[str] = list(node.get_parameter(array).value or ())
    seen = set()
    for entry in entries:
        problem = None
        if not _ENTRY.match(entry):
            problem = (f'entry {entry!r} is not a parameter name part (a letter, then '
                       'letters, digits and single underscores)')
        elif entry in seen:
            problem = f'entry {entry!r} is listed twice'
        else:
            clash = next((p.format(entry) for p in patterns
                          if node.has_parameter(p.format(entry))), None)
            if clash is not None:
                problem = (f"entry {entry!r} gives the parameter '{clash}', which the "
                           'component has')
        if problem is not None:
            raise ValueError(f"parameter '{array}': {problem}")
        seen.add(entry)
    return entries


def required_set(node: Node, names: Sequence[str]) -> bool:
    """Tell whether each parameter declared without a value has one; log each that has none."""
    unset = [n for n in names if node.get_parameter_or(n).type_ == Parameter.Type.NOT_SET]
    for name in unset:
        node.get_logger().error(
            f"configure failed: parameter '{name}' has no value (it has no default: set it in "
            f'a parameter file, or with -p {name}:=<value>)')
    return not unset
