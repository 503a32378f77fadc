# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A generation renders a package again exactly when something it reads has changed.

`colcon robmosys-generate` and `colcon build` skip a package whose stamp says that
nothing its generation reads has changed since (generators/stamp.py): its models and
those it depends on (an underlay's installed ones, the external components a system
starts), the templates, colcon-robmosys, Jinja, how it is generated, and the user's
files. Each input is changed here in turn, and the packages rendered again are
exactly those that read it; with nothing changed, nothing is rendered and no file
is touched.
"""

from __future__ import annotations

import importlib
from pathlib import Path
import shutil

import jinja2
import pytest

import colcon_robmosys
from colcon_robmosys.check import cache as cache_module
from colcon_robmosys.check import find_model_files, load_workspace, ModelCache
from colcon_robmosys.check.cache import CACHE_DIR
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.check.underlays import RESOURCE_TYPE
from colcon_robmosys.generators import (
    create_missing_user_files, Durable, fingerprint, generate_package, plan_package,
    StampStore, unchanged_package)
from colcon_robmosys.generators import stamp as stamp_module
from conftest import TEST_WORKSPACE
from harness.fake_ament import EXAMPLE_EXTRA, fake_ament_index

# the package exports a function of the name: the module itself
render_module = importlib.import_module('colcon_robmosys.generators.render')

#: the packages that read subscriber's model: itself and the systems running it
READ_SUBSCRIBER = {'subscriber', 'pubsub_system', 'fleet_system', 'mixed_system'}


class Generator:
    """Generates a workspace as `colcon robmosys-generate --output-dir` does."""

    def __init__(self, root: Path, index: InterfaceIndex):
        self.src, self.out, self.index = root / 'src', root / 'out', index
        self.cache = root / 'build' / CACHE_DIR

    def run(self, *, standalone: bool = True) -> set[str]:
        """Generate every package; return those rendered (not skipped)."""
        result = load_workspace(find_model_files([self.src]), self.index,
                                ModelCache(self.cache))
        result.raise_errors()
        stamps = StampStore(self.cache / 'stamps')
        created, writes, rendered = Durable(), Durable(), set()
        plans = []
        for model in result.workspace.generated_models:
            inputs = fingerprint(result, model.package, standalone=standalone)
            if unchanged_package(self.out / model.package, stamps, inputs) is None:
                plan = plan_package(result.workspace, model.package)
                create_missing_user_files(plan, created)
                plans.append((plan, inputs))
        created.commit()
        for plan, inputs in plans:
            generate_package(plan, self.out / plan.name, durable=writes, stamps=stamps,
                             fingerprint=inputs, standalone=standalone)
            rendered.add(plan.name)
        writes.commit()
        return rendered


@pytest.fixture
def index(tmp_path) -> InterfaceIndex:
    return fake_ament_index(tmp_path / 'prefix', EXAMPLE_EXTRA)


@pytest.fixture
def generator(tmp_path, index) -> Generator:
    shutil.copytree(TEST_WORKSPACE / 'src', tmp_path / 'src',
                    ignore=shutil.ignore_patterns('__pycache__'))
    generator = Generator(tmp_path, index)
    assert len(generator.run()) > 30
    return generator


def _forget_tools() -> None:
    """Forget the digests of the code and of the templates, and the compiled templates."""
    cache_module.code_digest.cache_clear()
    stamp_module.templates_digest.cache_clear()
    render_module.environment.cache_clear()


@pytest.fixture
def fresh_caches():
    """Forget what was read of the tools before the test, and what it read after it."""
    _forget_tools()
    yield _forget_tools
    _forget_tools()


def _files(root: Path) -> dict[Path, tuple[int, int, int]]:
    """Return every file and folder below root: inode, mtime, ctime."""
    return {p: (s.st_ino, s.st_mtime_ns, s.st_ctime_ns)
            for p in sorted(root.rglob('*')) for s in [p.lstat()]}


def test_nothing_changed_nothing_rendered_nothing_touched(generator, tmp_path, monkeypatch):
    before = _files(tmp_path)

    def no_rendering():
        raise AssertionError('a template was rendered')

    monkeypatch.setattr(render_module, 'environment', no_rendering)
    assert generator.run() == set()
    # the output, the user's files, the cache of the checked models, the stamps
    assert _files(tmp_path) == before


def test_a_model_renders_its_package_and_those_that_read_it(generator):
    model = generator.src / 'subscriber' / 'robmosys.yaml'
    model.write_text(model.read_text().replace('depth: 100', 'depth: 99'))
    assert generator.run() == READ_SUBSCRIBER
    assert b'depth=99,' in (generator.out / 'subscriber' / 'subscriber' / 'Subscriber.py'
                            ).read_bytes()
    # a subsystem: the systems that include it
    model = generator.src / 'pubsub_system' / 'robmosys.yaml'
    model.write_text(model.read_text() + '# a comment\n')
    assert generator.run() == {'pubsub_system', 'fleet_system'}
    # a service definition: its package and every one that uses its types
    model = generator.src / 'simple_msgs' / 'robmosys.yaml'
    model.write_text(model.read_text() + '# a comment\n')
    rendered = generator.run()
    assert {'simple_msgs', 'publisher', 'cpp_subscriber'} | READ_SUBSCRIBER <= rendered
    assert 'example_msgs' not in rendered and 'text_relay' not in rendered


def test_a_template_renders_every_package_that_uses_it(generator, tmp_path, monkeypatch,
                                                       fresh_caches):
    templates = tmp_path / 'templates'
    shutil.copytree(render_module.templates_dir(), templates)
    monkeypatch.setattr(render_module, 'templates_dir', lambda: templates)
    monkeypatch.setattr(stamp_module, 'templates_dir', lambda: templates)
    fresh_caches()
    assert generator.run() == set(), 'the same templates, elsewhere'
    template = templates / 'common' / 'package.xml.jinja'
    template.write_text(template.read_text().replace('</package>', '<!-- new -->\n</package>'))
    fresh_caches()
    rendered = generator.run()
    assert len(rendered) > 30
    assert b'<!-- new -->' in (generator.out / 'subscriber' / 'package.xml').read_bytes()


@pytest.mark.parametrize('change', ['colcon-robmosys', 'jinja2'])
def test_another_tool_renders_everything(generator, monkeypatch, fresh_caches, change):
    if change == 'colcon-robmosys':
        # another version, or the same version with other code
        monkeypatch.setattr(colcon_robmosys, '__version__', '0.0.0+other')
    else:
        monkeypatch.setattr(jinja2, '__version__', '0.0.0+other')
    assert len(generator.run()) > 30


def test_how_it_is_generated_is_an_input(generator):
    result = load_workspace(find_model_files([generator.src]), generator.index)
    assert fingerprint(result, 'subscriber', standalone=True) != \
        fingerprint(result, 'subscriber', standalone=False)
    assert fingerprint(result, 'subscriber', standalone=True) == \
        fingerprint(result, 'subscriber', standalone=True)


def test_the_users_files_render_their_package(generator):
    code = generator.src / 'subscriber' / 'src' / 'subscriber'
    impl = code / 'Subscriber_impl.py'
    # changed: copied into the package again
    impl.write_text(impl.read_text() + '\n# more of my work\n')
    assert generator.run() == {'subscriber'}
    copy = generator.out / 'subscriber' / 'src' / 'subscriber' / 'Subscriber_impl.py'
    assert copy.read_bytes() == impl.read_bytes()
    # a new module beside it, and a file in a folder installed with the package
    (code / 'helpers.py').write_text('HELP = 1\n')
    assert generator.run() == {'subscriber'}
    assert (generator.out / 'subscriber' / 'src' / 'subscriber' / 'helpers.py').is_file()
    (generator.src / 'subscriber' / 'config').mkdir()
    (generator.src / 'subscriber' / 'config' / 'extra.yaml').write_text('a: 1\n')
    assert generator.run() == {'subscriber'}
    assert (generator.out / 'subscriber' / 'config' / 'extra.yaml').is_file()
    # its mode, which the copy takes
    (code / 'helpers.py').chmod(0o755)
    assert generator.run() == {'subscriber'}
    assert (generator.out / 'subscriber' / 'src' / 'subscriber' / 'helpers.py').stat().st_mode \
        & 0o100
    # removed: the package no longer holds it
    (code / 'helpers.py').unlink()
    assert generator.run() == {'subscriber'}
    assert not (generator.out / 'subscriber' / 'src' / 'subscriber' / 'helpers.py').exists()
    # the implementation removed: created again from the model
    impl.unlink()
    assert generator.run() == {'subscriber'}
    assert 'class Subscriber_impl' in impl.read_text()
    assert generator.run() == set()


def test_a_generated_file_changed_by_hand_renders_its_package(generator):
    node = generator.out / 'subscriber' / 'package.xml'
    expected = node.read_bytes()
    node.write_bytes(expected + b'<!-- mine -->\n')
    assert generator.run() == {'subscriber'}
    assert node.read_bytes() == expected


def _install_model(prefix: Path, package: str, text: str) -> Path:
    """Install a model file into an ament prefix, as a generated package does."""
    marker = prefix / 'share' / 'ament_index' / 'resource_index' / RESOURCE_TYPE / package
    marker.parent.mkdir(parents=True, exist_ok=True)
    marker.write_text('')
    path = prefix / 'share' / package / 'robmosys' / 'robmosys.yaml'
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


SYSTEM_ON_AN_UNDERLAY = """\
robmosys: 1
systems:
  - package: relay_system
    license: Apache-2.0
    maintainers: [{name: A, email: a@example.com}]
    instances:
      talker: {component: handwritten_nodes/talker}
      relay: {component: text_relay}
    connections:
      - {from: talker.pChatter, to: relay.rIn}
