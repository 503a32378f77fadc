# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Rules on QoS: a reader of a connection must match its writer.

An instance may give ports of its component other QoS policies (``qos`` of
the instance): its connections are checked with them, and an override that
breaks a connection is reported where it is written.
"""

from __future__ import annotations

from colcon_robmosys.check.context import CheckContext
from colcon_robmosys.errors import Location
from colcon_robmosys.mapping.portkinds import port_kind
from colcon_robmosys.mapping.qos import resolve_qos
from colcon_robmosys.model.types import Component, Instance, Port, QoS

#: An end of a connection on a topic: the instance, and its port.
End = tuple[Instance, Port]


def check_qos_overrides(ctx: CheckContext, instance: Instance, component: Component) -> None:
    """Check the QoS an instance gives ports of its component: ports it may override."""
    # node_name: the instance as the file of the override names it (a
    # subsystem's instance too), so that the message is the same from the
    # subsystem and from the system that includes it
    who = f"instance '{instance.node_name}'"
    for override in instance.qos:
        port = component.port(override.port)
        if component.external:
            ctx.error(override.location, f"{who}: '{component.name}' is an external "
                      "node: the QoS of its ports is its own code's, and a QoS "
                      'override works only where the node declares it')
        elif port is None:
            known = ', '.join(p.name for p in component.ports) or 'none'
            ctx.error(override.location, f"{who}: component '{component.name}' has "
                      f"no port '{override.port}' (its ports: {known})")
        elif not port_kind(port).topic_qos:
            ctx.error(override.location, f"{who}: port '{port.name}' is "
                      f'{with_article(port.pattern.value)} port, which uses the QoS of ROS 2 '
                      "services and actions; 'qos' applies to push and send ports")
        elif port_kind(port).uses_actions:
            ctx.error(override.location, f"{who}: port '{port.name}' is an event "
                      'port, made of a ROS 2 action, whose topics take no QoS '
                      "overrides; set its 'qos' in the component")
        elif dict(override.policies).get('depth') is not None and \
                resolve_qos(instance.qos_of(port.name, port.qos)).history == 'keep_all':
            ctx.error(override.location, f"{who}, port '{port.name}': 'depth' has "
                      "no meaning with history 'keep_all' (of the component's port)")


def check_connection_qos(ctx: CheckContext, location: Location, writer: End, reader: End
                         ) -> bool:
    """Check that a connection's reader matches its writer; return whether it does.

    A connection that the overrides of its instances break (or break
    otherwise than the components' own QoS) is reported at the override:
    the reader's if it is the one that breaks it, else the writer's.
    """
    (w_instance, w_port), (r_instance, r_port) = writer, reader
    w_qos = w_instance.qos_of(w_port.name, w_port.qos)
    r_qos = r_instance.qos_of(r_port.name, r_port.qos)
    problem = qos_incompatibility(w_qos, r_qos)
    if problem is None:
        return True
    message = (f"incompatible QoS between '{w_port.name}' (writer) and "
               f"'{r_port.name}' (reader): {problem}")
    w_override = w_instance.qos_override(w_port.name)
    r_override = r_instance.qos_override(r_port.name)
    if problem == qos_incompatibility(w_port.qos, r_port.qos):
        ctx.error(location, message)  # the components' own QoS say so
        return False
    blamed, instance, port = (w_override, w_instance, w_port)
    if r_override is not None and (
            w_override is None or qos_incompatibility(w_qos, r_port.qos) != problem):
        blamed, instance, port = (r_override, r_instance, r_port)
    assert blamed is not None
    same_file = location.path == blamed.location.path
    where = f'line {location.line}' if same_file else str(location)
    ctx.error(blamed.location, f'{message} (with the QoS instance '
              f"'{instance.node_name}' gives '{port.name}' here; the connection "
              f'is at {where})')
    return False


def qos_incompatibility(writer: QoS, reader: QoS) -> str | None:
    """Return why a reader would never match a writer, or None.

    These are the request/offer rules of DDS as ROS 2 documents them.
    """
    w, r = resolve_qos(writer), resolve_qos(reader)
    if w.adaptive or r.adaptive:
        return None
    if w.reliability == 'best_effort' and r.reliability == 'reliable':
        return 'a reliable reader cannot receive from a best-effort writer'
    if w.durability == 'volatile' and r.durability == 'transient_local':
        return ('a transient-local reader cannot receive from a volatile '
                'writer')
    if r.deadline is not None and (w.deadline is None or
                                   w.deadline > r.deadline):
        return (f'the reader requests a deadline of {r.deadline} s, the '
                f'writer offers {_seconds(w.deadline)}')
    if w.liveliness == 'automatic' and r.liveliness == 'manual_by_topic':
        return ('a manual-by-topic liveliness reader cannot match an '
                'automatic-liveliness writer')
    if r.liveliness_lease_duration is not None and (
            w.liveliness_lease_duration is None or
            w.liveliness_lease_duration > r.liveliness_lease_duration):
        return (f'the reader requests a liveliness lease of '
                f'{r.liveliness_lease_duration} s, the writer offers '
                f'{_seconds(w.liveliness_lease_duration)}')
    return None


def _seconds(value: float | None) -> str:
    return 'none' if value is None else f'{value} s'


def with_article(word: str) -> str:
    """Return a word with its indefinite article."""
    return f"{'an' if word[0] in 'aeiou' else 'a'} {word}"
