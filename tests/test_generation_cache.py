# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The cache of checked model files and the stamps of generated packages.

Both let a run skip work an earlier run did; neither may ever let it skip
work whose result would differ: a changed model, a changed user file, a file
of the build tree changed by hand, another colcon-robmosys, a corrupt entry.
"""

from __future__ import annotations

from pathlib import Path
import shutil
import sys

import pytest

from colcon_robmosys.check import cache as cache_module
from colcon_robmosys.check import find_model_files, load_workspace, ModelCache
from colcon_robmosys.check.cache import CACHE_DIR
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.generators import (
    create_missing_user_files, fingerprint, generate_package, MANIFEST, plan_package,
    read_manifest, StampStore, unchanged_package)
from colcon_robmosys.model import schema
from conftest import TEST_WORKSPACE
from harness.fake_ament import EXAMPLE_EXTRA, fake_ament_index


@pytest.fixture(scope='module')
def index(tmp_path_factory) -> InterfaceIndex:
    return fake_ament_index(tmp_path_factory.mktemp('ament_prefix'), EXAMPLE_EXTRA)


@pytest.fixture
def src(tmp_path) -> Path:
    shutil.copytree(TEST_WORKSPACE / 'src', tmp_path / 'src',
                    ignore=shutil.ignore_patterns('__pycache__'))
    return tmp_path / 'src'


def _load(src: Path, index: InterfaceIndex, cache: ModelCache | None):
    return load_workspace(find_model_files([src]), index, cache)


def _summary(result) -> tuple:
    return (result.workspace, result.diagnostics, result.broken_files,
            result.package_warnings)


def test_cached_files_give_the_same_result(src, tmp_path, index):
    cache = ModelCache(tmp_path / CACHE_DIR)
    fresh = _load(src, index, None)
    first = _load(src, index, cache)
    assert cache.hits == 0 and cache.misses == len(first.file_keys)
    again = _load(src, index, cache)
    assert cache.hits == len(first.file_keys)
    assert _summary(fresh) == _summary(first) == _summary(again)


def test_a_changed_file_is_checked_anew(src, tmp_path, index):
    cache = ModelCache(tmp_path / CACHE_DIR)
    _load(src, index, cache)
    model = src / 'subscriber' / 'robmosys.yaml'
    model.write_text(model.read_text().replace('trigger: rMap', 'trigger: rMapp'))
    result = _load(src, index, cache)
    assert cache.misses == 1 + len(result.file_keys)
    assert [str(e) for e in result.errors_of(str(model))] == [
        f"{model}:19:18: error: activity 'HandleMsg' is triggered by unknown port "
        "'rMapp' (known: rMap)"]
    # broken files are kept too, with their errors
    assert _summary(_load(src, index, cache)) == _summary(result)
    assert _summary(_load(src, index, None)) == _summary(result)


def test_another_colcon_robmosys_finds_no_entry(src, tmp_path, index, monkeypatch):
    cache = ModelCache(tmp_path / CACHE_DIR)
    _load(src, index, cache)
    monkeypatch.setattr(cache_module, 'code_digest', lambda: 'other code')
    cache.hits = 0
    _load(src, index, cache)
    assert cache.hits == 0


def test_corrupt_entries_are_ignored(src, tmp_path, index):
    cache = ModelCache(tmp_path / CACHE_DIR)
    expected = _summary(_load(src, index, cache))
    entries = sorted((tmp_path / CACHE_DIR).glob('*.model'))
    assert entries
    for number, entry in enumerate(entries):
        entry.write_bytes([b'', b'garbage', entry.read_bytes()[:20]][number % 3])
    assert _summary(_load(src, index, cache)) == expected
    assert cache.hits == 0


def test_a_cache_that_is_not_writable_writes_nothing(src, tmp_path, index):
    cache = ModelCache(tmp_path / CACHE_DIR, writable=False)
    _load(src, index, cache)
    assert not (tmp_path / CACHE_DIR).exists()


def test_the_compiled_schema_is_kept_and_read_back(src, tmp_path, index, monkeypatch):
    # compiling the schema took some 0.4 s in every colcon process that
    # checked a file: a build keeps the compiled code beside the entries
    monkeypatch.setattr(schema, '_fast', [])
    cache = ModelCache(tmp_path / CACHE_DIR)
    stale = tmp_path / CACHE_DIR / f'{"0" * 64}.schema-code'
    stale.parent.mkdir()
    stale.write_bytes(b'the schema of an older colcon-robmosys')
    expected = _summary(_load(src, index, cache))
    kept = sorted((tmp_path / CACHE_DIR).glob('*.schema-code'))
    assert [p.name for p in kept] == [f'{schema.compiled_key()}.schema-code']

    def compile_again():
        raise AssertionError('compiled again, not read back')

    monkeypatch.setattr(schema, '_fast', [])
    monkeypatch.setattr(schema, 'compile_fast_check', compile_again)
    # a new process, whose files are not in the cache (changed, say)
    for entry in (tmp_path / CACHE_DIR).glob('*.model'):
        entry.unlink()
    read_back = ModelCache(tmp_path / CACHE_DIR)
    assert _summary(_load(src, index, read_back)) == expected
    assert read_back.misses and schema.fast_check_ready()
    # read back, it judges as compiled: valid and broken files alike
    model = src / 'subscriber' / 'robmosys.yaml'
    model.write_text(model.read_text().replace('trigger: rMap', 'trigger: [rMap]'))
    assert _summary(_load(src, index, read_back)) == _summary(_load(src, index, None))
    assert _load(src, index, None).errors_of(str(model))


def test_a_corrupt_compiled_schema_is_compiled_again(src, tmp_path, index, monkeypatch):
    monkeypatch.setattr(schema, '_fast', [])
    entry = tmp_path / CACHE_DIR / f'{schema.compiled_key()}.schema-code'
    entry.parent.mkdir()
    entry.write_bytes(b'\xe3 not marshal')
    assert _summary(_load(src, index, ModelCache(tmp_path / CACHE_DIR))) == \
        _summary(_load(src, index, None))
    assert schema.fast_check_ready()
    assert entry.read_bytes() != b'\xe3 not marshal'


def test_without_fastjsonschema_jsonschema_judges_and_nothing_is_kept(
        src, tmp_path, index, monkeypatch):
    expected = _summary(_load(src, index, None))
    monkeypatch.setattr(schema, '_fast', [])
    monkeypatch.setitem(sys.modules, 'fastjsonschema', None)  # import fails
    assert _summary(_load(src, index, ModelCache(tmp_path / CACHE_DIR))) == expected
    assert schema.fast_check_ready() and schema._fast_check() is None
    assert not list((tmp_path / CACHE_DIR).glob('*.schema-code'))


def _generate_all(src: Path, out: Path, index: InterfaceIndex) -> dict[str, int]:
    """Generate every package as colcon build does; count what each step did."""
    cache = ModelCache(out / CACHE_DIR)
    stamps = StampStore(out / CACHE_DIR / 'stamps')
    result = _load(src, index, cache)
    counts = {'skipped': 0, 'generated': 0, 'written': 0}
    for model in result.workspace.generated_models:
        if model.package in result.broken_files or result.errors_of(model.info.model_file):
            continue
        inputs = fingerprint(result, model.package, standalone=True)
        target = out / model.package
        if unchanged_package(target, stamps, inputs) is not None:
            counts['skipped'] += 1
            continue
        plan = plan_package(result.workspace, model.package)
        create_missing_user_files(plan)
        report = generate_package(plan, target, stamps=stamps, fingerprint=inputs)
        counts['generated'] += 1
        counts['written'] += len(report.written)
    return counts


def _tree(root: Path) -> dict[str, object]:
    """Return the files below root; of a manifest, the files it lists.

    (A manifest may also list the content a file had before the last change.)
    """
    return {str(p.relative_to(root)):
            sorted(read_manifest(p)) if p.name == MANIFEST else p.read_bytes()
            for p in sorted(root.rglob('*')) if p.is_file() and CACHE_DIR not in p.parts}


def test_stamps_skip_only_what_would_not_change(src, tmp_path, index):
    out = tmp_path / 'out'
    first = _generate_all(src, out, index)
    assert first['skipped'] == 0 and first['written'] > 100
    packages = first['generated']
    assert _generate_all(src, out, index) == {
        'skipped': packages, 'generated': 0, 'written': 0}

    # a generated file changed by hand is generated again
    node = out / 'publisher' / 'publisher' / 'PeriodicPublisher.py'
    expected = node.read_bytes()
    node.write_bytes(expected + b'# mine\n')
    assert _generate_all(src, out, index) == {
        'skipped': packages - 1, 'generated': 1, 'written': 1}
    assert node.read_bytes() == expected

    # a generated file removed
    node.unlink()
    assert _generate_all(src, out, index)['generated'] == 1
    assert node.read_bytes() == expected

    # the user's file, copied into the (standalone) package at its path
    impl = src / 'subscriber' / 'src' / 'subscriber' / 'Subscriber_impl.py'
    impl.write_bytes(impl.read_bytes() + b'\n# more of my work\n')
    counts = _generate_all(src, out, index)
    assert counts['generated'] == 1 and counts['written'] == 1
    assert (out / 'subscriber' / 'src' / 'subscriber' / 'Subscriber_impl.py').read_bytes() == \
        impl.read_bytes()

    # a model: its package and those that depend on it (the systems using it)
    model = src / 'publisher' / 'robmosys.yaml'
    model.write_text(model.read_text() + '\n# a comment\n')
    counts = _generate_all(src, out, index)
    assert counts['generated'] >= 2 and counts['skipped'] >= packages - 4

    # whatever was skipped, the tree is what a generation from nothing gives
    fresh = tmp_path / 'fresh'
    _generate_all(src, fresh, index)
    assert _tree(out) == _tree(fresh)


def test_a_corrupt_stamp_means_generating(src, tmp_path, index):
    out = tmp_path / 'out'
    packages = _generate_all(src, out, index)['generated']
    for stamp in (out / CACHE_DIR / 'stamps').glob('*.stamp'):
        stamp.write_bytes(b'not a stamp')
    assert _generate_all(src, out, index) == {
        'skipped': 0, 'generated': packages, 'written': 0}
