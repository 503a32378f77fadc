# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Rules on the modes of a system: what each names exists, fits and can run.

A mode names managed instances of the system, values of their parameters
(which must fit the parameters' rules as an instance's own values must) and
modes of the subsystems. An instance active in a mode must not wait (``after``)
for one the mode leaves inactive; a required port of an active instance whose
providers the mode leaves inactive talks to nobody (a warning, unless the
instance lists the port as ``unconnected``).
"""

from __future__ import annotations

from dataclasses import replace

from colcon_robmosys.check.context import CheckContext
from colcon_robmosys.check.parameters import override_problems
from colcon_robmosys.model.build_base import choices
from colcon_robmosys.model.modes import active_instances
from colcon_robmosys.model.types import Component, Mode, model_key, Role, System


def check_modes(ctx: CheckContext) -> None:
    """Check the modes of every system of the workspace that has some."""
    installed = {model_key(m) for f in ctx.files if f.installed for m in f.systems}
    systems = {k: m for k, m in ctx.models.items() if isinstance(m, System)}
    for key, system in systems.items():
        if system.modes and key not in installed:
            _check_system_modes(ctx, system, systems)


def _managed(ctx: CheckContext, system: System, name: str) -> str | None:
    """Return why a mode cannot name an instance as active, None if it can."""
    instance = system.instance(name)
    if instance is None or '.' in name:
        own = sorted(i.name for i in system.instances if '.' not in i.name)
        return f"unknown instance '{name}'{choices(own)}"
    if not instance.activate:
        return f"instance '{name}' is not managed by the system (activate: false)"
    component = ctx.components.get(instance.component)
    if component is not None and not component.lifecycle_node:
        return f"instance '{name}' is not a lifecycle node: it is always active"
    return None


def _check_system_modes(ctx: CheckContext, system: System, systems: dict[str, System]) -> None:
    if system.mode(system.initial_mode) is None:
        assert system.initial_mode_location is not None
        ctx.error(system.initial_mode_location, f"initial mode '{system.initial_mode}' is "
                  f'not a mode of the system{choices(m.name for m in system.modes)}')
    for mode in system.modes:
        for name, location in zip(mode.active, mode.active_locations):
            problem = _managed(ctx, system, name)
            if problem:
                ctx.error(location, f"mode '{mode.name}': {problem}")
        _check_values(ctx, system, mode)
        _check_subsystem_modes(ctx, system, mode, systems)
        _check_after(ctx, system, mode, active_instances(system, mode, systems))


def _check_values(ctx: CheckContext, system: System, mode: Mode) -> None:
    """Check the values a mode gives: instances and parameters that exist, values that fit."""
    for given in mode.parameters:
        instance = system.instance(given.instance)
        if instance is None or '.' in given.instance:
            own = sorted(i.name for i in system.instances if '.' not in i.name)
            ctx.error(given.location, f"mode '{mode.name}': unknown instance "
                      f"'{given.instance}'{choices(own)}")
            continue
        component = ctx.components.get(instance.component)
        if component is None:
            continue  # reported with the instance
        # the mode's values as if they were the instance's own: the same rules
        moded = replace(instance, parameters=given.values,
                        parameter_locations=given.value_locations,
                        parameter_entry_locations=given.entry_locations)
        for problem in override_problems(moded, component, dict(system.parameters)):
            ctx.diagnostics.append(replace(
                problem, message=f"mode '{mode.name}': {problem.message}"))


def _check_subsystem_modes(ctx: CheckContext, system: System, mode: Mode,
                           systems: dict[str, System]) -> None:
    """Check that a mode names subsystems that exist, and modes they have."""
    subsystems = {s.name: s for s in system.subsystems}
    for (name, sub_mode), location in zip(mode.subsystems, mode.subsystem_locations):
        subsystem = subsystems.get(name)
        if subsystem is None:
            ctx.error(location, f"mode '{mode.name}': unknown subsystem '{name}'"
                      f'{choices(subsystems)}')
            continue
        included = systems.get(subsystem.system)
        if included is None:
            continue  # reported with the subsystem
        if included.mode(sub_mode) is None:
            modes = [m.name for m in included.modes]
            ctx.error(location, f"mode '{mode.name}': subsystem '{name}' (system "
                      f"'{subsystem.system}') has no mode '{sub_mode}'" +
                      (choices(modes) if modes else ' (it has no modes)'))


def _check_after(ctx: CheckContext, system: System, mode: Mode, active: set[str]) -> None:
    """Check what the active instances of a mode wait for and need."""
    components: dict[str, Component] = {}
    for instance in system.instances:
        component = ctx.components.get(instance.component)
        if component is not None:
            components[instance.name] = component
        if instance.name not in active or '.' in instance.name:
            continue  # a subsystem's own modes are checked with it
        for after in instance.after:
            if after not in active and system.instance(after) is not None:
                ctx.error(mode.active_location(instance.name),
                          f"mode '{mode.name}': instance '{instance.name}' is activated "
                          f"after '{after}', which the mode leaves inactive")
    providers: dict[tuple[str, str], list[str]] = {}
    for connection in system.connections:
        if connection.target is None:
            continue  # the other end is outside the model
        ends = [(ref, components.get(ref.instance)) for ref in connection.ends]
        roles = {ref: c.port(ref.port) for ref, c in ends if c is not None}
        if len(roles) != 2 or any(p is None for p in roles.values()):
            continue  # reported by the wiring rules
        for ref, port in roles.items():
            if port is not None and port.role is Role.REQUIRED:
                providers.setdefault((ref.instance, ref.port), []).extend(
                    r.instance for r in roles if r is not ref)
    for (name, port_name), serving in providers.items():
        needing = system.instance(name)
        if name not in active or needing is None or port_name in needing.unconnected:
            continue
        if not any(s in active or _always_on(components.get(s)) for s in serving):
            ctx.warning(system.package, mode.active_location(name),
                        f"mode '{mode.name}': required port '{name}.{port_name}' is served by "
                        f"{', '.join(sorted(set(serving)))}, which the mode leaves inactive")


def _always_on(component: Component | None) -> bool:
    """Tell whether an instance's node is active in every mode: not a lifecycle node."""
    return component is not None and not component.lifecycle_node
