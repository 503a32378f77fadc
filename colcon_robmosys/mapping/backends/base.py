# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""What a language backend is: everything a component's language decides.

The mapping decides what a component becomes in ROS 2, once for every
language (:mod:`colcon_robmosys.mapping.component`); a backend spells that
plan in its language and says which files make its package, what its build
needs of the ROS 2 prefix, how the user's implementation is checked and how
a system starts its nodes. Nothing outside the backends asks which language
a component is (``tests/test_architecture.py``).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable, Mapping

from colcon_robmosys.mapping.component import ComponentPlan
from colcon_robmosys.mapping.context import ComponentContext
from colcon_robmosys.mapping.portkinds import Entity, PortKind, Returns
from colcon_robmosys.mapping.tables import Row, UserRow
from colcon_robmosys.mapping.userfiles import UserFolders
from colcon_robmosys.model.types import Component, Executor, Language


@dataclass(frozen=True)
class NodeStart:
    """How a process of several instances creates a component's node.

    At most one is set: the language's way (a system's ``bringup.json``
    and launch files carry both keys).
    """

    #: ``module:class`` of the node (a shared Python process creates it)
    python_class: str = ''
    #: the rclcpp_components plugin its package registers (a container loads it)
    plugin: str = ''
    #: the executor threads its node needs at least (ComponentPlan.threads): a
    #: multi-threaded component container has those of all its nodes
    threads: int = 1


@dataclass(frozen=True)
class PackageFacts:
    """What a backend says of a component's package besides its files."""

    build_depends: tuple[str, ...]
    exec_depends: tuple[str, ...]
    #: a folder of the user's -> the generated folder it is installed with
    merged_folders: Mapping[str, str] = field(default_factory=dict)
    #: packages the build needs from the ROS 2 prefix, not from the workspace
    prefix_requirements: tuple[str, ...] = ()


class Backend(ABC):
    """A target language of components (see :data:`~colcon_robmosys.mapping.backends.BACKENDS`)."""

    #: the language of the model it serves
    language: Language
    #: template -> output path of a component's package
    files: tuple[Row, ...]
    #: the user's files: created once next to the model, never rewritten
    user_files: tuple[UserRow, ...]
    #: the ROS 2 entity of a port -> how the language holds and creates it:
    #: one row per entity (``tests/test_backends.py``)
    entities: Mapping[Entity, object]
    #: what a function gives back -> how the language writes its type
    return_types: Mapping[Returns, str]
    #: the template of what a starting component says and does in the
    #: language (colcon robmosys-new component)
    starter: str
    #: every package its components may need from the ROS 2 prefix, not
    #: from PyPI nor the workspace: without them a build is skipped
    prefix_packages: tuple[str, ...] = ()
    #: the executor of a component that blocks no thread and names none
    #: (mapping/executors.py)
    default_executor: Executor = Executor.EVENTS

    @abstractmethod
    def spell(self, component: Component, plan: ComponentPlan,
              folders: UserFolders) -> ComponentContext:
        """Return the context of the templates of a component.

        Its class derives from the shared one, built by
        :func:`~colcon_robmosys.mapping.context.component_context`.
        """

    @abstractmethod
    def package(self, context: ComponentContext) -> PackageFacts:
        """Return what the package of a spelled component depends on."""

    def prefix_dependencies(self, kinds: Iterable[PortKind]) -> tuple[str, ...]:
        """Return the prefix packages a component with ports of these kinds is built with.

        Discovery makes them dependencies: built first where the workspace
        has them, and the package selection skips the component where no
        prefix has them.
        """
        return ()

    @abstractmethod
    def implements(self, cls: str, texts: Mapping[Path, str | None]) -> bool:
        """Tell whether files hold what the generator made of a component ``cls``.

        :param texts: the files ``<cls>_impl<suffix>`` of the suffixes of
          :attr:`user_files`, by path: their texts, None where unreadable
        """

    @abstractmethod
    def node_start(self, plan: ComponentPlan) -> NodeStart:
        """Return how a process of several instances creates the component's node."""
