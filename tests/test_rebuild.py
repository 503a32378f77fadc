# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Builds that can be trusted: parallel like sequential, nothing rebuilt for nothing.

One workspace of many models (synthetic components and a system that launches
them all, over test_workspace as underlay for their messages) is
built with four parallel workers and again sequentially: the generated and
installed trees must be the same byte for byte. A second build without a
model change must then rewrite no generated file and leave CMake and rosidl
nothing to do, and changing one component must regenerate that package only.
"""

from __future__ import annotations

import os
from pathlib import Path
import re
import shutil
import subprocess
import sys

import pytest

from colcon_robmosys.devtools import ros_env
from conftest import mtimes, requires_ros, TEST_WORKSPACE

pytestmark = requires_ros

#: How many synthetic components the workspace has.
EXTRA = 6

#: Files colcon itself writes on every build, whatever changed.
COLCON_FILES = (
    'colcon_build.rc', 'colcon_command_prefix_build.sh',
    'colcon_command_prefix_build.sh.env', '.colcon_install_layout', 'COLCON_IGNORE',
)

COMPONENT = """\
robmosys: 1
components:
  - name: Relay{k}
    package: relay{k}
    language: python
    description: Relay number {k}.
    license: Apache-2.0
    maintainers: [{{name: A, email: a@example.com}}]
    ports:
      rMap: {{pattern: push, role: required, type: simple_msgs/msg/Map}}
      pMap: {{pattern: push, role: provided, type: simple_msgs/msg/Map}}
    activities:
      OnMap: {{trigger: rMap, functions: [fRelay]}}
    functions:
      fRelay:
        code: |
          self.pMap.publish(commobj)  # relay {k}
    parameters:
      gain: {{type: double, default: {k}.5, description: Gain {k}.}}
