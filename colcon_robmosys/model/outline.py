# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""What discovery needs of a model file: its packages, their kinds and dependencies.

colcon lists, orders and selects packages by their names and dependencies
alone, and colcon-ros reads no more of a package.xml for it. Reading the
same of a model file costs a fraction of loading and checking it (the
loader alone: no schema, no rules): discovery outlines every file, and the
check stage runs once, in the build and in ``robmosys-generate``. The
loader is the check stage's own, so that a text it refuses (a duplicate key,
a key YAML reads as a boolean) is refused here too.

An outline is only taken where it is sure to name the packages and
dependencies the checked models would give; for anything unusual (a text
that is not plain YAML, a model without a package name, a type that does
not parse) it gives up, and discovery checks the whole workspace at once
instead, as it reports what the check finds.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Iterator

from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.model.base import Pattern, PATTERN_INTERFACE, Role
from colcon_robmosys.model.fieldtypes import parse_field_type, parse_interface, TypeNameError
from colcon_robmosys.model.files import MODEL_KINDS
from colcon_robmosys.model.loader import load_file

#: The parts of each section of a service definition that hold structures.
_STRUCTURES = {'communication_objects': (None, ), 'queries': ('request', 'answer'),
               'actions': ('goal', 'result', 'feedback'),
               'events': ('activation', 'event')}


class NoOutline(Exception):
    """The file needs the check stage to tell what it declares."""


@dataclass(frozen=True)
class PackageOutline:
    """A package a model file generates, as discovery sees it."""

    name: str
    #: interfaces, component or system (package_discovery's kinds)
    kind: str
    #: the packages it needs, as model_dependencies() gives them of the
    #: checked model
    dependencies: tuple[str, ...]
    #: a component: its language, as the model names it, and the pattern
    #: and role of its ports, which decide what its language's backend needs
    #: of the ROS 2 prefix (mapping/backends/)
    language: str = ''
    ports: tuple[tuple[Pattern, Role], ...] = ()
    #: a system: the packages of its own instances' components, and the
    #: systems it includes (the check stage expands them into instances)
    components: tuple[str, ...] = ()
    subsystems: tuple[str, ...] = ()


def outline_file(path: Path) -> list[PackageOutline]:
    """Return the packages a model file generates.

    :raises NoOutline: where only the check stage can tell
    """
    try:
        data = load_file(Path(path), keep=True).data
        if not isinstance(data, dict) or data.get('robmosys') != 1:
            raise NoOutline()
        packages = [
            _outline(section, model)
            for section in MODEL_KINDS if data.get(section) is not None
            for model in _expect(data[section], list)
            if not (isinstance(model, dict) and model.get('external'))]
    except (NoOutline, RobmosysError, TypeNameError, ValueError):
        raise NoOutline() from None
    if not packages:
        # only external models: nothing of its own reports its errors
        raise NoOutline()
    return packages


def _outline(section: str, model: Any) -> PackageOutline:
    _expect(model, dict)
    name = _expect(model.get('package'), str)
    depends = [_expect(d, str) for d in _expect(model.get('depends', []), list)]
    kind = MODEL_KINDS[section]
    language = ''
    ports: list[tuple[Pattern, Role]] = []
    components: list[str] = []
    subsystems: list[str] = []
    if section == 'service_definitions':
        depends += [p for p in _field_packages(model, name) if p != name]
    elif section == 'components':
        for port in _expect(model.get('ports', {}), dict).values():
            # an unknown pattern or role is a ValueError, a type the builder
            # would refuse a TypeNameError: both go to the check
            pattern = Pattern(_expect(port, dict).get('pattern'))
            ports.append((pattern, Role(port.get('role'))))
            depends.append(parse_interface(
                _expect(port.get('type'), str), PATTERN_INTERFACE[pattern]).package)
        language = _expect(model.get('language'), str)
    else:
        instances = _expect(model.get('instances', {}), dict)
        components = [
            c for c in (_expect(_expect(body, dict).get('component'), str).split('/')[0]
                        for body in instances.values()) if c != name]
        subsystems = [
            s for s in (_expect(_expect(body, dict).get('system'), str)
                        for body in _expect(model.get('subsystems', {}), dict).values())
            if s != name]
        depends += components + subsystems
    return PackageOutline(name, kind, tuple(dict.fromkeys(depends)), language,
                          tuple(ports), tuple(components), tuple(subsystems))


def with_subsystems(packages: dict[str, PackageOutline]) -> dict[str, PackageOutline]:
    """Return the outlines with each system's subsystems expanded, as the check does.

    A system then also depends on the components of the instances it
    includes. Only the subsystems among the outlines are expanded: colcon
    orders the packages of the workspace alone. The outlines must have no
    dependency cycle.
    """
    expanded = dict(packages)

    def components(name: str) -> tuple[str, ...]:
        system = expanded[name]
        found = list(system.components)
        for subsystem in system.subsystems:
            if subsystem in expanded:
                found += components(subsystem)
        return tuple(dict.fromkeys(found))

    for name, package in packages.items():
        if package.subsystems:
            expanded[name] = replace(package, dependencies=tuple(dict.fromkeys(
                package.dependencies + components(name))))
    return expanded


def _field_packages(definition: dict[str, Any], own: str) -> Iterator[str]:
    for section, parts in _STRUCTURES.items():
        for body in _expect(definition.get(section, {}), dict).values():
            for part in parts:
                structure = body if part is None else \
                    _expect(body, dict).get(part) or {}
                fields = _expect(_expect(structure, dict).get('fields', {}), dict)
                for spec in fields.values():
                    text = spec.get('type') if isinstance(spec, dict) else spec
                    message = parse_field_type(_expect(text, str), own).message
                    if message is not None:
                        yield message.package


def _expect(value: Any, kind: type) -> Any:
    if not isinstance(value, kind):
        raise NoOutline()
    return value
