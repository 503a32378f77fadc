# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The ROS 2 plan of a package: what to write, where, from which template."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping


@dataclass(frozen=True)
class FileSpec:
    """A generated file: a template and its variables."""

    #: path inside the generated package, with forward slashes
    path: str
    template: str
    context: Mapping[str, Any]
    executable: bool = False


@dataclass(frozen=True)
class UserFile:
    """A file the user owns: created once from a template, never rewritten.

    Its content is copied into the generated package at ``package_path``.
    """

    #: path relative to the directory of the model file
    source_path: str
    #: where the build uses it, inside the generated package
    package_path: str
    template: str
    context: Mapping[str, Any]
    #: the names the user's code has to define
    required_functions: tuple[str, ...] = ()
    #: the class that has to define them
    required_class: str = ''
    #: the regenerated blueprint, inside the generated package
    skeleton_path: str = ''


@dataclass(frozen=True)
class PackagePlan:
    """Everything needed to generate one ROS 2 package."""

    name: str
    #: 'interfaces', 'component' or 'system'
    kind: str
    #: the directory of the model file the package comes from
    model_dir: Path
    build_depends: tuple[str, ...]
    exec_depends: tuple[str, ...]
    files: tuple[FileSpec, ...]
    user_files: tuple[UserFile, ...] = ()
    #: packages the build needs from the ROS 2 prefix, not from the
    #: workspace (rclcpp for C++): without them the build is skipped
    prefix_requirements: tuple[str, ...] = ()
    #: human-readable facts for logs, e.g. the executables
    summary: Mapping[str, Any] = field(default_factory=dict)

    @property
    def depends(self) -> tuple[str, ...]:
        """Return every package this one depends on, build or run."""
        return tuple(dict.fromkeys(self.build_depends + self.exec_depends))
