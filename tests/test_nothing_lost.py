# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Whatever the model does, generation never loses a file of the user.

Hypothesis drives random model edits (rename a component, add or remove a
function, move or rename a package, change ports), user edits (implementation
files, files of their own, a file where a generated one would go) and
regenerations, the way ``colcon robmosys-generate --output-dir`` does them.
After every step each file the user owns is there, byte for byte.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import os
from pathlib import Path
import shutil
import tempfile
from typing import Any

from hypothesis import given, HealthCheck, settings, strategies as st
import pytest
import yaml

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.generators import create_missing_user_files, generate_package
from colcon_robmosys.generators import plan_package
from conftest import colcon, requires_ros
from harness.fake_ament import fake_ament_index

NAMES = ['Alpha', 'Beta', 'Gamma']
PACKAGES = ['comp_a', 'comp_b', 'comp_c']
FUNCTIONS = ['fTick', 'fPublish', 'fCheck', 'fLog']
PORTS = {
    'pText': {'pattern': 'push', 'role': 'provided', 'type': 'std_msgs/msg/String'},
    'rText': {'pattern': 'push', 'role': 'required', 'type': 'std_msgs/msg/String'},
    'sHeader': {'pattern': 'send', 'role': 'required', 'type': 'std_msgs/msg/Header'},
}


@dataclass
class Component:
    """A component model as the test edits it."""

    name: str
    package: str
    folder: str
    functions: dict[str, bool] = field(default_factory=lambda: {'fTick': False})
    ports: list[str] = field(default_factory=list)

    def model(self) -> dict[str, Any]:
        activities = {'Loop': {'period': 1.0, 'functions': sorted(self.functions)}} \
            if self.functions else {}
        return {'robmosys': 1, 'components': [{
            'name': self.name, 'package': self.package, 'language': 'python',
            'license': 'Apache-2.0',
            'maintainers': [{'name': 'A', 'email': 'a@example.com'}],
            'ports': {p: PORTS[p] for p in self.ports},
            'activities': activities,
            'functions': {f: ({'code': 'pass\n'} if coded else {})
                          for f, coded in sorted(self.functions.items())},
        }]}


class Workspace:
    """A workspace of component models, its output and the user's files."""

    def __init__(self, root: Path, index: InterfaceIndex):
        self.root, self.index = root, index
        self.src, self.out = root / 'src', root / 'out'
        self.components = [Component(n, p, p) for n, p in zip(NAMES[:2], PACKAGES[:2])]
        #: every file the user owns -> its content
        self.user_files: dict[Path, bytes] = {}
        self.save_models()

    def save_models(self) -> None:
        for path in self.src.rglob('robmosys.yaml'):
            path.unlink()
        for component in self.components:
            path = self.src / component.folder / 'robmosys.yaml'
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(yaml.safe_dump(component.model(), sort_keys=False))

    def generate(self) -> None:
        """Regenerate every package, as the verb does with --output-dir."""
        result = load_workspace(find_model_files([self.src]), self.index)
        for model in result.workspace.generated_models:
            try:
                plan = plan_package(result.workspace, model.package)
                for path in create_missing_user_files(plan):
                    # created once from the model: the user's from now on
                    self.user_files[path] = path.read_bytes()
                generate_package(plan, self.out / model.package)
            except RobmosysError:
                pass  # a broken model or implementation writes nothing

    def check(self) -> None:
        for path, data in self.user_files.items():
            assert path.is_file(), f'{path} was removed'
            assert path.read_bytes() == data, f'{path} was changed'
        leftovers = list(self.root.rglob('*.tmp'))
        assert not leftovers

    def own(self, path: Path, data: bytes) -> None:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
        self.user_files[path] = data

    def move_user_files(self, old: Path, new: Path) -> None:
        self.user_files = {
            (new / p.relative_to(old) if old in p.parents else p): data
            for p, data in self.user_files.items()}


