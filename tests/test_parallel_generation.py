# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Above a few dozen model files, the check and robmosys-generate fork processes to share the work.

With the same outcome as one process: the same files, the same lines in the same
order, the same exit status, the user's files as safe, and a next run that finds
nothing to do (verb/generation.py, check/forked.py).
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
import yaml

from colcon_robmosys import check as check_module
from colcon_robmosys.check import find_model_files, load_workspace, ModelCache
from colcon_robmosys.check.cache import file_key
from colcon_robmosys.check.forked import fork_map, MIN_FILES_PER_WORKER
from colcon_robmosys.errors import Diagnostic, Location, RobmosysError
from colcon_robmosys.verb.generation import _shares, Package
from conftest import colcon, contents, requires_ros

#: Enough model files for two workers.
COMPONENTS = 2 * MIN_FILES_PER_WORKER + 4
#: A Python component's implementation file, in the workspace.
IMPL = 'src/comp{n}/src/comp{n}/C{n}_impl.py'
METADATA = {'license': 'Apache-2.0',
            'maintainers': [{'name': 'Test Team', 'email': 'test@example.com'}]}


def _component(number: int) -> dict:
    return {
        'name': f'C{number}', 'package': f'comp{number}',
        'language': 'python' if number % 4 else 'cpp',
        'ports': {'pOut': {'pattern': 'push', 'role': 'provided',
                           'type': 'std_msgs/msg/Header'},
                  'rIn': {'pattern': 'push', 'role': 'required',
                          'type': 'std_msgs/msg/Header'}},
        'activities': {'Tick': {'period': 0.5, 'functions': ['fTick']},
                       'OnIn': {'trigger': 'rIn', 'functions': ['fOnIn']}},
        'functions': {'fTick': {'description': 'Publish a header.'},
                      'fOnIn': {'description': 'Take a header.'}},
        'parameters': {'label': {'type': 'string', 'default': f'c{number}'}},
    }


def _write(src: Path, package: str, key: str, model: dict) -> None:
    folder = src / package
    folder.mkdir(parents=True)
    (folder / 'robmosys.yaml').write_text(yaml.safe_dump(
        {'robmosys': 1, 'defaults': METADATA, key: [model]}, sort_keys=False),
        encoding='utf-8')


def write_workspace(src: Path, *, broken: bool = False) -> None:
    """Write COMPONENTS components and a system of four of them."""
    for number in range(COMPONENTS):
        _write(src, f'comp{number}', 'components', _component(number))
    _write(src, 'ring_system', 'systems', {
        'package': 'ring_system', 'name': 'Ring',
        'instances': {f'n{i}': {'component': f'comp{i}'} for i in range(1, 5)},
        'connections': [{'from': f'n{i}.pOut', 'to': f'n{i % 4 + 1}.rIn'}
                        for i in range(1, 5)]})
    if broken:
        # a name no schema accepts: a check error of one file among many
        text = (src / 'comp9' / 'robmosys.yaml').read_text(encoding='utf-8')
        (src / 'comp9' / 'robmosys.yaml').write_text(
            text.replace('name: C9', 'name: 9C'), encoding='utf-8')


def test_fork_map_runs_each_share_but_the_last_in_a_process_of_its_own():
    parent = os.getpid()
    held = {'value': 42}  # inherited at the fork, never pickled

    def where(share: int) -> tuple[int, int, int]:
        return share, os.getpid(), held['value']

    results = fork_map(where, [1, 2, 3])
    assert [share for share, _, _ in results] == [1, 2, 3]
    assert {value for _, _, value in results} == {42}
    pids = [pid for _, pid, _ in results]
    # the last share runs in this process meanwhile
    assert parent not in pids[:2] and len(set(pids[:2])) == 2 and pids[2] == parent
    # one share: no fork
    assert fork_map(where, [7]) == [(7, parent, 42)]


def test_a_failure_in_a_worker_reaches_the_caller():
    def fail(share: int) -> int:
        if share == 1:
            raise ValueError(f'share {share}')
        return share

    # share 1 in a forked process, share 2 here
    with pytest.raises(ValueError, match='share 1'):
        fork_map(fail, [1, 2])

    def fail_here(share: int) -> int:
        if share == 2:
            raise ValueError('here')
        return share

    with pytest.raises(ValueError, match='here'):
        fork_map(fail_here, [1, 2])


def test_shares_keep_model_files_whole_and_even(tmp_path):
    files = []
    for number in range(40):
        path = tmp_path / f'm{number}.yaml'
        # a few large files among many small ones
        path.write_text('x' * (5000 if number % 10 == 0 else 100))
        files.append(path)
    # two packages from each model file
    packages = [Package(f'p{n}_{k}', str(files[n]), None, False)
                for n in range(40) for k in range(2)]
    todo = [(index, f'fingerprint{index}') for index in range(len(packages))]
    shares = _shares(packages, todo, workers=2)
    assert len(shares) == 2
    assert sorted(entry for share in shares for entry in share) == todo
    for share in shares:
        assert share == sorted(share)
    owner = {packages[index].model_file: number
             for number, share in enumerate(shares) for index, _ in share}
    for number, share in enumerate(shares):
        assert all(owner[packages[index].model_file] == number for index, _ in share)
    loads = [sum(os.stat(f).st_size for f in {packages[i].model_file for i, _ in share})
             for share in shares]
    assert max(loads) <= 1.2 * min(loads)
    # too few model files for a second worker: one share, everything in this process
    assert _shares(packages[:2 * (MIN_FILES_PER_WORKER - 1)],
                   todo[:2 * (MIN_FILES_PER_WORKER - 1)], workers=8) == \
        [todo[:2 * (MIN_FILES_PER_WORKER - 1)]]


