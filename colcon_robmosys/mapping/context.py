# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The context of a component's templates that no language spells differently.

It is built once, here, from the component's plan; a language backend
(:mod:`colcon_robmosys.mapping.backends`) derives its context class from
:class:`ComponentContext` and adds only its spelling: types, signatures,
imports, includes.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Iterable, Mapping, TypeVar

from colcon_robmosys.mapping.common import Banner, banner_of, package_xml, PackageXml
from colcon_robmosys.mapping.component import ComponentPlan
from colcon_robmosys.mapping.parameters import (
    camel, parameter_groups, parameter_page, ParameterGroup, ParameterPage)
from colcon_robmosys.mapping.userfiles import UserFolders
from colcon_robmosys.model.build_mapped import map_accessor
from colcon_robmosys.model.types import Component, Parameter


@dataclass(frozen=True)
class ParameterRange:
    """The range of a numeric parameter's descriptor, bounds as the language writes them."""

    #: the descriptor's field: integer_range or floating_point_range
    field: str
    #: the message class of the range, as the language names it
    cls: str
    start: str
    end: str
    step: str


@dataclass(frozen=True, kw_only=True)
class SpelledPort:
    """A port as every language creates it; ``type`` is the language's name of its interface."""

    name: str
    #: the entity it becomes (portkinds' Entity value)
    entity: str
    type: str
    description: str
    #: the activity it triggers, and that activity's functions
    activity: str | None
    functions: tuple[str, ...]


@dataclass(frozen=True, kw_only=True)
class SpelledFunction:
    """A function of the model as every language declares it."""

    name: str
    #: its return type, as the language writes it
    returns: str
    #: the embedded code, indented for its body; None: the user writes it
    code: str | None
    #: the text that documents it
    description: str


@dataclass(frozen=True, kw_only=True)
class SpelledActivity:
    """An activity as every language runs it."""

    name: str
    #: seconds between two runs, if periodic
    period: float | None
    functions: tuple[str, ...]
    description: str


@dataclass(frozen=True, kw_only=True)
class SpelledParameter:
    """A parameter as every language declares it: its accessor, range and rule."""

    name: str
    #: the text that documents its accessor
    doc: str
    range: ParameterRange | None
    #: the last part of its name: its accessor in its group
    attr: str = ''
    #: its ParameterRule as the language fills it (statements or arguments),
    #: none without rules beyond the descriptor
    rule: tuple[str, ...] = ()
    #: of a mapped parameter: the array it is repeated for, and its ROS 2 name
    #: with {} for the entry (``gains.{}.p``)
    for_each: str = ''
    pattern: str = ''
    #: no default: declared without a value, which the node needs to configure
    required: bool = False


@dataclass(frozen=True)
class EntryClass:
    """The class of the mapped parameters of one entry of an array, in a group.

    ``gains.p`` and ``gains.i`` repeated for each entry of ``joints`` are read
    as ``gains.joints_map['a'].p`` (Python), ``gains.joints_map().at("a").p()`` (C++).
    """

    cls: str
    doc: str
    #: the member of the group that maps each entry to its class (``joints_map``)
    accessor: str
    array: str
    parameters: tuple[SpelledParameter, ...]


@dataclass(frozen=True)
class MappedDeclarations:
    """The parameters a node declares for each entry of an array, once it has the array."""

    array: str
    #: the name of each, with {} for the entry: the node checks them before it declares them
    patterns: tuple[str, ...]
    parameters: tuple[SpelledParameter, ...]


@dataclass(frozen=True)
class GroupClass:
    """The class of a group of parameters: typed access, nested by dotted names."""

    #: its name, as the language names it
    cls: str
    doc: str
    parameters: tuple[SpelledParameter, ...]
    #: (accessor, class) of each subgroup
    groups: tuple[tuple[str, str], ...]
    #: the classes of the entries of arrays its mapped parameters are repeated for
    mapped: tuple[EntryClass, ...] = ()


#: a backend's class of a group
Group = TypeVar('Group', bound=GroupClass)


