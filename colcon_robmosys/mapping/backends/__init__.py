# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The language backends, one per language a component may be written in.

A new language is a backend (a subpackage here: its spelling, its file
tables, its checks), a template folder (``templates/component_<language>``),
its part of the runtime, and one row in :data:`BACKENDS`.

One table, not entry points as colcon finds its extensions: the model's
``Language`` and the schema name every language, and a backend's templates
and runtime are package data of this distribution, so no other distribution
could add one; the table is typed and costs discovery nothing.
"""

from __future__ import annotations

from typing import Iterable

from colcon_robmosys.mapping.backends.base import Backend, NodeStart, PackageFacts
from colcon_robmosys.mapping.backends.cpp import CppBackend
from colcon_robmosys.mapping.backends.python import PythonBackend
from colcon_robmosys.mapping.component import plan_component
from colcon_robmosys.mapping.portkinds import PortKind
from colcon_robmosys.model.types import Component, Executor, Language

#: language -> its backend
BACKENDS: dict[Language, Backend] = {
    Language.CPP: CppBackend(),
    Language.PYTHON: PythonBackend(),
}

#: every package a backend may need from the ROS 2 prefix
PREFIX_PACKAGES = tuple(dict.fromkeys(
    name for backend in BACKENDS.values() for name in backend.prefix_packages))

#: language -> the executor of its components that name none and block no
#: thread, for mapping/executors.py (it lies under the backends: it cannot ask them)
DEFAULT_EXECUTORS: dict[Language, Executor] = {
    language: backend.default_executor for language, backend in BACKENDS.items()}


def backend(language: Language) -> Backend:
    """Return the backend of a language."""
    return BACKENDS[language]


def prefix_dependencies(language: str, kinds: Iterable[PortKind]) -> tuple[str, ...]:
    """Return the prefix packages a component is built with, by its language's name.

    A name no backend has (a model the check refuses) needs none.
    """
    try:
        known = Language(language)
    except ValueError:
        return ()
    return backend(known).prefix_dependencies(kinds)


def node_start(component: Component) -> NodeStart:
    """Return how a process of several instances creates a component's node.

    Neither for an external component: its package is the user's.
    """
    if component.external:
        return NodeStart()
    language = backend(component.language)
    return language.node_start(plan_component(component, language.default_executor))


__all__ = ['Backend', 'BACKENDS', 'backend', 'DEFAULT_EXECUTORS', 'NodeStart', 'node_start',
           'PackageFacts', 'prefix_dependencies', 'PREFIX_PACKAGES']
