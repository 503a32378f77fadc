# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A generation killed at any moment leaves each file complete-old or complete-new.

A subprocess regenerates test_workspace's packages from changed models (large
descriptions, so that there is much to write) and is killed with SIGKILL at
random moments; every file must then hold the whole old or the whole new
content, and the next generation must finish the work and leave no
temporary file behind.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path
import random
import shutil
import signal
import subprocess
import sys
import time

import pytest

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.generators import Durable, generate_package, MANIFEST, read_manifest
from colcon_robmosys.generators import plan_package
from colcon_robmosys.generators.durable import NEW_SUFFIX
from colcon_robmosys.generators.fileops import TEMP_SUFFIX
from conftest import TEST_WORKSPACE

#: Generates every model of argv[1] into argv[2]/<package>; says 'go' once
#: imported and planned, so that the kill falls into the writing. With a
#: number argv[3], the child SIGKILLs itself at that file operation (creating,
#: renaming or removing a file: Python's audit events), a moment that a
#: machine's load cannot shift.
CHILD = """
import os
import signal
import sys
from pathlib import Path
from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.generators import Durable, generate_package
from colcon_robmosys.generators import plan_package

src, out = Path(sys.argv[1]), Path(sys.argv[2])
# the writes of output a user keeps wait for one commit, as the verb's do
durable = Durable() if os.environ.get('ROBMOSYS_TEST_DURABLE') else None
result = load_workspace(find_model_files([src]), InterfaceIndex([Path(sys.prefix)]))
result.raise_errors()
plans = [plan_package(result.workspace, m.package) for m in result.workspace.generated_models]
events = []

def hook(event, args):
    if event in ('open', 'os.rename', 'os.remove', 'os.link') and len(sys.argv) > 3:
        if event != 'open' or str(args[0]).startswith(str(out)):
            events.append(event)
            if len(events) == int(sys.argv[3]):
                os.kill(os.getpid(), signal.SIGKILL)

sys.addaudithook(hook)
print('go', flush=True)
for plan in plans:
    generate_package(plan, out / plan.name, durable=durable)
if durable is not None:
    durable.commit()
print('events', len(events), flush=True)
"""

ITERATIONS = 8


def _version(src: Path, text: str) -> None:
    """Give every model of src a long description made of text."""
    description = ' '.join([text] * 3000)
    for model in src.rglob('robmosys.yaml'):
        lines = model.read_text().splitlines(keepends=True)
        lines = [line for line in lines if not line.startswith('    description:')]
        index = next(i for i, line in enumerate(lines) if line.startswith('  - '))
        lines.insert(index + 1, f'    description: {description}\n')
        model.write_text(''.join(lines))


def _generate(src: Path, out: Path, *, kill_after: float | None = None,
              kill_at: int | None = None, durable: bool = False) -> tuple[float, str]:
    """Run the child; kill it kill_after seconds after 'go' or at its kill_at-th file operation.

    :returns: how long the child ran after 'go', and what it printed then
    """
    command = [sys.executable, '-c', CHILD, str(src), str(out)]
    if kill_at is not None:
        command.append(str(kill_at))
    env = dict(os.environ, ROBMOSYS_TEST_DURABLE='1' if durable else '')
    child = subprocess.Popen(command, stdout=subprocess.PIPE, text=True, env=env)
    try:
        assert child.stdout is not None
        assert child.stdout.readline() == 'go\n'
        start = time.monotonic()
        if kill_after is not None:
            time.sleep(kill_after)
            child.send_signal(signal.SIGKILL)
        rest = child.stdout.read()
        child.wait(timeout=120)
        if kill_after is None and kill_at is None:
            assert child.returncode == 0
        return time.monotonic() - start, rest
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()


def _plans(src: Path) -> list:
    """Return the plan of each package the models of src generate."""
    result = load_workspace(find_model_files([src]), InterfaceIndex([Path(sys.prefix)]))
    return [plan_package(result.workspace, m.package) for m in result.workspace.generated_models]


def _generate_here(plans: list, out: Path) -> None:
    for plan in plans:
        generate_package(plan, out / plan.name)


