# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The one Jinja environment, and where the templates are found."""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import fields, is_dataclass
from functools import lru_cache
from pathlib import Path
import threading
from typing import Any

import jinja2

from colcon_robmosys.generators.filters import FILTERS


def templates_dir() -> Path:
    """Return the templates folder of the installed package.

    In a source checkout the folder is ``templates/`` at the top level; an
    installed package carries it as ``colcon_robmosys/templates``.
    """
    package_dir = Path(__file__).resolve().parent.parent
    installed = package_dir / 'templates'
    if installed.is_dir():
        return installed
    return package_dir.parent / 'templates'


@lru_cache(maxsize=1)
def environment() -> jinja2.Environment:
    """Return the Jinja environment shared by every generator."""
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(templates_dir())),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
        autoescape=False,
        # the templates are package data: no need to stat each one again
        # at every render to see whether it changed
        auto_reload=False,
    )
    env.filters.update(FILTERS)
    return env


#: The variables of the contexts rendered last: id -> (context, variables).
#: The context is kept with them, so that its id names no other object meanwhile.
_recent: OrderedDict[int, tuple[Any, dict[str, Any]]] = OrderedDict()

#: How many contexts :data:`_recent` keeps: more than the contexts of one package.
_RECENT = 8
_recent_lock = threading.Lock()


def variables(context: Any) -> dict[str, Any]:
    """Return the variables of a template: the fields and properties of a context.

    Contexts are frozen dataclasses of the mapping; a template reads their
    attributes as top-level names. The files of a package share a context:
    its properties (a system's bringup.json, say) are computed once for all
    of them, not once per file (which was half of the rendering).
    """
    with _recent_lock:
        kept = _recent.get(id(context))
        if kept is not None and kept[0] is context:
            _recent.move_to_end(id(context))
            return kept[1]
    if not is_dataclass(context) or isinstance(context, type):
        raise TypeError(f'a template context is a dataclass, not {context!r}')
    found = {name: getattr(context, name) for name in _names(type(context))}
    with _recent_lock:
        _recent[id(context)] = (context, found)
        if len(_recent) > _RECENT:
            _recent.popitem(last=False)
    return found


@lru_cache(maxsize=None)
def _names(cls: type) -> tuple[str, ...]:
    """Return the names of the fields and properties of a context class.

    Inherited ones too: a language's context derives from the shared one
    (:class:`~colcon_robmosys.mapping.context.ComponentContext`).
    """
    names = [f.name for f in fields(cls)]
    for base in reversed(cls.__mro__):
        names += [name for name, value in vars(base).items()
                  if isinstance(value, property) and name not in names]
    return tuple(names)


def render(template: str, context: Any) -> str:
    """Render one template with a typed context."""
    return environment().get_template(template).render(**variables(context))
