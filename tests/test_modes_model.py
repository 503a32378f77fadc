# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The warnings of modes: a required port whose providers a mode leaves inactive.

The errors of modes are in the corpus (tests/models/invalid/system_mode_*.yaml),
which compares errors only; these are warnings, and what silences them.
"""

from __future__ import annotations

from pathlib import Path

from colcon_robmosys.check import load_workspace
from harness.fake_ament import fake_ament_index

VALID = Path(__file__).parent / 'models' / 'valid'

MODEL = """\
robmosys: 1
defaults:
  license: Apache-2.0
  maintainers: [{name: A, email: a@example.com}]
systems:
  - package: moded_system
    instances:
      talker: {component: demo_talker, unconnected: [rCommand, sLog, qAdd, eObstacle, aFibonacci]}
      listener: {component: demo_listener, unconnected: [UNCONNECTED]}
    connections:
      - {from: talker.pGrid, to: listener.rGrid}
      - {from: talker.sInbox, to: listener.sInbox}
      - {from: talker.qGetCell, to: listener.qGetCell}
      - {from: talker.eAlarm, to: listener.eAlarm}
      - {from: talker.aExplore, to: listener.aExplore}
    modes:
      initial: both
      both: {active: [talker, listener]}
      listening: {active: [listener]}
"""


def _diagnostics(tmp_path: Path, unconnected: str) -> list[str]:
    path = tmp_path / 'src' / 'moded_system' / 'robmosys.yaml'
    path.parent.mkdir(parents=True)
    path.write_text(MODEL.replace('UNCONNECTED', unconnected))
    result = load_workspace(
        [path, VALID / 'service_definition.yaml', VALID / 'component_python.yaml',
         VALID / 'component_cpp.yaml'], fake_ament_index(tmp_path / 'prefix'))
    return [f'{d.location.line}:{d.location.column}: {d.severity}: {d.message}'
            for d in result.diagnostics]


def test_a_mode_that_leaves_a_provider_inactive_warns(tmp_path):
    assert _diagnostics(tmp_path, 'aExplore') == [
        f"19:28: warning: mode 'listening': required port 'listener.{port}' is served by "
        'talker, which the mode leaves inactive'
        for port in ('eAlarm', 'qGetCell', 'rGrid', 'sInbox')]


def test_unconnected_silences_it_though_the_port_is_connected(tmp_path):
    assert _diagnostics(tmp_path, 'rGrid, sInbox, qGetCell, eAlarm, aExplore') == []
