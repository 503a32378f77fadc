# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Models across workspaces: a workspace builds on the models its underlay installed.

Workspace A holds a service definition, two components and a system of them; every
generated package installs its model (share/<package>/robmosys/robmosys.yaml, ament
index resource robmosys_models). Workspace B, built with only A's install sourced, has a
system of A's components, A's system as a subsystem under a namespace, and a component
of its own that uses A's service definition; the system runs with data flowing.
"""

from __future__ import annotations

from pathlib import Path
import re
import shutil
import sys

import pytest

from colcon_robmosys.devtools import ros_env
from colcon_robmosys.devtools.ros_env import background, free_domain_id
from colcon_robmosys.devtools.system import wait_until
from conftest import requires_ros, TEST_WORKSPACE

pytestmark = [pytest.mark.integration, requires_ros]

#: workspace B: a component on A's service definition, a system of A's components and it
MODEL_B = """\
robmosys: 1
defaults:
  license: Apache-2.0
  maintainers: [{name: B Team, email: b@example.com}]
components:
  - name: MapCounter
    package: map_counter
    language: python
    ports:
      rMap: {pattern: push, role: required, type: simple_msgs/msg/Map}
    activities:
      Count: {trigger: rMap, functions: [fCount]}
    functions:
      fCount:
        code: |
          self.counted = getattr(self, 'counted', 0) + 1
          self.get_logger().info(f'maps counted: {self.counted}')
systems:
  - package: chained_system
    # A's whole pubsub system once more, under /site: site.publisher, site.subscriber
    subsystems:
      site: {system: pubsub_system}
    instances:
      publisher: {component: publisher, parameters: {indoor: true}}
      subscriber: {component: subscriber}
      counter: {component: map_counter}
      site_counter: {component: map_counter, after: [site.publisher]}
    connections:
      - {from: publisher.pMap, to: subscriber.rMap}
      - {from: publisher.pMap, to: counter.rMap}
      - {from: site.publisher.pMap, to: site_counter.rMap}
"""


@pytest.fixture(scope='module')
def underlay(test_workspace_built) -> Path:
    """Return the install of workspace A: test_workspace, built once for the session.

    Its simple_msgs, publisher, subscriber and pubsub_system are what B builds on.
    """
    return test_workspace_built.install


def test_every_generated_package_installs_its_model(underlay):
    for package in ('simple_msgs', 'publisher', 'subscriber', 'pubsub_system'):
        share = underlay / package / 'share'
        model = share / package / 'robmosys' / 'robmosys.yaml'
        assert f'package: {package}' in model.read_text(), package
        assert (share / 'ament_index' / 'resource_index' / 'robmosys_models' /
                package).is_file()


def test_a_workspace_builds_on_the_models_of_its_underlay(underlay, tmp_path):
    root = tmp_path / 'b_ws'
    (root / 'src' / 'b').mkdir(parents=True)
    (root / 'src' / 'b' / 'robmosys.yaml').write_text(MODEL_B)
    domain_id = free_domain_id()
    env = ros_env.workspace_env(underlay, ros_env.loopback_env(domain_id))
    # B builds its own two packages only: A's are built, and their models known
    result = ros_env.run([str(Path(sys.prefix) / 'bin' / 'colcon'), 'build',
                          '--event-handlers', 'console_cohesion+'],
                         env=env, cwd=root, timeout=900)
    assert result.returncode == 0, result.stdout + result.stderr
    assert sorted(re.findall(r'Finished <<< (\w+)', result.stdout)) == [
        'chained_system', 'map_counter'], result.stdout
    install = root / 'install'
    bringup = install / 'chained_system' / 'lib' / 'chained_system' / 'bringup'
    with background([sys.executable, str(bringup)],
                    env=ros_env.workspace_env(install, env), stop_timeout=30) as running:
        assert wait_until(lambda: 'bringup: 6 of 6 managed instances active' in
                          running.output(), timeout=120), running.output()
        # A's publisher feeds A's subscriber and B's counter; A's system, in /site, B's other
        assert wait_until(lambda: '[counter]: maps counted: 2' in running.output() and
                          '[site_counter]: maps counted: 2' in running.output() and
                          '[site.subscriber]: got map data' in running.output(),
                          timeout=30), running.output()


def test_a_name_of_the_workspace_hides_the_underlay_one(underlay, tmp_path):
    """The workspace first, then the underlays, as for packages: no clash reported."""
    from colcon_robmosys.check import find_model_files, load_workspace
    from colcon_robmosys.check.index import InterfaceIndex
    src = tmp_path / 'src'
    shutil.copytree(TEST_WORKSPACE / 'src' / 'subscriber', src / 'subscriber')
    prefixes = [underlay / p for p in ('simple_msgs', 'publisher', 'subscriber')]
    result = load_workspace(find_model_files([src]),
                            InterfaceIndex(prefixes + [Path(sys.prefix)]))
    assert result.errors == []
    subscriber = result.workspace.model('subscriber')
    assert subscriber.info.model_file == str(src / 'subscriber' / 'robmosys.yaml')
    # the underlay's others are known, and generate nothing here
    assert result.workspace.model('publisher') is not None
    assert [m.package for m in result.workspace.generated_models] == ['subscriber']


def _fake_install(prefix: Path, packages: list[str]) -> Path:
    """Install the models of test_workspace packages into a prefix, as a build does."""
    for package in packages:
        share = prefix / 'share'
        (share / package / 'robmosys').mkdir(parents=True)
        shutil.copy(TEST_WORKSPACE / 'src' / package / 'robmosys.yaml',
                    share / package / 'robmosys' / 'robmosys.yaml')
        index = share / 'ament_index' / 'resource_index' / 'robmosys_models'
        index.mkdir(parents=True, exist_ok=True)
        (index / package).touch()
    return prefix


def test_a_package_two_underlays_install_is_reported_with_both(tmp_path):
    """The first prefix wins, as for packages; the workspace models using it are warned."""
    from colcon_robmosys.check import find_model_files, load_workspace
    from colcon_robmosys.check.index import InterfaceIndex
    first = _fake_install(tmp_path / 'first', ['simple_msgs', 'publisher', 'subscriber',
                                               'pubsub_system'])
    second = _fake_install(tmp_path / 'second', ['publisher'])
    src = tmp_path / 'src' / 'b'
    src.mkdir(parents=True)
    (src / 'robmosys.yaml').write_text(MODEL_B)
    result = load_workspace(find_model_files([src]),
                            InterfaceIndex([first, second, Path(sys.prefix)]))
    assert result.errors == []
    used = first / 'share' / 'publisher' / 'robmosys' / 'robmosys.yaml'
    hidden = second / 'share' / 'publisher' / 'robmosys' / 'robmosys.yaml'
    assert result.workspace.model('publisher').info.model_file == str(used)
    # the system uses it; the component of B does not
    assert [str(w) for w in result.warnings_of('chained_system')] == [
        f'{src / "robmosys.yaml"}:19:14: warning: package \'publisher\' is installed by more '
        f"than one underlay: the model '{used}' is used (its prefix comes first in "
        f"AMENT_PREFIX_PATH), '{hidden}' not"]
    assert result.warnings_of('map_counter') == []
