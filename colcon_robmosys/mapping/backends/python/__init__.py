# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The Python backend: rclpy lifecycle nodes, installed with ament_cmake_python.

``<pkg>/`` holds the generated node and main, ``scripts/`` the executable,
``src-skel/<pkg>/`` the regenerated skeleton, ``src/<pkg>/<Component>_impl.py``
(next to the model) the user's implementation; the user's modules join the
generated ones in one Python package.
"""

from __future__ import annotations

from pathlib import Path
from typing import Mapping

from colcon_robmosys.mapping.backends.base import Backend, NodeStart, PackageFacts
from colcon_robmosys.mapping.backends.python import usercode
from colcon_robmosys.mapping.backends.python.context import PyComponent
from colcon_robmosys.mapping.backends.python.spelling import (
    ENTITIES, RETURN_TYPES, spell_python)
from colcon_robmosys.mapping.component import ComponentPlan
from colcon_robmosys.mapping.context import ComponentContext
from colcon_robmosys.mapping.tables import Row, UserRow
from colcon_robmosys.mapping.userfiles import UserFolders
from colcon_robmosys.model.types import Component, Executor, Language

_SKEL = 'src-skel/{package}/{cls}_impl_skel.py'

#: template -> output path
FILES = (
    Row('{package}/__init__.py', 'component_python/init.py.jinja'),
    Row('{package}/{cls}.py', 'component_python/node.py.jinja'),
    Row('{package}/{cls}_main.py', 'component_python/main.py.jinja'),
    Row('scripts/{cls}', 'component_python/executable.jinja', executable=True),
    Row('CMakeLists.txt', 'component_python/CMakeLists.txt.jinja'),
    Row('package.xml', 'common/package.xml.jinja', part='package_xml'),
    Row('doc/parameters.md', 'common/parameters.md.jinja', part='parameter_page',
        when='parameter_page'),
    Row(_SKEL, 'component_python/impl.py.jinja', when='has_impl',
        skeleton=True),
)

#: the user's file: created once next to the model, installed from there
USER_FILES = (
    UserRow('src/{package}/{cls}_impl.py', 'component_python/impl.py.jinja', _SKEL,
            when='has_impl',
            required_functions='user_functions', required_class='{cls}_impl',
            check=usercode.module_problems),
)


class PythonBackend(Backend):
    """Python: rclpy lifecycle nodes; rclpy comes from the prefix or from PyPI."""

    language = Language.PYTHON
    files = FILES
    user_files = USER_FILES
    entities = ENTITIES
    starter = 'component_python/starter.jinja'
    return_types = RETURN_TYPES
    # rclpy's EventsExecutor (7.1.6, 9.1.2) kills a lifecycle node configured again
    # after its cleanup: an event queued for a destroyed action port drops the last
    # reference to rclpy's ScopedWith without the GIL (docs/model-format.md, Executors;
    # tools/events_executor_cycle.py), which no runtime code can prevent. Python
    # components keep the executor they have always had unless the model names one
    default_executor = Executor.MULTI_THREADED

    def spell(self, component: Component, plan: ComponentPlan,
              folders: UserFolders) -> PyComponent:
        """Return the context of the templates of a component."""
        return spell_python(component, plan, folders)

    def package(self, context: ComponentContext) -> PackageFacts:
        """Return what the package depends on."""
        assert isinstance(context, PyComponent)
        return PackageFacts(
            build_depends=context.depends, exec_depends=context.exec_depends,
            # the user's modules join the generated ones in one Python package
            merged_folders={context.folders.code: context.package})

    def implements(self, cls: str, texts: Mapping[Path, str | None]) -> bool:
        """Tell whether files hold what the generator made of a component ``cls``."""
        return usercode.implements(cls, texts)

    def node_start(self, plan: ComponentPlan) -> NodeStart:
        """Return module:class of the node the component's executable runs.

        A process of several instances creates the nodes with it
        (robmosys_runtime.hosting.container).
        """
        return NodeStart(python_class=f'{plan.package}.{plan.node_module}:{plan.node_cls}')
