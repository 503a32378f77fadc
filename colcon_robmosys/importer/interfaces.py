# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Service definitions from installed interface packages.

An interface package found through the ament index (resource type
``rosidl_interfaces``) is read with rosidl_adapter's own parser: its messages,
services and actions, with their constants, defaults, arrays, bounds, nested
types and comments (kept as descriptions and comments). Its package.xml gives the
package metadata. The model describes the installed package (``external: true``:
checked against it, nothing generated) or, re-declared, generates the same
package again, for a team that wants to own and evolve it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import math
from pathlib import Path
from typing import Any

import yaml

from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.errors import Diagnostic, Location, RobmosysError
from colcon_robmosys.model import rosidl
from colcon_robmosys.model.fieldtypes import interface_comment_problem

#: the ament index resource type that lists a package's interface files
RESOURCE_TYPE = 'rosidl_interfaces'


@dataclass
class ImportedModel:
    """The model file of one imported package."""

    package: str
    #: the model, in the order it is written
    data: dict[str, Any]
    #: what could not be recovered, written as comments at the top
    notes: list[str] = field(default_factory=list)

    def text(self) -> str:
        """Return the robmosys.yaml of the package."""
        header = [f'# Imported by colcon robmosys-import interfaces from the installed '
                  f'package {self.package}.']
        header += [f'# {note}' for note in self.notes]
        return '\n'.join(header) + '\n' + yaml.dump(
            self.data, Dumper=_Dumper, sort_keys=False, allow_unicode=True, width=88)


def import_interfaces(packages: list[str], index: InterfaceIndex, *,
                      redeclare: bool = False) -> list[ImportedModel]:
    """Return the model of each installed interface package.

    :param redeclare: write models that generate the packages again; by
      default they describe the installed packages (``external: true``)
    :raises RobmosysError: if a package is not an installed interface package
    """
    rosidl.require()
    problems = []
    found = []
    for package in packages:
        share = index.package_share(package)
        listing = _listing(index, package)
        if share is None or listing is None:
            problems.append(Diagnostic(
                Location(package), f"'{package}' is not an installed interface package "
                f'(no {RESOURCE_TYPE} resource in AMENT_PREFIX_PATH)'))
            continue
        found.append(_package_model(package, share, listing, redeclare))
    if problems:
        raise RobmosysError(problems)
    return found


def _listing(index: InterfaceIndex, package: str) -> list[str] | None:
    found = index.resource(RESOURCE_TYPE, package)
    if found is None:
        return None
    return [line.strip() for line in found[0].splitlines() if line.strip()]


def _package_model(package: str, share: Path, listing: list[str],
                   redeclare: bool) -> ImportedModel:
    from rosidl_adapter.parser import (
        parse_action_file, parse_message_file, parse_service_file)
    model = ImportedModel(package, {})
    definition: dict[str, Any] = {'package': package}
    if not redeclare:
        definition['external'] = True
    definition.update(package_metadata(share / 'package.xml'))
    sections: dict[str, dict[str, Any]] = {
        'communication_objects': {}, 'queries': {}, 'actions': {}}
    stems: dict[tuple[str, str], set[str]] = {}
    for entry in listing:
        path = Path(entry)
        stems.setdefault((path.parent.as_posix(), path.stem), set()).add(path.suffix)
    for (kind, name), suffixes in sorted(stems.items()):
        source = share / kind / f'{name}.{kind}'
        if f'.{kind}' not in suffixes or not source.is_file():
            model.notes.append(f'{kind}/{name}: only its .idl file is installed, which '
                               'this import does not read: not imported')
            continue
        where = f'{kind}/{name}'
        if kind == 'msg':
            message = parse_message_file(package, str(source))
            sections['communication_objects'][name] = _structure(
                message, model, where, described=True)
        elif kind == 'srv':
            service = parse_service_file(package, str(source))
            # the file's comment is the request's, as rosidl reads it
            query = _described(_comment(service.request, model, where))
            query['request'] = _structure(service.request, model, where)
            query['answer'] = _structure(service.response, model, where, described=True)
            sections['queries'][name] = query
        elif kind == 'action':
            action_spec = parse_action_file(package, str(source))
            action = _described(_comment(action_spec.goal, model, where))
            action['goal'] = _structure(action_spec.goal, model, where)
            action['result'] = _structure(action_spec.result, model, where, described=True)
            action['feedback'] = _structure(action_spec.feedback, model, where,
                                            described=True)
            sections['actions'][name] = action
    definition.update((k, v) for k, v in sections.items() if v)
    model.data = {'robmosys': 1, 'service_definitions': [definition]}
    return model


def package_metadata(package_xml: Path) -> dict[str, Any]:
    """Return the package metadata of the model, from the package's package.xml."""
    from catkin_pkg.package import parse_package
    manifest = parse_package(str(package_xml))
    data: dict[str, Any] = {}
    description = ' '.join((manifest.description or '').split())
    if description:
        data['description'] = description
    data['version'] = manifest.version
    data['license'] = ' AND '.join(str(lic) for lic in manifest.licenses)
    data['maintainers'] = [{'name': m.name, 'email': m.email} for m in manifest.maintainers]
    return data


def _comment(spec: Any, model: ImportedModel, where: str) -> str:
    """Return the comment rosidl read for a part, or '' if a model cannot carry it."""
    return _carried('\n'.join(spec.annotations.get('comment', [])), model, where)


def _carried(text: str, model: ImportedModel, where: str) -> str:
    text = text.strip('\n')
    problem = interface_comment_problem(text)
    if problem:
        model.notes.append(f'{where}: a comment left out ({problem})')
        return ''
    return text


def _described(description: str) -> dict[str, Any]:
    return {'description': description} if description else {}


def _structure(spec: Any, model: ImportedModel, where: str, *,
               described: bool = False) -> dict[str, Any]:
    """Return a structure of the model: description, constants and fields."""
    data = _described(_comment(spec, model, where)) if described else {}
    constants = {}
    for constant in spec.constants:
        spec_of: dict[str, Any] = {'type': constant.type, 'value': _value(constant.value)}
        comment = _carried('\n'.join(constant.annotations.get('comment', [])), model,
                           f'{where} {constant.name}')
        if comment:
            spec_of['comment'] = comment
        constants[constant.name] = spec_of
    fields: dict[str, Any] = {}
    for field_ in spec.fields:
        spelled = str(field_.type)
        comment = _carried('\n'.join(field_.annotations.get('comment', [])), model,
                           f'{where} {field_.name}')
        entry: dict[str, Any] = {'type': spelled}
        if field_.default_value is not None:
            entry['default'] = _value(field_.default_value)
        if comment:
            entry['comment'] = comment
        fields[field_.name] = spelled if len(entry) == 1 else entry
    if constants:
        data['constants'] = constants
    if fields:
        data['fields'] = fields
    return data


def _value(value: Any) -> Any:
    """Return a value of rosidl as the model writes it."""
    if isinstance(value, (list, tuple)):
        return [_value(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return value  # YAML writes .inf and .nan
    return value


class _Dumper(yaml.SafeDumper):
    """Write text of several lines as a block, as a person writes it."""


def _represent_str(dumper: yaml.SafeDumper, text: str) -> yaml.Node:
    style = '|' if '\n' in text else None
    return dumper.represent_scalar('tag:yaml.org,2002:str', text, style=style)


_Dumper.add_representer(str, _represent_str)
