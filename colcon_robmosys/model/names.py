# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Naming rules: what a name must be to work in ROS 2, C++ and Python.

The names of interfaces, fields and constants follow rosidl_adapter's rules
(``rosidl.py``); the rules here are what C++ and Python add to them.
"""

from __future__ import annotations

import keyword

from colcon_robmosys.model import rosidl
from colcon_robmosys.model.base import InterfaceKind

CPP_KEYWORDS = frozenset("""
alignas alignof and and_eq asm atomic_cancel atomic_commit atomic_noexcept
auto bitand bitor bool break case catch char char8_t char16_t char32_t class
compl concept const consteval constexpr constinit const_cast continue
co_await co_return co_yield decltype default delete do double dynamic_cast
else enum explicit export extern false float for friend goto if inline int
long mutable namespace new noexcept not not_eq nullptr operator or or_eq
private protected public reflexpr register reinterpret_cast requires return
short signed sizeof static static_assert static_cast struct switch
synchronized template this thread_local throw true try typedef typeid
typename union unsigned using virtual void volatile wchar_t while xor xor_eq
final override import module NULL
""".split())

#: Python's keywords. Not its soft keywords (match, case, type, _): they are
#: identifiers Python accepts anywhere (sensor_msgs/JoyFeedback has a field
#: 'type'), and their list grows with Python ('type' since 3.12), while a
#: model, like the JSON Schema, must mean the same on every Python.
PYTHON_KEYWORDS = frozenset(keyword.kwlist)

#: Members of rclpy's and rclcpp_lifecycle's LifecycleNode, of robmosys_runtime's
#: ComponentNode (both languages), and names the generated classes use: a
#: function or port of that name would replace them.
NODE_MEMBERS = frozenset("""
add_managed_entity add_on_set_parameters_callback
add_post_set_parameters_callback add_pre_set_parameters_callback add_waitable
clients context count_clients count_publishers count_services
count_subscribers create_client create_guard_condition
create_lifecycle_publisher create_publisher create_rate create_service
create_subscription create_timer create_wall_timer create_callback_group
declare_parameter declare_parameters default_callback_group
describe_parameter describe_parameters destroy_client destroy_guard_condition
destroy_lifecycle_publisher destroy_node destroy_publisher destroy_rate
destroy_service destroy_subscription destroy_timer executor get_clock
get_fully_qualified_name get_fully_qualified_node_names get_logger get_name
get_namespace get_node_names get_node_names_and_namespaces get_parameter
get_parameter_or get_parameter_type get_parameter_types get_parameters
get_parameters_by_prefix get_topic_names_and_types guards handle
has_parameter list_parameters on_activate on_cleanup on_configure
on_deactivate on_error on_shutdown publishers remove_waitable
resolve_service_name resolve_topic_name services set_descriptor
set_parameters set_parameters_atomically subscriptions timers
trigger_activate trigger_cleanup trigger_configure trigger_deactivate
trigger_shutdown undeclare_parameter wait_for_node waitables now configure
activate deactivate cleanup shutdown get_current_state
params ports main
active activities activity add_action_client add_action_server add_activity
add_event_client add_event_server add_periodic add_publisher add_query_client
add_service add_subscription create_action_server create_ports
create_query_server in_activity is_active keep keep_publisher own_group release
run_activity_callback set_lifecycle
""".split())


def identifier_problems(name: str) -> list[str]:
    """Return every reason why a name cannot be a C++ and Python identifier.

    A user who fixes one problem should not meet the next only on the next
    run: a name that is non-ASCII and starts with a digit hears both.
    """
    problems = []
    non_ascii = sorted({c for c in name if not c.isascii()})
    if non_ascii:
        problems.append(
            f'holds {_characters(non_ascii)}, which is not ASCII (ROS 2 names '
            'are ASCII)')
    others = sorted({c for c in name if c.isascii() and
                     not (c.isalnum() or c == '_')})
    if others:
        problems.append(f'holds {_characters(others)}, which a name cannot '
                        'hold (letters, digits and single underscores)')
    if not name:
        problems.append('is empty')
    elif not (name[0].isascii() and name[0].isalpha()):
        problems.append('must start with a letter')
    if '__' in name:
        problems.append('holds a double underscore, which C++ reserves')
    cpp, python = name in CPP_KEYWORDS, name in PYTHON_KEYWORDS
    if cpp and python:
        problems.append('is a C++ keyword and a Python keyword')
    elif cpp:
        problems.append('is a C++ keyword')
    elif python:
        problems.append('is a Python keyword')
    return problems


def identifier_problem(name: str) -> str | None:
    """Return why a name cannot be a C++ and Python identifier, or None."""
    problems = identifier_problems(name)
    return join_problems(problems) if problems else None


def join_problems(problems: list[str]) -> str:
    """Join problems into one clause: ``a, b and c``."""
    if len(problems) < 2:
        return ''.join(problems)
    return f"{', '.join(problems[:-1])} and {problems[-1]}"


def _characters(characters: list[str]) -> str:
    shown = ', '.join(repr(c) if c.isprintable() else ascii(c)
                      for c in characters)
    return f"the character{'s' if len(characters) > 1 else ''} {shown}"


def shown(name: str) -> str:
    """Quote a name for a message; an invisible character is shown escaped."""
    return f"'{name}'" if name.isprintable() else repr(name)


#: Names that are identifiers (members, classes, nodes): kind -> what it is called
IDENTIFIER_KINDS = {
    'component': 'component name', 'system': 'system name', 'port': 'port name',
    'activity': 'activity name', 'function': 'function name',
    'parameter': 'parameter name', 'instance': 'instance name',
    'subsystem': 'subsystem name',
}


#: the sections of a service definition -> what the names in them name (an
#: event is an action of its own)
INTERFACE_SECTIONS = {
    'communication_objects': InterfaceKind.MSG, 'queries': InterfaceKind.SRV,
    'actions': InterfaceKind.ACTION, 'events': InterfaceKind.ACTION,
}


def name_problem(kind: str, name: str,
                 interface_kind: InterfaceKind = InterfaceKind.MSG) -> str | None:
    """Return the message about a name of a kind of the model, or None if it is valid.

    :param kind: 'package', 'interface', 'field', 'constant' or a key of
        :data:`IDENTIFIER_KINDS`
    :param interface_kind: what an interface name names (rosidl derives
        other names from a service's or an action's)
    """
    if kind == 'package':
        problem = package_problem(name)
        return f'package {shown(name)} {problem}' if problem else None
    if kind == 'interface':
        return None if rosidl.is_interface_name(name, interface_kind) else (
            f'{shown(name)} is not a valid interface name: CamelCase, '
            'starting with a capital letter')
    if kind == 'field':
        if not rosidl.is_field_name(name):
            return (f'field {shown(name)} is not a valid field name: lower case '
                    'letters, digits and single underscores, starting with a letter')
        if name in CPP_KEYWORDS or name in PYTHON_KEYWORDS:
            return f'field {shown(name)} is a C++ or Python keyword'
        return None
    if kind == 'constant':
        return None if rosidl.is_constant_name(name) else (
            f'constant {shown(name)} is not a valid constant name: upper case '
            'letters, digits and single underscores, starting with a letter')
    what = IDENTIFIER_KINDS[kind]
    problem = identifier_problem(name)
    if problem:
        return f'{what} {shown(name)} {problem}'
    if kind == 'function' and name in NODE_MEMBERS:
        return (f'function name {shown(name)} would hide a member of the '
                'lifecycle node class')
    if kind == 'instance' and name == 'nodes':
        return ("instance name 'nodes' is reserved: <system>.nodes.launch.py "
                'is the launch file of every instance')
    return None


def package_problem(name: str) -> str | None:
    """Return why a name cannot be a ROS 2 package name (REP 144), or None.

    rosidl_adapter's rule, which every package of ours meets: components and
    systems are the packages of the interfaces their nodes announce. REP 144
    also wants two characters at least, which rosidl does not check.
    """
    if not rosidl.is_package_name(name) or len(name) < 2:
        return ('is not a valid ROS 2 package name: lower case letters, '
                'digits and single underscores, starting with a letter, '
                'at least two characters, not ending with an underscore')
    if name in CPP_KEYWORDS or name in PYTHON_KEYWORDS:
        return 'is a C++ or Python keyword, which cannot name a package'
    return None