def _apply(ws: Workspace, data: st.DataObject) -> str:
    """Make one random edit; return what it was."""
    component = data.draw(st.sampled_from(ws.components), label='component')
    action = data.draw(st.sampled_from([
        'rename', 'add_function', 'remove_function', 'code', 'move', 'repackage',
        'port', 'edit_impl', 'user_file', 'block_generated', 'add_component']),
        label='action')
    if action == 'rename':
        old_name = component.name
        component.name = data.draw(st.sampled_from(NAMES), label='name')
        code = ws.src / component.folder / 'src' / component.package
        old, new = code / f'{old_name}_impl.py', code / f'{component.name}_impl.py'
        # generation refuses while the implementation is left behind: the user
        # renames it, as the error says, or not (yet)
        if old in ws.user_files and not new.exists() and \
                data.draw(st.booleans(), label='rename the implementation'):
            content = ws.user_files.pop(old)
            old.unlink()
            ws.own(new, content.replace(old_name.encode(), component.name.encode()))
    elif action == 'add_function':
        component.functions[data.draw(st.sampled_from(FUNCTIONS), label='f')] = \
            data.draw(st.booleans(), label='coded')
    elif action == 'remove_function' and component.functions:
        del component.functions[data.draw(st.sampled_from(sorted(component.functions)))]
    elif action == 'code' and component.functions:
        name = data.draw(st.sampled_from(sorted(component.functions)), label='f')
        component.functions[name] = not component.functions[name]
    elif action == 'move':
        old = ws.src / component.folder
        component.folder = data.draw(st.sampled_from(
            [component.package, f'moved/{component.package}', f'deep/er/{component.package}']),
            label='folder')
        new = ws.src / component.folder
        if old != new and old.exists() and not new.exists():
            new.parent.mkdir(parents=True, exist_ok=True)
            shutil.move(old, new)
            ws.move_user_files(old, new)
        elif old != new:
            component.folder = str(old.relative_to(ws.src))
    elif action == 'repackage':
        taken = {c.package for c in ws.components}
        component.package = data.draw(st.sampled_from(
            [p for p in PACKAGES if p not in taken] or [component.package]), label='package')
    elif action == 'port':
        port = data.draw(st.sampled_from(sorted(PORTS)), label='port')
        if port in component.ports:
            component.ports.remove(port)
        else:
            component.ports.append(port)
    elif action == 'edit_impl':
        impls = sorted(p for p in ws.user_files if p.name.endswith('_impl.py'))
        if impls:
            path = data.draw(st.sampled_from(impls), label='impl')
            ws.own(path, data.draw(st.binary(max_size=200), label='content'))
    elif action == 'user_file':
        base = data.draw(st.sampled_from(
            [ws.src / component.folder, ws.src / component.folder / 'src' / component.package,
             ws.out / component.package, ws.out / component.package / 'scripts']),
            label='where')
        name = data.draw(st.sampled_from(['notes.txt', 'helper.py', 'README.md']))
        ws.own(base / name, data.draw(st.binary(max_size=100), label='content'))
    elif action == 'block_generated':
        # a file without the banner where a generated one would go
        # (the node module and the impl copy go away when the component is
        # renamed: the user's file that replaced them must stay)
        name = data.draw(st.sampled_from([
            'package.xml', 'CMakeLists.txt', f'{component.package}/__init__.py',
            f'{component.package}/{component.name}.py',
            f'{component.package}/{component.name}_impl.py']))
        path = ws.out / component.package / name
        ws.own(path, b'mine, not generated\n')
    elif action == 'add_component' and len(ws.components) < 3:
        taken = {c.package for c in ws.components}
        free = [p for p in PACKAGES if p not in taken]
        if free and not (ws.src / free[0]).exists():
            ws.components.append(Component(NAMES[len(ws.components)], free[0], free[0]))
    ws.save_models()
    return action


@pytest.fixture(scope='module')
def index(tmp_path_factory) -> InterfaceIndex:
    return fake_ament_index(tmp_path_factory.mktemp('ament_prefix'))


@settings(derandomize=True, database=None, deadline=None, max_examples=30,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_random_edits_and_regenerations_keep_every_user_file(index, data):
    with tempfile.TemporaryDirectory() as tmp:
        ws = Workspace(Path(tmp), index)
        ws.generate()
        assert ws.user_files, 'the first generation creates the implementation files'
        ws.check()
        for _ in range(data.draw(st.integers(3, 10), label='steps')):
            _apply(ws, data)
            ws.generate()
            ws.check()


@requires_ros
def test_the_verb_keeps_user_files_through_renames_and_moves(tmp_path, index):
    """The same through the real `colcon robmosys-generate`."""
    ws = Workspace(tmp_path, index)
    alpha = ws.components[0]
    alpha.functions.update(fPublish=False, fCheck=True)
    ws.save_models()

    def generate() -> None:
        before = set(ws.src.rglob('*_impl.py'))
        result = colcon(['robmosys-generate', '--output-dir', 'out'], cwd=tmp_path)
        assert result.returncode == 0, result.stdout + result.stderr
        for path in set(ws.src.rglob('*_impl.py')) - before:
            ws.user_files[path] = path.read_bytes()
        ws.check()

    generate()
    impl = ws.src / 'comp_a' / 'src' / 'comp_a' / 'Alpha_impl.py'
    assert impl in ws.user_files
    ws.own(impl, impl.read_bytes() + b'\n# my own work \xe2\x9c\x93\n')
    ws.own(ws.src / 'comp_a' / 'notes.txt', b'not generated')
    ws.own(ws.out / 'comp_a' / 'extra.txt', b'dropped into the output')
    generate()

    # rename the component, drop a function, move the package, change ports
    alpha.name = 'Gamma'
    del alpha.functions['fPublish']
    alpha.ports = ['pText', 'rText']
    old = ws.src / 'comp_a'
    alpha.folder = 'moved/comp_a'
    (ws.src / 'moved').mkdir()
    shutil.move(old, ws.src / alpha.folder)
    ws.move_user_files(old, ws.src / alpha.folder)
    ws.save_models()
    # the implementation of Alpha is left behind: one error, nothing made beside it
    result = colcon(['robmosys-generate', '--output-dir', 'out'], cwd=tmp_path)
    assert result.returncode == 1
    code = ws.src / 'moved/comp_a/src/comp_a'
    assert "was 'Alpha' renamed to 'Gamma'? rename Alpha_impl.py to Gamma_impl.py" in \
        result.stderr, result.stderr
    assert not (code / 'Gamma_impl.py').exists()
    ws.check()
    # the user does as it says
    alpha_impl = ws.user_files.pop(code / 'Alpha_impl.py')
    (code / 'Alpha_impl.py').unlink()
    ws.own(code / 'Gamma_impl.py', alpha_impl.replace(b'Alpha', b'Gamma'))
    generate()
    assert not (ws.out / 'comp_a' / 'comp_a' / 'Alpha.py').exists(), 'stale file removed'
    assert os.listdir(ws.out / 'comp_a')
