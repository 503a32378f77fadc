# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Rules on systems: instances, connections, remapped names, overrides."""

from __future__ import annotations

from dataclasses import dataclass, field

from colcon_robmosys.check.activities import system_executor_problems
from colcon_robmosys.check.context import CheckContext
from colcon_robmosys.check.parameters import (
    everywhere_problems, override_problems, unset_problems)
from colcon_robmosys.check.qos import (
    check_connection_qos, check_qos_overrides, End, with_article as _a)
from colcon_robmosys.errors import Location
from colcon_robmosys.mapping.names import connection_name, node_name
from colcon_robmosys.mapping.portkinds import port_kind
from colcon_robmosys.model.types import (
    Component, Connection, Instance, model_key, Pattern, Port, PortRef, Role, System)


def check_systems(ctx: CheckContext) -> None:
    """Check what every system instantiates and connects, and the names it gives.

    An installed system was checked when its workspace built it; a workspace
    system that includes it is checked with its instances.
    """
    installed = {model_key(m) for f in ctx.files if f.installed for m in f.systems}
    for key, model in ctx.models.items():
        if isinstance(model, System) and key not in installed:
            _check_system(ctx, model)


def _managed(ctx: CheckContext, instance: Instance) -> bool:
    """Tell whether the system activates an instance: a lifecycle node, not left out."""
    component = ctx.components.get(instance.component)
    return instance.activate and (component is None or component.lifecycle_node)


def _check_system(ctx: CheckContext, system: System) -> None:
    components: dict[str, Component] = {}
    node_names: dict[str, str] = {}
    for instance in system.instances:
        if instance.component == system.package:
            ctx.error(instance.location,
                      f"instance '{instance.name}': package "
                      f"'{instance.component}' is this system itself, "
                      'not a component')
            continue
        component = ctx.components.get(instance.component)
        if component is None and \
                instance.component in ctx.broken_packages:
            continue
        if component is None:
            what = ('is not a component'
                    if instance.component in ctx.models
                    else 'is not a component of this workspace')
            ctx.error(instance.location,
                      f"instance '{instance.name}': package "
                      f"'{instance.component}' {what}")
            continue
        components[instance.name] = component
        fqn = node_name(instance.namespace, instance.node_name)
        if fqn in node_names:
            ctx.error(instance.location,
                      f"instance '{instance.name}' has the node name "
                      f"'{fqn}' of instance '{node_names[fqn]}'")
        node_names[fqn] = instance.name
        ctx.diagnostics += override_problems(instance, component, dict(system.parameters))
        ctx.diagnostics += unset_problems(system, instance, component)
        check_qos_overrides(ctx, instance, component)
        for after in instance.after:
            other = system.instance(after)
            if other is None:
                ctx.error(instance.after_location(after),
                          f"instance '{instance.name}' is activated "
                          f"after unknown instance '{after}'")
            elif not _managed(ctx, other) or not _managed(ctx, instance):
                unmanaged = instance if not _managed(ctx, instance) else other
                why = '(activate: false)' if not unmanaged.activate else \
                    '(an external node that is not a lifecycle node)'
                ctx.error(instance.after_location(after),
                          f"instance '{instance.name}' is activated "
                          f"after '{after}', but '{unmanaged.name}' is "
                          f'not activated by the system {why}')
    ctx.diagnostics += system_executor_problems(system, components)
    connected: set[tuple[str, str]] = set()
    names = _Names()
    for connection in system.connections:
        ends: list[tuple[PortRef, Port]] = []
        for ref in connection.ends:
            component = components.get(ref.instance)
            if system.instance(ref.instance) is None:
                if _in_broken_subsystem(ctx, system, ref.instance):
                    continue  # one mistake, one message: the subsystem's
                ctx.error(ref.location,
                          f"connection end '{ref}': unknown instance "
                          f"'{ref.instance}'")
            elif component is not None:
                port = component.port(ref.port)
                if port is None:
                    ctx.error(ref.location,
                              f"connection end '{ref}': component "
                              f"'{component.name}' has no port "
                              f"'{ref.port}'")
                else:
                    ends.append((ref, port))
                    connected.add((ref.instance, ref.port))
        if len(ends) == len(connection.ends) == 1 or len(ends) == 2 and \
                _check_connection(ctx, system, connection.location, ends[0], ends[1]):
            _check_names(ctx, system, connection, ends, names)
    _check_own_names(ctx, system, components, connected, names)
    if len(components) == len(system.instances):
        # (an instance whose component is unknown might have been the one)
        ctx.diagnostics += everywhere_problems(system, (
            (i, components[i.name]) for i in system.instances))
    for instance in system.instances:
        component = components.get(instance.name)
        for port in component.ports if component else ():
            if port.role is Role.REQUIRED and port.name not in instance.unconnected and \
                    (instance.name, port.name) not in connected:
                ctx.warning(system.package, instance.location,
                            f"required port '{instance.name}."
                            f"{port.name}' is not connected")
        if component is not None:
            _check_watch_lists(ctx, instance, component,
                               set() if system.modes else connected)


