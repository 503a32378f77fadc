# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The rules of one model file on its own: the schema, then each model's own rules."""

from __future__ import annotations

from pathlib import Path

from colcon_robmosys.check.activities import activity_problems, port_problems
from colcon_robmosys.check.results import CheckedFile
from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.model.build import FileBuilder
from colcon_robmosys.model.build_base import MODEL_SECTIONS
from colcon_robmosys.model.files import external_components_of, packages_of
from colcon_robmosys.model.loader import load_bytes, load_file
from colcon_robmosys.model.schema import structure_problems
from colcon_robmosys.model.types import (
    Component, model_key, ModelFile, ServiceDefinition, System)


def check_file(path: Path, raw: bytes) -> CheckedFile:
    """Load and check the content of one model file on its own.

    A model whose part of the file breaks a rule is left out; the others
    are kept for the rules of the workspace, so that an error in one model
    hides no error of another.
    """
    try:
        loaded = load_bytes(raw, path)
    except RobmosysError as exc:
        return CheckedFile(None, exc.diagnostics)
    located = structure_problems(loaded)
    diagnostics = [d for _, d in located]
    everything = packages_of(loaded.data)
    if any(len(p) < 2 or p[0] not in MODEL_SECTIONS for p, _ in located):
        # the file as a whole (its version, its defaults) is broken
        return CheckedFile(ModelFile(str(loaded.path)), tuple(diagnostics),
                           tuple(everything))
    skip = frozenset((str(p[0]), int(p[1])) for p, _ in located)
    builder = FileBuilder(loaded)
    models = builder.build_models(skip)
    diagnostics += builder.diagnostics
    broken = set(skip) | builder.broken_models
    for key, model in models:
        if isinstance(model, Component):
            # an external node answers its ports with code nobody generates
            problems = port_problems(model) + (
                [] if model.external else activity_problems(model))
            diagnostics += problems
            if problems:
                broken.add(key)
    kept = [m for key, m in models if key not in broken]
    kept_packages = {m.package for m in kept}
    return CheckedFile(
        ModelFile(
            str(loaded.path),
            tuple(m for m in kept if isinstance(m, ServiceDefinition)),
            tuple(m for m in kept if isinstance(m, Component)),
            tuple(m for m in kept if isinstance(m, System))),
        tuple(diagnostics),
        tuple(p for p in everything if p[0] not in kept_packages))


def broken_external_components(path: Path, kept: ModelFile | None) -> set[str]:
    """Return the external components of a broken file that did not pass."""
    try:
        described = external_components_of(load_file(path).data)
    except RobmosysError:
        return set()
    return set(described) - {model_key(c) for c in kept.components} if kept else set(described)
