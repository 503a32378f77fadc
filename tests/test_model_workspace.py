# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A workspace finds the model of a package without scanning every model again.

colcon plans and builds the packages of a workspace one by one, and each asks the
workspace for its model: a scan per lookup made a workspace of 1000 components
spend as long finding models as generating them (bench/bench_generation.py).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from colcon_robmosys.check import load_model_file
from colcon_robmosys.model.types import model_key, ModelFile, Workspace

VALID = sorted((Path(__file__).resolve().parent / 'models' / 'valid').glob('*.yaml'))


@pytest.fixture(scope='module')
def files() -> tuple[ModelFile, ...]:
    return tuple(load_model_file(path) for path in VALID)


def test_every_model_is_found(files):
    workspace = Workspace(files)
    models = [m for f in files for m in f.models]
    assert workspace.models == tuple(models)
    assert len(models) > len(files)  # multi_model.yaml holds several
    for model in models:
        # an external component is found by package/executable: a package may hold several
        assert workspace.model(model_key(model)) is model
    assert workspace.model('no_such_package') is None
    talker = workspace.model('demo_nodes_py/talker')
    assert talker is not None and talker.package == 'demo_nodes_py'
    assert workspace.model('demo_nodes_py') is None


def test_a_package_claimed_twice_keeps_its_first_model(files):
    copy = dataclasses.replace(files[0], path='/elsewhere/robmosys.yaml')
    first = files[0].models[0]
    assert Workspace((files[0], copy)).model(first.package) is first
    assert Workspace((copy, files[0])).model(first.package) is copy.models[0]


def test_lookups_read_each_file_once(files, monkeypatch):
    reads = []
    original = ModelFile.models

    def counting(self: ModelFile):
        reads.append(self.path)
        return original.fget(self)

    monkeypatch.setattr(ModelFile, 'models', property(counting))
    many = tuple(dataclasses.replace(f, path=f'{f.path}.{i}')
                 for i in range(20) for f in files)
    workspace = Workspace(many)
    for _ in range(3):
        for model in workspace.models:
            workspace.model(model.package)
    assert len(reads) == len(many)
