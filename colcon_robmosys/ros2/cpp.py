# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""C++ components become ament_cmake packages of rclcpp lifecycle nodes.

The layout is the reference's (Papyrus for Robotics): ``src-gen/<pkg>/`` holds
the generated class and main, ``src-skel/<pkg>/`` the regenerated skeleton of
the implementation, ``src/<pkg>/<Component>_impl.{hpp,cpp}`` (next to
the model) the user's implementation, which derives from the generated class.
Headers are ``.hpp`` where the reference has ``.h``: ament_uncrustify reads
``.h`` files as C.

The decisions live here; the templates under ``templates/component_cpp``
only print what this module computes.
"""

from __future__ import annotations

from pathlib import Path
import re
import textwrap
from typing import Any

from colcon_robmosys.errors import RobmosysError
# a leaf module of escaping functions: defaults are C++ expressions decided here
from colcon_robmosys.generate.filters import cpp_str, split_literal
from colcon_robmosys.model.qos import resolve_qos
from colcon_robmosys.model.types import (
    Activity, Component, InterfaceKind, InterfaceRef, Parameter, Pattern, Port, QoS)
from colcon_robmosys.model.workspace import model_dependencies
from colcon_robmosys.ros2.common import (
    banner_context, ENTITIES, package_xml_context)
from colcon_robmosys.ros2.plan import FileSpec, PackagePlan, UserFile

#: The ROS 2 packages a C++ component needs in the prefix to build at all.
CPP_CLIENT_PACKAGES = ('rclcpp', 'rclcpp_lifecycle', 'rclcpp_components')

#: The entities that hold the ports header's classes, and which need actions.
_PORT_CLASSES = {'client', 'action_client', 'event_server', 'event_client'}
_ACTIONS = {'action_server', 'action_client', 'event_server', 'event_client'}
_TOPICS = {'publisher', 'subscription', 'event_server', 'event_client'}

#: model type -> (C++ type, ParameterValue accessor)
_PARAMETER_TYPES = {
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


def impl_source_paths(component: Component) -> tuple[str, str]:
    """Return where the user's header and source live, next to the model."""
    stem = f'src/{component.package}/{component.name}_impl'
    return f'{stem}.hpp', f'{stem}.cpp'


def header_name(ref: InterfaceRef) -> str:
    """Return the include of an interface, as rosidl_generator_cpp names it.

    ``simple_msgs/msg/MapCell`` is ``simple_msgs/msg/map_cell.hpp``.
    """
    # rosidl's convert_camel_case_to_lower_case_underscore
    name = re.sub(r'(.)([A-Z][a-z]+)', r'\1_\2', ref.name)
    name = re.sub(r'([a-z0-9])([A-Z])', r'\1_\2', name).lower()
    return f'{ref.package}/{ref.kind.value}/{name}.hpp'


def cpp_type(ref: InterfaceRef) -> str:
    """Return the C++ type of an interface, e.g. ``simple_msgs::msg::Map``."""
    return f'{ref.package}::{ref.kind.value}::{ref.name}'


def _seconds(value: float) -> str:
    return f'rclcpp::Duration::from_seconds({float(value)!r})'


def qos_statements(qos: QoS) -> list[str]:
    """Return the statements that set every policy of ``qos`` (a QoS)."""
    resolved = resolve_qos(qos)
    lines = []
    if resolved.history == 'keep_all':
        lines.append('qos.keep_all();')
    else:
        lines.append(f'qos.keep_last({resolved.depth});')
    if resolved.adaptive and qos.reliability is None:
        lines.append('qos.reliability(RMW_QOS_POLICY_RELIABILITY_BEST_AVAILABLE);')
    else:
        lines.append('qos.reliable();' if resolved.reliability == 'reliable'
                     else 'qos.best_effort();')
    if resolved.adaptive and qos.durability is None:
        lines.append('qos.durability(RMW_QOS_POLICY_DURABILITY_BEST_AVAILABLE);')
    else:
        lines.append('qos.durability_volatile();'
                     if resolved.durability == 'volatile'
                     else 'qos.transient_local();')
    if resolved.deadline is not None:
        lines.append(f'qos.deadline({_seconds(resolved.deadline)});')
    if resolved.lifespan is not None:
        lines.append(f'qos.lifespan({_seconds(resolved.lifespan)});')
    lines.append('qos.liveliness(RMW_QOS_POLICY_LIVELINESS_'
                 f'{resolved.liveliness.upper()});')
    if resolved.liveliness_lease_duration is not None:
        lines.append('qos.liveliness_lease_duration('
                     f'{_seconds(resolved.liveliness_lease_duration)});')
    return lines


