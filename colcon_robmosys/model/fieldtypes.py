# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Parse type names of fields and ports, and check values against them."""

from __future__ import annotations

import math
import re
from typing import Any

from colcon_robmosys.model.types import (
    FieldType, InterfaceKind, InterfaceRef, PRIMITIVE_TYPES)

_FIELD_TYPE_RE = re.compile(
    r'^(?:(?P<package>[a-z][a-z0-9_]*)/(?:msg/)?)?(?P<base>[A-Za-z][A-Za-z0-9_]*)'
    r'(?:<=(?P<string_bound>[0-9]+))?'
    r'(?:\[(?P<array>(?:<=)?[0-9]*)\])?\Z')

_INTERFACE_RE = re.compile(
    r'^(?P<package>[a-z][a-z0-9_]*)/(?:(?P<kind>msg|srv|action)/)?'
    r'(?P<name>[A-Z][A-Za-z0-9]*)\Z')

#: rosidl reads a .msg line up to its first '#' and splits it at its first
#: '=': no spelling carries them in a value (backslashes and quotes are
#: escaped, see generators/filters.py msg_default).
_MSG_UNSAFE = frozenset('#=')

_INT_RANGES = {
    'int8': (-2 ** 7, 2 ** 7 - 1), 'uint8': (0, 2 ** 8 - 1),
    'int16': (-2 ** 15, 2 ** 15 - 1), 'uint16': (0, 2 ** 16 - 1),
    'int32': (-2 ** 31, 2 ** 31 - 1), 'uint32': (0, 2 ** 32 - 1),
    'int64': (-2 ** 63, 2 ** 63 - 1), 'uint64': (0, 2 ** 64 - 1),
    'byte': (0, 255), 'char': (0, 255),
}


class TypeNameError(ValueError):
    """A type name that does not parse."""


def parse_field_type(text: str, own_package: str) -> FieldType:
    """Parse a field type such as ``uint8[<=4]`` or ``geometry_msgs/Pose``.

    A capitalised name without a package refers to a communication object of
    ``own_package``.

    :raises TypeNameError: if the text is not a type name
    """
    match = _FIELD_TYPE_RE.match(text.strip())
    if not match:
        raise TypeNameError(
            f"'{text}' is not a type: expected a primitive type, Name, "
            'pkg/Name or pkg/msg/Name, optionally followed by [], [N] or '
            '[<=N]')
    package, base = match['package'], match['base']
    array, size = None, None
    if match['array'] is not None:
        spec = match['array']
        if spec == '':
            array = 'dynamic'
        elif spec.startswith('<='):
            if spec == '<=':
                raise TypeNameError(f"'{text}': '[<=]' lacks its bound")
            array, size = 'bounded', int(spec[2:])
        else:
            array, size = 'fixed', int(spec)
        if size == 0:
            raise TypeNameError(f"'{text}': an array size must be positive")
    string_bound = None
    if match['string_bound'] is not None:
        if base not in ('string', 'wstring') or package:
            raise TypeNameError(
                f"'{text}': only string and wstring take a bound (<=N)")
        string_bound = int(match['string_bound'])
        if string_bound == 0:
            raise TypeNameError(f"'{text}': a string bound must be positive")
    if package is None and base in PRIMITIVE_TYPES:
        return FieldType(primitive=base, string_bound=string_bound,
                         array=array, array_size=size)
    if not base[0].isupper():
        raise TypeNameError(
            f"'{text}' is neither a primitive type (bool, byte, char, "
            'float32, float64, int8..uint64, string, wstring) nor a message '
            'name (message names start with a capital letter)')
    return FieldType(
        message=InterfaceRef(package or own_package, InterfaceKind.MSG, base),
        array=array, array_size=size)


def parse_interface(text: str, kind: InterfaceKind) -> InterfaceRef:
    """Parse a port type such as ``simple_msgs/msg/Map`` or ``pkg/Map``.

    :param kind: the kind the port's pattern exchanges
    :raises TypeNameError: if the text names another kind of interface
    """
    match = _INTERFACE_RE.match(text)
    if not match:
        raise TypeNameError(f"'{text}' is not an interface name")
    written = match['kind']
    if written is not None and written != kind.value:
        raise TypeNameError(
            f"'{text}' is a {written} type, but the pattern exchanges "
            f'{kind.value} types')
    return InterfaceRef(match['package'], kind, match['name'])


