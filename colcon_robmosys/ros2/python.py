# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Python components become ament_cmake packages of rclpy lifecycle nodes.

The decisions live here; the templates under ``templates/component_python``
only print what this module computes.
"""

from __future__ import annotations

from pathlib import Path
import textwrap
from typing import Any

from colcon_robmosys.model.qos import resolve_qos
from colcon_robmosys.model.types import (
    Activity, Component, InterfaceRef, Parameter, Pattern, Port, QoS)
from colcon_robmosys.model.workspace import model_dependencies
from colcon_robmosys.ros2.common import (
    banner_context, ENTITIES, package_xml_context)
from colcon_robmosys.ros2.plan import FileSpec, PackagePlan, UserFile

#: The helper classes of the node module each entity needs.
HELPERS = {
    'client': 'QueryClient', 'action_client': 'ActionClientPort',
    'event_server': 'EventServer', 'event_client': 'EventClient',
}

_PARAMETER_TYPES = {
    'bool': ('bool', 'BOOL'), 'int': ('int', 'INTEGER'),
    'double': ('float', 'DOUBLE'), 'string': ('str', 'STRING'),
    'bool[]': ('list[bool]', 'BOOL_ARRAY'),
    'int[]': ('list[int]', 'INTEGER_ARRAY'),
    'double[]': ('list[float]', 'DOUBLE_ARRAY'),
    'string[]': ('list[str]', 'STRING_ARRAY'),
    'byte[]': ('bytes', 'BYTE_ARRAY'),
}


def impl_source_path(component: Component) -> str:
    """Return where the user's implementation lives, next to the model."""
    return f'src/{component.package}/{component.name}_impl.py'


def _python_names(refs: list[InterfaceRef]) -> dict[InterfaceRef, str]:
    """Name each interface type in Python; alias only clashing names."""
    by_name: dict[str, set[str]] = {}
    for ref in refs:
        by_name.setdefault(ref.name, set()).add(ref.package)
    return {ref: ref.name if len(by_name[ref.name]) == 1
            else f'{ref.package}_{ref.name}' for ref in refs}


#: Modules of the Python standard library the generated code imports.
STDLIB = frozenset({'os', 'sys', 'threading', 'time', 'traceback'})


def import_lines(modules: dict[str, set[str]]) -> list[str]:
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
        return groups[0] + [''] + groups[1]
    return groups[0] + groups[1]


def _node_imports(names: dict[InterfaceRef, str], component: Component,
                  entities: set[str], uses_duration: bool) -> list[str]:
    modules: dict[str, set[str]] = {
        'rclpy.lifecycle': {'LifecycleNode', 'LifecycleState',
                            'TransitionCallbackReturn'},
    }
    if component.ports or component.activities or component.lifecycle:
        # every piece of user code runs in a try that logs the traceback
        modules['traceback'] = set()
    for ref, local in names.items():
        alias = '' if local == ref.name else f' as {local}'
        modules.setdefault(f'{ref.package}.{ref.kind.value}', set()).add(
            f'{ref.name}{alias}')
    if component.parameters:
        modules.setdefault('rcl_interfaces.msg', set()).add(
            'ParameterDescriptor')
        for parameter in component.parameters:
            if parameter.range is not None:
                modules['rcl_interfaces.msg'].add(
                    'IntegerRange' if parameter.type == 'int'
                    else 'FloatingPointRange')
    if component.activities or entities & set(HELPERS):
        # a callback group and a lock per activity, and in the port helpers
        modules['rclpy.callback_groups'] = {'MutuallyExclusiveCallbackGroup'}
        modules['threading'] = set()
    if entities & {'publisher', 'subscription', 'event_server',
                   'event_client'}:
        modules['rclpy.qos'] = {'DurabilityPolicy', 'HistoryPolicy',
                                'LivelinessPolicy', 'QoSProfile',
                                'ReliabilityPolicy'}
    if uses_duration:
        modules['rclpy.duration'] = {'Duration'}
    if entities & {'client', 'action_client', 'event_client'}:
        modules['time'] = set()
    if entities & {'client', 'action_client', 'event_client',
                   'event_server'}:
        modules['rclpy.task'] = {'Future'}
    if entities & {'action_server', 'event_server'}:
        modules['rclpy.action'] = {'ActionServer', 'CancelResponse',
                                   'GoalResponse'}
    if entities & {'action_client', 'event_client'}:
        modules.setdefault('rclpy.action', set()).add('ActionClient')
    if 'event_client' in entities:
        modules['action_msgs.msg'] = {'GoalStatus'}
    if entities & {'event_server'}:
        modules['time'] = set()
    return import_lines(modules)


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


