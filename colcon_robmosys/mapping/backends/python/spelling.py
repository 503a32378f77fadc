# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""How Python spells a component plan: imports, types, signatures and QoS.

Nothing here decides what a port becomes (that is the port-kind table of
:mod:`colcon_robmosys.mapping.portkinds`, read through
:mod:`colcon_robmosys.mapping.component`): the tables below only spell it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import textwrap
from typing import Any, Mapping

from colcon_robmosys.mapping.backends.python.context import (
    PyActivity, PyComponent, PyFunction, PyParameter, PyPort, PyTransition)
from colcon_robmosys.mapping.common import RUNTIME_PACKAGE
from colcon_robmosys.mapping.component import (
    ComponentPlan, FunctionPlan, PortPlan)
from colcon_robmosys.mapping.context import (
    component_context, group_classes, GroupClass, ParameterRange)
from colcon_robmosys.mapping.parameters import camel, group_class_names
from colcon_robmosys.mapping.portkinds import Entity, Returns
from colcon_robmosys.mapping.qos import resolve_qos
from colcon_robmosys.mapping.userfiles import UserFolders
from colcon_robmosys.model.types import Component, InterfaceRef, Parameter, QoS

_QOS_NAMES = frozenset({'DurabilityPolicy', 'HistoryPolicy', 'LivelinessPolicy',
                        'QoSProfile', 'ReliabilityPolicy'})

_QOS = {'rclpy.qos': _QOS_NAMES}


@dataclass(frozen=True)
class PyEntity:
    """How the Python node creates the entity of a port: its row."""

    #: the method of robmosys_runtime.ComponentNode that creates it
    method: str
    #: module -> the names its code imports (an empty set: the module)
    imports: Mapping[str, frozenset[str]] = field(default_factory=dict)


#: entity -> its row, one per entity
ENTITIES = {
    Entity.PUBLISHER: PyEntity('add_publisher', _QOS),
    Entity.SUBSCRIPTION: PyEntity('add_subscription', _QOS),
    Entity.SERVICE: PyEntity('add_service'),
    Entity.CLIENT: PyEntity('add_query_client'),
    Entity.ACTION_SERVER: PyEntity('add_action_server'),
    Entity.ACTION_CLIENT: PyEntity('add_action_client'),
    Entity.EVENT_SERVER: PyEntity('add_event_server', _QOS),
    Entity.EVENT_CLIENT: PyEntity('add_event_client', _QOS),
}

#: packages the code of every component needs at run time
EXEC_DEPENDS = ('rclpy', 'lifecycle_msgs', 'rcl_interfaces', RUNTIME_PACKAGE)

#: what a function gives back -> its annotation
RETURN_TYPES = {
    Returns.NOTHING: 'None', Returns.ANSWER: '{type}.Response',
    Returns.RESULT: '{type}.Result', Returns.CONDITION: 'bool', Returns.PROBLEM: 'str',
}

#: model type -> (Python type, ParameterType name)
PARAMETER_TYPES = {
    'bool': ('bool', 'BOOL'), 'int': ('int', 'INTEGER'),
    'double': ('float', 'DOUBLE'), 'string': ('str', 'STRING'),
    'bool[]': ('list[bool]', 'BOOL_ARRAY'),
    'int[]': ('list[int]', 'INTEGER_ARRAY'),
    'double[]': ('list[float]', 'DOUBLE_ARRAY'),
    'string[]': ('list[str]', 'STRING_ARRAY'),
    'byte[]': ('bytes', 'BYTE_ARRAY'),
}

#: Modules of the Python standard library the generated code imports.
STDLIB = frozenset({'os', 'sys', 'threading', 'time', 'traceback'})

#: the longest line a list of methods is written on (ament_flake8: 99)
_LINE = 99