@requires_ros
def test_the_check_in_two_processes_finds_what_one_finds(tmp_path, monkeypatch):
    write_workspace(tmp_path / 'src', broken=True)
    paths = find_model_files([tmp_path / 'src'])
    alone = load_workspace(paths, cache=ModelCache(tmp_path / 'alone'))
    forks = []
    real_fork_map = check_module.fork_map

    def spy(function, shares):
        forks.append(len(shares))
        return real_fork_map(function, shares)

    monkeypatch.setattr(check_module, 'fork_map', spy)
    cache = ModelCache(tmp_path / 'forked')
    forked = load_workspace(paths, cache=cache, workers=2)
    assert forks == [2]
    assert forked.diagnostics == alone.diagnostics
    assert any(str(d.location).startswith(str(tmp_path / 'src' / 'comp9'))
               for d in forked.errors)
    assert forked.broken_files == alone.broken_files
    assert forked.workspace == alone.workspace
    # the workers stored what they checked: the next run reads it back, forks nothing
    assert all(cache.has(file_key(p, p.read_bytes())) for p in paths)
    again = load_workspace(paths, cache=cache, workers=2)
    assert forks == [2] and cache.misses == 0 and cache.hits == len(paths)
    assert again.workspace == alone.workspace


@requires_ros
def test_the_verb_in_two_processes_generates_what_one_generates(tmp_path):
    for name in ('one', 'two'):
        write_workspace(tmp_path / name / 'src')
        # the user's own code of one component, not what the model asks for: an
        # error of the generation of that package only
        own = tmp_path / name / IMPL.format(n=5)
        own.parent.mkdir(parents=True)
        own.write_text('# my own, unfinished\n', encoding='utf-8')
    runs = {}
    for name, workers in (('one', '1'), ('two', '2')):
        runs[name] = colcon(['robmosys-generate', '--output-dir', 'gen',
                             '--parallel-workers', workers], cwd=tmp_path / name)
    one, two = runs['one'], runs['two']
    assert one.returncode == two.returncode == 1, one.stdout + one.stderr
    assert two.stdout == one.stdout
    assert two.stderr.replace(str(tmp_path / 'two'), str(tmp_path / 'one')) == one.stderr
    assert 'comp5' in two.stderr and two.stderr.count('error:') == one.stderr.count('error:')
    lines = two.stdout.splitlines()
    assert sum(line.startswith('created ') for line in lines) >= COMPONENTS - 1
    assert sum(line.startswith('generated ') for line in lines) == COMPONENTS
    # the same files, generated and created, and the user's untouched
    assert contents(tmp_path / 'two', 'gen', 'src') == contents(tmp_path / 'one', 'gen', 'src')
    assert (tmp_path / 'two' / IMPL.format(n=5)).read_text(
        encoding='utf-8') == '# my own, unfinished\n'
    # the user mends it from the model's blueprint; the next run generates that package
    # alone, and the one after finds nothing to do
    text = (tmp_path / 'one' / IMPL.format(n=6)).read_text(encoding='utf-8')
    (tmp_path / 'two' / IMPL.format(n=5)).write_text(
        text.replace('C6', 'C5').replace('comp6', 'comp5'), encoding='utf-8')
    mended = colcon(['robmosys-generate', '--output-dir', 'gen'], cwd=tmp_path / 'two')
    assert mended.returncode == 0, mended.stdout + mended.stderr
    written = [line for line in mended.stdout.splitlines() if ' 0 written' not in line]
    assert written == [line for line in written if 'comp5 ' in line] and len(written) == 1
    before = contents(tmp_path / 'two', 'gen')
    again = colcon(['robmosys-generate', '--output-dir', 'gen'], cwd=tmp_path / 'two')
    assert again.returncode == 0, again.stdout + again.stderr
    assert all(' 0 written' in line for line in again.stdout.splitlines()
               if line.startswith('generated '))
    assert contents(tmp_path / 'two', 'gen') == before


def test_a_model_error_in_a_worker_reaches_the_caller_whole():
    diagnostics = [Diagnostic(Location('a/robmosys.yaml', 3, 5), 'first'),
                   Diagnostic(Location('b/robmosys.yaml', 1, 1), 'second')]

    def fail(share: int) -> int:
        if share == 1:
            raise RobmosysError(diagnostics)
        return share

    with pytest.raises(RobmosysError) as raised:
        fork_map(fail, [1, 2])
    assert raised.value.diagnostics == tuple(diagnostics)