def _cpp_value(value: Any, type_: str) -> str:
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
            f'default_value.push_back({_cpp_value(v, element)});'
            for v in default]
    if isinstance(default, str):
        return [f'{ctype} default_value;'] + string_lines('default_value', default)
    return [f'const {ctype} default_value = '
            f'{_cpp_value(parameter.default, parameter.type)};']


def _parameter_context(parameter: Parameter) -> dict[str, Any]:
    ctype, accessor = _PARAMETER_TYPES[parameter.type]
    range_ = None
    if parameter.range is not None:
        integer = parameter.type == 'int'
        cast = (lambda v: f'INT64_C({int(v)})') if integer else \
            (lambda v: repr(float(v)))
        range_ = {
            'field': 'integer_range' if integer else 'floating_point_range',
            'cls': 'rcl_interfaces::msg::IntegerRange' if integer
            else 'rcl_interfaces::msg::FloatingPointRange',
            'from': cast(parameter.range.start),
            'to': cast(parameter.range.end),
            'step': cast(parameter.range.step),
        }
    return {
        'name': parameter.name,
        'cpp_type': ctype,
        'accessor': accessor,
        'default_lines': _default_lines(parameter, ctype),
        'description_lines': string_lines('descriptor.description',
                                          parameter.description),
        'doc': parameter.description or f'The parameter {parameter.name}.',
        'read_only': 'true' if parameter.read_only else 'false',
        'range': range_,
    }


def _port_context(port: Port, activity: Activity | None) -> dict[str, Any]:
    entity = ENTITIES[(port.pattern, port.role)]
    type_ = cpp_type(port.type)
    member_type = {
        'publisher': f'rclcpp_lifecycle::LifecyclePublisher<{type_}>::SharedPtr',
        'subscription': f'rclcpp::Subscription<{type_}>::SharedPtr',
        'service': f'rclcpp::Service<{type_}>::SharedPtr',
        'client': f'std::shared_ptr<ports::QueryClient<{type_}>>',
        'action_server': f'rclcpp_action::Server<{type_}>::SharedPtr',
        'action_client': f'std::shared_ptr<ports::ActionClient<{type_}>>',
        'event_server': f'std::shared_ptr<ports::EventServer<{type_}>>',
        'event_client': f'std::shared_ptr<ports::EventClient<{type_}>>',
    }[entity]
    return {
        'name': port.name,
        'entity': entity,
        'type': type_,
        'member_type': member_type,
        'description': port.description or
        f'{port.role.value.capitalize()} {port.pattern.value} port ({port.type}).',
        # events: the QoS of the feedback topic
        'qos': qos_statements(port.qos) if entity in _TOPICS else [],
        'activity': activity.name if activity else None,
        'functions': list(activity.functions) if activity else [],
        # clients wait for answers in a group of their own, so that a
        # blocking call from an activity never waits for its own thread
        'own_group': entity in ('client', 'action_client', 'event_client'),
    }


#: How a function receives what the port triggering its activity delivers:
#: entity -> (return type, parameters, the wrapper's call arguments).
_SIGNATURES = {
    'subscription': ('void', 'const {type} & commobj', 'commobj'),
    'service': ('void', 'const {type}::Request & request, {type}::Response & response',
                '*request, *response'),
    'client': ('void', 'const {type}::Response & commobj', 'commobj'),
    'action_server': (
        '{type}::Result', 'const std::shared_ptr<GoalHandle_{port}> goal_handle',
        'goal_handle'),
    'action_client': ('void', 'const {type}::Result & commobj', 'commobj'),
    # the condition of an activation
    'event_server': ('bool', 'const {type}::Goal & activation, const {type}::Feedback & event',
                     'activation, event'),
    'event_client': ('void', 'const {type}::Feedback & commobj', 'commobj'),
}


