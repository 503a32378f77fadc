# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""What a mode of a system means once its subsystems are expanded.

A mode names the system's own instances that are active and the values it
gives their parameters; a subsystem takes the mode the including mode names
for it (its initial mode where it names none), and a subsystem without modes
keeps every instance it activates. The instances of a subsystem are named
``subsystem.instance`` here, as in the expanded system (check.subsystems).
"""

from __future__ import annotations

from typing import Any, Mapping

from colcon_robmosys.model.systems import Mode, System


def subsystem_mode(system: System, mode: Mode, subsystem: str,
                   included: System) -> Mode | None:
    """Return the mode a subsystem is in while the system is in a mode (None: it has none)."""
    name = dict(mode.subsystems).get(subsystem, included.initial_mode)
    return included.mode(name)


def active_instances(system: System, mode: Mode, systems: Mapping[str, System],
                     prefix: str = '') -> set[str]:
    """Return the instances active in a mode, those of the subsystems too.

    :param systems: every system by package, the included ones among them
    """
    active = {prefix + name for name in mode.active}
    for subsystem in system.subsystems:
        included = systems.get(subsystem.system)
        if included is None:
            continue
        inner = prefix + subsystem.name + '.'
        sub_mode = subsystem_mode(system, mode, subsystem.name, included)
        if sub_mode is None:
            active |= {inner + name for name in _activated(included, systems)}
        else:
            active |= active_instances(included, sub_mode, systems, inner)
    return active


def _activated(system: System, systems: Mapping[str, System]) -> set[str]:
    """Return every instance a system without modes activates, its subsystems' too."""
    names = {i.name for i in system.instances if i.activate and '.' not in i.name}
    for subsystem in system.subsystems:
        included = systems.get(subsystem.system)
        if included is None:
            continue
        mode = included.mode(included.initial_mode)
        inner = {f'{subsystem.name}.{name}' for name in (
            _activated(included, systems) if mode is None
            else active_instances(included, mode, systems))}
        names |= inner
    return names


def mode_values(system: System, mode: Mode, systems: Mapping[str, System],
                prefix: str = '') -> dict[str, dict[str, Any]]:
    """Return instance -> parameter -> value that a mode gives, its subsystems' modes too."""
    values = {prefix + v.instance: dict(v.values) for v in mode.parameters}
    for subsystem in system.subsystems:
        included = systems.get(subsystem.system)
        if included is None:
            continue
        sub_mode = subsystem_mode(system, mode, subsystem.name, included)
        if sub_mode is not None:
            values.update(mode_values(included, sub_mode, systems,
                                      prefix + subsystem.name + '.'))
    return values
