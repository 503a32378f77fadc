# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Turn the checked data of one model file into typed models."""

from __future__ import annotations

import ast
import math
import textwrap
from typing import Any, Callable, Iterable, TypeVar

from colcon_robmosys.errors import Diagnostic, Location
from colcon_robmosys.model import names
from colcon_robmosys.model.fieldtypes import (
    parse_field_type, parse_interface, TypeNameError, value_problem)
from colcon_robmosys.model.loader import LoadedFile, NodePath
from colcon_robmosys.model.types import (
    Action, Activity, CommunicationObject, Component, Connection, Constant,
    Event, Field, FieldType, Function, Instance, Language,
    LIFECYCLE_TRANSITIONS, Maintainer, ModelFile, PackageInfo, Parameter,
    ParameterRange, Pattern, PATTERN_INTERFACE, Port, PortRef, QoS, Query,
    Role, ServiceDefinition, Structure, System)

T = TypeVar('T')

DEFAULT_VERSION = '0.1.0'

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


class FileBuilder:
    """Build the typed models of one loaded, structurally valid file."""

    def __init__(self, loaded: LoadedFile) -> None:
        self.loaded = loaded
        self.diagnostics: list[Diagnostic] = []

    def error(self, path: NodePath, message: str, *, key: bool = False) -> None:
        """Record a problem at the node of that path."""
        self.diagnostics.append(
            Diagnostic(self.loaded.location(path, key=key), message))

    def at(self, path: NodePath, *, key: bool = False) -> Location:
        """Return the location of a node."""
        return self.loaded.location(path, key=key)

    def check_identifier(self, path: NodePath, what: str, name: str) -> None:
        """Report a name that is not a usable identifier."""
        problem = names.identifier_problem(name)
        if problem:
            self.error(path, f"{what} '{name}' {problem}", key=True)

    def build(self) -> ModelFile:
        """Return the typed models of the file."""
        data = self.loaded.data
        defaults = data.get('defaults', {})
        return ModelFile(
            path=str(self.loaded.path),
            service_definitions=tuple(
                self._service_definition(('service_definitions', i), raw,
                                         defaults)
                for i, raw in enumerate(data.get('service_definitions', []))),
            components=tuple(
                self._component(('components', i), raw, defaults)
                for i, raw in enumerate(data.get('components', []))),
            systems=tuple(
                self._system(('systems', i), raw, defaults)
                for i, raw in enumerate(data.get('systems', []))),
        )

    # package metadata ---------------------------------------------------

    def _info(self, path: NodePath, raw: dict, defaults: dict,
              kind: str) -> PackageInfo:
        name = raw['package']
        problem = names.package_problem(name)
        if problem:
            self.error(path + ('package',), f"package '{name}' {problem}")
        maintainers = raw.get('maintainers', defaults.get('maintainers'))
        license_ = raw.get('license', defaults.get('license'))
        if not maintainers:
            self.error(path, f"{kind} '{name}' lacks 'maintainers' (set them "
                       "in the model or in the file's 'defaults')")
        if not license_:
            self.error(path, f"{kind} '{name}' lacks 'license' (set it in the "
                       "model or in the file's 'defaults')")
        return PackageInfo(
            name=name,
            description=raw.get('description', '').strip() or
            f'The {kind} {name}, generated from a RobMoSys model.',
            version=raw.get('version', defaults.get('version',
                                                    DEFAULT_VERSION)),
            license=license_ or '',
            maintainers=tuple(Maintainer(m['name'], m['email'])
                              for m in maintainers or ()),
            depends=tuple(raw.get('depends', ())),
            model_file=str(self.loaded.path),
            location=self.at(path + ('package',)),
        )

    # service definitions ------------------------------------------------

    def _service_definition(self, path: NodePath, raw: dict,
                            defaults: dict) -> ServiceDefinition:
        info = self._info(path, raw, defaults, 'service definition')
        package = info.name
        seen: dict[str, str] = {}

        def named(section: str, name: str) -> None:
            if not names.INTERFACE_TYPE_RE.match(name):
                self.error(path + (section, name),
                           f"'{name}' is not a valid interface name: "
                           'CamelCase, starting with a capital letter',
                           key=True)
            if name in seen:
                self.error(path + (section, name),
                           f"'{name}' is already defined in {seen[name]}",
                           key=True)
            seen[name] = section

        objects = []
        for name, body in raw.get('communication_objects', {}).items():
            named('communication_objects', name)
            objects.append(CommunicationObject(
                name, self._structure(
                    path + ('communication_objects', name), body, package),
                self.at(path + ('communication_objects', name), key=True)))
        queries = []
        for name, body in raw.get('queries', {}).items():
            named('queries', name)
            qpath = path + ('queries', name)
            queries.append(Query(
                name, body.get('description', ''),
                self._structure(qpath + ('request',),
                                body.get('request', {}), package),
                self._structure(qpath + ('answer',),
                                body.get('answer', {}), package),
                self.at(qpath, key=True)))
        actions = []
        for name, body in raw.get('actions', {}).items():
            named('actions', name)
            apath = path + ('actions', name)
            goal, result, feedback = (
                self._structure(apath + (part,), body.get(part, {}), package)
                for part in ('goal', 'result', 'feedback'))
            actions.append(Action(
                name, body.get('description', ''), goal, result, feedback,
                self.at(apath, key=True)))
        events = []
        for name, body in raw.get('events', {}).items():
            named('events', name)
            epath = path + ('events', name)
            if 'single' in ((body.get('activation') or {}).get('fields') or
                            {}):
                self.error(epath + ('activation', 'fields', 'single'),
                           f"event '{name}': the activation field 'single' "
                           'is reserved: it carries the mode of an '
                           'activation (single or continuous)', key=True)
            events.append(Event(
                name, body.get('description', ''),
                self._structure(epath + ('activation',),
                                body.get('activation', {}), package),
                self._structure(epath + ('event',), body.get('event', {}),
                                package),
                self.at(epath, key=True)))
        if not (objects or queries or actions or events):
            self.error(path, f"service definition '{package}' defines no "
                       'communication object, query, action or event')
        return ServiceDefinition(info, tuple(objects), tuple(queries),
                                 tuple(actions), tuple(events))

    def _field_type(self, path: NodePath, text: str, package: str,
                    what: str) -> FieldType | None:
        try:
            return parse_field_type(text, package)
        except TypeNameError as exc:
            self.error(path, f'{what}: {exc}')
            return None

    def _structure(self, path: NodePath, raw: dict | None,
                   package: str) -> Structure:
        raw = raw or {}
        fields = []
        for name, spec in raw.get('fields', {}).items():
            fpath = path + ('fields', name)
            if not names.FIELD_RE.match(name):
                self.error(fpath, f"field '{name}' is not a valid field name: "
                           'lower case letters, digits and single '
                           'underscores, starting with a letter', key=True)
            elif name in names.CPP_KEYWORDS or name in names.PYTHON_KEYWORDS:
                self.error(fpath, f"field '{name}' is a C++ or Python keyword",
                           key=True)
            if isinstance(spec, str):
                spec = {'type': spec}
                tpath = fpath
            else:
                tpath = fpath + ('type',)
            field_type = self._field_type(tpath, spec['type'], package,
                                          f"field '{name}'")
            default = spec.get('default')
            if field_type is not None and 'default' in spec:
                problem = value_problem(field_type, default)
                if problem:
                    self.error(fpath + ('default',),
                               f"field '{name}': {problem}")
            if field_type is not None:
                fields.append(Field(name, field_type, default,
                                    spec.get('comment', ''),
                                    self.at(fpath, key=True)))
        constants = []
        for name, spec in raw.get('constants', {}).items():
            cpath = path + ('constants', name)
            if not names.CONSTANT_RE.match(name):
                self.error(cpath, f"constant '{name}' is not a valid constant "
                           'name: upper case letters, digits and single '
                           'underscores, starting with a letter', key=True)
            field_type = self._field_type(cpath + ('type',), spec['type'],
                                          package, f"constant '{name}'")
            if field_type is None:
                continue
            if field_type.message is not None or field_type.array is not None:
                self.error(cpath + ('type',), f"constant '{name}' must have a "
                           'primitive, non-array type')
                continue
            problem = value_problem(field_type, spec['value'])
            if problem:
                self.error(cpath + ('value',), f"constant '{name}': {problem}")
            constants.append(Constant(name, field_type, spec['value'],
                                      spec.get('comment', ''),
                                      self.at(cpath, key=True)))
        return Structure(raw.get('description', ''), tuple(fields),
                         tuple(constants))

    # components ---------------------------------------------------------

    def _component(self, path: NodePath, raw: dict,
                   defaults: dict) -> Component:
        info = self._info(path, raw, defaults, 'component')
        name = raw['name']
        self.check_identifier(path + ('name',), 'component name', name)
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
                               _choices(function_names))

        activities = []
        for aname, body in raw.get('activities', {}).items():
            apath = path + ('activities', aname)
            self.check_identifier(apath, 'activity name', aname)
            period, trigger = body.get('period'), body.get('trigger')
            if (period is None) == (trigger is None):
                which = 'not both' if period is not None else 'has neither'
                self.error(apath, f"activity '{aname}' needs either 'period' "
                           f"(periodic) or 'trigger' (a port), {which}",
                           key=True)
            if trigger is not None and trigger not in port_by_name:
                self.error(apath + ('trigger',),
                           f"activity '{aname}' is triggered by unknown "
                           f"port '{trigger}'{_choices(port_by_name)}")
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
        self._check_member_names(path, ports, functions, activities,
                                 parameters)
        return Component(info, name, language, ports, tuple(activities),
                         functions, parameters, tuple(lifecycle),
                         self.at(path + ('name',)))

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
        for parameter in parameters:
            self.check_identifier(path + ('parameters', parameter.name),
                                  'parameter name', parameter.name)

    def _port(self, path: NodePath, name: str, raw: dict) -> Port:
        self.check_identifier(path, 'port name', name)
        pattern, role = Pattern(raw['pattern']), Role(raw['role'])
        kind = PATTERN_INTERFACE[pattern]
        try:
            type_ = parse_interface(raw['type'], kind)
        except TypeNameError as exc:
            self.error(path + ('type',), f"port '{name}': {exc}")
            type_ = parse_interface(_strip_kind(raw['type']), kind)
        qos_raw = raw.get('qos', {})
        if qos_raw and pattern in (Pattern.QUERY, Pattern.ACTION):
            self.error(path + ('qos',), f"port '{name}': {pattern.value} ports "
                       'use the QoS of ROS 2 services and actions; '
                       "'qos' applies to push, send and event ports")
        qos = QoS(**{k.replace('-', '_'): v for k, v in qos_raw.items()})
        if qos.history == 'keep_all' and qos.depth is not None:
            self.error(path + ('qos', 'depth'), f"port '{name}': 'depth' has no "
                       "meaning with history 'keep_all'")
        return Port(name, pattern, role, type_, qos,
                    raw.get('description', ''), self.at(path, key=True))

    def _function(self, path: NodePath, name: str, raw: dict | None,
                  language: Language) -> Function:
        self.check_identifier(path, 'function name', name)
        if name in names.NODE_MEMBERS:
            self.error(path, f"function name '{name}' would hide a member of "
                       'the lifecycle node class', key=True)
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

    def _parameter(self, path: NodePath, name: str, raw: dict) -> Parameter:
        type_name = raw['type']
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
        return Parameter(
            name, type_name, freeze_parameter_value(type_name, default),
            raw.get('description', ''), raw.get('read_only', False), range_,
            self.at(path, key=True))

    # systems ------------------------------------------------------------

    def _system(self, path: NodePath, raw: dict, defaults: dict) -> System:
        info = self._info(path, raw, defaults, 'system')
        name = raw.get('name') or _camel(info.name)
        if 'name' in raw:
            self.check_identifier(path + ('name',), 'system name', name)
        instances = []
        for iname, body in raw['instances'].items():
            ipath = path + ('instances', iname)
            self.check_identifier(ipath, 'instance name', iname)
            namespace = body.get('namespace', '')
            if namespace and not namespace.startswith('/'):
                namespace = '/' + namespace
            parameters = tuple(body.get('parameters', {}).items())
            instances.append(Instance(
                iname, body['component'], namespace.rstrip('/'), parameters,
                body.get('activate', True), tuple(body.get('after', ())),
                body.get('description', ''), self.at(ipath, key=True),
                tuple(self.at(ipath + ('parameters', n), key=True)
                      for n, _ in parameters)))
        connections = []
        for index, body in enumerate(raw.get('connections', [])):
            cpath = path + ('connections', index)

            def ref(end: str) -> PortRef:
                instance, port = body[end].split('.')
                return PortRef(instance, port, self.at(cpath + (end,)))

            connections.append(Connection(ref('from'), ref('to'),
                                          body.get('topic'),
                                          self.at(cpath, key=True)))
        return System(info, name, tuple(instances), tuple(connections),
                      self.at(path + ('package',)))


def _camel(package: str) -> str:
    return ''.join(part.capitalize() for part in package.split('_'))


def _strip_kind(text: str) -> str:
    parts = text.split('/')
    return f'{parts[0]}/{parts[-1]}'


def _choices(known: Iterable[str]) -> str:
    if not known:
        return ' (none is defined)'
    return f" (known: {', '.join(sorted(known))})"