def group_classes(
        kind: type[Group], parameters: tuple[Parameter, ...],
        spelled: Mapping[str, SpelledParameter],
        names: Callable[[tuple[ParameterGroup, ...]], Mapping[tuple[str, ...], str]],
        doc: Callable[[tuple[str, ...]], str],
        entry_name: Callable[[tuple[str, ...]], str] = camel) -> tuple[Group, ...]:
    """Return the classes of the groups of parameters, a subgroup first, the root last.

    :param spelled: the parameters as the language spells them, by name
    :param names: the classes' names, by the path of their groups
    :param doc: the docstring of a group's class, by its path
    :param entry_name: the name of the class of an array's entries in a group,
      by the group's path and the array (made unique here)
    """
    groups = parameter_groups(parameters)
    named = names(groups)
    taken = set(named.values())

    def entry_class(path: tuple[str, ...], array: str) -> EntryClass:
        cls = entry_name(path + (array,))
        while cls in taken:
            cls += '_'
        taken.add(cls)
        where = '.'.join(path + ('<entry>', '*'))
        return EntryClass(
            cls, f'Typed access to the parameters {where} of one entry of {array}.',
            map_accessor(array), array, tuple(
                spelled[p.name] for p in parameters
                if p.for_each == array and p.path[:-1] == path))

    return tuple(kind(
        named[g.path], doc(g.path), tuple(spelled[p.name] for p in g.parameters),
        tuple((sub, named[g.path + (sub,)]) for sub in g.groups),
        tuple(entry_class(g.path, array) for array in g.mapped)) for g in groups)


def mapped_declarations(parameters: Iterable[SpelledParameter]
                        ) -> tuple[MappedDeclarations, ...]:
    """Return the mapped parameters to declare, by array, in the order of the model."""
    arrays = dict.fromkeys(p.for_each for p in parameters if p.for_each)
    return tuple(MappedDeclarations(
        array, tuple(p.pattern for p in parameters if p.for_each == array),
        tuple(p for p in parameters if p.for_each == array)) for array in arrays)


@dataclass(frozen=True, kw_only=True)
class ComponentContext:
    """What the templates of a component print, whatever its language."""

    banner: Banner
    package: str
    cls: str
    #: the class the executable instantiates: the user's, if they write functions
    node_cls: str
    #: the user implements functions in a class of theirs
    has_impl: bool
    #: the executor threads its process needs at least (ComponentPlan.threads)
    threads: int
    #: what spins the node in a process of its own: events, single-threaded or
    #: multi-threaded (ComponentPlan.executor)
    executor: str
    #: transition -> functions run on it (the transitions that run any)
    lifecycle: Mapping[str, tuple[str, ...]]
    #: where the user's files are, next to the model
    folders: UserFolders
    package_xml: PackageXml
    #: the parameters, spelled
    parameters: tuple[SpelledParameter, ...]
    #: functions of the component validate parameter values (on configure too)
    validates: bool
    #: the page of its parameters (doc/parameters.md), if it has any
    parameter_page: ParameterPage | None = None
    #: the skeleton or the user's file (impl templates)
    skeleton: bool = False

    @property
    def rules(self) -> tuple[SpelledParameter, ...]:
        """Return the parameters with rules beyond their descriptors (not the mapped ones)."""
        return tuple(p for p in self.parameters if p.rule and not p.for_each)

    @property
    def has_rules(self) -> bool:
        """Tell whether a parameter, mapped or not, has rules beyond its descriptor."""
        return any(p.rule for p in self.parameters)

    @property
    def declared(self) -> tuple[SpelledParameter, ...]:
        """Return the parameters declared once (not the mapped ones)."""
        return tuple(p for p in self.parameters if not p.for_each)

    @property
    def mapped(self) -> tuple[MappedDeclarations, ...]:
        """Return the mapped parameters, declared for each entry of their arrays."""
        return mapped_declarations(self.parameters)

    @property
    def required(self) -> tuple[str, ...]:
        """Return the names of the parameters without default: the node needs their values."""
        return tuple(p.name for p in self.parameters if p.required)


#: a backend's context class
Context = TypeVar('Context', bound=ComponentContext)


def component_context(context: type[Context], component: Component, plan: ComponentPlan,
                      folders: UserFolders, *, xml: Mapping[str, Iterable[str]],
                      **spelling: Any) -> Context:
    """Return the context of a component's templates: the shared part, and a backend's.

    :param context: the backend's context class
    :param xml: the package.xml's dependencies of the language (keywords of
      :func:`~colcon_robmosys.mapping.common.package_xml`)
    :param spelling: the backend's fields, the parameters among them
    """
    banner = banner_of(component)
    return context(
        banner=banner, package=plan.package, cls=plan.cls, node_cls=plan.node_cls,
        has_impl=plan.has_impl, threads=plan.threads, executor=plan.executor.value,
        lifecycle={t: f for t, f in plan.lifecycle if f}, folders=folders,
        package_xml=package_xml(banner, component.info, **xml),
        validates=any(p.validate for p in plan.parameters),
        parameter_page=parameter_page(component, banner), **spelling)