def _function_signatures(component: Component,
                         ports: list[dict[str, Any]]) -> dict[str, tuple[str, str]]:
    """Return each function's (return type, parameters), from what runs it."""
    signatures: dict[str, tuple[str, str]] = {
        f.name: ('void', '') for f in component.functions}
    decided_by: dict[str, str] = {}
    for port in ports:
        for name in port['functions']:
            returns, params, _ = _SIGNATURES[port['entity']]
            signature = (returns.format(type=port['type']),
                         params.format(type=port['type'], port=port['name']))
            if name in decided_by and signatures[name] != signature:
                function = next(f for f in component.functions if f.name == name)
                raise RobmosysError.at(
                    function.location,
                    f"function '{name}' runs for the ports '{decided_by[name]}' "
                    f"and '{port['name']}', which deliver different things; "
                    'a C++ function has one signature')
            signatures[name] = signature
            decided_by[name] = port['name']
    # periodic and lifecycle functions take nothing: no port may decide
    others = [(f"runs periodically (activity '{a.name}')", a.functions)
              for a in component.activities if a.period is not None]
    others += [('runs on a lifecycle transition', names)
               for _, names in component.lifecycle]
    for what, names in others:
        for name in names:
            if name in decided_by:
                function = next(f for f in component.functions if f.name == name)
                raise RobmosysError.at(
                    function.location,
                    f"function '{name}' {what} and for the port "
                    f"'{decided_by[name]}'; a C++ function has one signature")
    return signatures


def _function_context(component: Component, name: str,
                      signature: tuple[str, str]) -> dict[str, Any]:
    function = next(f for f in component.functions if f.name == name)
    code = None
    if function.code is not None:
        code = textwrap.indent(textwrap.dedent(function.code).strip('\n'), '  ')
    returns, params = signature
    param_list = [p.strip() for p in params.split(', ')] if params else []
    longest = max(
        len(f'  virtual {returns} {name}({params}) = 0;'),
        len(f'{returns} {component.name}_impl::{name}({params})'))
    return {
        'name': name, 'returns': returns, 'params': param_list,
        # what the skeleton does not use yet
        'param_names': [p.rsplit(' ', 1)[1] for p in param_list],
        # one parameter a line when one line would be too long for cpplint
        'wrap': longest > 100,
        'code': code,
        'description': function.description or f'The function {name} of the model.',
    }


def _includes(component: Component, ports: list[dict[str, Any]]) -> dict[str, list[str]]:
    """Return the system and ROS includes of the generated header."""
    system = ['atomic', 'chrono', 'memory', 'mutex', 'string']
    ros = ['rclcpp/rclcpp.hpp', 'rclcpp_lifecycle/lifecycle_node.hpp',
           'rclcpp_lifecycle/lifecycle_publisher.hpp']
    entities = {p['entity'] for p in ports}
    if _ACTIONS & entities:
        ros.append('rclcpp_action/rclcpp_action.hpp')
    if 'action_server' in entities:
        system += ['future', 'vector']
    if any(p.type.endswith('[]') for p in component.parameters):
        system.append('vector')
    ros += sorted({header_name(p.type) for p in component.ports})
    return {'system': sorted(set(system)), 'ros': ros}


def _thread_count(component: Component, ports: list[dict[str, Any]]) -> int:
    """Return the executor threads that keep every callback group served.

    Each activity and each client has a callback group; one thread more than
    groups means that activities blocked in calls never starve the threads
    that deliver the answers, nor the lifecycle and parameter services.
    """
    groups = len(component.activities) + sum(1 for p in ports if p['own_group'])
    return groups + 1


