# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Literals of C++ and Python: the spelling tables write values with these.

The template filters (:mod:`colcon_robmosys.generators.filters`) use them too.
"""

from __future__ import annotations

from typing import Any, Callable


def split_literal(text: str, width: int,
                  quote: Callable[[str], str]) -> list[str]:
    """Split text into quoted literals of at most ``width`` characters each.

    Python and C++ join adjacent literals back into the text. A split falls
    between characters, never inside an escape, and at a space where one
    allows it, so that words stay whole; a character whose escape alone is
    wider than ``width`` still gets a literal of its own.
    """
    parts, start = [], 0
    while start < len(text):
        end = start + 1
        while end < len(text) and len(quote(text[start:end + 1])) <= width:
            end += 1
        space = text.rfind(' ', start + 1, end)
        if end < len(text) and space != -1:
            end = space + 1
        parts.append(quote(text[start:end]))
        start = end
    return parts


_CPP_ESCAPES = {'\\': '\\\\', '"': '\\"', '\n': '\\n', '\t': '\\t',
                '\r': '\\r', '?': '\\?'}


def cpp_str(text: Any) -> str:
    r"""Write a C++ string literal, in plain ASCII.

    Other bytes of the UTF-8 text become three-digit octal escapes, which
    (unlike ``\x``) cannot swallow the character that follows; ``?`` is
    escaped so that no trigraph forms.
    """
    out = []
    for char in str(text):
        if char in _CPP_ESCAPES:
            out.append(_CPP_ESCAPES[char])
        elif ' ' <= char <= '~':
            out.append(char)
        else:
            out.extend(f'\\{byte:03o}' for byte in char.encode('utf-8'))
    return '"' + ''.join(out) + '"'
