# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""QoS profiles of ports, and the compatibility rules ROS 2 applies."""

from __future__ import annotations

from dataclasses import dataclass, replace

from colcon_robmosys.model.types import QoS


@dataclass(frozen=True)
class ResolvedQoS:
    """Every policy of a port's QoS, profile applied."""

    history: str
    depth: int
    reliability: str
    durability: str
    deadline: float | None
    lifespan: float | None
    liveliness: str
    liveliness_lease_duration: float | None
    #: the rmw picks policies that match its peers (best_available)
    adaptive: bool = False


#: The rclpy/rclcpp predefined profiles, by the name the model uses.
PROFILES = {
    'default': ResolvedQoS('keep_last', 10, 'reliable', 'volatile', None,
                           None, 'automatic', None),
    'services_default': ResolvedQoS('keep_last', 10, 'reliable', 'volatile',
                                    None, None, 'automatic', None),
    'system_default': ResolvedQoS('keep_last', 10, 'reliable', 'volatile',
                                  None, None, 'automatic', None),
    'sensor_data': ResolvedQoS('keep_last', 5, 'best_effort', 'volatile',
                               None, None, 'automatic', None),
    'parameters': ResolvedQoS('keep_last', 1000, 'reliable', 'volatile', None,
                              None, 'automatic', None),
    'parameter_events': ResolvedQoS('keep_last', 1000, 'reliable', 'volatile',
                                    None, None, 'automatic', None),
    'best_available': ResolvedQoS('keep_last', 10, 'reliable', 'volatile',
                                  None, None, 'automatic', None, True),
}


def resolve_qos(qos: QoS) -> ResolvedQoS:
    """Apply the explicit policies of a port over its profile."""
    overrides = {
        name: getattr(qos, name)
        for name in ('history', 'depth', 'reliability', 'durability',
                     'deadline', 'lifespan', 'liveliness',
                     'liveliness_lease_duration')
        if getattr(qos, name) is not None}
    return replace(PROFILES[qos.profile], **overrides)


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