def _files(root: Path) -> dict[str, bytes]:
    return {str(p.relative_to(root)): p.read_bytes()
            for p in sorted(root.rglob('*')) if p.is_file()}


def _outputs(root: Path) -> dict[str, bytes]:
    """Return the files below root, each manifest as the files it lists.

    The manifest, written once before the files, may also list the content
    a file had before; what counts is that it knows every file as generated.
    """
    files = _files(root)
    for name in files:
        if Path(name).name == MANIFEST:
            _check_manifest(root / name)
            files[name] = '\n'.join(sorted(read_manifest(root / name))).encode()
    return files


def _check_manifest(path: Path) -> None:
    """Check that the manifest knows each file of its package as generated.

    Between its two writes it lists the old and the new digest of each file.
    """
    manifest = read_manifest(path)
    for file in path.parent.rglob('*'):
        if file.is_file() and file != path and not file.name.endswith(TEMP_SUFFIX):
            digests = manifest[str(file.relative_to(path.parent))]
            assert digests and hashlib.sha256(file.read_bytes()).hexdigest() in digests


@pytest.mark.parametrize('durable', [False, True], ids=['build-tree', 'durable'])
def test_killed_generation_leaves_whole_files(tmp_path, durable):
    src = tmp_path / 'src'
    shutil.copytree(TEST_WORKSPACE / 'src', src, ignore=shutil.ignore_patterns('__pycache__'))
    users = _files(src)
    _version(src, 'Old text.')
    _generate(src, tmp_path / 'old')
    old = _files(tmp_path / 'old')
    _version(src, 'New words, longer.')
    shutil.copytree(tmp_path / 'old', tmp_path / 'new')
    duration, printed = _generate(src, tmp_path / 'new', kill_at=10 ** 9, durable=durable)
    events = int(printed.split()[1])
    new = _outputs(tmp_path / 'new')
    plans = _plans(src)
    assert old.keys() == new.keys()
    changed = {name for name in old
               if old[name] != new[name] and Path(name).name != MANIFEST}
    assert len(changed) >= 8

    rng = random.Random(6)
    mixed = 0
    for iteration in range(ITERATIONS):
        out = tmp_path / f'run{iteration}'
        shutil.copytree(tmp_path / 'old', out)
        if iteration % 2:
            # spread the kills over the whole run, and a little beyond
            _generate(src, out, kill_after=rng.uniform(0, duration * 1.2), durable=durable)
        else:
            # or at one of its file operations
            # durable: every file changed is written to a temporary file first, then
            # each renamed: its last operations, where a kill leaves a mix
            first = events - len(changed) + 2 if durable else 1
            _generate(src, out, kill_at=rng.randint(first, events), durable=durable)
        seen = set()
        for path in sorted(out.rglob('*')):
            if not path.is_file():
                continue
            name = str(path.relative_to(out))
            if path.name.endswith(TEMP_SUFFIX):
                continue  # a temporary file, not yet renamed: removed below
            assert name in old, f'{name}: unexpected file'
            data = path.read_bytes()
            if path.name == MANIFEST:
                _check_manifest(path)
                continue
            assert data in (old[name], new[name]), f'{name}: neither old nor new'
            if name in changed:
                seen.add(data == new[name])
        mixed += seen == {True, False}
        # the next generation completes the work and leaves nothing behind
        _generate_here(plans, out)
        assert _outputs(out) == new
    # the user's files beside the models were not touched
    assert {k: v for k, v in _files(src).items() if not k.endswith('robmosys.yaml')} == \
        {k: v for k, v in users.items() if not k.endswith('robmosys.yaml')}
    # else the kills fell outside the writing and tested nothing
    print(f'{mixed} of {ITERATIONS} kills fell amid {events} file operations in {duration:.3f} s')
    assert mixed >= 2, f'only {mixed} of {ITERATIONS} kills fell amid the writing'


