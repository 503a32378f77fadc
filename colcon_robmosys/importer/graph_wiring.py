# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The connections of an imported system: the ports on one ROS name, joined."""

from __future__ import annotations

from dataclasses import dataclass

from colcon_robmosys.mapping.names import connection_name

#: (pattern, role) -> the entity it is
ENTITIES = {('push', 'provided'): 'publisher', ('push', 'required'): 'subscription',
            ('send', 'provided'): 'subscription', ('send', 'required'): 'publisher',
            ('query', 'provided'): 'service', ('query', 'required'): 'client',
            ('action', 'provided'): 'action_server', ('action', 'required'): 'action_client',
            ('event', 'provided'): 'action_server', ('event', 'required'): 'action_client'}


@dataclass
class End:
    """A port of an instance, on the name the graph shows it."""

    instance: str
    port: str
    pattern: str
    role: str
    type: str
    name: str
    namespace: str
    #: the name the port is on when no connection remaps it; '': <namespace>/<port>
    unconnected: str = ''


def connections(ends: list[End]) -> list[dict[str, str]]:
    """Return the connections of the ends: each provider with each requirer of a name."""
    by_name: dict[str, list[End]] = {}
    for end in ends:
        by_name.setdefault(end.name, []).append(end)
    connections = []
    for name, on_name in sorted(by_name.items()):
        agree(on_name)
        providers = [e for e in on_name if e.role == 'provided']
        requirers = [e for e in on_name if e.role == 'required']
        for provider in providers:
            default = connection_name(provider.namespace.rstrip('/'), provider.instance,
                                      provider.port, None)
            for requirer in requirers:
                connection = {'from': f'{provider.instance}.{provider.port}',
                              'to': f'{requirer.instance}.{requirer.port}'}
                if default != name:
                    connection['topic'] = name
                connections.append(connection)
        if not providers or not requirers:
            # alone on its name: keep the name, unless it is a provided port's own
            # (a required port on a name outside the model is connected to it)
            for end in on_name:
                if end.role == 'required' or name != (
                        end.unconnected or f"{end.namespace.rstrip('/')}/{end.port}"):
                    key = 'from' if end.role == 'provided' else 'to'
                    connections.append({key: f'{end.instance}.{end.port}', 'topic': name})
    return sorted(connections, key=lambda c: (c.get('from', ''), c.get('to', '')))


def agree(ends: list[End]) -> None:
    """Give an external end on a generated port's name that port's pattern."""
    known = next((e for e in ends if e.pattern in ('send', 'event')), None)
    if known is None:
        return
    for end in ends:
        if end.pattern != known.pattern and ENTITIES.get((end.pattern, end.role)) in (
                ENTITIES[(known.pattern, 'provided')], ENTITIES[(known.pattern, 'required')]):
            entity = ENTITIES[(end.pattern, end.role)]
            end.pattern = known.pattern
            end.role = next(r for r in ('provided', 'required')
                            if ENTITIES[(known.pattern, r)] == entity)
