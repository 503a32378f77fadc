# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Jinja filters: every model string that reaches a file is escaped here."""

from __future__ import annotations

import json
import re
import textwrap
from typing import Any, Callable
from xml.sax.saxutils import escape as _xml_escape

from colcon_robmosys.mapping.literals import cpp_str, split_literal


def xml(text: Any) -> str:
    """Escape text for XML element content and attribute values.

    A carriage return is written as a character reference: XML parsers
    turn a raw one into a newline.
    """
    return _xml_escape(str(text), {'"': '&quot;', "'": '&apos;',
                                   '\r': '&#13;'})


def xml_attr(text: Any) -> str:
    """Escape text for an XML attribute value, keeping its white space.

    Parsers replace raw tabs and newlines in attribute values by spaces.
    """
    return xml(text).replace('\n', '&#10;').replace('\t', '&#9;')


def xml_comment(text: Any) -> str:
    """Make text safe inside an XML comment: no ``--``, no final ``-``."""
    text = ' '.join(str(text).splitlines())
    while '--' in text:
        text = text.replace('--', '- -')
    return text + ' ' if text.endswith('-') else text


def hash_comment(text: Any) -> str:
    """Turn text into ``#`` comment lines (.msg, Python, YAML, CMake)."""
    lines = str(text).strip().splitlines() or ['']
    return '\n'.join(('# ' + line).rstrip() for line in lines)


def msg_comment(text: Any) -> str:
    """Turn text into the ``#`` lines of a .msg, .srv or .action file.

    rosidl reads each comment line back as the same text in the IDL it makes,
    the C headers and every generator: rosidl_adapter passes the line
    through Python's ``unicode_escape`` codec and writes it into an IDL
    string literal, whose parser unescapes backslashes twice, so each
    backslash is written as eight. Non-ASCII text needs nothing: the adapter
    writes its IDL as Latin-1 and the parser reads it as UTF-8, which undoes
    the codec's mangling. What no spelling carries (``*/`` and a line ending
    in a backslash, in the C comments rosidl_generator_c writes) the check
    refuses (model/fieldtypes.py).
    """
    return hash_comment(str(text).replace('\\', '\\' * 8))


def py_str(text: Any) -> str:
    """Write a Python string literal (single quotes where possible)."""
    return repr(str(text))


#: the line length of ament_flake8 (and of our own code)
LINE_LENGTH = 99


def py_literal(value: Any, indent: int, prefix: int = 0) -> str:
    """Write a Python literal whose lines fit ament_flake8's line length.

    The literal starts after ``indent`` spaces and ``prefix`` more characters
    and is followed by one character (a comma or a parenthesis). A string
    that does not fit becomes adjacent literals in parentheses, a list or a
    tuple one item per line; the value the literal evaluates to stays the
    same.
    """
    text = repr(value)
    if len(text) + indent + prefix + 1 <= LINE_LENGTH or \
            not isinstance(value, (str, list, tuple)):
        return text
    inner = indent + 4
    pad = ' ' * inner
    if isinstance(value, str):
        lines = [pad + part for part in split_literal(value, LINE_LENGTH - inner, repr)]
        return '(\n' + '\n'.join(lines) + '\n' + ' ' * indent + ')'
    lines = [pad + py_literal(item, inner) + ',' for item in value]
    brackets = '[]' if isinstance(value, list) else '()'
    return brackets[0] + '\n' + '\n'.join(lines) + '\n' + ' ' * indent + brackets[1]


def py_docstring(text: Any, indent: int = 0) -> str:
    """Write a PEP 257 docstring, quotes included: summary line, then body.

    The summary ends with a period. A multi-line docstring starts on the
    line after the quotes, as the ament convention of pep257 wants (D213).
    The docstring holds the text exactly: it is raw when the text has a
    backslash (pep257's D301), and takes the quotes the text does not use.
    """
    lines = str(text).strip().splitlines() or ['']
    summary, body = lines[0].strip(), [line.rstrip() for line in lines[1:]]
    if summary and summary[-1] not in '.?!':
        summary += '.'
    while body and not body[0]:
        body.pop(0)
    if body:
        pad = ' ' * indent
        # long lines of the model's text are wrapped to the line length of
        # ament_flake8
        width = max(LINE_LENGTH - indent, 40)
        wrapped = [part for line in body
                   for part in (textwrap.wrap(line, width,
                                              break_long_words=False,
                                              break_on_hyphens=False)
                                if len(line) > width else [line])]
        rest = '\n'.join(pad + line if line else '' for line in wrapped)
        content = f'\n{pad}{summary}\n\n{rest}\n{pad}'
    else:
        content = summary
    quotes = '"""' if '"""' not in content else "'''"
    if quotes in content:
        # both kinds of triple quotes: escape, the only way left
        return '"""' + content.replace('\\', '\\\\').replace(
            '"""', '\\"\\"\\"') + '"""'
    prefix = 'r' if '\\' in content else ''
    return f'{prefix}{quotes}{content}{quotes}'


