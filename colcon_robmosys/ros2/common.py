# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""What every generated package shares: metadata, banner, file names."""

from __future__ import annotations

from typing import Any, Iterable

from colcon_robmosys.model.types import (
    Component, InterfaceRef, Model, PackageInfo, Pattern, Role,
    ServiceDefinition)

#: What each port becomes in ROS 2, by pattern and role: the same in rclpy
#: and rclcpp, so that both generators give a model one meaning.
ENTITIES = {
    (Pattern.PUSH, Role.PROVIDED): 'publisher',
    (Pattern.SEND, Role.REQUIRED): 'publisher',
    (Pattern.PUSH, Role.REQUIRED): 'subscription',
    (Pattern.SEND, Role.PROVIDED): 'subscription',
    (Pattern.QUERY, Role.PROVIDED): 'service',
    (Pattern.QUERY, Role.REQUIRED): 'client',
    (Pattern.ACTION, Role.PROVIDED): 'action_server',
    (Pattern.ACTION, Role.REQUIRED): 'action_client',
    (Pattern.EVENT, Role.PROVIDED): 'event_server',
    (Pattern.EVENT, Role.REQUIRED): 'event_client',
}


def model_title(model: Model) -> str:
    """Return how banners name a model, e.g. ``the component Foo``."""
    if isinstance(model, ServiceDefinition):
        return f'the service definition {model.package}'
    if isinstance(model, Component):
        return f'the component {model.name}'
    return f'the system {model.name}'


def banner_context(model: Model) -> dict[str, Any]:
    """Return the variables of the banner of a generated file."""
    # no path of the workspace: generated files must not depend on where
    # the workspace lies
    return {'model_title': model_title(model), 'package': model.package}


def package_xml_context(
        info: PackageInfo, *, buildtool: Iterable[str] = (),
        build: Iterable[str] = (), exec_: Iterable[str] = (),
        depend: Iterable[str] = (), test: Iterable[str] = (),
        groups: Iterable[str] = ()) -> dict[str, Any]:
    """Return the variables of a package.xml (format 3)."""
    depend = _unique(list(depend) + list(info.depends))
    return {
        'name': info.name,
        'version': info.version,
        'description': info.description,
        'maintainers': [{'name': m.name, 'email': m.email}
                        for m in info.maintainers],
        'license': info.license,
        'buildtool_depends': _unique(buildtool),
        'depends': depend,
        'build_depends': [d for d in _unique(build) if d not in depend],
        'exec_depends': [d for d in _unique(exec_) if d not in depend],
        'test_depends': _unique(test),
        'groups': _unique(groups),
    }


def interface_packages(refs: Iterable[InterfaceRef | None]) -> list[str]:
    """Return the packages of some interfaces, in first-use order."""
    return _unique(r.package for r in refs if r is not None)


def _unique(items: Iterable[str]) -> list[str]:
    return list(dict.fromkeys(items))