def _check_watch_lists(ctx: CheckContext, instance: Instance, component: Component,
                       connected: set[tuple[str, str]]) -> None:
    """Check the ports an instance lists as ``unconnected`` and ``quiet``.

    In a system with modes, a connected port may be listed too: it stays
    without its provider in the modes that leave the provider inactive.
    """
    listed = [('unconnected', p) for p in instance.unconnected] + \
        [('quiet', p) for p in instance.quiet]
    for (key, name), location in zip(listed, instance.watch_locations):
        port = component.port(name)
        if port is None:
            known = ', '.join(p.name for p in component.ports) or 'none'
            ctx.error(location, f"'{key}' of instance '{instance.name}': component "
                      f"'{component.name}' has no port '{name}' (known: {known})")
        elif key == 'unconnected' and port.role is not Role.REQUIRED:
            ctx.error(location, f"'unconnected' of instance '{instance.name}': port "
                      f"'{name}' is provided (an unconnected provided port is "
                      'nothing to report)')
        elif key == 'unconnected' and (instance.name, name) in connected:
            ctx.error(location, f"'unconnected' of instance '{instance.name}': port "
                      f"'{name}' is connected")
        elif key == 'quiet' and (port.pattern is not Pattern.PUSH or
                                 port.role is not Role.PROVIDED):
            ctx.error(location, f"'quiet' of instance '{instance.name}': port "
                      f"'{name}' is no provided push port (only those are watched "
                      'for silence)')


def _in_broken_subsystem(ctx: CheckContext, system: System, instance: str) -> bool:
    """Tell whether an instance would be one of a subsystem that is reported broken."""
    for subsystem in system.subsystems:
        if instance.startswith(f'{subsystem.name}.'):
            return subsystem.system == system.package or \
                not isinstance(ctx.models.get(subsystem.system), System)
    return False


def _check_connection(ctx: CheckContext, system: System, location: Location,
                      end_a: tuple[PortRef, Port], end_b: tuple[PortRef, Port]) -> bool:
    """Check that two ports fit; return whether they do."""
    a, b = end_a[1], end_b[1]
    if a.pattern is not b.pattern:
        ctx.error(location, f'cannot connect {_a(a.pattern.value)} '
                  f"port ('{a.name}') to {_a(b.pattern.value)} port "
                  f"('{b.name}')")
        return False
    if a.role is b.role:
        ctx.error(location, f'cannot connect two {a.role.value} ports '
                  f"('{a.name}', '{b.name}'): a connection joins a "
                  'provided port to a required one')
        return False
    if a.type != b.type:
        if {a.location, b.location} & ctx.mistyped:
            # one mistake, one message: the type is reported already
            return False
        ctx.error(location, f"type mismatch: '{a.name}' exchanges "
                  f"{a.type}, '{b.name}' exchanges {b.type}")
        return False
    if not port_kind(a).topic_qos:
        return True
    instance_a, instance_b = (system.instance(end_a[0].instance),
                              system.instance(end_b[0].instance))
    assert instance_a is not None and instance_b is not None
    writer: End = (instance_a, a)
    reader: End = (instance_b, b)
    if port_kind(b).topic_writer:
        writer, reader = reader, writer
    return check_connection_qos(ctx, location, writer, reader)


