# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Starting models (``colcon robmosys-new``): commented, valid, ready to build.

A starting model is a template of ``templates/starter/`` fed by a context of
this module; the decisions (names, the type a component exchanges, how a
system wires its instances) are made here, where they can be tested.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterable, Sequence

from colcon_robmosys.check.qos import qos_incompatibility
from colcon_robmosys.generators.filters import yaml_value
from colcon_robmosys.generators.render import render
from colcon_robmosys.mapping.backends import backend
from colcon_robmosys.model.names import identifier_problem, package_problem
from colcon_robmosys.model.schema import schema
from colcon_robmosys.model.types import (
    Component, Language, Maintainer, Pattern, Port, Role)

__all__ = ['class_name', 'KINDS', 'Maintainer', 'name_problems', 'render_starter',
           'starter_component', 'starter_system', 'StarterComponent', 'StarterDefinition',
           'StarterInfo', 'StarterInstance', 'StarterSystem']

#: the kinds of starting model, as the verb names them
KINDS = ('definition', 'component', 'system')
#: the message of a starting service definition, which a starting component
#: uses when it is given the definition's package
STARTER_MESSAGE = 'Sample'
#: its text field; std_msgs/msg/String's is ``data``
STARTER_TEXT_FIELD = 'text'
#: what a starting component exchanges without a service definition of its own
DEFAULT_TYPE = ('std_msgs', 'String', 'data')


@dataclass(frozen=True)
class StarterInfo:
    """What every starting model holds: its package and its metadata."""

    package: str
    license: str
    maintainers: tuple[Maintainer, ...]

    @property
    def schema_uri(self) -> str:
        """Return the ``$id`` of the format's JSON Schema, for the editor modeline."""
        return str(schema()['$id'])


@dataclass(frozen=True)
class StarterDefinition:
    """The context of a starting service definition."""

    info: StarterInfo
    #: the names a starting component relies on (``--interfaces``)
    message: str = STARTER_MESSAGE
    text_field: str = STARTER_TEXT_FIELD


@dataclass(frozen=True)
class StarterComponent:
    """The context of a starting component."""

    info: StarterInfo
    name: str
    language: str
    #: what the component says and does in its language (its backend's)
    starter: str
    #: the package of the message the component exchanges
    message_package: str
    message: str
    #: a string field of the message, which the component fills
    text_field: str

    @property
    def message_type(self) -> str:
        """Return the type of the component's ports."""
        return f'{self.message_package}/msg/{self.message}'


@dataclass(frozen=True)
class StarterInstance:
    """An instance of a starting system, and the parameters it could override."""

    name: str
    component: str
    #: (name, type, default as YAML) of each parameter of the component
    parameters: tuple[tuple[str, str, str], ...]


@dataclass(frozen=True)
class StarterSystem:
    """The context of a starting system."""

    info: StarterInfo
    instances: tuple[StarterInstance, ...]
    #: ('instance.port' provided, 'instance.port' required)
    connections: tuple[tuple[str, str], ...]
    #: 'instance.port' of each required port nothing among the instances provides
    unconnected: tuple[str, ...]
    #: the instances a mode may make active (lifecycle nodes); none: no modes
    managed: tuple[str, ...] = ()


def name_problems(kind: str, name: str) -> list[str]:
    """Return why a name cannot name a starting model of a kind, by the checks' rules."""
    problem = package_problem(name)
    if problem:
        return [f"'{name}' {problem}"]
    if kind == 'component':
        problem = identifier_problem(class_name(name))
        if problem:
            return [f"the class name '{class_name(name)}' made of '{name}' {problem}"]
    return []


def class_name(package: str) -> str:
    """Return the CamelCase class name of a component package (``my_node``: MyNode)."""
    return ''.join(part[:1].upper() + part[1:] for part in package.split('_'))


def starter_component(info: StarterInfo, language: Language,
                      interfaces: str | None) -> StarterComponent:
    """Return a starting component: it publishes a message and receives it back.

    :param interfaces: the package of a starting service definition, whose
      message the component exchanges (otherwise std_msgs/msg/String)
    """
    package, message, field = DEFAULT_TYPE if interfaces is None else (
        interfaces, STARTER_MESSAGE, STARTER_TEXT_FIELD)
    return StarterComponent(info, class_name(info.package), language.value,
                            backend(language).starter, package, message, field)


def starter_system(info: StarterInfo, components: Sequence[Component],
                   modes: bool = False) -> StarterSystem:
    """Return a starting system: one instance per component, wired where it can be.

    With modes, it starts with two: every managed instance active, and none.

    Each required port is connected to a provided port of the same pattern
    and type whose QoS it can match, of another instance first, else of its
    own (a starting component receives what it publishes); a required port
    that nothing provides is named in a comment.
    """
    names: list[str] = []
    for component in components:
        name, number = component.package, 2
        while name in names:
            name, number = f'{component.package}_{number}', number + 1
        names.append(name)
    connections, unconnected = [], []
    for name, component in zip(names, components):
        for port in component.ports:
            if port.role is not Role.REQUIRED:
                continue
            provider = _provider(port, name, zip(names, components))
            if provider is None:
                unconnected.append(f'{name}.{port.name}')
            else:
                connections.append((provider, f'{name}.{port.name}'))
    instances = tuple(StarterInstance(name, c.package, tuple(
        (p.name, p.type, yaml_value(p.default)) for p in c.parameters))
        for name, c in zip(names, components))
    managed = tuple(n for n, c in zip(names, components) if c.lifecycle_node) if modes else ()
    return StarterSystem(info, instances, tuple(connections), tuple(unconnected), managed)


def _provider(port: Port, own: str,
              candidates: Iterable[tuple[str, Component]]) -> str | None:
    """Return 'instance.port' of the provided port a required port connects to."""
    found = []
    for name, component in candidates:
        for other in component.ports:
            if other.role is Role.PROVIDED and other.pattern is port.pattern and \
                    other.type == port.type and _qos_match(other, port):
                found.append((name == own, f'{name}.{other.name}'))
    return min(found)[1] if found else None


def _qos_match(provided: Port, required: Port) -> bool:
    if provided.pattern in (Pattern.QUERY, Pattern.ACTION):
        return True
    writer, reader = (required, provided) if provided.pattern is Pattern.SEND else \
        (provided, required)
    return qos_incompatibility(writer.qos, reader.qos) is None


#: context class -> its template
TEMPLATES: dict[type[Any], str] = {
    StarterDefinition: 'starter/definition.yaml.jinja',
    StarterComponent: 'starter/component.yaml.jinja',
    StarterSystem: 'starter/system.yaml.jinja',
}


def render_starter(context: StarterDefinition | StarterComponent | StarterSystem) -> str:
    """Return the text of a starting model."""
    return render(TEMPLATES[type(context)], context)
