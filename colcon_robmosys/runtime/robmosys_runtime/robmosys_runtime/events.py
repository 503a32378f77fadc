# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The event pattern over a ROS 2 action: the server and the client of an event port.

An activation is a goal (its fields are the activation's parameters, and a
``single`` field asks for one event only); each event is a feedback message of
that goal; the client deactivates by cancelling the goal. The result of a
single activation is its one event, so that it arrives even if the feedback is
lost. The feedback and the result of the action hold the same fields.
"""

from __future__ import annotations

import threading
import time
import traceback
from typing import Any, Callable, Dict, List, Optional, Tuple

from action_msgs.msg import GoalStatus
from rclpy.action import CancelResponse, GoalResponse
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
from rclpy.node import Node
from rclpy.qos import QoSProfile
from rclpy.task import Future
from robmosys_runtime.ports import _unless_destroyed, ActionClient, ActionServer

#: the statuses of a goal its server ended
_GOAL_ENDED = (GoalStatus.STATUS_SUCCEEDED, GoalStatus.STATUS_CANCELED, GoalStatus.STATUS_ABORTED)

#: What a provided event port tests each event against: (activation, event) -> holds.
Condition = Callable[[Any, Any], bool]


def copy_fields(source: Any, target: Any) -> Any:
    """Copy the fields of the message target from source (same field names); return target."""
    for field in target.get_fields_and_field_types():
        setattr(target, field, getattr(source, field))
    return target


def _is_single(activation: Any) -> bool:
    # an event type written by hand may have no single field: then no
    # activation is single
    return bool(getattr(activation, 'single', False))


class EventServer:
    """
    The server of an event port, over a ROS 2 action.

    Each goal is an activation, kept (no thread is used for it) until the
    client cancels it or, for a single activation, until its first event.
    ``fire`` notifies an event to each activation whose condition holds.
    """

    def __init__(self, node: Node, action_type: Any, name: str,
                 qos: Optional[QoSProfile] = None,
                 active: Optional[Callable[[], bool]] = None,
                 condition: Optional[Condition] = None) -> None:
        """
        Serve the event port name of a node.

        :param qos: the QoS of the events (the action's feedback topic)
        :param active: whether activations are accepted now (default: always)
        :param condition: whether an event is notified to an activation
            (default: every event to every activation)
        """
        self._node = node
        self.name = name
        self._type = action_type
        self._active = active
        self._condition = condition
        self._lock = threading.Lock()
        self._activations: Dict[bytes, Any] = {}
        self._ending: List[Any] = []
        self.callback_group = MutuallyExclusiveCallbackGroup()
        self.server = ActionServer(
            node, action_type, name, execute_callback=self._aborted,
            goal_callback=self._goal, handle_accepted_callback=self._accepted,
            cancel_callback=self._cancel, callback_group=self.callback_group,
            feedback_pub_qos_profile=qos if qos is not None else QoSProfile(depth=10))

    @property
    def activations(self) -> int:
        """Return how many activations are kept."""
        with self._lock:
            return len(self._activations)

    def fire(self, event: Any) -> int:
        """
        Notify an event to each activation whose condition holds.

        Return how many activations were notified.
        """
        notified = 0
        with self._lock:
            for key, goal_handle in list(self._activations.items()):
                try:
                    holds = self._condition is None or \
                        bool(self._condition(goal_handle.request, event))
                except Exception:  # noqa: B902 - a failing condition does not hold
                    self._node.get_logger().error(
                        f'the condition of {self.name} failed:\n' + traceback.format_exc())
                    continue
                if not holds:
                    continue
                goal_handle.publish_feedback(event)
                notified += 1
                if _is_single(goal_handle.request):
                    del self._activations[key]
                    goal_handle.execute(lambda handle, event=event: self._fired(handle, event))
        return notified

    def _goal(self, goal_request: Any) -> GoalResponse:
        if self._active is not None and not self._active():
            self._node.get_logger().warning(f'an activation of {self.name} was refused: inactive')
            return GoalResponse.REJECT
        return GoalResponse.ACCEPT

    def _accepted(self, goal_handle: Any) -> None:
        with self._lock:
            self._activations[bytes(goal_handle.goal_id.uuid)] = goal_handle

    def _cancel(self, goal_handle: Any) -> CancelResponse:
        with self._lock:
            kept = self._activations.pop(bytes(goal_handle.goal_id.uuid), None)
        if kept is None:
            return CancelResponse.REJECT
        goal_handle.execute(self._canceled)
        return CancelResponse.ACCEPT

    def _fired(self, goal_handle: Any, event: Any) -> Any:
        goal_handle.succeed()
        return copy_fields(event, self._type.Result())

    def _canceled(self, goal_handle: Any) -> Any:
        # the server marks the goal canceling as soon as _cancel returns
        deadline = time.monotonic() + 1.0
        while not goal_handle.is_cancel_requested and time.monotonic() < deadline:
            time.sleep(0.001)
        if goal_handle.is_cancel_requested:
            goal_handle.canceled()
        else:
            goal_handle.abort()
        return self._type.Result()

    def _aborted(self, goal_handle: Any) -> Any:
        goal_handle.abort()
        if goal_handle in self._ending:
            self._ending.remove(goal_handle)
        return self._type.Result()

    def destroy(self) -> None:
        """Abort the activations still kept, then release the server."""
        with self._lock:
            self._ending = list(self._activations.values())
            self._activations.clear()
        for goal_handle in list(self._ending):
            goal_handle.execute(self._aborted)
        deadline = time.monotonic() + 1.0
        while self._ending and time.monotonic() < deadline:
            time.sleep(0.01)
        self.server.destroy()


class EventActivation:
    """An activation of an event by a client."""

    def __init__(self, single: bool) -> None:
        self.single = single
        #: the goal handle, once the server accepted the activation
        self.goal_handle: Any = None
        #: how many events of this activation ran the activity
        self.events = 0
        #: deactivated, ended by its single event, refused or aborted, as the client saw it
        self.finished = False

    @property
    def ended(self) -> bool:
        """Tell whether the activation is over: finished, or ended by its server."""
        # the status (transient local) comes where the result may not (rmw_fastrtps#467)
        return self.finished or (self.goal_handle is not None and
                                 self.goal_handle.status in _GOAL_ENDED)


class EventClient:
    """
    The client of an event port, over a ROS 2 action.

    An activation is a goal; each event is its feedback; deactivating
    cancels the goal. An activation made before the server is there (a
    client activated before discovery found the server) is sent once it is:
    a goal sent to no server is lost, and so would be every event of it.
    """

    #: seconds between two looks for the server, while activations wait for it
    WAIT_PERIOD = 0.1
    #: seconds the server has been seen before the activations that waited go: the
    #: client sees the server before the server has matched the client (DDS matches
    #: each direction on its own), and a goal sent in between was lost
    SERVER_SETTLE = 0.5

    def __init__(self, node: Node, action_type: Any, name: str,
                 qos: Optional[QoSProfile] = None,
                 on_event: Optional[Callable[[Any], None]] = None) -> None:
        """
        Use the event port name of a node.

        :param qos: the QoS of the events (the action's feedback topic)
        :param on_event: what each event of an activation runs
        """
        self._node = node
        self.name = name
        self._type = action_type
        self._on_event = on_event
        self._lock = threading.Lock()
        self._activations: List[EventActivation] = []
        #: activations made before the server was there, and the timer that sends them
        self._waiting: List[Tuple[EventActivation, Any]] = []
        self._waiting_timer: Any = None
        self._server_since: Optional[float] = None
        self.callback_group = MutuallyExclusiveCallbackGroup()
        self.client: Any = ActionClient(
            node, action_type, name, callback_group=self.callback_group,
            feedback_sub_qos_profile=qos if qos is not None else QoSProfile(depth=10))

    def wait_for_server(self, timeout_sec: Optional[float] = None) -> bool:
        """Wait until the event server is there; return whether it is."""
        return self.client.wait_for_server(timeout_sec=timeout_sec)

    def activate(self, activation: Any, single: bool = False) -> EventActivation:
        """
        Activate the event with an activation (a Goal of the event's action).

        Each event runs the activity the port triggers; with single, the
        first event ends the activation.
        """
        if hasattr(activation, 'single'):
            activation.single = single
        elif single:
            raise ValueError(f'the activations of {self.name} have no single field')
        handle = EventActivation(single)
        with self._lock:
            self._activations.append(handle)
            if self._waiting or not self.client.server_is_ready():
                self._waiting.append((handle, activation))
                if self._waiting_timer is None:
                    self._waiting_timer = self._node.create_timer(
                        self.WAIT_PERIOD, self._send_waiting,
                        callback_group=self.callback_group)
                return handle
        self._send(handle, activation)
        return handle

    def _send(self, handle: EventActivation, activation: Any) -> None:
        future = self.client.send_goal_async(
            activation, feedback_callback=lambda message: self._event(handle, message.feedback))
        future.add_done_callback(lambda future: self._accepted(handle, future))

    def _send_waiting(self) -> None:
        """Send the activations that waited for the server, in their order, once it is there."""
        with self._lock:
            if self._waiting_timer is None:
                return
            if not self.client.server_is_ready():
                self._server_since = None
                return
            now = time.monotonic()
            if self._server_since is None:
                self._server_since = now
            if now - self._server_since < self.SERVER_SETTLE:
                return
            waiting, self._waiting = self._waiting, []
            self._node.destroy_timer(self._waiting_timer)
            self._waiting_timer = self._server_since = None
        for handle, activation in waiting:
            if not handle.finished:  # deactivated while it waited: nothing to send
                self._send(handle, activation)

    def deactivate(self, handle: EventActivation) -> None:
        """End an activation: none of its events runs the activity any more."""
        with self._lock:
            goal_handle = handle.goal_handle if not handle.finished else None
            handle.finished = True
        if goal_handle is not None:
            self._cancel(goal_handle)

    def _cancel(self, goal_handle: Any) -> None:
        """
        Ask the server to end an activation, unless the port is released already.

        An activation accepted while the port was released (a cleanup, in
        another thread) is ended too late to be cancelled: the client is
        gone, and its server ends the goal when it sees it go. rclpy then
        raised, which ended the process (and every instance it held).
        """
        _unless_destroyed(self.client._client_handle, goal_handle.cancel_goal_async, None)

    def _accepted(self, handle: EventActivation, future: Future) -> None:
        goal_handle = future.result()
        if goal_handle is None or not goal_handle.accepted:
            self._node.get_logger().warning(f'an activation of {self.name} was refused')
            handle.finished = True
            return
        with self._lock:
            handle.goal_handle = goal_handle
            finished = handle.finished
        if finished:
            self._cancel(goal_handle)
            return
        # released meanwhile (see _cancel): no result to ask a client that is gone
        _unless_destroyed(
            self.client._client_handle,
            lambda: goal_handle.get_result_async().add_done_callback(
                lambda future: self._finished(handle, future)), None)

    def _event(self, handle: EventActivation, event: Any) -> None:
        with self._lock:
            if handle.finished:
                return
            handle.events += 1
            handle.finished = handle.single
        if self._on_event is not None:
            self._on_event(event)

    def _finished(self, handle: EventActivation, future: Future) -> None:
        response: Any = future.result()
        with self._lock:
            # the event that ended a single activation is its result too:
            # it counts if its feedback was lost
            missed = not handle.finished and handle.single and \
                response.status == GoalStatus.STATUS_SUCCEEDED
            if missed:
                handle.events += 1
            handle.finished = True
        if missed and self._on_event is not None:
            self._on_event(copy_fields(response.result, self._type.Feedback()))

    def destroy(self) -> None:
        """Deactivate every activation, then release the client."""
        with self._lock:
            activations = list(self._activations)
            timer, self._waiting_timer, self._waiting = self._waiting_timer, None, []
        if timer is not None:
            self._node.destroy_timer(timer)
        for handle in activations:
            self.deactivate(handle)
        self.client.destroy()
