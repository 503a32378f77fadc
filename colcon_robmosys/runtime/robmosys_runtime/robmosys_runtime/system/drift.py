# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
Managed instances that leave the state the manager brought them to, and come back to it.

An operator (``ros2 lifecycle set``), a fault or a respawn may take a managed
instance through a transition behind the manager's back. Each instance says
so on its ``transition_event``
(:class:`~robmosys_runtime.watch.states.LifecycleStates`), and the heartbeat
asks (:mod:`.heartbeat`): :class:`Drift` holds what they tell against what the
activation believes. An instance seen out of ``active`` is failed (reported,
and a difference of the watch); one seen ``active`` again, whatever brought it
back, is no longer failed, and what its failure held back is brought up.

An event is news, not a state: one of the manager's own transitions may
arrive after the manager took its answer, or after it moved on to the next.
So an event is taken as a reason to ask the instance (``get_state``), and
none of an instance that the activation takes through a transition counts.
"""

from __future__ import annotations

import re
import threading
from typing import Callable, Dict, Mapping, Optional

from rclpy.node import Node
from robmosys_runtime.hosting.output import say
from robmosys_runtime.system.activation import SystemActivation
from robmosys_runtime.watch.states import LifecycleStates, PRIMARY_STATES

#: a failure that says the state its instance is in, kept up to date
_STATED = re.compile(r'is \w+, not active')


class Drift:
    """
    The states managed instances are seen in, outside the manager's transitions.

    :param up: whether the system is meant to be up now (not after
        ``~/bring_down``): only then is an instance out of ``active`` failed
    :param timeout: seconds an instance has to tell its state after an event
    """

    def __init__(self, activation: SystemActivation, up: Callable[[], bool],
                 timeout: float = 2.0) -> None:
        self._activation = activation
        self._up = up
        self._timeout = timeout
        self._lock = threading.Lock()
        #: the transition events of the managed instances, once followed
        self.events: Optional[LifecycleStates] = None

    def follow(self, node: Node, instances: Mapping[str, str],
               stopping: threading.Event) -> None:
        """
        Follow the transition events of instances until stopping is set (a thread's target).

        They come to a node of their own (``<node>_states``, in node's context)
        and an executor of their own, which sleeps until one comes: an executor
        goes over every entity of its nodes at each wake, and the manager's wakes
        at every answer (a subscription per instance on the manager's node cost
        it 1 % of a CPU more at 50 instances with a heartbeat of 1 s, 0.25 % idle;
        on a node of their own, nothing measurable).

        :param instances: instance name -> fully qualified node name
        """
        import rclpy
        from rclpy.executors import SingleThreadedExecutor
        follower = rclpy.create_node(
            f'_{node.get_name()}_states', namespace=node.get_namespace(), context=node.context,
            # a remap of __node among the global arguments (bringup's) renames every node
            use_global_arguments=False, start_parameter_services=False, enable_rosout=False)
        executor = SingleThreadedExecutor(context=node.context)
        executor.add_node(follower)
        self.events = LifecycleStates(follower, instances, on_state=self._told)
        spinner = threading.Thread(target=executor.spin, daemon=True, name='transition events')
        spinner.start()
        try:
            while not stopping.wait(0.5) and node.context.ok():
                pass
        finally:
            executor.shutdown()
            spinner.join(10)
            if node.context.ok():
                follower.destroy_node()

    def _told(self, name: str, state: str) -> None:
        # in the thread of the events' own executor: asking here holds only them
        try:
            self._confirm(name)
        except Exception as error:  # noqa: B902 - the next events count
            say('error', f'the state of instance {name} could not be taken: '
                         f'{type(error).__name__}: {error}')

    def _confirm(self, name: str) -> None:
        """Ask an instance whose event came its state, unless the activation drives it."""
        if not self._up() or self._activation.driving(name):
            return
        state = self._activation.probe(name, timeout=self._timeout)
        if state is not None and self._up() and not self._activation.driving(name):
            self.seen(name, state, 'transition_event')

    def seen(self, name: str, state: str, how: str) -> None:
        """
        Take the state an instance told outside the manager's transitions.

        :param how: what told it, in the reports (``heartbeat``, ``transition_event``)
        """
        if state not in PRIMARY_STATES:
            return  # on its way: its next state tells
        with self._lock:
            believed = self._activation.states().get(name)
            if name in self._activation.held:
                # the mode leaves it inactive: the watch and ~/report compare what it is in
                if believed != state:
                    self._activation.recovered(name)
                    self._activation.set_state(name, state)
                    say('info' if state == 'inactive' else 'error',
                        f'instance {name} is {state} ({how}); the mode leaves it inactive')
                return
            if state == 'active':
                if believed != 'active':
                    held = self._activation.recovered(name)
                    say('info', f'instance {name} is active again ({how})')
                    held = [n for n in held if not self._activation.driving(n)]
                    if held and self._up():
                        self._activation.restart(*held)
                return
            why = f'is {state}, not active'
            failure = self._activation.failures().get(name, '')
            if believed == 'active' or (
                    _STATED.fullmatch(failure) and failure != why):
                self._activation.instance_failed(name, why, report=False)
                say('error', f'instance {name} {why} ({how})')

    def ended(self, name: str) -> None:
        """
        Forget the state an instance's events told: its process ended.

        Its last event (``inactive``, say) told of a process that is gone; the
        watch then said ``is inactive`` of an instance that has no process.
        """
        if self.events is not None:
            self.events.forget(name)

    def states_for_watch(self, states: Dict[str, str]) -> Dict[str, str]:
        """
        Return states with, for each failed instance, the state its last event told.

        So the watch says ``is inactive, not active`` as ``bringup --check`` does,
        where the manager says ``failed``; ``failed`` where no event told one
        (its process ended, or it left active before it was followed).
        """
        events = self.events
        if events is None:
            return states
        told = events.states()
        states = dict(states)
        for name, state in states.items():
            if state == 'failed' and told.get(name, 'active') != 'active':
                states[name] = told[name]
        return states