"""


def test_models_of_an_underlay_render_what_uses_them(tmp_path, index):
    # the underlay installed simple_msgs and the system of the hand-written nodes
    # (the file that describes them as external components)
    prefix = tmp_path / 'prefix'
    msgs = _install_model(prefix, 'simple_msgs',
                          (TEST_WORKSPACE / 'src/simple_msgs/robmosys.yaml').read_text())
    handwritten = (TEST_WORKSPACE / 'src/handwritten_system/robmosys.yaml').read_text()
    external = _install_model(prefix, 'handwritten_system', handwritten)
    _install_model(prefix, 'text_relay', handwritten)
    src = tmp_path / 'src'
    for package in ('publisher', 'subscriber'):
        shutil.copytree(TEST_WORKSPACE / 'src' / package, src / package,
                        ignore=shutil.ignore_patterns('__pycache__'))
    (src / 'relay_system').mkdir()
    (src / 'relay_system' / 'robmosys.yaml').write_text(SYSTEM_ON_AN_UNDERLAY)
    generator = Generator(tmp_path, InterfaceIndex([prefix]))
    assert generator.run() == {'publisher', 'subscriber', 'relay_system'}
    assert generator.run() == set()
    msgs.write_text(msgs.read_text() + '# a comment\n')
    assert generator.run() == {'publisher', 'subscriber'}
    # an external component the system starts, described by the underlay's file
    external.write_text(handwritten + '# a comment\n')
    assert generator.run() == {'relay_system'}