def import_lines(modules: Mapping[str, set[str] | frozenset[str]]) -> tuple[str, ...]:
    """Write ``from module import names`` lines, sorted as flake8 wants.

    An empty set of names stands for ``import module``. The standard
    library comes first, then a blank line, then the other modules.
    """
    groups: list[list[str]] = [[], []]
    for module in sorted(modules, key=str.lower):
        lines = groups[0 if module in STDLIB else 1]
        if not modules[module]:
            lines.append(f'import {module}')
            continue
        names = ', '.join(sorted(modules[module], key=str.lower))
        line = f'from {module} import {names}'
        if len(line) > 99:
            items = ''.join(f'    {n},\n' for n in
                            sorted(modules[module], key=str.lower))
            line = f'from {module} import (\n{items})'
        lines.append(line)
    if groups[0] and groups[1]:
        return tuple(groups[0] + [''] + groups[1])
    return tuple(groups[0] + groups[1])


def _add(modules: dict[str, set[str]], module: str, names: frozenset[str] | set[str]) -> None:
    modules.setdefault(module, set()).update(names)


def _node_imports(names: dict[InterfaceRef, str], plan: ComponentPlan,
                  uses_duration: bool) -> tuple[str, ...]:
    # the lifecycle bookkeeping is the runtime's ComponentNode
    modules: dict[str, set[str]] = {'robmosys_runtime': {'ComponentNode'}}
    for ref, local in names.items():
        alias = '' if local == ref.name else f' as {local}'
        _add(modules, f'{ref.package}.{ref.kind.value}', {f'{ref.name}{alias}'})
    if any(_rule(p) for p in plan.parameters):
        _add(modules, 'robmosys_runtime', {'ParameterRule', 'ParameterRules'})
    if any(p.for_each for p in plan.parameters):
        _add(modules, 'robmosys_runtime', {'map_entries'})
    if plan.parameters:
        _add(modules, 'rcl_interfaces.msg', {'ParameterDescriptor'})
        if any(p.required for p in plan.parameters):
            # declared by type, without a value, which configure needs
            _add(modules, 'rclpy.parameter', {'Parameter'})
            _add(modules, 'rclpy.lifecycle', {'LifecycleState', 'TransitionCallbackReturn'})
            _add(modules, 'robmosys_runtime', {'required_set'})
        for parameter in plan.parameters:
            if parameter.range is not None:
                _add(modules, 'rcl_interfaces.msg', {
                    'IntegerRange' if parameter.type == 'int'
                    else 'FloatingPointRange'})
    for entity in plan.entities:
        for module, imported in ENTITIES[entity].imports.items():
            _add(modules, module, imported)
    if uses_duration:
        modules['rclpy.duration'] = {'Duration'}
    return import_lines(modules)


def methods(names: tuple[str, ...], indent: int, prefix: int = 0) -> str:
    """Write the list of the methods ``self.<name>``, one a line if it is long.

    The list starts after ``indent`` spaces and ``prefix`` more characters,
    and is followed by two (a parenthesis or a comma, and another).
    """
    text = '[' + ', '.join(f'self.{n}' for n in names) + ']'
    if indent + prefix + len(text) + 2 <= _LINE:
        return text
    pad = ' ' * (indent + 4)
    return '[\n' + ''.join(f'{pad}self.{n},\n' for n in names) + ' ' * indent + ']'


def _python_names(refs: list[InterfaceRef]) -> dict[InterfaceRef, str]:
    """Name each interface type in Python; alias only clashing names."""
    by_name: dict[str, set[str]] = {}
    for ref in refs:
        by_name.setdefault(ref.name, set()).add(ref.package)
    return {ref: ref.name if len(by_name[ref.name]) == 1
            else f'{ref.package}_{ref.name}' for ref in refs}