def value_problem(field_type: FieldType, value: Any) -> str | None:
    """Return why a value cannot be a default of the type, or None."""
    if field_type.message is not None:
        return 'fields of message types cannot have a default value'
    if field_type.array is not None:
        if not isinstance(value, list):
            return f'the default of an array field must be a list, not {value!r}'
        if field_type.array == 'fixed' and len(value) != field_type.array_size:
            return (f'the default must have exactly {field_type.array_size} '
                    f'items, not {len(value)}')
        if field_type.array == 'bounded' and \
                len(value) > (field_type.array_size or 0):
            return (f'the default must have at most {field_type.array_size} '
                    f'items, not {len(value)}')
        for item in value:
            problem = _scalar_problem(field_type, item) or \
                _string_item_problem(field_type, item)
            if problem:
                return problem
        return None
    return _scalar_problem(field_type, value)


#: rosidl_adapter writes the default of a string array into the IDL as the
#: repr() of a tuple, with no unicode_escape pass, and its generators read it
#: back with their own parsers: only plain text survives that.
_ARRAY_ITEM_UNSAFE = frozenset('"\',[]\\#=')


def _string_item_problem(field_type: FieldType, item: Any) -> str | None:
    if field_type.primitive not in ('string', 'wstring') or \
            not isinstance(item, str):
        return None
    unsafe = next((c for c in item if c in _ARRAY_ITEM_UNSAFE or
                   not c.isascii()), None)
    if unsafe is not None:
        return (f'the string {item!r} holds {unsafe!r}, which rosidl cannot '
                'carry in the default of a string array (quotes, brackets, '
                "commas, backslashes, '#', '=' and non-ASCII characters are "
                'lost or break its build)')
    if item != item.strip():
        return (f'the string {item!r} starts or ends with white space, which '
                'rosidl strips from the items of a string array default')
    return None


def _scalar_problem(field_type: FieldType, value: Any) -> str | None:
    primitive = field_type.primitive
    assert primitive is not None
    if primitive == 'bool':
        return None if isinstance(value, bool) else \
            f'{value!r} is not a bool (true or false)'
    if primitive in ('string', 'wstring'):
        if not isinstance(value, str):
            return f'{value!r} is not a string'
        if field_type.string_bound is not None and \
                len(value) > field_type.string_bound:
            return (f'the string is longer than its bound of '
                    f'{field_type.string_bound}')
        unsafe = next((c for c in value if c in _MSG_UNSAFE or
                       not c.isprintable()), None)
        if unsafe is not None:
            return (f'the string {value!r} holds {unsafe!r}, which the .msg '
                    'format cannot carry in a value (it has no escapes for '
                    "'#', '=' and control characters)")
        return None
    if primitive in ('float32', 'float64'):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return f'{value!r} is not a number'
        if not math.isfinite(value):
            return f'{value!r} is not a finite number'
        return None
    if isinstance(value, bool) or not isinstance(value, int):
        return f'{value!r} is not an integer'
    low, high = _INT_RANGES[primitive]
    if not low <= value <= high:
        return f'{value} is out of the range of {primitive} ({low}..{high})'
    return None


def interface_comment_problem(text: str) -> str | None:
    """Return why text cannot be a comment of an interface file, or None.

    rosidl_generator_c copies the comments of a .msg into the C header of the
    message, inside ``/** ... */`` and after ``///``, with no escaping: a
    ``*/`` would end the comment and make the rest C code, and a line ending
    in a backslash (or the trigraph ``??/``) would continue a ``///`` comment
    onto the declaration after it.
    """
    if '*/' in text:
        return ("holds '*/', which would end the C comment rosidl writes it "
                'into (C has no escape for it)')
    for line in text.splitlines():
        if line.rstrip().endswith(('\\', '??/')):
            return ('has a line that ends with a backslash, which would '
                    'continue the C comment rosidl writes it into onto the '
                    'next line of code')
    return None
