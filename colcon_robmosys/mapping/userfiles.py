# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Which files next to a model belong to the package of a component.

The convention (docs/model-format.md, "Your own files"), relative to the
directory of the model file:

- ``src/<package>/``: the user's code. Python: every module and data file of
  it joins the package's Python package; C++: every ``.cpp`` below it is
  compiled into the component's library, where it lives.
- the component's own folder: the model's directory when the component is
  the only one of its file, else the folder ``<package>/`` in it. Below it,
  ``include/`` (C++ headers, installed to ``include/<package>``), ``launch/``,
  ``config/`` and ``resource/`` (installed to ``share/<package>/``),
  ``test/`` (the user's pytest and gtest tests, which ``colcon test`` runs)
  and ``cmake/`` (``*.cmake`` files the package's CMakeLists.txt includes:
  ``find_package`` of a system dependency, say).
"""

from __future__ import annotations

from dataclasses import dataclass

from colcon_robmosys.model.types import Component, Workspace

#: Folders of the component's own folder installed to share/<package>/.
SHARE_FOLDERS = ('launch', 'config', 'resource')
#: The user's tests.
TEST_FOLDER = 'test'
#: The user's C++ headers for other packages.
INCLUDE_FOLDER = 'include'
#: The user's CMake code, included by the generated CMakeLists.txt.
CMAKE_FOLDER = 'cmake'


@dataclass(frozen=True)
class UserFolders:
    """Where the user's files of one component package are, next to its model."""

    #: the user's code: ``src/<package>``
    code: str
    #: the component's own folder: '' (the model's directory) or ``<package>``
    own: str
    share: tuple[str, ...] = SHARE_FOLDERS

    @property
    def own_prefix(self) -> str:
        """Return the own folder as a prefix of a path: '' or ``<package>/``."""
        return f'{self.own}/' if self.own else ''

    @property
    def all(self) -> tuple[str, ...]:
        """Return every folder of the user's, relative to the model's directory."""
        return (self.code,) + tuple(
            self.own_prefix + name
            for name in (INCLUDE_FOLDER, *self.share, TEST_FOLDER, CMAKE_FOLDER))


def user_folders(component: Component, workspace: Workspace | None = None
                 ) -> UserFolders:
    """Return where the user's files of a component are.

    :param workspace: the models the component is checked with; without
      it, the component is taken to be the only one of its file
    """
    siblings = 0 if workspace is None else \
        workspace.components_in_file(component.info.model_file)
    own = component.package if siblings > 1 else ''
    return UserFolders(code=f'src/{component.package}', own=own)
