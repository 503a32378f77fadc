# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Parse type names of fields and ports, and check values against them."""

from __future__ import annotations

import math
from typing import Any

from colcon_robmosys.model import rosidl
from colcon_robmosys.model.types import FieldType, InterfaceKind, InterfaceRef

#: rosidl reads a .msg line up to its first '#' and splits it at its first
#: '=': no spelling carries them in a value (backslashes and quotes are
#: escaped, see msg_literal).
_MSG_UNSAFE = frozenset('#=')

_TYPE_SYNTAX = ('expected a primitive type, Name, pkg/Name or pkg/msg/Name, optionally '
                'followed by [], [N] or [<=N]')


class TypeNameError(ValueError):
    """A type name that does not parse."""


def parse_field_type(text: str, own_package: str) -> FieldType:
    """Parse a field type such as ``uint8[<=4]`` or ``geometry_msgs/Pose``.

    rosidl_adapter parses it, as it will parse the .msg file; the model also
    spells a message ``pkg/msg/Name``, as ports do. A capitalised name without
    a package refers to a communication object of ``own_package``.

    :raises TypeNameError: if the text is not a type name
    """
    spelled = text.strip()
    package, slash, rest = spelled.partition('/msg/')
    if slash and '/' not in package:
        spelled = f'{package}/{rest}'
    try:
        parsed = rosidl.parse_type(spelled, own_package)
    except ValueError:
        raise TypeNameError(_type_problem(text, spelled)) from None
    if parsed.pkg_name is None and parsed.type in rosidl.COMPATIBILITY_TYPES:
        raise TypeNameError(
            f"'{text}': rosidl reads '{parsed.type}' for compatibility with ROS 1 "
            f'only: write {rosidl.COMPATIBILITY_TYPES[parsed.type]}')
    array, size = None, None
    if parsed.is_array:
        size = parsed.array_size
        array = 'dynamic' if size is None else 'bounded' if parsed.is_upper_bound \
            else 'fixed'
    if parsed.pkg_name is None:
        return FieldType(primitive=parsed.type,
                         string_bound=parsed.string_upper_bound,
                         array=array, array_size=size)
    return FieldType(
        message=InterfaceRef(parsed.pkg_name, InterfaceKind.MSG, parsed.type),
        array=array, array_size=size)


def _type_problem(text: str, spelled: str) -> str:
    """Say what is wrong with a type rosidl refuses, in the model's words."""
    base, array = spelled, None
    if spelled.endswith(']') and '[' in spelled:
        index = spelled.rindex('[')
        base, array = spelled[:index], spelled[index + 1:-1]
    if array == '<=':
        return f"'{text}': '[<=]' lacks its bound"
    if array is not None and array != '' and \
            not (array.removeprefix('<=').isdigit() and int(array.removeprefix('<=')) > 0):
        return f"'{text}': an array size must be a positive integer"
    name, bounded, bound = base.partition('<=')
    if bounded and name not in ('string', 'wstring'):
        return f"'{text}': only string and wstring take a bound (<=N)"
    if bounded:
        return f"'{text}': a string bound must be a positive integer"
    package, _, name = base.rpartition('/')
    if '/' in package or '[' in base:
        return f"'{text}' is not a type: {_TYPE_SYNTAX}"
    if package and not rosidl.is_package_name(package):
        return (f"'{text}': '{package}' is not a package name (lower case letters, "
                'digits and single underscores, starting with a letter)')
    if name[:1].isascii() and name[:1].islower():
        return (f"'{text}' is neither a primitive type (bool, byte, char, float32, "
                'float64, int8..uint64, string, wstring) nor a message name (message '
                'names start with a capital letter)')
    return f"'{text}' is not a type: {_TYPE_SYNTAX}"


def parse_interface(text: str, kind: InterfaceKind) -> InterfaceRef:
    """Parse a port type such as ``simple_msgs/msg/Map`` or ``pkg/Map``.

    :param kind: the kind the port's pattern exchanges
    :raises TypeNameError: if the text names another kind of interface
    """
    parts = text.split('/')
    package, name = parts[0], parts[-1]
    written = parts[1] if len(parts) == 3 else None
    if len(parts) not in (2, 3) or \
            written not in (None, *(k.value for k in InterfaceKind)) or \
            not rosidl.is_package_name(package) or \
            not rosidl.is_interface_name(name, InterfaceKind.MSG):
        raise TypeNameError(f"'{text}' is not an interface name")
    if written is not None and written != kind.value:
        raise TypeNameError(
            f"'{text}' is a {written} type, but the pattern exchanges "
            f'{kind.value} types')
    return InterfaceRef(package, kind, name)


