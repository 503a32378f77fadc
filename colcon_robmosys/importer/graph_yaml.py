# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""YAML that reads as if written by hand: flow style where a line holds it, comments kept.

PyYAML writes no comments; an imported model says in comments what the graph
could not tell. Every value is written by PyYAML's safe dumper, so any text a
node reports (a parameter's value or description) stays text.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import textwrap
from typing import Any

import yaml

#: the longest line written in flow style
WIDTH = 99


@dataclass
class Commented:
    """A value with comments: above its key, and at the end of its line."""

    value: Any
    above: list[str] = field(default_factory=list)
    after: str = ''


def flow(value: Any) -> str:
    """Return a value in YAML flow style, on one line."""
    text = yaml.safe_dump(value, default_flow_style=True, width=2 ** 31, allow_unicode=True,
                          sort_keys=False)
    return text[:-len('\n...\n')] if text.endswith('\n...\n') else text.rstrip('\n')


def dump(data: dict[str, Any], header: list[str]) -> str:
    """Return a document: the header comment lines, then the mapping."""
    lines = [_comment(line, '') for line in header]
    _mapping(data, '', lines)
    return '\n'.join(lines) + '\n'


def _comment(text: str, indent: str) -> str:
    # what a node reports cannot start a line of its own: newlines are folded
    return '\n'.join(textwrap.wrap(' '.join(text.split()), WIDTH,
                                   initial_indent=f'{indent}# ',
                                   subsequent_indent=f'{indent}#   ',
                                   break_long_words=False, break_on_hyphens=False))


def _mapping(data: dict[str, Any], indent: str, lines: list[str]) -> None:
    for key, value in data.items():
        _entry(flow(key) + ':', value, indent, lines)


def _entry(prefix: str, value: Any, indent: str, lines: list[str]) -> None:
    after = ''
    if isinstance(value, Commented):
        lines.extend(_comment(line, indent) for line in value.above)
        after = f'  # {value.after}' if value.after else ''
        value = value.value
    plain = _plain(value)
    line = f'{indent}{prefix} {flow(plain)}'
    if not isinstance(value, (dict, list)) or not _has_comments(value) and len(line) <= WIDTH:
        lines.append(line + after)
        return
    lines.append(f'{indent}{prefix}{after}')
    if isinstance(value, dict):
        _mapping(value, indent + '  ', lines)
        return
    for item in value:
        if isinstance(item, (dict, Commented)):
            _item(item, indent + '  ', lines)
        else:
            lines.append(f'{indent}  - {flow(_plain(item))}')


def _item(item: Any, indent: str, lines: list[str]) -> None:
    """Write a mapping of a list, its first key on the line of the dash."""
    if isinstance(item, Commented):
        lines.extend(_comment(line, indent) for line in item.above)
        item = item.value
    line = f'{indent}- {flow(_plain(item))}'
    if not _has_comments(item) and len(line) <= WIDTH:
        lines.append(line)
        return
    inner: list[str] = []
    _mapping(item, indent + '  ', inner)
    first = next(i for i, text in enumerate(inner) if not text.lstrip().startswith('#'))
    inner[first] = f'{indent}- {inner[first][len(indent) + 2:]}'
    lines.extend(inner)


def _plain(value: Any) -> Any:
    """Return a value without its comments."""
    if isinstance(value, Commented):
        return _plain(value.value)
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_plain(item) for item in value]
    return value


def _has_comments(value: Any) -> bool:
    if isinstance(value, Commented):
        return True
    if isinstance(value, dict):
        return any(_has_comments(item) for item in value.values())
    if isinstance(value, list):
        return any(_has_comments(item) for item in value)
    return False