"""


def _make_workspace(root: Path, *, messages: bool = False) -> Path:
    """Lay out the sources of the workspace of many models under root/src.

    :param messages: include the message package (else it comes from an underlay)
    """
    src = root / 'src'
    src.mkdir(parents=True)
    if messages:
        shutil.copytree(TEST_WORKSPACE / 'src' / 'simple_msgs', src / 'simple_msgs')
    instances, connections = [], []
    for k in range(EXTRA):
        (src / f'relay{k}').mkdir()
        (src / f'relay{k}' / 'robmosys.yaml').write_text(COMPONENT.format(k=k))
        instances.append(f'      relay{k}: {{component: relay{k}}}\n')
        if k:
            connections.append(f'      - {{from: relay{k - 1}.pMap, to: relay{k}.rMap}}\n')
    (src / 'relay_system').mkdir()
    (src / 'relay_system' / 'robmosys.yaml').write_text(
        'robmosys: 1\nsystems:\n  - package: relay_system\n    license: Apache-2.0\n'
        '    maintainers: [{name: A, email: a@example.com}]\n    instances:\n' +
        ''.join(instances) + '    connections:\n' + ''.join(connections))
    return root


def _tree(root: Path) -> dict[str, bytes]:
    """Return the generated and the installed files, but what colcon writes anew."""
    files = {}
    for path in [*sorted(root.glob('build/*/src-gen/**/*')), *sorted(root.glob('install/**/*'))]:
        relative = path.relative_to(root)
        if path.is_file() and '__pycache__' not in relative.parts and \
                path.name not in COLCON_FILES and len(relative.parts) > 2:
            files[str(relative)] = path.read_bytes()
    return files


#: What colcon and ament_cmake_python rewrite on every build, changed or not:
#: colcon's environment hooks and setup files, ament_cmake_python's copy of
#: the package and its egg-info, make's dependency notes.
REWRITTEN_ANYWAY = re.compile(
    r'^install/[^/]*$|/share/[^/]+/hook/|/share/[^/]+/package\.[a-z0-9]+$|'
    r'/share/colcon-core/packages/|\.egg-info/|^build/[^/]+/ament_cmake_python/|'
    r'/compiler_depend\.(make|internal|ts)$|'
    r'^build/[^/]+/(cmake_args\.last|install_manifest\.txt)$|'
    # an ament_python package of the user's (handwritten_nodes): setuptools
    # installs it anew on every build, whatever colcon-robmosys does
    r'^(build|install)/handwritten_nodes/')


def _kept(stamps: dict[str, int]) -> dict[str, int]:
    """Return the stamps of the files that a build may keep."""
    return {name: stamp for name, stamp in stamps.items()
            if Path(name).name not in COLCON_FILES and not REWRITTEN_ANYWAY.search(name)}


def _stamps(root: Path, *bases: str) -> dict[str, int]:
    """Return the mtimes of the files of build and install that builds may keep."""
    return _kept(mtimes(root, *bases))


def _build(root: Path, env: dict[str, str], *extra: str) -> str:
    result = ros_env.run([str(Path(sys.prefix) / 'bin' / 'colcon'), 'build',
                          '--event-handlers', 'console_cohesion+', *extra],
                         env=env, cwd=root, timeout=900)
    output = result.stdout + result.stderr
    assert result.returncode == 0, output
    return output


@pytest.fixture(scope='module')
def relays(test_workspace_built, tmp_path_factory) -> tuple[Path, dict, dict[str, bytes]]:
    """Build the relays with four workers, then again sequentially in the same place.

    The messages come from test_workspace, as an underlay: no rosidl work here.

    :returns: the sequentially built workspace, its environment, the parallel build's tree
    """
    root = _make_workspace(tmp_path_factory.mktemp('many'))
    env = test_workspace_built.env(ros_env.free_domain_id())
    _build(root, env, '--parallel-workers', '4')
    parallel = _tree(root)
    for base in ('build', 'install', 'log'):
        shutil.rmtree(root / base)
    _build(root, env, '--executor', 'sequential')
    return root, env, parallel


def test_parallel_build_equals_sequential_build(relays):
    root, _, parallel = relays
    sequential = _tree(root)
    assert sorted(parallel) == sorted(sequential)
    differ = [name for name in parallel if parallel[name] != sequential[name]]
    assert not differ, differ
    assert len([n for n in sequential if '/src-gen/' in n]) > 8 * EXTRA
    assert len([n for n in sequential if n.startswith('install/relay')]) > 8 * EXTRA


def test_changing_one_component_regenerates_that_package_only(relays):
    root, env, _ = relays
    before = _stamps(root, 'build', 'install')
    model = root / 'src' / 'relay2' / 'robmosys.yaml'
    model.write_text(model.read_text().replace('# relay 2', '# relay two'))
    _build(root, env)
    after = _stamps(root, 'build', 'install')
    # the generator's own records (the cache of checked models, the stamps of
    # the packages it looked at) are no package's work
    changed = sorted(n for n in before if after.get(n) != before[n]
                     and not n.startswith('build/.robmosys-cache/'))
    generated = [n for n in changed if '/src-gen/' in n]
    # the module, and the copy of the model the package installs
    assert generated == ['build/relay2/src-gen/.robmosys-generated',
                         'build/relay2/src-gen/relay2/Relay2.py',
                         'build/relay2/src-gen/robmosys/robmosys.yaml']
    # the module is installed anew; no other package did any work
    assert 'install/relay2/lib/python3.11/site-packages/relay2/Relay2.py'.replace(
        'python3.11', f'python{sys.version_info[0]}.{sys.version_info[1]}') in changed
    assert all(n.startswith(('build/relay2/', 'install/relay2/')) for n in changed), changed


def test_build_without_change_rewrites_nothing(test_workspace_built):
    """A second build of test_workspace: no generated file, no rosidl output rewritten.

    Every file of build/ and install/ keeps its mtime, but what colcon and
    ament_cmake_python rewrite on every build (REWRITTEN_ANYWAY): so no
    generation wrote, CMake did not configure again (its file API replies
    would be new), rosidl generated nothing and nothing was compiled. Where
    the session's build came over an earlier one (the demo's, in CI) and changed
    nothing, it was that second build; else (no earlier build, or sources changed
    since) the test builds once more.
    """
    built = test_workspace_built
    bases = (built.bases.build, built.bases.install)
    before, after = (_kept(stamps) for stamps in built.rebuilt or ({}, {}))
    if not before or _changed(before, after):
        before = _stamps(built.root, *bases)
        result = built.colcon('build', '--event-handlers', 'console_cohesion+')
        assert result.returncode == 0, result.stdout + result.stderr
        after = _stamps(built.root, *bases)
    assert not _changed(before, after), _changed(before, after)
    assert [n for n in before if '/src-gen/' in n]
    assert [n for n in before if '/rosidl_generator_c/' in n]
    assert [n for n in before if '/.cmake/api/v1/reply/' in n]


def _changed(before: dict[str, int], after: dict[str, int]) -> list[str]:
    return sorted(n for n in before.keys() | after.keys() if after.get(n) != before.get(n))


#: Generates every model of argv[1] into argv[2]/<package>.
CHILD = """
import sys
import os
from pathlib import Path
import re
from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.generators import generate_package
from colcon_robmosys.generators import plan_package

src, out = Path(sys.argv[1]), Path(sys.argv[2])
result = load_workspace(find_model_files([src]), InterfaceIndex([Path(sys.prefix)]))
result.raise_errors()
for model in result.workspace.models:
    generate_package(plan_package(result.workspace, model.package), out / model.package)
"""


def test_output_is_the_same_for_any_hash_seed_and_place(tmp_path):
    trees = []
    for seed, place in (('0', 'a'), ('1', 'b/deeper'), ('4242', 'c/with space')):
        root = _make_workspace(tmp_path / place, messages=True)
        out = root / 'out'
        env = {**os.environ, 'PYTHONHASHSEED': seed}
        subprocess.run([sys.executable, '-c', CHILD, str(root / 'src'), str(out)],
                       env=env, check=True, timeout=120)
        files = {str(p.relative_to(out)): p.read_bytes()
                 for p in sorted(out.rglob('*')) if p.is_file()}
        assert not [n for n, data in files.items() if str(tmp_path).encode() in data]
        trees.append(files)
    assert len(trees[0]) > 8 * EXTRA
    assert trees[0] == trees[1] == trees[2]
