# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The modes of a system reach its package: bringup.json, for its manager, and doc/modes.md."""

from __future__ import annotations

import json
from pathlib import Path

from colcon_robmosys.check import load_workspace
from colcon_robmosys.generators import generate_package, plan_package
from harness.fake_ament import fake_ament_index

VALID = Path(__file__).parent / 'models' / 'valid'


def _generated(tmp_path: Path, package: str) -> Path:
    result = load_workspace(sorted(VALID.glob('*.yaml')), fake_ament_index(tmp_path / 'prefix'))
    result.raise_errors()
    generate_package(plan_package(result.workspace, package), tmp_path / package)
    return tmp_path / package


def test_the_manager_reads_each_mode_whole(tmp_path):
    """Every active instance, in activation order; the system's value where a mode sets none."""
    description = json.loads((_generated(tmp_path, 'modes_robot') / 'bringup.json').read_text())
    assert description['initial_mode'] == 'docking'
    modes = {m['name']: m for m in description['modes']}
    assert list(modes) == ['docking', 'cruising', 'mapping']
    assert modes['docking']['active'] == ['driver', 'arm.talker']
    assert modes['mapping']['active'] == ['planner', 'arm.talker', 'arm.listener']
    # the mode's value, else the instance's own (gain 1.5), else the component's default
    assert modes['cruising']['values']['driver'] == {'rate': 100, 'gain': 1.5}
    assert modes['mapping']['values']['driver'] == {'rate': 10, 'gain': 1.5}
    assert modes['mapping']['values']['arm.talker'] == {'rate': 50, 'names': ['x', 'y']}
    assert modes['docking']['location'].startswith('share/modes_')


def test_a_system_without_modes_keeps_its_description(tmp_path):
    description = json.loads((_generated(tmp_path, 'demo_system') / 'bringup.json').read_text())
    assert 'modes' not in description and 'initial_mode' not in description
    assert not (tmp_path / 'demo_system' / 'doc' / 'modes.md').exists()


def test_the_page_of_the_modes(tmp_path):
    page = (_generated(tmp_path, 'modes_robot') / 'doc' / 'modes.md').read_text()
    assert '| `docking` | driver, arm.talker |  |' in page
    assert '| `driver` | `rate` | 2 | 100 | 10 |' in page
    assert 'set_mode/NAME' in page


def test_the_diagram_names_the_modes_of_each_instance(tmp_path):
    dot = (_generated(tmp_path, 'modes_robot') / 'doc' / 'modes_robot.dot').read_text()
    assert '/base/driver\\nTalker (demo_talker)\\nactive in: docking, cruising|' in dot
    assert '/spare\\nListener (demo_listener)\\nactive in: no mode|' in dot