#: What a YAML double-quoted scalar must escape: its quote, backslash and
#: every character YAML does not allow raw or reads as a line break.
_YAML_ESCAPED = re.compile(
    '["\\\\\x00-\x1f\x7f-\x9f\u2028\u2029\ud800-\udfff\ufffe\uffff]')


def _yaml_escape(match: re.Match[str]) -> str:
    char = match.group()
    if char in '"\\':
        return '\\' + char
    code = ord(char)
    return f'\\x{code:02x}' if code < 0x100 else f'\\u{code:04x}'


def yaml_value(value: Any) -> str:
    """Write a value as a YAML flow scalar or sequence.

    Strings are double-quoted, with escapes only where YAML needs them, so
    that the file reads back exactly the text of the model.
    """
    if isinstance(value, (tuple, list)):
        return '[' + ', '.join(yaml_value(v) for v in value) + ']'
    if isinstance(value, str):
        return '"' + _YAML_ESCAPED.sub(_yaml_escape, value) + '"'
    return json.dumps(value)


def cpp_comment(text: Any, prefix: str = '//') -> str:
    """Turn text into C++ line comments (``//``, or ``///`` for Doxygen).

    A comment line ending in a backslash would continue onto the next line
    of code, so such a line gets a closing period.
    """
    lines = str(text).strip().splitlines() or ['']
    out = []
    for line in lines:
        line = f'{prefix} {line}'.rstrip()
        # ('??/' is a backslash where a compiler still reads trigraphs)
        if line.endswith(('\\', '??/')):
            line += '.'
        out.append(line)
    return '\n'.join(out)


_CMAKE_ESCAPES = {'\\': '\\\\', '"': '\\"', '$': '\\$', '\n': '\\n',
                  '\r': '\\r', '\t': '\\t'}


def cmake_str(text: Any) -> str:
    """Write a quoted CMake argument: no variable or generator expansion.

    A quoted argument is never split at semicolons, so they stay as they
    are (an escaped one would keep its backslash there).
    """
    return '"' + ''.join(_CMAKE_ESCAPES.get(c, c) for c in str(text)) + '"'


def dot_str(text: Any) -> str:
    """Write a Graphviz double-quoted string."""
    return '"' + str(text).replace('\\', '\\\\').replace('"', '\\"') \
        .replace('\\\\n', '\\n') + '"'


#: what a Markdown text escapes with a backslash: what could start markup, a
#: table cell's end, an HTML tag or an entity (CommonMark escapes any ASCII
#: punctuation so)
_MARKDOWN_ESCAPED = re.compile(r'([\\`*_{}\[\]()#+\-!|<>&~])')


def md_text(text: Any) -> str:
    """Write text as Markdown text that renders as itself, in a table cell too.

    Line breaks become ``<br>`` (a cell is one line), after the text is
    escaped, so the only tags are those.
    """
    escaped = _MARKDOWN_ESCAPED.sub(r'\\\1', str(text))
    return '<br>'.join(line.strip() for line in escaped.strip().splitlines())


FILTERS: dict[str, Callable[..., str]] = {
    'xml': xml,
    'xml_attr': xml_attr,
    'xml_comment': xml_comment,
    'msg_comment': msg_comment,
    'hash_comment': hash_comment,
    'py_str': py_str,
    'py_literal': py_literal,
    'py_docstring': py_docstring,
    'yaml_value': yaml_value,
    'cpp_str': cpp_str,
    'cpp_comment': cpp_comment,
    'cmake_str': cmake_str,
    'dot_str': dot_str,
    'md_text': md_text,
}
