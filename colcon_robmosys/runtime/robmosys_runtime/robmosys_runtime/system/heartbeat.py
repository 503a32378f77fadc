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
    - any other state than ``active``: reported as failed. One of another
      host stays asked: once it went silent (its process ended) and comes back
      ``unconfigured``, it is brought back too (a host's ``bringup`` stops its
      instances when it is killed, and they may pass through ``finalized``).

    :param silent: instance -> why it is unknown, shared with the manager's reports
    :param instances: instance -> its entry of the system's description
    :param here: the instances whose processes this manager started
    :param up: whether the system is meant to be up now
    """

    def __init__(self, activation: SystemActivation, period: float, silent: Dict[str, str],
                 instances: Dict[str, Dict[str, Any]], here: Set[str],
                 up: Callable[[], bool]) -> None:
        self._activation = activation
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
                states = self._activation.states()
                names = [n for n, s in states.items()
                         if s != 'failed' or n not in self._here]
                answers = dict(zip(names, pool.map(
                    lambda name: self._activation.probe(name, timeout=self.period), names)))
                if not stopping.is_set():
                    self.heard(answers, {n for n in names if states[n] == 'failed'})

    def heard(self, answers: Dict[str, Optional[str]],
              failed: AbstractSet[str] = frozenset()) -> None:
        """Take the answers of one heartbeat (None: no answer) of instances, failed ones of it."""
        back: List[str] = []
        for name, answer in sorted(answers.items()):
            if name in failed:
                if answer is None:
                    self._gone.add(name)
                elif answer == 'unconfigured' and name in self._gone:
                    say('info', f'instance {name} came back (heartbeat): bringing it up')
                    back.append(name)
                continue
            if answer is None:
                if self._activation.discovering(name):
                    # told active by its process; its service not discovered yet
                    continue
                self._missed[name] = self._missed.get(name, 0) + 1
                if self._missed[name] == MISSED and name not in self._silent:
                    why = f'no answer for {MISSED * self.period:g} s'
                    self._silent[name] = why
                    say('error', f'instance {name} does not answer (heartbeat): {why}')
                continue
            self._missed[name] = 0
            if answer == 'unconfigured' and self.restartable(name):
                # started again where it runs: bring it back
                say('info', f'instance {name} came back (heartbeat): bringing it up')
                back.append(name)
            elif answer != 'active':
                self._silent[name] = f'it is {answer}, not active'
                say('error', f'instance {name} is {answer}, not active (heartbeat)')
                self._activation.instance_failed(name, f'is {answer}, not active')
            elif self._silent.pop(name, None) is not None:
                say('info', f'instance {name} answers again (heartbeat)')
        for name in back:
            self._silent.pop(name, None)
            self._gone.discard(name)
        if back:
            # one bring-up for all: two would take a shared successor up twice
            self._activation.restart(*back)