def qos_expression(qos: QoS) -> str:
    """Return the rclpy expression of a port's QoS, every policy explicit."""
    resolved = resolve_qos(qos)
    args = [f'history=HistoryPolicy.{resolved.history.upper()}']
    if resolved.history == 'keep_last':
        args.append(f'depth={resolved.depth}')
    if resolved.adaptive and qos.reliability is None:
        args.append('reliability=ReliabilityPolicy.BEST_AVAILABLE')
    else:
        args.append(
            f'reliability=ReliabilityPolicy.{resolved.reliability.upper()}')
    if resolved.adaptive and qos.durability is None:
        args.append('durability=DurabilityPolicy.BEST_AVAILABLE')
    else:
        args.append(
            f'durability=DurabilityPolicy.{resolved.durability.upper()}')
    for name in ('deadline', 'lifespan', 'liveliness_lease_duration'):
        seconds = getattr(resolved, name)
        if seconds is not None:
            args.append(f'{name}=Duration(seconds={seconds!r})')
    args.append(
        f'liveliness=LivelinessPolicy.{resolved.liveliness.upper()}')
    return 'QoSProfile(\n' + ''.join(f'    {a},\n' for a in args) + ')'


def _default_body(returns: str) -> str:
    """Return what an unimplemented function of the skeleton returns."""
    if returns == 'bool':
        return 'return True'
    if returns.endswith('.Response'):
        return 'return response'
    if returns == 'str':
        return "return ''"
    if returns != 'None':
        return f'return {returns}()'
    return ''


def _doc(summary: str, text: str) -> str:
    return f'{summary}\n\n{text}' if text.strip() else summary


def _class_doc(cls: str, description: str) -> str:
    """Return the docstring of the node class.

    The first line of the model's description is its summary when it fits
    on the line of the class docstring; pep257 wants a one-line summary and
    ament_flake8 lines of at most 99 characters.
    """
    lines = description.strip().splitlines()
    # 4 spaces, two triple quotes and the period pep257 may add
    if lines and len(lines[0].replace('\\', '\\\\')) + 11 <= 99:
        return description
    return _doc(f'The lifecycle node of the component {cls}.', description)


def _port(port: PortPlan, type_name: str) -> PyPort:
    # a port whose activity has one function (the one that answers) hands
    # over that method, others the list of the activity's methods
    run = f'self.{port.functions[0]}' if port.kind.one_function and port.functions \
        else methods(port.functions, 12, len(repr(port.activity)) + 2)
    return PyPort(
        name=port.name, description=port.description, entity=port.entity,
        type=type_name, type_full=str(port.type),
        # query and action ports use the QoS of services and actions
        qos=qos_expression(port.qos) if port.kind.topic_qos else None,
        qos_const=f'QOS_{port.name.upper()}', activity=port.activity,
        functions=port.functions, method=ENTITIES[port.kind.entity].method, run=run)


def _range(parameter: Parameter) -> ParameterRange | None:
    if parameter.range is None:
        return None
    integer = parameter.type == 'int'
    cast = int if integer else float
    return ParameterRange(
        'integer_range' if integer else 'floating_point_range',
        'IntegerRange' if integer else 'FloatingPointRange',
        repr(cast(parameter.range.start)), repr(cast(parameter.range.end)),
        repr(cast(parameter.range.step)))


def _parameter(parameter: Parameter) -> PyParameter:
    py_type, ros_type = PARAMETER_TYPES[parameter.type]
    default: Any = parameter.default
    if isinstance(default, tuple):
        default = list(default)
    if parameter.type == 'byte[]':
        default = [bytes([b]) for b in default]
    return PyParameter(
        name=parameter.name, py_type=py_type, ros_type=ros_type,
        default=default, description=parameter.description,
        # pep257 wants an imperative summary; the model's text follows it
        doc=_doc(f'Return the parameter {parameter.name}.',
                 parameter.description),
        read_only=parameter.read_only, range=_range(parameter),
        attr=parameter.path[-1], rule=_rule(parameter), for_each=parameter.for_each or '',
        pattern=parameter.ros_name('{}') if parameter.for_each else '',
        required=parameter.required)