def plan_cpp_component(component: Component) -> PackagePlan:
    """Map a C++ component to its package plan."""
    # an event is a ROS 2 action: an event port whose type is a message
    # comes from a model of before events belonged to service definitions
    problems = [p for p in component.ports
                if (p.pattern, p.role) not in ENTITIES or
                (p.pattern is Pattern.EVENT and p.type.kind is not InterfaceKind.ACTION)]
    if problems:
        raise RobmosysError.at(
            problems[0].location,
            f"port '{problems[0].name}': the C++ generator does not map "
            f'{problems[0].role.value} {problems[0].pattern.value} ports '
            'yet')
    package, cls = component.package, component.name
    banner = banner_context(component)
    by_trigger = {a.trigger: a for a in component.activities if a.trigger}
    ports = [_port_context(p, by_trigger.get(p.name)) for p in component.ports]
    signatures = _function_signatures(component, ports)
    for port in ports:
        port['call_args'] = _SIGNATURES[port['entity']][2] \
            if port['entity'] in _SIGNATURES else ''
    functions = [_function_context(component, f.name, signatures[f.name])
                 for f in component.functions]
    user_functions = [f for f in functions if f['code'] is None]
    has_impl = bool(user_functions)
    entities = {p['entity'] for p in ports}
    uses_actions = bool(_ACTIONS & entities)
    uses_ports_header = bool(_PORT_CLASSES & entities)
    node_cls = f'{cls}_impl' if has_impl else cls
    node_header = f'{package}/{node_cls}.hpp'
    activities = [{
        'name': a.name, 'period': a.period,
        'period_ns': round(a.period * 1e9) if a.period is not None else None,
        'functions': list(a.functions),
        'description': a.description or f'The activity {a.name}.',
    } for a in component.activities]
    context = {
        'banner': banner, 'package': package, 'cls': cls,
        'description': component.info.description or f'The component {cls}.',
        'includes': _includes(component, ports),
        'uses_ports_header': uses_ports_header,
        'ports': ports,
        'activities': activities,
        'periodic': [a for a in activities if a['period'] is not None],
        'functions': functions,
        'parameters': [_parameter_context(p) for p in component.parameters],
        'lifecycle': {t: list(names) for t, names in component.lifecycle},
    }
    impl_context = {
        'banner': banner, 'package': package, 'cls': cls,
        'functions': user_functions, 'skeleton': False,
    }
    depends = model_dependencies(component)
    client_packages = list(CPP_CLIENT_PACKAGES)
    if uses_actions:
        client_packages.append('rclcpp_action')
    # the parameter descriptors and the lifecycle states are used directly
    interfaces = list(dict.fromkeys(['rcl_interfaces', 'lifecycle_msgs'] + depends))
    build_depends = client_packages + interfaces
    exec_depends = build_depends
    src = f'src-gen/{package}'
    files = [
        FileSpec(f'{src}/{cls}.hpp', 'component_cpp/node.hpp.jinja', context),
        FileSpec(f'{src}/{cls}.cpp', 'component_cpp/node.cpp.jinja', context),
        FileSpec(f'{src}/{cls}_main.cpp', 'component_cpp/main.cpp.jinja', {
            'banner': banner, 'package': package, 'cls': cls,
            'node_cls': node_cls, 'node_header': node_header,
            'threads': _thread_count(component, ports)}),
        FileSpec(f'{src}/{cls}_component.cpp', 'component_cpp/component.cpp.jinja', {
            'banner': banner, 'package': package, 'node_cls': node_cls,
            'node_header': node_header}),
        FileSpec('CMakeLists.txt', 'component_cpp/CMakeLists.txt.jinja', {
            'banner': banner, 'package': package, 'cls': cls,
            'node_cls': node_cls,
            'find_packages': build_depends,
            'link_targets': [f'{p}::{p}' for p in ('rclcpp', 'rclcpp_lifecycle')] +
            (['rclcpp_action::rclcpp_action'] if uses_actions else []) +
            ['rclcpp_components::component'],
            'interface_packages': interfaces,
            'sources': [f'{src}/{cls}.cpp'] +
            ([f'src/{package}/{cls}_impl.cpp'] if has_impl else []) +
            [f'{src}/{cls}_component.cpp'],
        }),
        FileSpec('package.xml', 'common/package.xml.jinja', {
            'banner': banner,
            **package_xml_context(
                component.info, buildtool=['ament_cmake'],
                depend=build_depends,
                test=['ament_cmake_cpplint', 'ament_cmake_uncrustify'])}),
    ]
    if uses_ports_header:
        files.append(FileSpec(f'{src}/ports.hpp', 'component_cpp/ports.hpp.jinja', {
            'banner': banner, 'package': package,
            'query': 'client' in entities, 'action': 'action_client' in entities,
            'event': bool({'event_server', 'event_client'} & entities)}))
    user_files = []
    if has_impl:
        header_path, source_path = impl_source_paths(component)
        skel = f'src-skel/{package}/{cls}_impl'
        for suffix, template in (('hpp', 'impl.hpp.jinja'), ('cpp', 'impl.cpp.jinja')):
            files.append(FileSpec(f'{skel}.{suffix}', f'component_cpp/{template}',
                                  {**impl_context, 'skeleton': True}))
        user_files.append(UserFile(
            source_path=header_path,
            package_path=header_path,
            template='component_cpp/impl.hpp.jinja',
            context=impl_context,
            required_functions=tuple(f['name'] for f in user_functions),
            required_class=f'{cls}_impl',
            skeleton_path=f'{skel}.hpp'))
        user_files.append(UserFile(
            source_path=source_path,
            package_path=source_path,
            template='component_cpp/impl.cpp.jinja',
            context=impl_context,
            skeleton_path=f'{skel}.cpp'))
    return PackagePlan(
        name=package, kind='component',
        model_dir=Path(component.info.model_file).parent,
        build_depends=tuple(build_depends),
        exec_depends=tuple(exec_depends),
        files=tuple(files), user_files=tuple(user_files),
        prefix_requirements=tuple(client_packages),
        summary={'executables': [cls], 'language': 'cpp'})
