# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""QoS profiles of ports, and the compatibility rules ROS 2 applies."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

from colcon_robmosys.model.types import QoS, QoSOverride


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


#: Policies whose ROS 2 parameter holds nanoseconds (the model: seconds).
_DURATIONS = frozenset({'deadline', 'lifespan', 'liveliness_lease_duration'})


def override_parameters(topic: str, entity: str, override: QoSOverride
                        ) -> tuple[tuple[str, Any], ...]:
    """Return the parameters that give a port the QoS an instance overrides.

    They are ROS 2's own QoS overrides, ``qos_overrides.<topic>.<entity>.<policy>``,
    which generated publishers and subscriptions declare (read-only) when
    they are created; durations are integer nanoseconds there.

    :param topic: the fully qualified name of the port's topic, remapped
    :param entity: ``publisher`` or ``subscription``
    """
    return tuple(
        (f'qos_overrides.{topic}.{entity}.{policy}',
         round(value * 1e9) if policy in _DURATIONS else value)
        for policy, value in override.policies)
