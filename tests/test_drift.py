# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A managed instance taken out of ``active`` behind the manager's back, and back.

examples_system runs under ``bringup`` (the default check period, 1 s). An
operator takes instances through their lifecycle services from another node:
a deactivation, a cleanup and a shutdown (to ``finalized``) are reported within
three check periods, without ``--heartbeat`` (each instance's
``transition_event`` tells the manager) and with it, on ``~/report``,
``~/conformance`` and ``/diagnostics``, at the model's line, as ``bringup
--check`` reports them. Once the operator activates the instance again, the
difference clears everywhere, and ``bringup --check`` finds none either.
"""

from __future__ import annotations

import re
import signal
import subprocess
import sys
import time

import pytest

from colcon_robmosys.devtools.ros_env import background, free_domain_id
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from conftest import assert_no_traceback, BuiltWorkspace, requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

SYSTEM = 'examples_system'
#: the manager's check period (bringup's default)
PERIOD = 1.0
#: three check periods, and the time the test's own calls take on a busy machine
WITHIN = 3 * PERIOD + 1.5


class Operator:
    """What an operator sees of the system and does to it: services, /diagnostics, --check."""

    def __init__(self, built: BuiltWorkspace, domain_id: int, driver: LifecycleDriver) -> None:
        from diagnostic_msgs.msg import DiagnosticArray
        self.built = built
        self.domain_id = domain_id
        self.driver = driver
        self.arrays: list = []
        driver.node.create_subscription(DiagnosticArray, '/diagnostics', self.arrays.append, 10)

    def trigger(self, service: str):
        from std_srvs.srv import Trigger
        # only reading services here: asked again when an answer is lost
        return self.driver.call(Trigger, f'/{SYSTEM}_bringup/{service}', Trigger.Request(),
                                timeout=20.0, attempt=0.5)

    def report(self) -> tuple[bool, dict[str, str], str]:
        """Return ~/report's success, each instance's line, and its message."""
        answer = self.trigger('report')
        lines = dict(re.findall(r'^(\w+): (.*)$', answer.message, re.MULTILINE))
        return answer.success, lines, answer.message

    def conformance(self) -> tuple[bool, list[str]]:
        answer = self.trigger('conformance')
        return answer.success, answer.message.splitlines()

    def diagnostics(self) -> dict:
        """Return the last /diagnostics of the system: name -> (level, values)."""
        self.driver.spin(0.05)
        if not self.arrays:
            return {}
        level = self.arrays[-1].status[0].level
        to_int = (lambda v: int.from_bytes(v, 'little')) if isinstance(level, bytes) else int
        return {s.name: (to_int(s.level), [(v.key, v.value) for v in s.values])
                for s in self.arrays[-1].status}

    def check(self) -> tuple[int, list[str]]:
        """Run ``bringup --check``; return its exit code and its lines, sorted."""
        executable = self.built.install / SYSTEM / 'lib' / SYSTEM / 'bringup'
        check = subprocess.run([sys.executable, str(executable), '--check'],
                               env=self.built.env(self.domain_id), capture_output=True,
                               text=True, timeout=120)
        assert check.returncode in (0, 1), check.stdout + check.stderr
        return check.returncode, sorted(check.stdout.splitlines())

    def transition(self, instance: str, *labels: str) -> None:
        for label in labels:
            assert self.driver.transition(f'/examples/{instance}', label), (instance, label)


def _reported(operator: Operator, instance: str, state: str, since: float) -> list[str]:
    """Wait until report, conformance and /diagnostics tell an instance in state; return lines."""
    expected = f': error: instance {instance} is {state}, not active'
    seen: dict = {}
    took: dict = {}

    def told(what: str, holds: bool) -> bool:
        if holds:
            took.setdefault(what, time.monotonic() - since)
        return what in took

    def everywhere() -> bool:
        seen['report'] = operator.report()
        seen['conformance'] = operator.conformance()
        seen['diagnostics'] = operator.diagnostics()
        ok, lines = seen['conformance']
        level, values = seen['diagnostics'].get(f'{SYSTEM}: {instance}', (0, []))
        return all([
            told('report', not seen['report'][0] and
                 seen['report'][1][instance] == f'failed (is {state}, not active)'),
            told('conformance', not ok and any(line.endswith(expected) for line in lines)),
            told('diagnostics', level == 2 and any(
                k == 'difference' and v.endswith(expected) for k, v in values))])
    assert wait_until(everywhere, WITHIN, period=0.05), (took, seen)
    print(f'{instance} {state}: told after (s): {took}')
    assert max(took.values()) < WITHIN, took
    _, lines = seen['conformance']
    line = next(line for line in lines if line.endswith(expected))
    # at the model's line of the instance, which /diagnostics gives as its location
    _, values = seen['diagnostics'][f'{SYSTEM}: {instance}']
    location = dict(values)['location']
    assert re.fullmatch(r'.*robmosys\.yaml:\d+:\d+', location), location
    assert line == f'{location}{expected}', (line, location)
    return sorted(lines)


def _cleared(operator: Operator, instance: str) -> None:
    """Wait until report, conformance and /diagnostics say the system is as its model."""
    seen: dict = {}

    def everywhere() -> bool:
        seen['report'] = operator.report()
        seen['conformance'] = operator.conformance()
        seen['diagnostics'] = operator.diagnostics()
        return seen['report'][0] and seen['report'][1][instance] == 'active' and \
            seen['conformance'] == (True, []) and \
            all(level == 0 for level, _ in seen['diagnostics'].values())
    # the watch checks the ports of an instance from a few seconds after it is active
    assert wait_until(everywhere, 30, period=0.2), seen


@pytest.mark.parametrize('heartbeat', [(), ('--heartbeat', '1')], ids=['events', 'heartbeat'])
def test_an_instance_out_of_active_is_reported_and_clears_once_active_again(
        test_workspace_built, heartbeat):
    built = test_workspace_built
    domain_id = free_domain_id()
    executable = built.install / SYSTEM / 'lib' / SYSTEM / 'bringup'
    with background([sys.executable, str(executable), *heartbeat],
                    env=built.env(domain_id), stop_timeout=30) as bringup, \
            LifecycleDriver(domain_id) as driver:
        assert wait_until(lambda: 'bringup: 8 of 8 managed instances active' in
                          bringup.output(), timeout=90), bringup.output()
        operator = Operator(built, domain_id, driver)
        # the watch has compared the whole system: nothing differs
        assert wait_until(lambda: operator.conformance() == (True, []), 60), \
            operator.conformance()

        # deactivated (ros2 lifecycle set /examples/receiver deactivate)
        since = time.monotonic()
        operator.transition('receiver', 'deactivate')
        lines = _reported(operator, 'receiver', 'inactive', since)
        assert re.search(r'^bringup: error: instance receiver is inactive, not active \('
                         r'(transition_event|heartbeat)\)$', bringup.output(), re.MULTILINE)
        # the one-shot check says the same, line for line
        assert operator.check() == (1, lines)
        operator.transition('receiver', 'activate')
        _cleared(operator, 'receiver')
        assert operator.check() == (0, [])

        # cleaned up, then configured and activated again by hand
        since = time.monotonic()
        operator.transition('fibonacci_client', 'deactivate', 'cleanup')
        lines = _reported(operator, 'fibonacci_client', 'unconfigured', since)
        assert operator.check() == (1, lines)
        operator.transition('fibonacci_client', 'configure', 'activate')
        _cleared(operator, 'fibonacci_client')
        assert operator.check() == (0, [])

        # shut down: finalized for good
        since = time.monotonic()
        operator.transition('level_watcher', 'active_shutdown')
        lines = _reported(operator, 'level_watcher', 'finalized', since)
        assert operator.check() == (1, lines)
        bringup.proc.send_signal(signal.SIGINT)
        assert bringup.proc.wait(timeout=60) == 0, bringup.output()
        assert_no_traceback(bringup.output())
