# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Build the components of a file: ports, activities, functions, parameters."""

from __future__ import annotations

import ast
from functools import partial
import textwrap
from typing import Any

from colcon_robmosys.errors import Diagnostic, Location
from colcon_robmosys.model import schema_messages
from colcon_robmosys.model.build_base import choices
from colcon_robmosys.model.build_mapped import MappedParameterBuilder
from colcon_robmosys.model.fieldtypes import parse_interface, TypeNameError
from colcon_robmosys.model.loader import NodePath, RawData
from colcon_robmosys.model.parameters import (
    freeze_parameter_value, parameter_value_problem, PARAMETER_ZERO, rule_problem)
from colcon_robmosys.model.types import (
    Activity, Component, Executor, Function, Language, LIFECYCLE_TRANSITIONS, Parameter,
    ParameterRange, ParameterSize, Pattern, PATTERN_INTERFACE, Port, QoS, Role)


class ComponentBuilder(MappedParameterBuilder):
    """Components, with the rules a single component has to follow."""

    def component(self, path: NodePath, raw: RawData,
                  defaults: RawData) -> Component:
        """Build the component at the path of the file."""
        info = self._info(path, raw, defaults, 'component')
        name = raw['name']
        self.check_name(path + ('name',), 'component', name, key=False)
        language = Language(raw['language'])
        ports = tuple(self._port(path + ('ports', n), n, body)
                      for n, body in raw.get('ports', {}).items())
        functions = tuple(self._function(path + ('functions', n), n, body,
                                         language)
                          for n, body in raw.get('functions', {}).items())
        function_names = {f.name for f in functions}
        port_by_name = {p.name: p for p in ports}

        def check_functions(fpath: NodePath, listed: list[str]) -> None:
            for index, fname in enumerate(listed):
                if fname not in function_names:
                    self.error(fpath + (index,), f"unknown function '{fname}'" +
                               choices(function_names))

        activities = []
        for aname, body in raw.get('activities', {}).items():
            apath = path + ('activities', aname)
            self.check_name(apath, 'activity', aname)
            period, trigger = body.get('period'), body.get('trigger')
            if (period is None) == (trigger is None):
                which = 'not both' if period is not None else 'has neither'
                self.error(apath, f"activity '{aname}' needs either 'period' "
                           f"(periodic) or 'trigger' (a port), {which}",
                           key=True)
            if trigger is not None and trigger not in port_by_name:
                self.error(apath + ('trigger',),
                           f"activity '{aname}' is triggered by unknown "
                           f"port '{trigger}'{choices(port_by_name)}")
                trigger = None
            check_functions(apath + ('functions',), body['functions'])
            activities.append(Activity(
                aname, tuple(body['functions']), period, trigger,
                body.get('description', ''), self.at(apath, key=True),
                self.at(apath + ('trigger',)), self.at(apath + ('functions',))))
        lifecycle = []
        for transition in LIFECYCLE_TRANSITIONS:
            listed = raw.get('lifecycle', {}).get(transition)
            if listed is not None:
                check_functions(path + ('lifecycle', transition), listed)
                lifecycle.append((transition, tuple(listed)))
        parameters = tuple(self._parameter(path + ('parameters', n), n, body)
                           for n, body in raw.get('parameters', {}).items())
        for n, body in raw.get('parameters', {}).items():
            for key in ('validate', 'on_change'):
                listed, kpath = body.get(key, ()), path + ('parameters', n, key)
                if not isinstance(listed, str):
                    check_functions(kpath, listed)
                elif listed not in function_names:
                    self.error(kpath, f"unknown function '{listed}'" + choices(function_names))
        self._check_member_names(path, ports, functions, activities,
                                 parameters)
        self._check_mapped(path, parameters)
        external = raw.get('external') or {}
        for port in ports:
            if port.ros_name is not None and not external:
                self.error(path + ('ports', port.name, 'name'),
                           f"port '{port.name}': only the port of an external component "
                           'has a name of its own (a generated node uses the port name)')
        if external:
            for section in ('activities', 'functions', 'lifecycle', 'executor'):
                if raw.get(section):
                    # nothing is generated: no code of the model would run
                    self.error(path + (section,), f"external component '{name}' has no "
                               f'{section}: its node is not generated', key=True)
        return Component(info, name, language, ports, tuple(activities),
                         functions, parameters, tuple(lifecycle),
                         self.at(path + ('name',)), external.get('executable', ''),
                         bool(external.get('lifecycle', True)),
                         Executor(raw['executor']) if 'executor' in raw else None,
                         self.at(path + ('executor',)) if 'executor' in raw else None)

    def _check_member_names(
            self, path: NodePath, ports: tuple[Port, ...],
            functions: tuple[Function, ...], activities: list[Activity],
            parameters: tuple[Parameter, ...]) -> None:
        owners: dict[str, str] = {}
        for section, items in (('ports', ports), ('functions', functions),
                               ('activities', activities)):
            for item in items:
                if item.name in owners:
                    self.error(path + (section, item.name),
                               f"'{item.name}' already names a "
                               f'{owners[item.name]} of this component',
                               key=True)
                owners.setdefault(item.name, section[:-1].replace('ie', 'y'))
        groups = {'.'.join(p.path[:i]): p.name for p in parameters
                  for i in range(1, len(p.path))}
        for parameter in parameters:
            ppath = path + ('parameters', parameter.name)
            for part in parameter.path:
                # (a dotted name: each part is a name of the generated code)
                self.check_name(ppath, 'parameter', part)
            if parameter.name in groups:
                self.error(ppath, f"parameter '{parameter.name}' is also the group of "
                           f"'{groups[parameter.name]}': typed access cannot have both",
                           key=True)

    def _port(self, path: NodePath, name: str, raw: RawData) -> Port:
        self.check_name(path, 'port', name)
        pattern, role = Pattern(raw['pattern']), Role(raw['role'])
        kind = PATTERN_INTERFACE[pattern]
        try:
            type_ = parse_interface(raw['type'], kind)
        except TypeNameError as exc:
            self.error(path + ('type',), f"port '{name}': {exc}")
            type_ = parse_interface(_strip_kind(raw['type']), kind)
        qos_raw = raw.get('qos', {})
        qos = QoS(**{k.replace('-', '_'): v for k, v in qos_raw.items()})
        if qos.history == 'keep_all' and qos.depth is not None:
            self.error(path + ('qos', 'depth'), f"port '{name}': 'depth' has no "
                       "meaning with history 'keep_all'")
        return Port(name, pattern, role, type_, qos,
                    raw.get('description', ''), self.at(path, key=True),
                    self.at(path + ('qos',)) if qos_raw else None,
                    self.at(path + ('type',)), raw.get('name'))

    def _function(self, path: NodePath, name: str, raw: RawData | None,
                  language: Language) -> Function:
        self.check_name(path, 'function', name)
        raw = raw or {}
        code = raw.get('code')
        if code is not None and language is Language.PYTHON:
            self._check_python(path + ('code',), name, code)
        return Function(name, code, raw.get('description', ''),
                        self.at(path, key=True))

    def _check_python(self, path: NodePath, name: str, code: str) -> None:
        dedented = textwrap.dedent(code)
        body = textwrap.indent(dedented, '    ')
        try:
            ast.parse(f'def {name}(self, *args):\n{body or "    pass"}\n')
        except SyntaxError as exc:
            # the location of the code is that of its first line (for a
            # block scalar too); line 1 of the parsed text is the 'def'
            start = self.at(path)
            lines, kept = code.split('\n'), dedented.split('\n')
            index = min(max((exc.lineno or 2) - 2, 0), len(lines) - 1)
            column = start.column
            if exc.offset and exc.lineno and exc.lineno >= 2:
                removed = len(lines[index]) - len(kept[index])
                column += max(exc.offset - 1 - 4, 0) + removed
            self.diagnostics.append(Diagnostic(
                Location(start.path, start.line + index, column),
                f"function '{name}': Python syntax error in its code: "
                f'{exc.msg}'))

    def _parameter(self, path: NodePath, name: str, raw: RawData) -> Parameter:
        type_name, on_change = raw['type'], raw.get('on_change', ())
        default = raw.get('default', PARAMETER_ZERO[type_name])
        if 'default' in raw:
            problem = parameter_value_problem(type_name, default)
            if problem:
                self.error(path + ('default',), f"parameter '{name}': "
                           f'{problem}')
        range_ = None
        if 'range' in raw:
            rpath = path + ('range',)
            bounds = raw['range']
            start, end = bounds['from'], bounds['to']
            step = bounds.get('step', 0)
            if type_name not in ('int', 'double'):
                self.error(rpath, f"parameter '{name}': only int and double "
                           'parameters take a range')
            elif type_name == 'int' and not all(
                    isinstance(v, int) for v in (start, end, step)):
                self.error(rpath, f"parameter '{name}': the range of an int "
                           'parameter must be made of integers')
            elif start > end:
                self.error(rpath, f"parameter '{name}': the range starts "
                           f'({start}) after it ends ({end})')
            else:
                range_ = ParameterRange(start, end, step)
                if isinstance(default, (int, float)) and \
                        not isinstance(default, bool) and \
                        not start <= default <= end:
                    self.error(path + ('default',), f"parameter '{name}': the "
                               f'default {default} is out of its range '
                               f'[{start}, {end}]')
        parameter = Parameter(
            name, type_name, freeze_parameter_value(type_name, default),
            raw.get('description', ''), raw.get('read_only', False), range_,
            self.at(path, key=True), self._one_of(path, name, raw),
            self._size(path, name, raw), raw.get('validate'),
            tuple([on_change] if isinstance(on_change, str) else on_change),
            self.at(path + ('validate',)) if 'validate' in raw else None,
            self.at(path + ('on_change',)) if on_change else None,
            raw.get('for_each'), self.at(path + ('for_each',)) if 'for_each' in raw else None,
            required='default' not in raw and 'for_each' not in raw)
        if parameter.read_only and on_change:
            self.error(path + ('on_change',), f"parameter '{name}': 'on_change' has no "
                       'meaning for a read-only parameter: it never changes after start',
                       key=True)
        if 'default' in raw and (parameter.one_of or parameter.size) and \
                not parameter_value_problem(type_name, default):
            problem = rule_problem(parameter, default)
            if problem:
                self.error_in_list(path + ('default',), default, problem,
                                   f"parameter '{name}': default {problem}",
                                   partial(rule_problem, parameter))
        return parameter

    def _one_of(self, path: NodePath, name: str, raw: RawData) -> tuple[Any, ...] | None:
        if 'one_of' not in raw:
            return None
        type_name, values = raw['type'], raw['one_of']
        element = type_name.removesuffix('[]')
        if element == 'bool':
            self.error(path + ('one_of',), f"parameter '{name}': 'one_of' has no meaning "
                       f'for a {type_name} parameter (true and false are all there is)',
                       key=True)
            return None
        for index, value in enumerate(values):
            kind = _JSON_KINDS.get(element)
            if kind is not None and not _is_kind(value, kind):
                # the words of the schema, which finds this first
                self.error(path + ('one_of', index), f"parameter '{name}': item "
                           f"{index + 1} of 'one_of' must be {schema_messages.kinds(kind)}, "
                           f'not {schema_messages.describe(value)}')
                return None
            problem = parameter_value_problem(element, value) if element != 'byte' else \
                parameter_value_problem('byte[]', [value])
            if problem:
                self.error(path + ('one_of', index), f"parameter '{name}': in 'one_of', "
                           f'{problem}')
                return None
        return tuple(freeze_parameter_value(element, v) for v in values)

    def _size(self, path: NodePath, name: str, raw: RawData) -> ParameterSize | None:
        if 'size' not in raw:
            return None
        type_name, bounds = raw['type'], raw['size']
        low, high = bounds.get('min', 0), bounds.get('max')
        if type_name != 'string' and not type_name.endswith('[]'):
            self.error(path + ('size',), f"parameter '{name}': 'size' is only for string "
                       f'and array parameters (this one is {type_name})', key=True)
            return None
        if high is not None and low > high:
            self.error(path + ('size',), f"parameter '{name}': the size's min ({low}) "
                       f'is greater than its max ({high})')
            return None
        return ParameterSize(low, high)


#: element type of a parameter -> the JSON kind the schema wants of its one_of values
_JSON_KINDS = {'string': 'string', 'int': 'integer', 'double': 'number'}


def _is_kind(value: Any, kind: str) -> bool:
    if kind == 'string':
        return isinstance(value, str)
    if isinstance(value, bool):
        return False
    return isinstance(value, int) or kind == 'number' and isinstance(value, float)


def _strip_kind(text: str) -> str:
    parts = text.split('/')
    return f'{parts[0]}/{parts[-1]}'
