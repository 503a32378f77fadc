# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Service definitions become interface packages: .msg, .srv, .action."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from colcon_robmosys.model.types import (
    Constant, Field, ServiceDefinition, Structure)
from colcon_robmosys.model.workspace import model_dependencies
from colcon_robmosys.ros2.common import banner_context, package_xml_context
from colcon_robmosys.ros2.plan import FileSpec, PackagePlan


def _literal(value: Any, primitive: str | None) -> str:
    """Write a default or constant value in .msg syntax."""
    if isinstance(value, list):
        return '[' + ', '.join(_literal(v, primitive) for v in value) + ']'
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, str):
        # rosidl strips the outer quotes and unescapes only inner ones; the
        # model refuses what else it could not read back (fieldtypes.py)
        return '"' + value.replace('"', '\\"') + '"'
    return repr(value)


def _field_line(field_: Field, own_package: str) -> dict[str, Any]:
    type_ = field_.type
    if type_.message is not None and type_.message.package == own_package:
        # a type of the same package is written without its package
        type_text = str(type_).split('/', 1)[1]
    else:
        type_text = str(type_)
    default = '' if field_.default is None else ' ' + _literal(
        field_.default, type_.primitive)
    return {'line': f'{type_text} {field_.name}{default}',
            'comment': field_.comment}


def _constant_line(constant: Constant) -> dict[str, Any]:
    return {'line': f'{constant.type} {constant.name}='
                    f'{_literal(constant.value, constant.type.primitive)}',
            'comment': constant.comment}


def _structure(structure: Structure, package: str) -> dict[str, Any]:
    return {
        'description': structure.description,
        'constants': [_constant_line(c) for c in structure.constants],
        'fields': [_field_line(f, package) for f in structure.fields],
    }


def plan_interfaces(definition: ServiceDefinition) -> PackagePlan:
    """Map a service definition to its interface package."""
    package = definition.package
    banner = banner_context(definition)
    files, interface_files = [], []
    for obj in definition.communication_objects:
        path = f'msg/{obj.name}.msg'
        interface_files.append(path)
        files.append(FileSpec(path, 'interfaces/interface.jinja', {
            'banner': banner, 'parts': [_structure(obj.structure, package)],
        }))
    for query in definition.queries:
        path = f'srv/{query.name}.srv'
        interface_files.append(path)
        files.append(FileSpec(path, 'interfaces/interface.jinja', {
            'banner': banner, 'description': query.description,
            'parts': [_structure(query.request, package),
                      _structure(query.answer, package)],
        }))
    for action in definition.actions:
        path = f'action/{action.name}.action'
        interface_files.append(path)
        files.append(FileSpec(path, 'interfaces/interface.jinja', {
            'banner': banner, 'description': action.description,
            'parts': [_structure(s, package) for s in
                      (action.goal, action.result, action.feedback)],
        }))
    for event in definition.events:
        # goal = activation; result (the event that ended a single
        # activation) and feedback (each event) = event
        path = f'action/{event.name}.action'
        interface_files.append(path)
        goal = _structure(event.activation, package)
        goal['fields'].append({'line': 'bool single false', 'comment': (
            'true: the first event ends the activation (the result); '
            'false: events until the client cancels')})
        files.append(FileSpec(path, 'interfaces/interface.jinja', {
            'banner': banner, 'description': event.description,
            'parts': [goal] + [_structure(event.event, package)] * 2,
        }))
    depends = model_dependencies(definition)
    if (definition.actions or definition.events) and 'action_msgs' not in depends:
        # rosidl needs it for the goal status of every action
        depends.append('action_msgs')
    files.append(FileSpec('CMakeLists.txt', 'interfaces/CMakeLists.txt.jinja', {
        'banner': banner, 'package': package,
        'interface_files': interface_files, 'depends': depends,
    }))
    files.append(FileSpec('package.xml', 'common/package.xml.jinja', {
        'banner': banner,
        **package_xml_context(
            definition.info,
            buildtool=['ament_cmake', 'rosidl_default_generators'],
            depend=depends, exec_=['rosidl_default_runtime'],
            groups=['rosidl_interface_packages']),
    }))
    return PackagePlan(
        name=package, kind='interfaces',
        model_dir=Path(definition.info.model_file).parent,
        build_depends=tuple(depends), exec_depends=tuple(depends),
        files=tuple(files),
        summary={'interfaces': interface_files})
