# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Rules on types: every interface a model names exists, and is of its kind."""

from __future__ import annotations

from colcon_robmosys.check.context import CheckContext
from colcon_robmosys.model.types import (
    Component, InterfaceKind, InterfaceRef, Pattern, Port, ServiceDefinition)


def check_definitions(ctx: CheckContext) -> None:
    """Check that the fields of every service definition name interfaces that exist.

    An external one (a description of an installed package): that the
    package and each interface it describes are installed.
    """
    for definition in ctx.definitions.values():
        _check_definition(ctx, definition)


def check_components(ctx: CheckContext) -> None:
    """Check the type of every port of every component, and the packages it depends on.

    A port whose type is wrong is recorded (``ctx.mistyped``): the rules of
    systems report nothing that follows from it.
    """
    for component in ctx.components.values():
        _check_component(ctx, component)


def _interface_problem(ctx: CheckContext, ref: InterfaceRef) -> str | None:
    if ref.package in ctx.broken_packages:
        return None
    definition = ctx.definitions.get(ref.package)
    if definition is not None:
        names = {
            InterfaceKind.MSG: [c.name for c in
                                definition.communication_objects],
            InterfaceKind.SRV: [q.name for q in definition.queries],
            # an event is an action of ROS 2 too
            InterfaceKind.ACTION: [a.name for a in definition.actions] +
            [e.name for e in definition.events],
        }[ref.kind]
        if ref.name in names:
            return None
        known = ', '.join(names) or 'none'
        return (f"unknown type '{ref}': service definition "
                f"'{ref.package}' defines no {ref.kind.value} "
                f"'{ref.name}' (its {ref.kind.value} types: {known})")
    if ref.package in ctx.models:
        return (f"unknown type '{ref}': package '{ref.package}' is not "
                'a service definition')
    if ctx.index.has_interface(ref):
        return None
    if ctx.index.has_package(ref.package):
        return (f"unknown type '{ref}': the installed package "
                f"'{ref.package}' has no such interface")
    return (f"unknown type '{ref}': package '{ref.package}' is neither "
            'a service definition of this workspace nor installed in '
            'AMENT_PREFIX_PATH')


def _event_problem(ctx: CheckContext, port: Port) -> str | None:
    """Tell when an event port names a plain action, or the reverse."""
    definition = ctx.definitions.get(port.type.package)
    if definition is None or port.pattern not in (Pattern.EVENT,
                                                  Pattern.ACTION):
        return None
    events = {e.name for e in definition.events}
    if port.pattern is Pattern.EVENT and port.type.name not in events:
        return (f"'{port.type}' is an action, not an event: an event "
                f"port names an entry of 'events' of '{definition.package}'")
    if port.pattern is Pattern.ACTION and port.type.name in events:
        return (f"'{port.type}' is an event: name it from an event port "
                '(pattern: event)')
    return None


def _check_definition(ctx: CheckContext, definition: ServiceDefinition) -> None:
    if definition.external:
        _check_installed(ctx, definition)
    structures = [o.structure for o in definition.communication_objects]
    structures += [s for q in definition.queries
                   for s in (q.request, q.answer)]
    structures += [s for a in definition.actions
                   for s in (a.goal, a.result, a.feedback)]
    structures += [s for e in definition.events
                   for s in (e.activation, e.event)]
    for structure in structures:
        for field_ in structure.fields:
            ref = field_.type.message
            if ref is None:
                continue
            problem = _interface_problem(ctx, ref)
            if problem:
                ctx.error(field_.location,
                          f"field '{field_.name}': {problem}")


def _check_installed(ctx: CheckContext, definition: ServiceDefinition) -> None:
    """Check that an external service definition describes an installed package."""
    package = definition.package
    if not ctx.index.has_package(package):
        ctx.error(definition.info.location,
                  f"service definition '{package}' is external, but no package "
                  f"'{package}' is installed in AMENT_PREFIX_PATH")
        return
    parts = [(InterfaceKind.MSG, o.name, o.location)
             for o in definition.communication_objects]
    parts += [(InterfaceKind.SRV, q.name, q.location) for q in definition.queries]
    parts += [(InterfaceKind.ACTION, a.name, a.location) for a in definition.actions]
    for kind, name, location in parts:
        if not ctx.index.has_interface(InterfaceRef(package, kind, name)):
            ctx.error(location, f"the installed package '{package}' has no "
                      f"{kind.value} '{name}'")


def _check_component(ctx: CheckContext, component: Component) -> None:
    for port in component.ports:
        problem = _interface_problem(ctx, port.type) or \
            _event_problem(ctx, port)
        if problem:
            ctx.error(port.type_location or port.location,
                      f"port '{port.name}': {problem}")
            ctx.mistyped.add(port.location)
    info = component.info
    for package, location in zip(info.depends, info.depends_locations):
        if package not in ctx.models and \
                package not in ctx.broken_packages and \
                not ctx.index.has_package(package):
            ctx.error(location,
                      f"component '{component.name}' depends on "
                      f"unknown package '{package}' (a rosdep key of a "
                      "system dependency goes in 'system_depends')")
