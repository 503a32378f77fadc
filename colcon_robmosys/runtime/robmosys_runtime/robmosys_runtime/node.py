# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The lifecycle bookkeeping of a component: what a generated node does not state.

A component's ports and timers exist from configure to cleanup (or shutdown, or error
handling); its activities run only while it is active, one callback at a time each (a mutually
exclusive callback group and a lock per activity); a function that raises fails the transition
it runs in, or is logged if it runs in an activity, and never stops the node.
"""

from __future__ import annotations

from functools import partial
import traceback
from typing import (
    Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, TypeVar)

from rclpy.action import CancelResponse, GoalResponse
from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from rclpy.qos import QoSProfile
from rclpy.timer import Timer
from robmosys_runtime.activity import Activity, call_each
from robmosys_runtime.announce import announce_component
from robmosys_runtime.events import EventClient, EventServer
from robmosys_runtime.ports import ActionClientPort, ActionServer, QueryClient
from robmosys_runtime.qos import overridable
from robmosys_runtime.sends import count_sends
from robmosys_runtime.transitions import guard_transitions, TRANSITION_VERBS

Function = Callable[..., Any]
Entity = TypeVar('Entity')


class ComponentNode(LifecycleNode):
    """
    A lifecycle node whose ports and timers live from configure to cleanup.

    A subclass creates its ports and timers in :meth:`create_ports` with the
    ``add_*`` methods, which make each port an attribute of the node named
    after the port, and release it on cleanup, shutdown and error handling.
    """

    def __init__(self, node_name: str, *, ports: Sequence[str] = (),
                 activities: Iterable[str] = (),
                 lifecycle: Optional[Mapping[str, Sequence[Function]]] = None,
                 component: Optional[str] = None, **kwargs: Any) -> None:
        """
        Create the node; nothing of its ports exists before configure.

        :param ports: the names of the ports (attributes, None until configure)
        :param activities: the names of the activities
        :param lifecycle: the functions each transition runs (``on_configure``,
            ``on_activate``, ``on_deactivate``, ``on_cleanup``, ``on_shutdown``,
            ``on_error``), in order
        :param component: a generated component's package, announced with its ports
        """
        super().__init__(node_name, **kwargs)
        guard_transitions(self)
        if component is not None:
            announce_component(self, component, ports)
        self._active = False
        self.activities: Dict[str, Activity] = {name: Activity(name) for name in activities}
        self._lifecycle = {key: tuple(functions) for key, functions in (lifecycle or {}).items()}
        self._ports: List[Tuple[str, Callable[[], object]]] = []
        self._activity_timers: List[Timer] = []
        for name in ports:
            setattr(self, name, None)

    @property
    def active(self) -> bool:
        """Return whether the node is active: its activities run only then."""
        return self._active

    def create_ports(self) -> None:
        """Create the ports and the timers (on configure); subclasses override it."""

    # ports

    def add_publisher(self, name: str, msg_type: Any, qos: QoSProfile) -> Any:
        """Create a lifecycle publisher (a provided push or a required send port)."""
        entity = self.create_lifecycle_publisher(msg_type, name, **overridable(qos))
        count_sends(entity)
        return self._keep(name, entity, lambda: self.destroy_lifecycle_publisher(entity))

    def add_subscription(self, name: str, msg_type: Any, qos: QoSProfile,
                         activity: Optional[str] = None,
                         functions: Sequence[Function] = ()) -> Any:
        """Create a subscription whose messages run the functions of an activity."""
        group = self.activities[activity].callback_group if activity else None
        callback = (self.run_activity_callback(activity, functions) if activity
                    else lambda message: None)  # no activity is triggered by it
        entity = self.create_subscription(msg_type, name, callback, **overridable(qos),
                                          callback_group=group)
        return self._keep(name, entity, lambda: self.destroy_subscription(entity))

    def add_service(self, name: str, srv_type: Any, activity: str, function: Function) -> Any:
        """Create a service whose requests are answered by a function of an activity."""
        run = self.activities[activity]

        def answer(request: Any, response: Any) -> Any:
            if not self._active:
                self.get_logger().warning(
                    f'request on {name} while inactive: answered with the default response')
                return response
            with run.lock:
                if not self._active:
                    return response
                try:
                    result = function(request, response)
                except Exception:  # noqa: B902 - an activity failure must not stop the node
                    self._activity_failed(activity)
                    return response
            return response if result is None else result

        entity = self.create_service(srv_type, name, answer, callback_group=run.callback_group)
        return self._keep(name, entity, lambda: self.destroy_service(entity))

    def add_query_client(self, name: str, srv_type: Any, activity: Optional[str] = None,
                         functions: Sequence[Function] = ()) -> QueryClient:
        """Create the client of a query; its asynchronous answers run an activity."""
        on_answer = self.run_activity_callback(activity, functions) if activity else None
        entity = QueryClient(self, srv_type, name, on_answer)
        return self._keep(name, entity, entity.destroy)

    def add_action_server(self, name: str, action_type: Any, activity: str,
                          function: Function) -> Any:
        """Create an action server whose goals are executed by a function of an activity."""
        run = self.activities[activity]

        def goal(goal_request: Any) -> GoalResponse:
            if not self._active:
                self.get_logger().warning(f'goal on {name} rejected: inactive')
                return GoalResponse.REJECT
            return GoalResponse.ACCEPT

        def end_at_shutdown(goal_handle: Any, result: Any = None) -> Any:
            # SIGINT or SIGTERM ended the context under the goal: its state
            # ends here, quietly; telling the clients cannot work any more
            try:
                goal_handle.abort()
            except Exception:  # noqa: B902 - the context is gone
                pass
            return action_type.Result() if result is None else result

        def execute(goal_handle: Any) -> Any:
            with run.lock:
                try:
                    result = function(goal_handle)
                except Exception:  # noqa: B902 - an activity failure must not stop the node
                    if not self.context.ok():
                        return end_at_shutdown(goal_handle)
                    self._activity_failed(activity)
                    goal_handle.abort()
                    return action_type.Result()
            if not self.context.ok():
                return end_at_shutdown(goal_handle, result)
            if goal_handle.is_active:
                # the function left the end of the goal to us
                if goal_handle.is_cancel_requested:
                    goal_handle.canceled()
                else:
                    goal_handle.succeed()
            return action_type.Result() if result is None else result

        entity = ActionServer(
            self, action_type, name, execute, goal_callback=goal,
            cancel_callback=lambda goal_handle: CancelResponse.ACCEPT,
            callback_group=run.callback_group)
        return self._keep(name, entity, entity.destroy)

    def add_action_client(self, name: str, action_type: Any, activity: Optional[str] = None,
                          functions: Sequence[Function] = ()) -> ActionClientPort:
        """Create the client of an action; the results of its goals run an activity."""
        on_result = self.run_activity_callback(activity, functions) if activity else None
        entity = ActionClientPort(self, action_type, name, on_result)
        return self._keep(name, entity, entity.destroy)

    def add_event_server(self, name: str, action_type: Any, qos: QoSProfile,
                         activity: Optional[str] = None,
                         condition: Optional[Function] = None) -> EventServer:
        """Create the server of an event; a function of an activity is its condition."""
        holds: Optional[Callable[[Any, Any], bool]] = None
        if activity is not None and condition is not None:
            holds = self._under_lock(activity, condition)
        entity = EventServer(self, action_type, name, qos, lambda: self._active, holds)
        return self._keep(name, entity, entity.destroy)

    def add_event_client(self, name: str, action_type: Any, qos: QoSProfile,
                         activity: Optional[str] = None,
                         functions: Sequence[Function] = ()) -> EventClient:
        """Create the client of an event; each event runs the functions of an activity."""
        on_event = self.run_activity_callback(activity, functions) if activity else None
        entity = EventClient(self, action_type, name, qos, on_event)
        return self._keep(name, entity, entity.destroy)

    def add_periodic(self, activity: str, period: float, functions: Sequence[Function]) -> Timer:
        """Create the timer of a periodic activity: runs from activate to deactivate."""
        run = self.run_activity_callback(activity, functions)
        # no argument: the EventsExecutor of rclpy 9.1 hands rclpy's TimerInfo to a
        # callback that takes some, and a periodic function takes none
        timer = self.create_timer(period, lambda: run(), autostart=False,
                                  callback_group=self.activities[activity].callback_group)
        self._activity_timers.append(timer)
        return timer

    # activities

    def run_activity_callback(self, activity: str,
                              functions: Sequence[Function]) -> Callable[..., None]:
        """
        Return a callback that runs functions in an activity, with what it receives.

        The functions run only while the node is active, under the activity's
        lock; a function that raises is logged and the node goes on.
        """
        lock = self.activities[activity].lock
        # one function (the most common) is called with no loop around it, per message
        call = functions[0] if len(functions) == 1 else partial(call_each, tuple(functions))

        def run(*received: Any) -> None:
            if not self._active:
                return
            with lock:
                if not self._active:
                    # deactivated while it waited: the ports may be gone
                    return
                try:
                    call(*received)
                except Exception:  # noqa: B902 - an activity failure must not stop the node
                    self._activity_failed(activity)
        return run

    def _under_lock(self, activity: str, condition: Function) -> Callable[[Any, Any], bool]:
        lock = self.activities[activity].lock

        def holds(activation: Any, event: Any) -> bool:
            with lock:
                return bool(condition(activation, event))
        return holds

    def _activity_failed(self, activity: str) -> None:
        if not self.context.ok():
            # SIGINT or SIGTERM shut the context down under the activity: that
            # is the shutdown, not a failure of the activity
            return
        self.get_logger().error(f'activity {activity} failed:\n' + traceback.format_exc())

    # lifecycle

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Create the ports and timers, then run the configure functions."""
        try:
            self.create_ports()
            self._run_lifecycle('on_configure')
        except Exception:  # noqa: B902 - any failure fails the transition
            self._transition_failed('on_configure')
            self.release()
            return TransitionCallbackReturn.FAILURE
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Run the activate functions, then publish and start the activities."""
        try:
            self._run_lifecycle('on_activate')
        except Exception:  # noqa: B902 - any failure fails the transition
            self._transition_failed('on_activate')
            return TransitionCallbackReturn.FAILURE
        result = super().on_activate(state)
        self._active = True
        for timer in self._activity_timers:
            timer.reset()
        return result

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Stop the activities and publishing, then run the deactivate functions."""
        self._active = False
        for timer in self._activity_timers:
            timer.cancel()
        self._wait_for_activities()
        result = super().on_deactivate(state)
        try:
            self._run_lifecycle('on_deactivate')
        except Exception:  # noqa: B902 - any failure fails the transition
            self._transition_failed('on_deactivate')
            return TransitionCallbackReturn.FAILURE
        return result

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Run the cleanup functions, then release the ports and timers."""
        return self._end('on_cleanup')

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Run the shutdown functions, then release the ports and timers."""
        return self._end('on_shutdown')

    def on_error(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Run the error handling functions, then release the ports and timers."""
        return self._end('on_error')

    def release(self) -> None:
        """Destroy the ports and timers created on configure."""
        timers, self._activity_timers = self._activity_timers, []
        for timer in timers:
            self.destroy_timer(timer)
        ports, self._ports = self._ports, []
        for name, destroy in ports:
            destroy()
            setattr(self, name, None)

    def _keep(self, name: str, entity: Entity, destroy: Callable[[], object]) -> Entity:
        setattr(self, name, entity)
        self._ports.append((name, destroy))
        return entity

    def _run_lifecycle(self, transition: str) -> None:
        for function in self._lifecycle.get(transition, ()):
            function()

    def _transition_failed(self, transition: str) -> None:
        self.get_logger().error(
            f'{TRANSITION_VERBS[transition]} failed:\n' + traceback.format_exc())

    def _wait_for_activities(self, timeout: float = 5.0) -> None:
        """Wait until no function of an activity runs: after it, none starts."""
        for activity in self.activities.values():
            # an activity that deactivates its own node holds its lock: go on
            if activity.lock.acquire(timeout=timeout):
                activity.lock.release()

    def _end(self, transition: str) -> TransitionCallbackReturn:
        self._active = False
        self._wait_for_activities()
        result = TransitionCallbackReturn.SUCCESS
        try:
            self._run_lifecycle(transition)
        except Exception:  # noqa: B902 - any failure fails the transition
            self._transition_failed(transition)
            result = TransitionCallbackReturn.FAILURE
        self.release()
        return result