def value_problem(field_type: FieldType, value: Any) -> str | None:
    """Return why a value cannot be a default of the type, or None.

    The YAML types of the values are checked here; rosidl_adapter then judges
    the value as the .msg file will spell it (ranges, bounds, sizes).
    """
    if field_type.message is not None:
        return 'fields of message types cannot have a default value'
    if field_type.array is not None:
        if not isinstance(value, list):
            return f'the default of an array field must be a list, not {value!r}'
        for item in value:
            problem = _kind_problem(field_type, item) or \
                _string_item_problem(field_type, item)
            if problem:
                return problem
    else:
        problem = _kind_problem(field_type, value)
        if problem:
            return problem
    refusal = rosidl.value_refusal(str(field_type), msg_literal(value))
    return None if refusal is None else _refusal_problem(field_type, value, refusal)


def msg_literal(value: Any) -> str:
    """Write a default or constant value in .msg syntax."""
    if isinstance(value, list):
        return '[' + ', '.join(msg_literal(v) for v in value) + ']'
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, str):
        # rosidl_adapter unescapes inner quotes, then passes the value through
        # Python's unicode_escape codec into an IDL string literal, whose
        # parser unescapes backslashes twice: eight backslashes read back as
        # one. The model refuses what no spelling carries (value_problem).
        return '"' + value.replace('\\', '\\' * 8).replace('"', '\\"') + '"'
    return repr(value)


def _refusal_problem(field_type: FieldType, value: Any, refusal: str) -> str:
    """Say why rosidl refuses a value of the right YAML type, in the model's words."""
    size = field_type.array_size
    if isinstance(value, list):
        if field_type.array == 'fixed' and len(value) != size:
            return f'the default must have exactly {size} items, not {len(value)}'
        if field_type.array == 'bounded' and len(value) > (size or 0):
            return f'the default must have at most {size} items, not {len(value)}'
        element = FieldType(primitive=field_type.primitive,
                            string_bound=field_type.string_bound)
        for item in value:
            item_refusal = rosidl.value_refusal(element.base_name, msg_literal(item))
            if item_refusal is not None:
                return _refusal_problem(element, item, item_refusal)
    primitive, bound = field_type.primitive, field_type.string_bound
    if isinstance(value, str) and bound is not None:
        if len(value) > bound:
            return f'the string is longer than its bound of {bound}'
        return (f'the string {value!r} fits its bound of {bound}, but not as the .msg '
                'file spells it, with its backslashes and quotes escaped, which is what '
                'rosidl checks against the bound')
    if isinstance(value, int) and primitive is not None:
        low, high = _integer_range(primitive)
        return f'{value} is out of the range of {primitive} ({low}..{high})'
    return f'rosidl refuses the value: {refusal}'


def _integer_range(primitive: str) -> tuple[int, int]:
    """Return the range rosidl checks an integer type against, for the message.

    rosidl_adapter tells it only inside the text of its exception.
    """
    if primitive in ('byte', 'char'):
        return 0, 255
    bits = int(primitive.removeprefix('u').removeprefix('int'))
    if primitive.startswith('u'):
        return 0, 2 ** bits - 1
    return -2 ** (bits - 1), 2 ** (bits - 1) - 1


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


def _kind_problem(field_type: FieldType, value: Any) -> str | None:
    """Return why a YAML value is not of the kind of the type, or None.

    rosidl reads text, the model YAML values: that a bool field has a bool
    (rosidl would read 1 as true) and a number field a number is ours to
    check, and so is what no .msg spelling carries (rosidl cannot tell: it
    reads a line cut at its '#').
    """
    primitive = field_type.primitive
    assert primitive is not None
    if primitive == 'bool':
        return None if isinstance(value, bool) else \
            f'{value!r} is not a bool (true or false)'
    if primitive in ('string', 'wstring'):
        if not isinstance(value, str):
            return f'{value!r} is not a string'
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
        # rosidl_adapter reads inf and nan, which its C++ and Python
        # generators cannot spell as literals
        if not math.isfinite(value):
            return f'{value!r} is not a finite number'
        return None
    if isinstance(value, bool) or not isinstance(value, int):
        return f'{value!r} is not an integer'
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