def _port_context(port: Port, type_name: str,
                  activity: Activity | None) -> dict[str, Any]:
    entity = ENTITIES[(port.pattern, port.role)]
    return {
        'name': port.name,
        'description': port.description or
        f'{port.role.value.capitalize()} {port.pattern.value} port '
        f'({port.type}).',
        'entity': entity,
        'type': type_name,
        'type_full': str(port.type),
        # query and action ports use the QoS of services and actions
        'qos': qos_expression(port.qos) if port.pattern not in (
            Pattern.QUERY, Pattern.ACTION) else None,
        'qos_const': f'QOS_{port.name.upper()}',
        'activity': activity.name if activity else None,
        'callback': f'_on_{port.name}',
        'functions': list(activity.functions) if activity else [],
    }


def _signature(port: dict[str, Any]) -> tuple[list[str], str]:
    """Return the arguments and return type of a function a port runs."""
    entity, type_ = port['entity'], port['type']
    if entity == 'service':
        return ['request', 'response'], f'{type_}.Response'
    if entity == 'action_server':
        return ['goal_handle'], f'{type_}.Result'
    if entity == 'event_server':
        return ['activation', 'event'], 'bool'
    return ['commobj'], 'None'


def _default_body(returns: str) -> str:
    """Return what an unimplemented function of the skeleton returns."""
    if returns == 'bool':
        return 'return True'
    if returns.endswith('.Response'):
        return 'return response'
    if returns != 'None':
        return f'return {returns}()'
    return ''


def _parameter_context(parameter: Parameter) -> dict[str, Any]:
    py_type, ros_type = _PARAMETER_TYPES[parameter.type]
    default: Any = parameter.default
    if isinstance(default, tuple):
        default = list(default)
    if parameter.type == 'byte[]':
        default = [bytes([b]) for b in default]
    range_ = None
    if parameter.range is not None:
        kind = 'integer' if parameter.type == 'int' else 'floating_point'
        cls = 'IntegerRange' if kind == 'integer' else 'FloatingPointRange'
        cast = int if kind == 'integer' else float
        range_ = {
            'field': f'{kind}_range', 'cls': cls,
            'from': repr(cast(parameter.range.start)),
            'to': repr(cast(parameter.range.end)),
            'step': repr(cast(parameter.range.step)),
        }
    return {
        'name': parameter.name,
        'py_type': py_type,
        'ros_type': ros_type,
        'default': default,
        'description': parameter.description,
        # pep257 wants an imperative summary; the model's text follows it
        'doc': _doc(f'Return the parameter {parameter.name}.',
                    parameter.description),
        'read_only': parameter.read_only,
        'range': range_,
    }


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


def _function_context(component: Component, name: str, args: list[str],
                      returns: str) -> dict[str, Any]:
    function = next(f for f in component.functions if f.name == name)
    code = None
    if function.code is not None:
        code = textwrap.indent(
            textwrap.dedent(function.code).strip('\n'), ' ' * 8) or \
            ' ' * 8 + 'pass'
    return {
        'name': name, 'args': args, 'code': code, 'returns': returns,
        'default_return': _default_body(returns),
        'description': _doc(f'Run the function {name} of the model.',
                            function.description),
    }


