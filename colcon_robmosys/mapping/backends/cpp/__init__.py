# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The C++ backend: rclcpp lifecycle nodes, built with ament_cmake.

The layout is the reference's (Papyrus for Robotics): ``src-gen/<pkg>/`` holds
the generated class and main, ``src-skel/<pkg>/`` the regenerated skeleton of
the implementation, ``src/<pkg>/<Component>_impl.{hpp,cpp}`` (next to the
model) the user's implementation, which derives from the generated class.
"""

from __future__ import annotations

from pathlib import Path
from typing import Iterable, Mapping

from colcon_robmosys.mapping.backends.base import Backend, NodeStart, PackageFacts
from colcon_robmosys.mapping.backends.cpp import usercode
from colcon_robmosys.mapping.backends.cpp.context import CppComponent
from colcon_robmosys.mapping.backends.cpp.spelling import (
    CPP_CLIENT_PACKAGES, ENTITIES, rclcpp_packages, RETURN_TYPES, spell_cpp)
from colcon_robmosys.mapping.component import ComponentPlan
from colcon_robmosys.mapping.context import ComponentContext
from colcon_robmosys.mapping.portkinds import PortKind
from colcon_robmosys.mapping.tables import Row, UserRow
from colcon_robmosys.mapping.userfiles import UserFolders
from colcon_robmosys.model.types import Component, Language

_SRC = 'src-gen/{package}'
_SKEL = 'src-skel/{package}/{cls}_impl'

#: template -> output path
FILES = (
    Row(f'{_SRC}/{{cls}}.hpp', 'component_cpp/node.hpp.jinja'),
    Row(f'{_SRC}/{{cls}}.cpp', 'component_cpp/node.cpp.jinja'),
    Row(f'{_SRC}/{{cls}}_main.cpp', 'component_cpp/main.cpp.jinja'),
    Row('CMakeLists.txt', 'component_cpp/CMakeLists.txt.jinja'),
    Row('package.xml', 'common/package.xml.jinja', part='package_xml'),
    Row('doc/parameters.md', 'common/parameters.md.jinja', part='parameter_page',
        when='parameter_page'),
    Row(f'{_SKEL}.hpp', 'component_cpp/impl.hpp.jinja', when='has_impl',
        skeleton=True),
    Row(f'{_SKEL}.cpp', 'component_cpp/impl.cpp.jinja', when='has_impl',
        skeleton=True),
)

#: the user's files: created once next to the model, compiled from there
USER_FILES = (
    UserRow('src/{package}/{cls}_impl.hpp', 'component_cpp/impl.hpp.jinja',
            f'{_SKEL}.hpp', when='has_impl',
            required_functions='user_functions', required_class='{cls}_impl',
            check=usercode.header_problems),
    UserRow('src/{package}/{cls}_impl.cpp', 'component_cpp/impl.cpp.jinja',
            f'{_SKEL}.cpp', when='has_impl'),
)


class CppBackend(Backend):
    """C++: rclcpp_lifecycle nodes, registered as rclcpp_components plugins."""

    language = Language.CPP
    files = FILES
    user_files = USER_FILES
    entities = ENTITIES
    starter = 'component_cpp/starter.jinja'
    return_types = RETURN_TYPES
    # rclcpp is not on PyPI: a machine without a ROS 2 install skips these
    prefix_packages = CPP_CLIENT_PACKAGES + ('rclcpp_action',)

    def spell(self, component: Component, plan: ComponentPlan,
              folders: UserFolders) -> CppComponent:
        """Return the context of the templates of a component."""
        return spell_cpp(component, plan, folders)

    def package(self, context: ComponentContext) -> PackageFacts:
        """Return what the package depends on."""
        assert isinstance(context, CppComponent)
        return PackageFacts(
            build_depends=context.find_packages, exec_depends=context.find_packages,
            prefix_requirements=context.prefix_requirements)

    def prefix_dependencies(self, kinds: Iterable[PortKind]) -> tuple[str, ...]:
        """Return the rclcpp packages of a component with ports of these kinds."""
        return rclcpp_packages(kinds)

    def implements(self, cls: str, texts: Mapping[Path, str | None]) -> bool:
        """Tell whether files hold what the generator made of a component ``cls``."""
        return usercode.implements(cls, texts)

    def node_start(self, plan: ComponentPlan) -> NodeStart:
        """Return the rclcpp_components plugin the component's package registers."""
        return NodeStart(plugin=f'{plan.package}::{plan.node_cls}', threads=plan.threads)