def _check_names(ctx: CheckContext, system: System, connection: Connection,
                 ends: list[tuple[PortRef, Port]], names: _Names) -> None:
    """Check the ROS 2 name a connection remaps its ends to.

    ROS 2 remaps a name once per node: a port in two connections must
    take one name in both. One name carries one pattern and type, and a
    service or action name has one server. A connection of one port
    takes its topic, a name outside the model.
    """
    ref, port = next((e for e in ends if e[1].role is Role.PROVIDED), ends[0])
    instance = system.instance(ref.instance)
    assert instance is not None
    name = connection_name(instance.namespace, instance.node_name, ref.port,
                           connection.topic)
    here = connection.location
    if len(ends) == 1 and port.role is Role.REQUIRED:
        # its server, if any, is outside the model
        _use_name(ctx, name, port, here, names)
        names.of_port.setdefault((ref.instance, ref.port), (name, here))
        return
    for end, _ in ends:
        key = (end.instance, end.port)
        if key in names.of_port and names.of_port[key][0] != name:
            other, where = names.of_port[key]
            ctx.error(here, f"port '{end}' is connected to '{name}' "
                      f"here but to '{other}' by the connection at "
                      f'line {where.line}: ROS 2 remaps a port to one '
                      'name (give both connections the same topic)')
        names.of_port.setdefault(key, (name, here))
    _use_name(ctx, name, port, here, names)
    if port_kind(port).unique_server:
        server, where = names.server.setdefault(name, (str(ref), here))
        if server != str(ref):
            ctx.error(here, f"'{name}' is served by '{ref}' here and "
                      f"by '{server}' at line {where.line}: a "
                      f'{port.pattern.value} name has one server')


def _use_name(ctx: CheckContext, name: str, port: Port, here: Location, names: _Names) -> None:
    """Check that a name carries one pattern and type."""
    kind = f'{port.pattern.value} ports of {port.type}'
    other_kind, where = names.kind.setdefault(name, (kind, here))
    if other_kind != kind:
        ctx.error(here, f"'{name}' connects {kind} here but "
                  f'{other_kind} at line {where.line}')


def _check_own_names(ctx: CheckContext, system: System, components: dict[str, Component],
                     connected: set[tuple[str, str]], names: _Names) -> None:
    """Check the names the unconnected ports of external nodes keep.

    An external node's port that no connection remaps keeps its own name
    (``name`` of the port): a connection to that name outside the model
    must carry its pattern and type.
    """
    for instance in system.instances:
        component = components.get(instance.name)
        if component is None or not component.external:
            continue
        for port in component.ports:
            if (instance.name, port.name) in connected:
                continue
            name = connection_name(instance.namespace, instance.node_name, port.name,
                                   port.node_name)
            if name in names.kind:
                _use_name(ctx, name, port, instance.location, names)


@dataclass
class _Names:
    """The ROS 2 names the connections of a system have used so far."""

    #: (instance, port) -> its name and the connection that gave it
    of_port: dict[tuple[str, str], tuple[str, Location]] = field(
        default_factory=dict)
    #: name -> the pattern and type of its ports, and where first seen
    kind: dict[str, tuple[str, Location]] = field(default_factory=dict)
    #: service, action or event name -> its server, and where first seen
    server: dict[str, tuple[str, Location]] = field(default_factory=dict)
