# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Generated component packages keep only what their model states: the runtime has the rest.

Counted without building: every component of test_workspace is generated, and
the lines of its sources (``src-gen/`` for C++, the node's Python package) are
counted; skeletons and the user's files are not.
"""

from __future__ import annotations

from pathlib import Path
import sys

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.generators import generate_package, plan_package
from colcon_robmosys.generators.render import templates_dir
from colcon_robmosys.model.types import Component
from conftest import TEST_WORKSPACE

#: the most lines a generated component package of test_workspace has on average
AVERAGE_LINES = 190

#: the most lines a template has
TEMPLATE_LINES = 250


def _source_lines(root: Path, package: str) -> int:
    lines = 0
    for path in root.rglob('*'):
        relative = path.relative_to(root).as_posix()
        if path.is_file() and relative.split('/')[0] in ('src-gen', package):
            lines += len(path.read_text().splitlines())
    return lines


def test_generated_components_average_under_the_limit(tmp_path):
    result = load_workspace(find_model_files([TEST_WORKSPACE / 'src']),
                            InterfaceIndex([Path(sys.prefix)]))
    result.raise_errors()
    counts = {}
    for model in result.workspace.generated_models:
        if isinstance(model, Component):
            generate_package(plan_package(result.workspace, model.package),
                             tmp_path / model.package)
            counts[model.package] = _source_lines(tmp_path / model.package, model.package)
    # both languages are counted
    assert {'publisher', 'cpp_publisher', 'level_watcher', 'cpp_level_watcher'} <= set(counts)
    average = sum(counts.values()) / len(counts)
    assert average < AVERAGE_LINES, sorted(counts.items(), key=lambda item: item[1])


def test_no_template_is_too_long():
    lengths = {path.relative_to(templates_dir()).as_posix(): len(path.read_text().splitlines())
               for path in templates_dir().rglob('*.jinja')}
    assert lengths
    assert max(lengths.values()) <= TEMPLATE_LINES, {
        name: n for name, n in lengths.items() if n > TEMPLATE_LINES}
