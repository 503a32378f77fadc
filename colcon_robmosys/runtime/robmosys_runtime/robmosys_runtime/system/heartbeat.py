# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The system manager's heartbeat: every managed instance is asked its state, in step.

Every period, each managed instance is asked its state (``get_state``, the
lifecycle service every node has: nav2's bond without a bond), all of them
at once, each with the period to answer. So an instance that stops answering
is reported after three heartbeats however many others are silent with it
(a host whose link went down takes all its instances with it), and the
others are still asked in step.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
import threading
import time
from typing import AbstractSet, Any, Callable, Dict, List, Optional, Set

from robmosys_runtime.hosting.output import say
from robmosys_runtime.system.activation import SystemActivation
from robmosys_runtime.system.drift import Drift

#: heartbeats in a row without an answer before an instance is reported
MISSED = 3


class Heartbeat:
    """
    Ask every managed instance its state every period; report and repair what changed.

    - no answer for :data:`MISSED` heartbeats: the instance is reported
      (``unknown``) until it answers again;
    - ``unconfigured`` where it was brought up, and started again by something
      else than this manager (its host's ``bringup``, a launch, or the
      manager's own respawn): brought back to the state of the system, with
      what it holds back;
    - any other state than ``active``: reported as failed (:class:`.drift.Drift`,
      which the transition events of the instances tell sooner). A failed
      instance stays asked: seen ``active`` again, whatever brought it back,
      it is no longer failed; one of another host that went silent (its
      process ended) and comes back ``unconfigured`` is brought back too (a
      host's ``bringup`` stops its instances when it is killed, and they may
      pass through ``finalized``).

    :param silent: instance -> why it is unknown, shared with the manager's reports
    :param instances: instance -> its entry of the system's description
    :param here: the instances whose processes this manager started
    :param up: whether the system is meant to be up now
    :param drift: what takes the states told outside the manager's transitions
    """

    def __init__(self, activation: SystemActivation, period: float, silent: Dict[str, str],
                 instances: Dict[str, Dict[str, Any]], here: Set[str],
                 up: Callable[[], bool], drift: Optional[Drift] = None) -> None:
        self._activation = activation
        self._drift = drift or Drift(activation, up)
        self.period = period
        self._silent = silent
        self._instances = instances
        self._here = here
        self._up = up
        self._missed: Dict[str, int] = {}
        #: failed instances of other hosts that went silent since they failed
        self._gone: Set[str] = set()

    def restartable(self, name: str) -> bool:
        """Tell whether an instance that came back unconfigured is to be brought up again."""
        return bool(self._instances[name].get('respawn')) or name not in self._here

    def run(self, stopping: threading.Event) -> None:
        """Beat until stopping is set."""
        with ThreadPoolExecutor(max_workers=16, thread_name_prefix='heartbeat') as pool:
            beat = time.monotonic()
            while True:
                # in step: a beat that took long (under load) is not followed by a burst
                beat = max(beat + self.period, time.monotonic())
                if stopping.wait(max(0.0, beat - time.monotonic())):
                    return
                if self._activation.running() or not self._up():
                    continue
                believed = self._activation.states()
                names = list(believed)
                answers = dict(zip(names, pool.map(
                    lambda name: self._activation.probe(name, timeout=self.period), names)))
                now = self._activation.states()
                # failed since it was asked (its transition event came first) or not
                failed = {n for n, s in now.items() if s == 'failed'}
                # one that the manager took through a transition meanwhile (a mode's
                # switch) answered what it was before: no word about it from this beat
                answers = {n: a for n, a in answers.items()
                           if now.get(n) == believed[n] or n in failed}
                if not stopping.is_set() and not self._activation.running() and self._up():
                    self.heard(answers, failed)

    def heard(self, answers: Dict[str, Optional[str]],
              failed: AbstractSet[str] = frozenset()) -> None:
        """Take the answers of one heartbeat (None: no answer) of instances, failed ones of it."""
        back: List[str] = []
        for name, answer in sorted(answers.items()):
            if answer is None:
                if name in failed:
                    self._gone.add(name)
                elif not self._activation.discovering(name):
                    # (one told active by its process, whose service is still
                    # being discovered, has no answer to miss)
                    self._missed[name] = self._missed.get(name, 0) + 1
                    if self._missed[name] == MISSED and name not in self._silent:
                        why = f'no answer for {MISSED * self.period:g} s'
                        self._silent[name] = why
                        say('error', f'instance {name} does not answer (heartbeat): {why}')
                continue
            self._missed[name] = 0
            if self._silent.pop(name, None) is not None and answer == 'active':
                say('info', f'instance {name} answers again (heartbeat)')
            if answer == 'unconfigured' and (
                    name in self._gone and name not in self._here if name in failed
                    else self.restartable(name)):
                # started again where it runs: bring it back
                say('info', f'instance {name} came back (heartbeat): bringing it up')
                back.append(name)
            else:
                # left active, or active again (its failure gone, whatever repaired it)
                self._drift.seen(name, answer, 'heartbeat')
        for name in back:
            self._gone.discard(name)
        if back:
            # one bring-up for all: two would take a shared successor up twice
            self._activation.restart(*back)