def test_writer_replaces_in_the_same_folder(tmp_path, monkeypatch):
    """The new content goes to a temporary file beside the target, then os.replace."""
    from colcon_robmosys.generators import writer
    calls = []
    real_replace = os.replace

    def replace(source, target):
        calls.append((Path(source), Path(target)))
        assert Path(target).read_bytes() == b'# Generated by colcon-robmosys\nold\n'
        real_replace(source, target)

    target = tmp_path / 'deep' / 'file.txt'
    target.parent.mkdir()
    target.write_bytes(b'# Generated by colcon-robmosys\nold\n')
    monkeypatch.setattr(writer.os, 'replace', replace)
    assert writer.write_generated(target, b'# Generated by colcon-robmosys\nnew\n')
    [(source, replaced)] = calls
    assert replaced == target and source.parent == target.parent
    assert source.name.endswith(TEMP_SUFFIX) and not source.exists()
    assert target.read_bytes() == b'# Generated by colcon-robmosys\nnew\n'


def test_a_killed_first_generation_leaves_each_package_whole_or_absent(tmp_path):
    # output a user keeps, generated for the first time: each package is written
    # whole into a hidden folder beside it, then renamed into place
    src = tmp_path / 'src'
    shutil.copytree(TEST_WORKSPACE / 'src', src, ignore=shutil.ignore_patterns('__pycache__'))
    _generate(src, tmp_path / 'reference')
    reference = _outputs(tmp_path / 'reference')
    packages = sorted(p.name for p in (tmp_path / 'reference').iterdir())
    _, printed = _generate(src, tmp_path / 'full', kill_at=10 ** 9, durable=True)
    assert _outputs(tmp_path / 'full') == reference
    events = int(printed.split()[1])
    rng = random.Random(28)
    mixed = 0
    for iteration in range(6):
        out = tmp_path / f'run{iteration}'
        # the renames are the run's last operations: half the kills fall among them
        first = events - len(packages) + 1 if iteration % 2 else 1
        _generate(src, out, kill_at=rng.randint(first, events), durable=True)
        present = sorted(p.name for p in out.iterdir() if not p.name.startswith('.')) \
            if out.exists() else []
        for package in present:
            assert _outputs(out / package) == _outputs(tmp_path / 'reference' / package), package
        mixed += 0 < len(present) < len(packages)
        # the next run writes the rest and removes what the killed one left
        _generate(src, out, durable=True)
        assert _outputs(out) == reference
        assert sorted(p.name for p in out.iterdir()) == packages
    assert mixed >= 1, 'no kill fell among the renames of the packages'


def test_a_package_folder_made_meanwhile_keeps_its_files(tmp_path):
    root = tmp_path / 'out' / 'pkg'
    durable = Durable()
    durable.new_package(root, {'CMakeLists.txt': (b'generated\n', False),
                               'scripts/run': (b'#!/bin/sh\n', True)})
    done = []
    durable.then(lambda: done.append('pkg'), root)
    durable.then(lambda: done.append('run'))
    # the user made the folder, with a file of theirs, after the run looked
    (root / 'scripts').mkdir(parents=True)
    (root / 'CMakeLists.txt').write_bytes(b'mine\n')
    durable.commit()
    # the package was not placed whole: no stamp of it, the next run looks at every file
    assert done == ['run']
    assert (root / 'CMakeLists.txt').read_bytes() == b'mine\n'
    assert (root / 'scripts' / 'run').read_bytes() == b'#!/bin/sh\n'
    assert os.access(root / 'scripts' / 'run', os.X_OK)
    assert sorted(p.name for p in root.parent.iterdir()) == ['pkg']


def test_what_a_killed_run_left_beside_a_package_is_removed_by_the_next(tmp_path):
    out = tmp_path / 'out'
    dead = subprocess.run([sys.executable, '-c', 'import os; print(os.getpid())'],
                          capture_output=True, text=True, check=True).stdout.strip()
    left = out / f'.pkg.{dead}-0{NEW_SUFFIX}'
    running = out / f'.other.{os.getpid()}-3{NEW_SUFFIX}'
    for folder in (left, running):
        (folder / 'src').mkdir(parents=True)
        (folder / 'src' / 'a.cpp').write_bytes(b'half')
    durable = Durable()
    durable.new_package(out / 'pkg', {'package.xml': (b'<package/>\n', False)})
    durable.commit()
    # a run still running keeps its folder; one no longer running does not
    assert sorted(p.name for p in out.iterdir()) == [running.name, 'pkg']
    assert (out / 'pkg' / 'package.xml').read_bytes() == b'<package/>\n'
