# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""What a generator makes of a mapping plan: the files of a package, each from a template.

A generator is a table of rows (template -> output path); the variables of
every template are a typed, frozen context of the mapping. "Plan" is the
mapping's word (ComponentPlan, the system's and the interfaces' plans); what
a generator makes of one is a package's files (:class:`PackageFiles`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path, PurePosixPath
from typing import Any, Callable, Mapping

from colcon_robmosys.errors import Location
from colcon_robmosys.mapping.tables import ImplementationCheck, Row, UserRow


@dataclass(frozen=True)
class FileSpec:
    """A generated file: a template and its context."""

    #: path inside the generated package, with forward slashes
    path: str
    template: str
    #: a frozen dataclass of the mapping, whose fields the template reads
    context: Any
    executable: bool = False


@dataclass(frozen=True)
class UserFile:
    """A file the user owns: created once from a template, never rewritten.

    The build uses it where it is; a standalone package holds a copy at the
    same path.
    """

    #: path relative to the directory of the model file
    source_path: str
    template: str
    context: Any
    #: the names the user's code has to define
    required_functions: tuple[str, ...] = ()
    #: the class that has to define them
    required_class: str = ''
    #: the regenerated blueprint, inside the generated package
    skeleton_path: str = ''
    #: what checks its text against the model (its language's), if anything
    check: ImplementationCheck | None = None


@dataclass(frozen=True)
class Implementation:
    """How the implementation files of a component are named, where they go.

    A file of that name after another class belongs to no component of the
    model: a component renamed, its files left behind (see
    :func:`colcon_robmosys.generators.usercode.orphan_problems`).
    """

    #: the folder of the user's code, relative to the model's directory
    folder: str
    #: the component's class: its files are ``<component>_impl<suffix>``
    component: str
    #: the suffixes of the files, the one that declares the class first
    suffixes: tuple[str, ...]
    #: where the model names the component
    location: Location
    #: whether files of a class hold what the generator made of a component
    #: of that name (its language's test, on their texts; None: unreadable)
    implements: Callable[[str, Mapping[Path, str | None]], bool]


@dataclass(frozen=True)
class PackageFiles:
    """Everything needed to generate one ROS 2 package: its files, and the user's."""

    name: str
    #: 'interfaces', 'component' or 'system'
    kind: str
    #: the directory of the model file the package comes from
    model_dir: Path
    build_depends: tuple[str, ...]
    exec_depends: tuple[str, ...]
    files: tuple[FileSpec, ...]
    user_files: tuple[UserFile, ...] = ()
    #: the folders of the user's own files, relative to model_dir (see
    #: mapping/userfiles.py): a standalone package holds a copy of them
    user_folders: tuple[str, ...] = ()
    #: a folder of the user's -> the generated folder it is installed with
    #: (a Python package): no file of the user's may take a generated name
    merged_folders: Mapping[str, str] = field(default_factory=dict)
    #: how the implementation files of a component are named (components)
    implementation: Implementation | None = None
    #: packages the build needs from the ROS 2 prefix, not from the
    #: workspace (rclcpp for C++): without them the build is skipped
    prefix_requirements: tuple[str, ...] = ()
    #: facts for logs and tests, e.g. the executables or the nodes
    summary: Mapping[str, Any] = field(default_factory=dict)

    @property
    def depends(self) -> tuple[str, ...]:
        """Return every package this one depends on, build or run."""
        return tuple(dict.fromkeys(self.build_depends + self.exec_depends))


class _Attributes(dict[str, Any]):
    """Format paths with the attributes of a context."""

    def __init__(self, context: Any) -> None:
        super().__init__()
        self.context = context

    def __missing__(self, key: str) -> Any:
        return getattr(self.context, key)


def _path(pattern: str, context: Any) -> str:
    return pattern.format_map(_Attributes(context))


def files_of(rows: tuple[Row, ...], context: Any) -> tuple[FileSpec, ...]:
    """Return the files a table makes of a context."""
    files = []
    for row in rows:
        if row.when and not getattr(context, row.when):
            continue
        part = getattr(context, row.part) if row.part else context
        if row.skeleton:
            part = replace(part, skeleton=True)
        files.append(FileSpec(_path(row.path, context), row.template, part,
                              row.executable))
    return tuple(files)


def user_files_of(rows: tuple[UserRow, ...],
                  context: Any) -> tuple[UserFile, ...]:
    """Return the user's files a table makes of a context."""
    return tuple(
        UserFile(
            source_path=_path(row.source_path, context),
            template=row.template, context=context,
            required_functions=tuple(
                f.name for f in getattr(context, row.required_functions))
            if row.required_functions else (),
            required_class=_path(row.required_class, context),
            skeleton_path=_path(row.skeleton_path, context), check=row.check)
        for row in rows if not row.when or getattr(context, row.when))


def implementation_of(
        rows: tuple[UserRow, ...], context: Any, location: Location,
        implements: Callable[[str, Mapping[Path, str | None]], bool]) -> Implementation:
    """Return how the implementation files of a table's component are named.

    Every row is ``<folder>/{cls}_impl<suffix>``; a component without
    functions of the user's has the same names, though no file is made.
    """
    paths = [PurePosixPath(_path(row.source_path, context)) for row in rows]
    return Implementation(str(paths[0].parent), context.cls,
                          tuple(p.suffix for p in paths), location, implements)
