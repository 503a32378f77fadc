# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
Bring the managed instances of a system up: configure them, activate them in order.

Each instance is driven through its lifecycle services (``get_state``, ``change_state``),
never by waiting for ``transition_event`` messages alone: those are volatile, and one
published before the subscription matched is lost, which left bring-ups waiting forever.
All are configured at once; each is activated once inactive and the instances it comes
after are active (not those the mode leaves out). A failure is reported with what it
holds back.
"""

from __future__ import annotations

import threading
import time
from typing import Callable, Dict, List, Mapping, Optional, Sequence, Set

from lifecycle_msgs.msg import Transition
from rclpy.node import Node
from robmosys_runtime.system import levels
from robmosys_runtime.system.levels import Outcome
from robmosys_runtime.system.lifecycle_calls import Failed, LifecycleCalls, Stopped


#: what tells the state of an instance its process told: (instance, stopped) -> state or None
Told = Callable[[str, Callable[[], bool]], Optional[str]]


class SystemActivation:
    """
    Configure every managed instance and activate each after the ones it names.

    The node's executor must spin in another thread (launch_ros spins its own
    node; a test spins one): answers are waited for on events.

    :param instances: instance name -> fully qualified node name
    :param after: instance name -> the instances that must be active first
    :param timeout: seconds for each transition
    :param start_timeout: seconds for each instance to appear (its process starts),
        by default ``timeout``
    :param report: called with ``(level, text)``, level ``'info'`` or ``'error'``
    :param timeouts: instance name -> seconds for each of its transitions, where
        the model sets it (``timeout`` otherwise)
    :param told: called with an instance and what says that its bring-up ended: the
        state its process told (:meth:`robmosys_runtime.hosting.reports.Reports.take`),
        taken as its state, or None: the instance is asked
    """

    def __init__(self, node: Node, instances: Mapping[str, str],
                 after: Mapping[str, Sequence[str]], *, timeout: float = 60.0,
                 start_timeout: Optional[float] = None,
                 report: Optional[Callable[[str, str], None]] = None,
                 timeouts: Optional[Mapping[str, float]] = None,
                 told: Optional[Told] = None) -> None:
        self._node = node
        self._instances = dict(instances)
        self._after = {name: list(after.get(name, ())) for name in instances}
        self._timeouts = dict(timeouts or {})
        self._report = report or self._log
        self._told = told
        self._states: Dict[str, str] = {}
        self._failed: Dict[str, str] = {}
        self._changed = threading.Condition()
        self._stop = threading.Event()
        self._threads: List[threading.Thread] = []
        #: instance -> the thread that takes it through its transitions, if any
        self._driving: Dict[str, threading.Thread] = {}
        # instances whose process told their state: their clients are made
        # once the bring-up threads have ended (see _prepare)
        self._unprepared: List[str] = []
        self._preparer: Optional[threading.Thread] = None
        self.calls = LifecycleCalls(
            node, instances, timeout=timeout,
            start_timeout=timeout if start_timeout is None else start_timeout,
            timeouts=self._timeouts, stop=self._stop, failed=self._has_failed)
        #: instances configured and left inactive: the system's mode leaves them out
        self.held: Set[str] = set()
        #: called with an instance once inactive, before it is activated (a mode's values)
        self.configured: Optional[Callable[[str], None]] = None

    def _has_failed(self, name: str) -> bool:
        with self._changed:
            return name in self._failed

    def _log(self, level: str, text: str) -> None:
        (self._node.get_logger().error if level == 'error' else self._node.get_logger().info)(
            text)

    def start(self, names: Optional[Sequence[str]] = None) -> None:
        """
        Start bringing instances up (every one by default), each in a thread of its own.

        An instance brought up again (its process was started again, or the
        system is brought up after a bring-down) loses its failure, and so
        does what it held back.
        """
        self._stop.clear()
        names = list(self._instances) if names is None else list(names)
        threads = {name: threading.Thread(target=self._bring_up, args=(name,), daemon=True,
                                          name=f'activate {name}') for name in names}
        with self._changed:
            self._threads = [t for t in self._threads if t.is_alive()]
            for name in names:
                self._failed.pop(name, None)
                self._states.pop(name, None)
            self._driving.update(threads)
        for thread in threads.values():
            thread.start()
            self._threads.append(thread)

    def restart(self, *names: str) -> None:
        """Bring instances up again, with what their failure held back."""
        states, todo = self.states(), list(names)
        for name in names:
            todo += [n for n in self._waiting_for(name)
                     if states.get(n) != 'active' and n not in todo]
        self.start(todo)

    def states(self) -> Dict[str, str]:
        """Return the last known state of each instance brought up (``failed`` if it failed)."""
        with self._changed:
            states = dict(self._states)
            states.update(dict.fromkeys(self._failed, 'failed'))
            return states

    def failures(self) -> Dict[str, str]:
        """Return the failed instances and why they failed."""
        with self._changed:
            return dict(self._failed)

    def driving(self, name: str) -> bool:
        """Tell whether this activation takes an instance through its transitions now."""
        thread = self._driving.get(name)  # one operation on a dict: atomic
        return thread is not None and thread.is_alive()

    def discovering(self, name: str) -> bool:
        """Tell whether an instance's get_state is still being discovered (see probe)."""
        return self.calls.discovering(name)

    def probe(self, name: str, timeout: float) -> Optional[str]:
        """Return the state an instance tells within timeout, or None; failed ones too."""
        try:
            return self.calls.get_state(name, timeout=timeout, failed_too=True)
        except (Failed, Stopped):
            return None

    def wait(self, timeout: Optional[float] = None) -> Outcome:
        """Wait until every instance is active or cannot be; return the outcome."""
        deadline = None if timeout is None else time.monotonic() + timeout
        for thread in self._threads:
            thread.join(None if deadline is None else max(0.0, deadline - time.monotonic()))
        with self._changed:
            outcome = Outcome(active=sorted(n for n, s in self._states.items() if s == 'active'),
                              failed=dict(self._failed))
        for name in self._instances:
            if name not in outcome.active and name not in outcome.failed and \
                    name not in self.held:
                outcome.held_back[name] = self._blockers(name)
        return outcome

    def running(self) -> bool:
        """Tell whether instances are still being brought up."""
        return any(thread.is_alive() for thread in self._threads)

    def stop(self) -> None:
        """Stop bringing instances up, quietly: the system is shutting down."""
        self._stop.set()
        with self._changed:
            self._changed.notify_all()

    def close(self, timeout: float = 5.0) -> None:
        """Stop; wait for the clients made in the background (one made as the node goes raises)."""
        self.stop()
        with self._changed:
            preparer = self._preparer
        if preparer is not None:
            preparer.join(timeout)

    def instance_failed(self, name: str, why: str, report: bool = True) -> None:
        """
        Take an instance that failed outside its transitions (its process died, it left).

        :param report: report it, with what it holds back, unless it failed
            before; if not, the caller reports it, and why replaces the why of
            a failure before (the state it is in now)
        """
        with self._changed:
            known = name in self._failed
            self._states.pop(name, None)
            if not report and not self._stop.is_set():
                self._failed[name] = why
                self._changed.notify_all()
        if report and not known:
            self._fail(name, why)

    def recovered(self, name: str) -> List[str]:
        """Take an instance seen active again, its failure gone; return what it held back."""
        with self._changed:
            self._failed.pop(name, None)
            self._states[name] = 'active'
            self._changed.notify_all()
            return [n for n in self._waiting_for(name) if self._states.get(n) != 'active'
                    and n not in self._failed and not self._blockers(n)]

    def bring_down(self, timeout: float = 10.0) -> List[str]:
        """
        Deactivate, then clean up, every instance, those that come after others first.

        An instance goes down once every instance that comes after it is down;
        the instances of one such level go down at once, each in a thread.

        :returns: what was done (``deactivate <name>``, ``cleanup <name>``): each
            instance's steps in order, a level's after the next level's
        """
        for thread in self._threads:
            thread.join()
        self._stop.clear()  # the bring-up is over (stopped or not): services are used again
        done: List[str] = []
        remaining = [n for n in reversed(self.order()) if n not in self._failed]
        while remaining:
            level = [n for n in remaining
                     if not any(n in self._after[m] for m in remaining)] or remaining
            threads = [threading.Thread(target=self._bring_down_one,
                                        args=(name, timeout, done), daemon=True,
                                        name=f'bring down {name}') for name in level]
            self._driving.update(zip(level, threads))
            for thread in threads:
                thread.start()
            for thread in threads:
                thread.join()
            remaining = [n for n in remaining if n not in level]
        return done

    def _bring_down_one(self, name: str, timeout: float, done: List[str]) -> None:
        try:
            wait = min(timeout, self._timeouts.get(name, timeout))
            state = self.calls.get_state(name, timeout=wait)
            if state == 'active':
                self.calls.change(name, Transition.TRANSITION_DEACTIVATE, wait)
                done.append(f'deactivate {name}')
                state = 'inactive'
            if state == 'inactive':
                self.calls.change(name, Transition.TRANSITION_CLEANUP, wait)
                done.append(f'cleanup {name}')
                state = 'unconfigured'
            self.set_state(name, state or 'unknown')
        except (Failed, Stopped) as problem:
            self._report('error', f'instance {name} could not be brought down: {problem}')

    def order(self) -> List[str]:
        """Return the instances in an order where each comes after those it names."""
        return levels.order(self._after)

    # one instance

    def _bring_up(self, name: str) -> None:
        try:
            state = self._told(name, lambda: self._stop.is_set() or self._has_failed(name)) \
                if self._told is not None else None
            if state is not None:
                self._prepare_later(name)
            else:
                state = self.calls.get_state(name) or 'unknown'
            if state == 'unconfigured':
                state = self.calls.change(name, Transition.TRANSITION_CONFIGURE)
            if state == 'inactive' and self.configured is not None:
                self.configured(name)
            if state == 'inactive' and name not in self.held:
                self._wait_for_predecessors(name)
                state = self.calls.change(name, Transition.TRANSITION_ACTIVATE)
                if state == 'active':
                    self._report('info', f'instance {name} is active')
            self.set_state(name, state)
            if state != 'active' and (state, name in self.held) != ('inactive', True):
                self._fail(name, f'is {state}, not active')
        except Stopped:
            return
        except Failed as failure:
            self._fail(name, str(failure))

    def _prepare_later(self, name: str) -> None:
        """Have the clients of an instance made, in the background, after the bring-up."""
        with self._changed:
            self._unprepared.append(name)
            if self._preparer is None:
                self._preparer = threading.Thread(target=self._prepare, daemon=True,
                                                  name='lifecycle clients')
                self._preparer.start()

    def _prepare(self) -> None:
        """
        Make the clients of the instances whose process told their state, one by one.

        Discovered in the background, for the heartbeat and the bring-down; after the
        bring-up threads: two clients per instance, made at once by every thread, held
        the GIL while the bring-up was to be reported (50 to 70 ms at 20, issue 28).
        """
        while True:
            # start() may add threads after the first told its state
            alive = [t for t in list(self._threads) if t.is_alive()]
            if not alive:
                break
            alive[0].join()
        while True:
            with self._changed:
                # none left, or the system is shutting down: its node goes (close)
                if not self._unprepared or self._stop.is_set():
                    self._preparer = None
                    return
                name = self._unprepared.pop(0)
            self.calls.prepare(name)

    def _wait_for_predecessors(self, name: str) -> None:
        with self._changed:
            while True:
                if self._stop.is_set():
                    raise Stopped()
                if self._blockers(name):
                    # held back, directly or through an instance held back
                    # itself: the report of the failure names it
                    raise Stopped()
                if all(self._states.get(other) == 'active' for other in self._after[name]):
                    return
                self._changed.wait(0.5)

    def set_state(self, name: str, state: str) -> None:
        """Take the state an instance is in now (a mode switch took it there)."""
        with self._changed:
            self._states[name] = state
            self._changed.notify_all()

    def _fail(self, name: str, why: str) -> None:
        if self._stop.is_set() or not self._node.context.ok():
            return
        with self._changed:
            self._failed[name] = why
            self._changed.notify_all()
        waiting = self._waiting_for(name)
        also = f'; not activated because of it: {", ".join(waiting)}' if waiting else ''
        self._report('error', f'instance {name} {why}{also}')

    def _blockers(self, name: str) -> List[str]:
        """Return the failed instances that name waits for, directly or not."""
        return sorted(levels.predecessors(self._after, name) & set(self._failed))

    def _waiting_for(self, name: str) -> List[str]:
        """Return the instances that come after name, directly or not."""
        return levels.successors(self._after, name)
