# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The fast path of the loader: plain models straight from libyaml's events."""

from __future__ import annotations

from pathlib import Path
import re
from typing import Any

import yaml

from colcon_robmosys.errors import Location
from colcon_robmosys.model.loaded import (
    MAX_MODEL_DEPTH, MAX_MODEL_NODES, NodePath, NOT_PRINTABLE)

#: libyaml's parser, where PyYAML was built with it (about ten times as
#: fast as the Python one); None where it was not.
CLoader: Any = getattr(yaml, 'CSafeLoader', None)

_STR_TAG = 'tag:yaml.org,2002:str'
#: What PyYAML's reader refuses in a text (yaml.reader.Reader.NON_PRINTABLE).
_READER_REFUSES = re.compile(
    '[^\x09\x0A\x0D\x20-\x7E\x85\xA0-\uD7FF\uE000-\uFFFD'
    '\U00010000-\U0010ffff]')


class Unusual(Exception):
    """The text needs the complete loader: an error, an alias, a merge..."""


class FastBuilder:
    """Build plain data and marks straight from libyaml's events.

    Only for the texts models consist of: mappings with string keys, lists,
    scalars, no anchor or alias, no problem at all. Anything else raises
    :class:`Unusual`, and the complete loader (which reports every problem
    with its location) loads the text instead; so both give the same
    result, the fast one only sooner. Events come in a flat stream, built
    with an explicit stack: no recursion, however deep the text nests.
    """

    def __init__(self, path: Path, text: str):
        self._display = str(path)
        self._text = text
        self._lines: list[str] | None = None
        self.value_marks: dict[NodePath, Location] = {}
        self.key_marks: dict[NodePath, Location] = {}

    def _value_location(self, event: Any) -> Location:
        mark = event.start_mark
        if event.style not in ('|', '>'):
            return Location(self._display, mark.line + 1, mark.column + 1)
        # as _Builder.value_location: a block's text starts on the next line
        if self._lines is None:
            self._lines = self._text.split('\n')
        first = mark.line + 1
        indent = next((len(line) - len(line.lstrip(' '))
                       for line in self._lines[first:event.end_mark.line + 1]
                       if line.strip()), mark.column)
        return Location(self._display, first + 1, indent + 1)

    def build(self) -> Any:
        """Return the data of the text's one document.

        :raises Unusual: if the text needs the complete loader
        """
        text = self._text
        # a byte order mark shifts libyaml's columns; PyYAML refuses tabs in
        # places where libyaml takes them, and characters libyaml reads
        if text.startswith('\ufeff') or '\t' in text or \
                _READER_REFUSES.search(text):
            raise Unusual()
        loader = CLoader(text)
        try:
            return self._build(loader)
        except yaml.YAMLError:
            raise Unusual() from None
        finally:
            loader.dispose()

    def _build(self, loader: Any) -> Any:  # noqa: C901 - one loop over events
        get_event = loader.get_event
        display = self._display
        value_marks, key_marks = self.value_marks, self.key_marks
        get_event()  # stream start
        if not isinstance(get_event(), yaml.DocumentStartEvent):
            raise Unusual()  # no document: the complete loader says so
        # per open collection: its data, its path, and for a mapping the key
        # waiting for its value (None: the next scalar is a key)
        stack: list[tuple[Any, NodePath, list[Any]]] = []
        nodes = 0
        root: Any = None
        while True:
            event = get_event()
            kind = type(event)
            if kind is yaml.MappingEndEvent or kind is yaml.SequenceEndEvent:
                stack.pop()
                if not stack:
                    break
                continue
            if kind is yaml.AliasEvent or event.anchor is not None or \
                    event.tag is not None:
                # aliases, anchors and tags: seldom in a model, and where
                # libyaml and PyYAML differ (e.g. a lone '!')
                raise Unusual()
            nodes += 1
            if nodes > MAX_MODEL_NODES or len(stack) >= MAX_MODEL_DEPTH:
                raise Unusual()
            if stack:
                container, path, pending = stack[-1]
                if type(container) is dict:
                    if pending[0] is None:
                        # a key: a plain string, said once
                        if kind is not yaml.ScalarEvent or \
                                _scalar_tag(loader, event) != _STR_TAG or \
                                event.value in container or \
                                NOT_PRINTABLE.search(event.value):
                            raise Unusual()
                        pending[0] = event
                        continue
                    key_event = pending[0]
                    pending[0] = None
                    key = key_event.value
                    here = path + (key,)
                    mark = key_event.start_mark
                    key_marks[here] = Location(
                        display, mark.line + 1, mark.column + 1)
                else:
                    here = path + (len(container),)
                    mark = event.start_mark
                    key_marks[here] = Location(
                        display, mark.line + 1, mark.column + 1)
            else:
                container, here = None, ()
            if kind is yaml.ScalarEvent:
                value_marks[here] = self._value_location(event)
                value = _scalar(loader, event)
            elif kind is yaml.MappingStartEvent or \
                    kind is yaml.SequenceStartEvent:
                mark = event.start_mark
                value_marks[here] = Location(
                    display, mark.line + 1, mark.column + 1)
                value = {} if kind is yaml.MappingStartEvent else []
            else:
                raise Unusual()
            if container is None:
                root = value
            elif type(container) is dict:
                container[here[-1]] = value
            else:
                container.append(value)
            if kind is not yaml.ScalarEvent:
                stack.append((value, here, [None]))
            elif container is None:
                break
        get_event()  # document end
        if not isinstance(get_event(), yaml.StreamEndEvent):
            raise Unusual()  # another document: the complete loader says so
        return root


def _scalar_tag(loader: Any, event: Any) -> str:
    # what the implicit resolvers make of an untagged scalar
    tag: str = loader.resolve(yaml.ScalarNode, event.value, event.implicit)
    return tag


def _scalar(loader: Any, event: Any) -> Any:
    """Construct a scalar as the complete loader does."""
    tag = _scalar_tag(loader, event)
    if tag == _STR_TAG:
        value = event.value
        if NOT_PRINTABLE.search(value):
            raise Unusual()
        return value
    # what SafeConstructor makes of it; an unknown tag raises a YAMLError
    return loader.construct_object(yaml.ScalarNode(
        tag, event.value, event.start_mark, event.end_mark, event.style),
        deep=True)