def plan_python_component(component: Component) -> PackagePlan:
    """Map a Python component to its package plan."""
    package, cls = component.package, component.name
    banner = banner_context(component)
    refs = [p.type for p in component.ports]
    type_names = _python_names(refs)
    by_trigger = {a.trigger: a for a in component.activities if a.trigger}
    ports = [_port_context(p, type_names[p.type], by_trigger.get(p.name))
             for p in component.ports]
    entities = {p['entity'] for p in ports}

    # the arguments each function receives, decided by what runs it
    signatures: dict[str, tuple[list[str], str]] = {
        f.name: ([], 'None') for f in component.functions}
    for port in ports:
        for name in port['functions']:
            signatures[name] = _signature(port)
    functions = [_function_context(component, f.name, *signatures[f.name])
                 for f in component.functions]
    activities = [{
        'name': a.name, 'period': a.period, 'functions': list(a.functions),
        'description': a.description,
    } for a in component.activities if a.period is not None]
    user_functions = [f for f in functions if f['code'] is None]
    uses_duration = 'Duration(' in ''.join(p['qos'] or '' for p in ports)
    has_impl = bool(user_functions)
    module_context = {
        'banner': banner, 'package': package, 'cls': cls,
        'description': _class_doc(cls, component.info.description),
        'imports': _node_imports(type_names, component, entities,
                                 uses_duration),
        'ports': ports, 'activities': activities,
        'activity_names': [a.name for a in component.activities],
        'helpers': sorted(HELPERS[e] for e in entities if e in HELPERS),
        'functions': functions,
        'parameters': [_parameter_context(p) for p in component.parameters],
        'lifecycle': dict(component.lifecycle),
    }
    impl_module = f'{cls}_impl'
    node_cls = f'{cls}_impl' if has_impl else cls
    node_module = impl_module if has_impl else cls
    # the user's file imports the types its signatures name
    used = {f['returns'].split('.')[0] for f in user_functions}
    impl_modules: dict[str, set[str]] = {f'{package}.{cls}': {cls}}
    for ref, local in type_names.items():
        if local in used:
            alias = '' if local == ref.name else f' as {local}'
            impl_modules.setdefault(f'{ref.package}.{ref.kind.value}',
                                    set()).add(f'{ref.name}{alias}')
    impl_imports = import_lines(impl_modules)
    impl_context = {
        'banner': banner, 'package': package, 'cls': cls,
        'functions': user_functions, 'skeleton': False,
        'imports': impl_imports,
    }
    depends = model_dependencies(component)
    exec_depends = ['rclpy', 'lifecycle_msgs', 'rcl_interfaces'] + (
        ['action_msgs'] if 'event_client' in entities
        else []) + depends
    files = [
        FileSpec(f'{package}/__init__.py', 'component_python/init.py.jinja',
                 {'banner': banner, 'cls': cls}),
        FileSpec(f'{package}/{cls}.py', 'component_python/node.py.jinja',
                 module_context),
        FileSpec(f'{package}/{cls}_main.py', 'component_python/main.py.jinja',
                 {'banner': banner, 'cls': cls, 'node_cls': node_cls,
                  'imports': import_lines({
                      'os': set(),
                      'rclpy': set(),
                      'rclpy.executors': {'ExternalShutdownException',
                                          'MultiThreadedExecutor'},
                      f'{package}.{node_module}': {node_cls}})}),
        FileSpec(f'scripts/{cls}', 'component_python/executable.jinja',
                 {'banner': banner, 'package': package, 'cls': cls},
                 executable=True),
        FileSpec('CMakeLists.txt', 'component_python/CMakeLists.txt.jinja',
                 {'banner': banner, 'package': package, 'cls': cls}),
        FileSpec('package.xml', 'common/package.xml.jinja', {
            'banner': banner,
            **package_xml_context(
                component.info,
                buildtool=['ament_cmake', 'ament_cmake_python'],
                exec_=exec_depends)}),
    ]
    user_files = []
    if has_impl:
        skeleton = f'src-skel/{package}/{cls}_impl_skel.py'
        files.append(FileSpec(skeleton, 'component_python/impl.py.jinja',
                              {**impl_context, 'skeleton': True}))
        user_files.append(UserFile(
            source_path=impl_source_path(component),
            package_path=f'{package}/{impl_module}.py',
            template='component_python/impl.py.jinja',
            context=impl_context,
            required_functions=tuple(f['name'] for f in user_functions),
            required_class=f'{cls}_impl',
            skeleton_path=skeleton))
    return PackagePlan(
        name=package, kind='component',
        model_dir=Path(component.info.model_file).parent,
        build_depends=tuple(depends), exec_depends=tuple(exec_depends),
        files=tuple(files), user_files=tuple(user_files),
        summary={'executables': [cls]})
