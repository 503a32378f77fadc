# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""How C++ spells a component plan: types, signatures, QoS and includes.

Headers are ``.hpp`` where the reference has ``.h``: ament_uncrustify reads
``.h`` files as C.

Nothing here decides what a port becomes (that is the port-kind table of
:mod:`colcon_robmosys.mapping.portkinds`, read through
:mod:`colcon_robmosys.mapping.component`): the tables below only spell it.
"""

from __future__ import annotations

from dataclasses import dataclass
import re
import textwrap
from typing import Iterable

from colcon_robmosys.mapping.backends.cpp.context import (
    CppActivity, CppComponent, CppFunction, CppIncludes, CppPort)
from colcon_robmosys.mapping.backends.cpp.parameters import (
    cpp_parameter, cpp_parameter_groups, PARAMETER_TYPES)
from colcon_robmosys.mapping.common import RUNTIME_PACKAGE, unique
from colcon_robmosys.mapping.component import (
    ActivityPlan, ComponentPlan, FunctionPlan, PortPlan)
from colcon_robmosys.mapping.context import component_context
from colcon_robmosys.mapping.portkinds import Delivery, Entity, port_kind, PortKind, Returns
from colcon_robmosys.mapping.qos import resolve_qos
from colcon_robmosys.mapping.userfiles import UserFolders
from colcon_robmosys.model.types import Component, InterfaceRef, QoS

#: The ROS 2 packages a C++ component needs in the prefix to build at all.
CPP_CLIENT_PACKAGES = ('rclcpp', 'rclcpp_lifecycle', 'rclcpp_components')


def cpp_client_packages(component: Component) -> tuple[str, ...]:
    """Return the rclcpp packages a C++ component is built with."""
    return rclcpp_packages(port_kind(p) for p in component.ports)


def rclcpp_packages(kinds: Iterable[PortKind]) -> tuple[str, ...]:
    """Return the rclcpp packages a C++ component with ports of these kinds is built with."""
    uses_actions = any(kind.uses_actions for kind in kinds)
    return CPP_CLIENT_PACKAGES + (('rclcpp_action',) if uses_actions else ())


@dataclass(frozen=True)
class CppEntity:
    """How the C++ node holds and creates the entity of a port: its row."""

    #: the type of the member that holds it
    member_type: str
    #: the fragment of create_ports that creates it (Inputs: port)
    template: str
    #: the header of robmosys_runtime its port needs, if any: its member
    #: type's, or create_action_server's, whose rclcpp_action headers other
    #: components skip
    runtime_header: str = ''


def _row(entity: Entity, member_type: str, runtime_header: str = '') -> tuple[Entity, CppEntity]:
    return entity, CppEntity(member_type, f'component_cpp/ports/{entity.value}.jinja',
                             runtime_header)


#: entity -> its row, one per entity
ENTITIES = dict((
    _row(Entity.PUBLISHER, 'robmosys_runtime::CountedPublisher<{type}>::SharedPtr',
         'robmosys_runtime/sends.hpp'),
    _row(Entity.SUBSCRIPTION, 'rclcpp::Subscription<{type}>::SharedPtr'),
    _row(Entity.SERVICE, 'rclcpp::Service<{type}>::SharedPtr'),
    _row(Entity.CLIENT, 'std::shared_ptr<ports::QueryClient<{type}>>',
         'robmosys_runtime/query_client.hpp'),
    _row(Entity.ACTION_SERVER, 'rclcpp_action::Server<{type}>::SharedPtr',
         'robmosys_runtime/action_server.hpp'),
    _row(Entity.ACTION_CLIENT, 'std::shared_ptr<ports::ActionClient<{type}>>',
         'robmosys_runtime/action_client.hpp'),
    _row(Entity.EVENT_SERVER, 'std::shared_ptr<ports::EventServer<{type}>>',
         'robmosys_runtime/event_server.hpp'),
    _row(Entity.EVENT_CLIENT, 'std::shared_ptr<ports::EventClient<{type}>>',
         'robmosys_runtime/event_client.hpp'),
))

#: what a port delivers -> the parameters of a function it runs
PARAMETERS = {
    Delivery.MESSAGE: 'const {type} & commobj',
    Delivery.REQUEST: 'const {type}::Request & request, {type}::Response & response',
    Delivery.ANSWER: 'const {type}::Response & commobj',
    Delivery.GOAL: 'const std::shared_ptr<GoalHandle_{port}> goal_handle',
    Delivery.RESULT: 'const {type}::Result & commobj',
    Delivery.ACTIVATION: 'const {type}::Goal & activation, const {type}::Feedback & event',
    Delivery.EVENT: 'const {type}::Feedback & commobj',
}

#: what a function gives back -> its C++ return type (an answer is filled in)
RETURN_TYPES = {
    Returns.NOTHING: 'void', Returns.ANSWER: 'void',
    Returns.RESULT: '{type}::Result', Returns.CONDITION: 'bool',
    Returns.PROBLEM: 'std::string',
}


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


def _parameters(delivers: Delivery, type_: str, port: str) -> tuple[str, ...]:
    """Return the parameters of a function a port runs, one a string."""
    return tuple(p.strip() for p in PARAMETERS[delivers].format(type=type_, port=port).split(', '))


def _port(port: PortPlan) -> CppPort:
    type_ = cpp_type(port.type)
    delivers = port.kind.delivers
    row = ENTITIES[port.kind.entity]
    return CppPort(
        name=port.name, entity=port.entity, type=type_,
        member_type=row.member_type.format(type=type_), template=row.template,
        params=_parameters(delivers, type_, port.name) if delivers is not None else (),
        description=port.description,
        # events: the QoS of the feedback topic
        qos=tuple(qos_statements(port.qos)) if port.kind.topic_qos else (),
        activity=port.activity, functions=port.functions,
        # clients wait for answers in a group of their own, so that a
        # blocking call from an activity never waits for its own thread
        own_group=port.kind.own_group,
        call_args=', '.join(port.kind.arguments) if delivers is not None else '')


def _signature(function: FunctionPlan) -> tuple[str, str]:
    """Return the return type and parameters of a function."""
    port = function.port
    if function.validates is not None:
        # an empty string accepts the value
        return 'std::string', f'const {PARAMETER_TYPES[function.validates][0]} & value'
    if port is None or port.kind.delivers is None:
        return 'void', ''
    type_ = cpp_type(port.type)
    return (RETURN_TYPES[function.returns].format(type=type_),
            ', '.join(_parameters(port.kind.delivers, type_, port.name)))


def _function(cls: str, function: FunctionPlan) -> CppFunction:
    code = None
    if function.code is not None:
        code = textwrap.indent(textwrap.dedent(function.code).strip('\n'), '  ')
    returns, params = _signature(function)
    param_list = tuple(p.strip() for p in params.split(', ')) if params else ()
    name = function.name
    longest = max(
        len(f'  virtual {returns} {name}({params}) = 0;'),
        len(f'{returns} {cls}_impl::{name}({params})'))
    return CppFunction(
        name=name, returns=returns, params=param_list,
        param_names=tuple(p.rsplit(' ', 1)[1] for p in param_list),
        wrap=longest > 100, code=code,
        description=function.description or f'The function {name} of the model.')


def _activity(activity: ActivityPlan) -> CppActivity:
    return CppActivity(name=activity.name, period=activity.period, period_ns=activity.period_ns,
                       functions=activity.functions,
                       description=activity.description or f'The activity {activity.name}.')


def _includes(plan: ComponentPlan, has_rules: bool) -> CppIncludes:
    system = ['memory', 'string']
    ros = ['rclcpp/rclcpp.hpp', 'rclcpp_lifecycle/lifecycle_node.hpp',
           'rclcpp_lifecycle/lifecycle_publisher.hpp']
    if plan.uses_actions:
        ros.append('rclcpp_action/rclcpp_action.hpp')
    if any(p.type.endswith('[]') for p in plan.parameters):
        system.append('vector')
    mapped = any(p.for_each for p in plan.parameters)
    if mapped:
        system.append('map')
    ros += sorted({header_name(p.type) for p in plan.ports})
    ros += ['robmosys_runtime/component_node.hpp'] + (
        ['robmosys_runtime/parameters.hpp'] if has_rules or mapped else []) + sorted(
        {ENTITIES[e].runtime_header for e in plan.entities if ENTITIES[e].runtime_header})
    return CppIncludes(tuple(sorted(set(system))), tuple(ros))


def spell_cpp(component: Component, plan: ComponentPlan,
              folders: UserFolders) -> CppComponent:
    """Spell the plan of a C++ component.

    :param folders: where the user's files are
    """
    package, cls = plan.package, plan.cls
    ports = tuple(_port(p) for p in plan.ports)
    functions = tuple(_function(cls, f) for f in plan.functions)
    activities = tuple(_activity(a) for a in plan.activities)
    parameters = tuple(cpp_parameter(p, cls) for p in plan.parameters)
    client_packages = cpp_client_packages(component)
    # the parameter descriptors and the lifecycle states are used directly
    interfaces = unique(('rcl_interfaces', 'lifecycle_msgs') + plan.depends)
    build_depends = client_packages + (RUNTIME_PACKAGE,) + interfaces
    src = f'src-gen/{package}'
    return component_context(
        CppComponent, component, plan, folders,
        xml={'buildtool': ['ament_cmake'], 'depend': build_depends,
             'test': ['ament_cmake_cpplint', 'ament_cmake_uncrustify',
                      'ament_cmake_gtest', 'ament_cmake_pytest']},
        node_header=f'{package}/{plan.node_cls}.hpp',
        description=plan.description or f'The component {cls}.',
        includes=_includes(plan, any(p.rule for p in parameters)), ports=ports,
        publishers=tuple(p for p in ports if p.entity == Entity.PUBLISHER),
        action_servers=tuple(p for p in ports
                             if p.entity == Entity.ACTION_SERVER),
        activities=activities,
        periodic=tuple(a for a in activities if a.period is not None),
        functions=functions,
        user_functions=tuple(f for f in functions if f.code is None),
        parameters=parameters,
        parameter_groups=cpp_parameter_groups(plan.parameters, parameters),
        find_packages=build_depends,
        link_targets=tuple(f'{p}::{p}' for p in ('rclcpp', 'rclcpp_lifecycle')) +
        (('rclcpp_action::rclcpp_action',) if plan.uses_actions else ()) +
        ('rclcpp_components::component', f'{RUNTIME_PACKAGE}::{RUNTIME_PACKAGE}'),
        interface_packages=interfaces,
        # the user's sources are compiled where they live (the template
        # finds them): only the generated ones here
        sources=(f'{src}/{cls}.cpp',),
        prefix_requirements=client_packages)