def _rule(parameter: Parameter) -> tuple[str, ...]:
    """Return the arguments of a parameter's ParameterRule, none without rules."""
    args = []
    if parameter.one_of is not None:
        args.append(f'one_of={parameter.one_of!r}')
    if parameter.size is not None:
        args.append(f'size=({parameter.size.min}, {parameter.size.max})')
    if parameter.validate:
        args.append(f'validate=self.{parameter.validate}')
    if parameter.on_change:
        args.append(f'on_change={methods(parameter.on_change, 20, 10)}')
    return tuple(args)


def _function(function: FunctionPlan,
              type_names: dict[InterfaceRef, str]) -> PyFunction:
    code = None
    if function.code is not None:
        code = textwrap.indent(
            textwrap.dedent(function.code).strip('\n'), ' ' * 8) or \
            ' ' * 8 + 'pass'
    type_ = type_names[function.port.type] if function.port else ''
    returns = RETURN_TYPES[function.returns].format(type=type_)
    return PyFunction(
        name=function.name, args=function.arguments, code=code,
        returns=returns, default_return=_default_body(returns),
        description=_doc(f'Run the function {function.name} of the model.',
                         function.description))


def spell_python(component: Component, plan: ComponentPlan,
                 folders: UserFolders) -> PyComponent:
    """Spell the plan of a Python component.

    :param folders: where the user's files are
    """
    package, cls = plan.package, plan.cls
    type_names = _python_names([p.type for p in plan.ports])
    ports = tuple(_port(p, type_names[p.type]) for p in plan.ports)
    functions = tuple(_function(f, type_names) for f in plan.functions)
    user_functions = tuple(f for f in functions if f.code is None)
    uses_duration = 'Duration(' in ''.join(p.qos or '' for p in ports)
    node_module = plan.node_module
    # the user's file imports the types its signatures name
    used = {f.returns.split('.')[0] for f in user_functions}
    impl_modules: dict[str, set[str]] = {f'{package}.{cls}': {cls}}
    for ref, local in type_names.items():
        if local in used:
            alias = '' if local == ref.name else f' as {local}'
            _add(impl_modules, f'{ref.package}.{ref.kind.value}',
                 {f'{ref.name}{alias}'})
    exec_depends = EXEC_DEPENDS + plan.depends
    spelled = {p.name: _parameter(p) for p in plan.parameters}
    return component_context(
        PyComponent, component, plan, folders,
        xml={'buildtool': ['ament_cmake', 'ament_cmake_python'], 'exec_': exec_depends,
             'test': ['ament_cmake_pytest']},
        node_module=node_module,
        description=_class_doc(cls, plan.description),
        node_imports=_node_imports(type_names, plan, uses_duration),
        main_imports=import_lines({
            'robmosys_runtime': {'run'},
            f'{package}.{node_module}': {plan.node_cls}}),
        impl_imports=import_lines(impl_modules),
        ports=ports,
        activities=tuple(PyActivity(
            name=a.name, period=a.period, functions=a.functions, description=a.description,
            run=methods(a.functions, 8, len(f'self.add_periodic({a.name!r}, {a.period}, ')))
                         for a in plan.activities if a.period is not None),
        activity_names=tuple(a.name for a in plan.activities),
        functions=functions, user_functions=user_functions,
        parameters=tuple(spelled.values()),
        parameter_groups=group_classes(
            GroupClass, plan.parameters, spelled,
            lambda groups: group_class_names(groups, f'{cls}Parameters'),
            lambda path: f'Typed access to the parameters {".".join(path)}.* of {cls}.'
            if path else f'Typed access to the current parameter values of {cls}.',
            lambda path: f'{cls}Parameters{camel(path)}Entry'),
        transitions=tuple(PyTransition(t, methods(tuple(f), 16, len(repr(t)) + 2))
                          for t, f in plan.lifecycle if f),
        depends=plan.depends, exec_depends=exec_depends)
