# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Rules on QoS: a reader of a connection must match its writer."""

from __future__ import annotations

from colcon_robmosys.mapping.qos import resolve_qos
from colcon_robmosys.model.types import QoS


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
