# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Service definitions become interface packages: .msg, .srv, .action."""

from __future__ import annotations

from dataclasses import dataclass

from colcon_robmosys.mapping.common import (
    Banner, banner_of, package_xml, PackageXml)
from colcon_robmosys.model.fieldtypes import msg_literal
from colcon_robmosys.model.files import model_dependencies
from colcon_robmosys.model.types import (
    Constant, Field, ServiceDefinition, Structure)


@dataclass(frozen=True)
class InterfaceLine:
    """A line of an interface file, with the comment above it."""

    line: str
    comment: str


@dataclass(frozen=True)
class InterfacePart:
    """A section of an interface file (parts are separated by ``---``)."""

    description: str
    constants: tuple[InterfaceLine, ...]
    fields: tuple[InterfaceLine, ...]


@dataclass(frozen=True)
class InterfaceFile:
    """A .msg, .srv or .action file."""

    #: path inside the package, e.g. ``msg/Map.msg``
    path: str
    banner: Banner
    description: str
    parts: tuple[InterfacePart, ...]


@dataclass(frozen=True)
class InterfacePackage:
    """The plan of an interface package."""

    banner: Banner
    package: str
    files: tuple[InterfaceFile, ...]
    depends: tuple[str, ...]
    package_xml: PackageXml

    @property
    def interface_files(self) -> tuple[str, ...]:
        """Return the paths of the interface files, for rosidl."""
        return tuple(f.path for f in self.files)


def _field_line(field_: Field, own_package: str) -> InterfaceLine:
    type_ = field_.type
    if type_.message is not None and type_.message.package == own_package:
        # a type of the same package is written without its package
        type_text = str(type_).split('/', 1)[1]
    else:
        type_text = str(type_)
    default = '' if field_.default is None else ' ' + msg_literal(field_.default)
    return InterfaceLine(f'{type_text} {field_.name}{default}', field_.comment)


def _constant_line(constant: Constant) -> InterfaceLine:
    return InterfaceLine(
        f'{constant.type} {constant.name}='
        f'{msg_literal(constant.value)}',
        constant.comment)


def _part(structure: Structure, package: str,
          extra: tuple[InterfaceLine, ...] = ()) -> InterfacePart:
    return InterfacePart(
        structure.description,
        tuple(_constant_line(c) for c in structure.constants),
        tuple(_field_line(f, package) for f in structure.fields) + extra)


#: The field rosidl adds to the goal of an event: its mode.
_SINGLE = InterfaceLine('bool single false', (
    'true: the first event ends the activation (the result); '
    'false: events until the client cancels'))


def plan_interfaces(definition: ServiceDefinition) -> InterfacePackage:
    """Map a service definition to its interface package."""
    package = definition.package
    banner = banner_of(definition)
    files = [InterfaceFile(f'msg/{o.name}.msg', banner, '',
                           (_part(o.structure, package),))
             for o in definition.communication_objects]
    files += [InterfaceFile(f'srv/{q.name}.srv', banner, q.description,
                            (_part(q.request, package), _part(q.answer, package)))
              for q in definition.queries]
    files += [InterfaceFile(f'action/{a.name}.action', banner, a.description,
                            tuple(_part(s, package)
                                  for s in (a.goal, a.result, a.feedback)))
              for a in definition.actions]
    # an event is an action: goal = activation; result (the event that
    # ended a single activation) and feedback (each event) = event
    files += [InterfaceFile(f'action/{e.name}.action', banner, e.description,
                            (_part(e.activation, package, (_SINGLE,)),
                             _part(e.event, package), _part(e.event, package)))
              for e in definition.events]
    depends = model_dependencies(definition)
    if (definition.actions or definition.events) and 'action_msgs' not in depends:
        # rosidl needs it for the goal status of every action
        depends.append('action_msgs')
    return InterfacePackage(
        banner=banner, package=package, files=tuple(files),
        depends=tuple(depends),
        package_xml=package_xml(
            banner, definition.info,
            buildtool=['ament_cmake', 'rosidl_default_generators'],
            depend=depends, exec_=['rosidl_default_runtime'],
            groups=['rosidl_interface_packages']))
