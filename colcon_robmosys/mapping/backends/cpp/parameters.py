# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""How C++ spells parameters: declarations, accessors in nested groups, rules."""

from __future__ import annotations

from typing import Any

from colcon_robmosys.mapping.backends.cpp.context import CppParameter, CppParameterGroup
from colcon_robmosys.mapping.context import group_classes, ParameterRange
from colcon_robmosys.mapping.literals import cpp_str, split_literal
from colcon_robmosys.mapping.parameters import camel, group_class_names, ParameterGroup
from colcon_robmosys.model.types import Parameter

#: model type -> (C++ type, ParameterValue accessor)
PARAMETER_TYPES = {
    'bool': ('bool', 'as_bool'),
    'int': ('int64_t', 'as_int'),
    'double': ('double', 'as_double'),
    'string': ('std::string', 'as_string'),
    'bool[]': ('std::vector<bool>', 'as_bool_array'),
    'int[]': ('std::vector<int64_t>', 'as_integer_array'),
    'double[]': ('std::vector<double>', 'as_double_array'),
    'string[]': ('std::vector<std::string>', 'as_string_array'),
    'byte[]': ('std::vector<uint8_t>', 'as_byte_array'),
}


#: model type -> rclcpp::ParameterType (a parameter declared without a value)
PARAMETER_TYPE_NAMES = {
    'bool': 'PARAMETER_BOOL', 'int': 'PARAMETER_INTEGER', 'double': 'PARAMETER_DOUBLE',
    'string': 'PARAMETER_STRING', 'bool[]': 'PARAMETER_BOOL_ARRAY',
    'int[]': 'PARAMETER_INTEGER_ARRAY', 'double[]': 'PARAMETER_DOUBLE_ARRAY',
    'string[]': 'PARAMETER_STRING_ARRAY', 'byte[]': 'PARAMETER_BYTE_ARRAY',
}


def cpp_value(value: Any, type_: str) -> str:
    """Write a parameter value as a C++ expression of its type."""
    if type_ == 'bool':
        return 'true' if value else 'false'
    if type_ == 'int':
        return f'INT64_C({int(value)})'
    if type_ == 'byte':
        return f'UINT8_C({int(value)})'
    if type_ == 'double':
        return repr(float(value))
    return f'std::string({cpp_str(value)})'


def string_lines(target: str, text: str, width: int = 72) -> list[str]:
    """Assign a string literal to target, split into lines cpplint accepts.

    Adjacent literals are joined by the compiler (see split_literal); no
    literal is wider than width.
    """
    literals = split_literal(text, width, cpp_str)
    if len(literals) <= 1:
        return [f'{target} = {cpp_str(text)};']
    return [f'{target} ='] + [f'  {literal}' for literal in literals[:-1]] + \
        [f'  {literals[-1]};']


def _default_lines(parameter: Parameter, ctype: str) -> list[str]:
    """Return the statements that set ``default_value`` to the default."""
    default = parameter.default
    if isinstance(default, (tuple, list)):
        element = parameter.type[:-2]
        return [f'{ctype} default_value;'] + [
            f'default_value.push_back({cpp_value(v, element)});'
            for v in default]
    if isinstance(default, str):
        return [f'{ctype} default_value;'] + string_lines('default_value', default)
    return [f'const {ctype} default_value = '
            f'{cpp_value(parameter.default, parameter.type)};']


def _range(parameter: Parameter) -> ParameterRange | None:
    if parameter.range is None:
        return None
    integer = parameter.type == 'int'

    def cast(value: float) -> str:
        return f'INT64_C({int(value)})' if integer else repr(float(value))

    return ParameterRange(
        'integer_range' if integer else 'floating_point_range',
        'rcl_interfaces::msg::IntegerRange' if integer
        else 'rcl_interfaces::msg::FloatingPointRange',
        cast(parameter.range.start), cast(parameter.range.end),
        cast(parameter.range.step))


def cpp_parameter(parameter: Parameter, cls: str) -> CppParameter:
    """Spell a parameter: its declaration, its accessor and its rule."""
    ctype, accessor = PARAMETER_TYPES[parameter.type]
    return CppParameter(
        name=parameter.name, cpp_type=ctype, accessor=accessor,
        default_lines=tuple(_default_lines(parameter, ctype)),
        description_lines=tuple(string_lines('descriptor.description',
                                             parameter.description)),
        doc=parameter.description or f'The parameter {parameter.name}.',
        read_only='true' if parameter.read_only else 'false',
        range=_range(parameter), attr=parameter.path[-1],
        rule=tuple(_rule_lines(parameter, cls, ctype)), for_each=parameter.for_each or '',
        pattern=parameter.ros_name('{}') if parameter.for_each else '',
        required=parameter.required, parameter_type=PARAMETER_TYPE_NAMES[parameter.type])


def _rule_lines(parameter: Parameter, cls: str, ctype: str) -> list[str]:
    """Return the statements that fill ``rule``, a ParameterRule; none without rules."""
    lines = []
    if parameter.one_of is not None:
        element = parameter.type.removesuffix('[]')
        lines.append('rule.one_of.emplace();')
        for value in parameter.one_of:
            if isinstance(value, str):
                lines += string_lines('value', value)
                lines.append('rule.one_of->push_back(value);')
            else:
                lines.append(f'rule.one_of->push_back({cpp_value(value, element)});')
        if any(isinstance(v, str) for v in parameter.one_of):
            lines.insert(1, 'std::string value;')
    if parameter.size is not None:
        if parameter.size.min:
            lines.append(f'rule.min_size = {parameter.size.min}u;')
        if parameter.size.max is not None:
            lines.append(f'rule.max_size = {parameter.size.max}u;')
    if parameter.validate:
        lines += ['rule.validate = std::bind(',
                  f'  &{cls}::{parameter.validate}, this, std::placeholders::_1);']
    for function in parameter.on_change:
        lines.append(f'rule.on_change.push_back(std::bind(&{cls}::{function}, this));')
    return lines


def cpp_parameter_groups(parameters: tuple[Parameter, ...],
                         spelled: tuple[CppParameter, ...]) -> tuple[CppParameterGroup, ...]:
    """Return the classes of the groups of parameters, a subgroup first, Parameters last."""
    def names(groups: tuple[ParameterGroup, ...]) -> dict[tuple[str, ...], str]:
        named = {path: f'{name}Group' for path, name in group_class_names(groups, '').items()}
        named[()] = ''
        return named

    return group_classes(
        CppParameterGroup, parameters, {p.name: p for p in spelled}, names,
        lambda path: f'Typed access to the parameters {".".join(path)}.*.' if path else '',
        lambda path: f'{camel(path)}Entry')
