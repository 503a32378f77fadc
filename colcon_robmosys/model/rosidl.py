# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""rosidl_adapter, the parser of .msg, .srv and .action files, judges types and names.

Whatever this module accepts is what rosidl accepts when it builds the interface
package: the type of a field, the name of a package, interface, field or
constant, the value of a default or constant as the .msg file spells it. It
answers yes or no, with rosidl's reason; the model's messages are phrased by
its callers (``fieldtypes.py``, ``names.py``), since rosidl's name regular
expressions and internal exceptions are no message for a user.

rosidl_adapter is not among the requirements of setup.cfg: it comes with every
ROS 2 installation (and its ``ros-rosidl-adapter`` wheel on PyPI), and a wheel
of one distribution would shadow the sourced installation of another. Where it
cannot be imported, :data:`MISSING` says why, and the check stage reports that
once instead of checking anything (``check.load_workspace``). It imports in a
few milliseconds (``re`` and ``typing``, which we import anyway).

rosidl_parser, the other parser of rosidl, reads the .idl files rosidl_adapter
writes from these: it has nothing to say about .msg syntax, and loads lark.
"""

from __future__ import annotations

from pathlib import Path

from colcon_robmosys.errors import Diagnostic, Location, RobmosysError
from colcon_robmosys.model.base import InterfaceKind

#: why rosidl_adapter cannot be imported, or None
MISSING: str | None = None
try:
    import rosidl_adapter.parser as adapter
except ImportError as error:
    MISSING = (f'rosidl_adapter, the parser of .msg, .srv and .action files that checks '
               f'the types and names of interfaces, cannot be imported ({error}): source '
               'a ROS 2 installation (/opt/ros/<distro>/setup.bash) or install it (pip '
               'install ros-rosidl-adapter)')

#: Where the error of a missing rosidl_adapter is: in no model file.
MISSING_LOCATION = Location('colcon-robmosys')

#: Types rosidl_adapter reads "for compatibility only" (ROS 1's time and
#: duration): the model spells them builtin_interfaces/Time and /Duration.
COMPATIBILITY_TYPES = {'time': 'builtin_interfaces/Time',
                       'duration': 'builtin_interfaces/Duration'}

#: rosidl_adapter's exceptions for a type or a name it refuses: its own, and
#: the built-in ones its Type and BaseType raise for sizes and bounds
_REFUSALS = (TypeError, ValueError, NameError, IndexError)


def require() -> None:
    """Raise the error of a missing rosidl_adapter, if it is missing."""
    if MISSING is not None:
        raise RobmosysError([Diagnostic(MISSING_LOCATION, MISSING)])


def parser_source() -> bytes:
    """Return the source of rosidl_adapter's parser, or nothing if it is missing."""
    return b'' if MISSING is not None else Path(adapter.__file__).read_bytes()


def parse_type(text: str, package: str) -> adapter.Type:
    """Return rosidl's parse of a type as a .msg file writes it (``pkg/Name[<=3]``).

    :param package: the package of a message named without one
    :raises ValueError: with rosidl's reason, if rosidl refuses the type
    """
    require()
    try:
        return adapter.Type(text, context_package_name=package)
    except (adapter.InvalidSpecification, *_REFUSALS) as exc:
        raise ValueError(str(exc) or text) from None


def is_package_name(name: str) -> bool:
    """Tell whether rosidl accepts the name as the package of an interface."""
    require()
    return bool(adapter.is_valid_package_name(name))


def is_field_name(name: str) -> bool:
    """Tell whether rosidl accepts the name as a field name."""
    require()
    return bool(adapter.is_valid_field_name(name))


def is_constant_name(name: str) -> bool:
    """Tell whether rosidl accepts the name as a constant name."""
    require()
    return bool(adapter.is_valid_constant_name(name))


def is_interface_name(name: str, kind: InterfaceKind) -> bool:
    """Tell whether rosidl reads a file ``<kind>/<name>.<kind>``.

    rosidl checks the names it derives from the file's (``Name_Request``,
    ``Name_Goal``...), so a name is parsed as the empty interface of its kind.
    """
    require()
    parse = {InterfaceKind.MSG: adapter.parse_message_string,
             InterfaceKind.SRV: adapter.parse_service_string,
             InterfaceKind.ACTION: adapter.parse_action_string}[kind]
    body = {InterfaceKind.MSG: '', InterfaceKind.SRV: '---',
            InterfaceKind.ACTION: '---\n---'}[kind]
    try:
        # the package is checked on its own (is_package_name): a valid one
        # here keeps an invalid one from refusing every name of its package
        parse('pkg', name, body)
    except (adapter.InvalidSpecification, *_REFUSALS):
        return False
    return True


def value_refusal(type_text: str, literal: str) -> str | None:
    """Return why rosidl refuses a value of a field or constant, or None.

    :param type_text: the type as the .msg file writes it
    :param literal: the value as the .msg file writes it
    """
    require()
    try:
        adapter.parse_value_string(adapter.Type(type_text), literal)
    except (adapter.InvalidValue, adapter.InvalidSpecification, *_REFUSALS) as exc:
        return str(exc)
    return None
