# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""What every generated package shares: the banner and the package.xml."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable

from colcon_robmosys.model.types import (
    Component, Maintainer, Model, PackageInfo, ServiceDefinition)


@dataclass(frozen=True)
class Banner:
    """What the banner of a generated file says: where it comes from.

    No path of the workspace: generated files must not depend on where the
    workspace lies.
    """

    model_title: str
    package: str


@dataclass(frozen=True)
class PackageXml:
    """The variables of a package.xml (format 3)."""

    banner: Banner
    name: str
    version: str
    description: str
    maintainers: tuple[Maintainer, ...]
    license: str
    buildtool_depends: tuple[str, ...]
    depends: tuple[str, ...]
    build_depends: tuple[str, ...]
    exec_depends: tuple[str, ...]
    test_depends: tuple[str, ...]
    groups: tuple[str, ...]


def model_title(model: Model) -> str:
    """Return how banners name a model, e.g. ``the component Foo``."""
    if isinstance(model, ServiceDefinition):
        return f'the service definition {model.package}'
    if isinstance(model, Component):
        return f'the component {model.name}'
    return f'the system {model.name}'


def banner_of(model: Model) -> Banner:
    """Return the banner of the files generated from a model."""
    return Banner(model_title(model), model.package)


def package_xml(
        banner: Banner, info: PackageInfo, *, buildtool: Iterable[str] = (),
        build: Iterable[str] = (), exec_: Iterable[str] = (),
        depend: Iterable[str] = (), test: Iterable[str] = (),
        groups: Iterable[str] = ()) -> PackageXml:
    """Return the variables of a package.xml."""
    depends = unique(list(depend) + list(info.depends))
    return PackageXml(
        banner=banner, name=info.name, version=info.version,
        description=info.description, maintainers=info.maintainers,
        license=info.license,
        buildtool_depends=unique(buildtool), depends=depends,
        build_depends=tuple(d for d in unique(build) if d not in depends),
        exec_depends=tuple(d for d in unique(exec_) if d not in depends),
        test_depends=unique(test), groups=unique(groups))


def unique(items: Iterable[str]) -> tuple[str, ...]:
    """Return the items without repeats, in first-use order."""
    return tuple(dict.fromkeys(items))
