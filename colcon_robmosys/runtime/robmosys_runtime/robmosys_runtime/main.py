# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The process of a component: its node on the executor its model names."""

from __future__ import annotations

import faulthandler
import os
import select
import signal
import threading
import time
from types import FrameType
from typing import Any, Callable, List, Optional, Sequence

import rclpy
from rclpy.exceptions import InvalidHandle
from rclpy.executors import Executor, ExternalShutdownException
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions
from rclpy.task import Future
from robmosys_runtime.executors import executor_kind, make_executor
from robmosys_runtime.transitions import close_transitions, TRANSITION_GRACE


#: seconds of each spin of an events executor (see :func:`spin`)
EVENTS_SPIN_PERIOD = 3600.0
#: seconds after a first SIGINT or SIGTERM in which another is the same request:
#: a terminal's Ctrl-C reaches every process of its group, and ros2 launch then
#: sends each its own SIGINT. A later one ends the process at once.
SAME_REQUEST = 1.0
#: seconds a process has to end once its nodes are brought down (after SIGINT
#: or SIGTERM); one still there prints where each of its threads is, to
#: stderr, and goes on ending
ENDING_REPORT = 3.0


#: when this process was first asked to end (SIGINT or SIGTERM), by time.monotonic()
_asked_to_end: List[float] = []


def _asked(signum: int, frame: Optional[FrameType]) -> None:
    """SIGINT or SIGTERM: noted, once (:func:`spin_until_signal` ends the process)."""
    if not _asked_to_end:
        _asked_to_end.append(time.monotonic())
    else:
        _exit_at_once(signum, frame)


def _exit_at_once(signum: int, frame: Optional[FrameType]) -> None:
    # a second SIGINT or SIGTERM while the node ends (an activity or a goal
    # still running): the user wants the process gone now, unless it is the
    # same request come twice (SAME_REQUEST)
    if not _asked_to_end or time.monotonic() - _asked_to_end[0] >= SAME_REQUEST:
        os._exit(128 + signum)


def run(node_factory: Callable[[], Node], args: Optional[List[str]] = None) -> int:
    """
    Spin the node node_factory() until SIGINT or SIGTERM, then shut down cleanly.

    The node's ``executor_name`` says what spins it (see
    :func:`robmosys_runtime.executors.executor_kind`). Return the exit
    status of the process (0).
    """
    return run_nodes([node_factory], args)


def run_nodes(node_factories: Sequence[Callable[[], Node]],
              args: Optional[List[str]] = None, executor_name: Optional[str] = None,
              before_spin: Optional[Callable[[List[Node]], Any]] = None,
              unspun: Sequence[Callable[[], Node]] = (),
              bring_down: Optional[Callable[[List[Node]], Any]] = None) -> int:
    """
    Spin several nodes in one process until SIGINT or SIGTERM, then shut down cleanly.

    :param executor_name: the executor of the process (one of
        :data:`robmosys_runtime.executors.EXECUTORS`); by default the most
        capable one its nodes need (:func:`~robmosys_runtime.executors.executor_kind`).
        On a multi-threaded one, every node has the threads it would have in
        a process of its own (:func:`~robmosys_runtime.executors.executor_threads`),
        so a blocking call of one cannot starve the others.
    :param before_spin: run once with the nodes when they are made, before any
        callback is.
    :param unspun: nodes made first, before the others, and never spun (they
        have no callback: they publish), destroyed with the others.
    :param bring_down: run once with the nodes at SIGINT or SIGTERM, while they
        are still spun and the context is up, so that it can take them through
        their transitions; the process then ends.

    At SIGINT or SIGTERM (:func:`spin_until_signal`), the transitions
    requested of the nodes are refused from then on, and one under way is
    waited for (:func:`robmosys_runtime.transitions.close_transitions`);
    then bring_down runs, the executor stops, the nodes go and the context
    is shut down last.
    Return the exit status (0).
    """
    # the signals are this process's: rclpy's handler would shut the context
    # down at once, under a transition under way, which then fails to publish
    # its event. One that comes while the nodes are made is taken once they spin.
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, _asked)
    # Made before the executor spins: served while the others were made, the
    # first nodes of a 50-node process came up later, not sooner (each node
    # added woke the executor to gather every entity again, under the GIL)
    quiet = [factory() for factory in unspun]
    nodes = [factory() for factory in node_factories]
    if before_spin is not None:
        before_spin(nodes)
    executor = make_executor(executor_kind(nodes, executor_name), nodes)
    for node in nodes:
        executor.add_node(node)
    try:
        spin_until_signal(executor, lambda: _end(nodes, bring_down))
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except Exception:  # noqa: B902 - re-raised unless shutting down
        # a callback that was running when the context was shut down (not by
        # the signals: they end the spin first) fails with it; that is the
        # shutdown, not an error
        if rclpy.ok():
            raise
    finally:
        for signum in (signal.SIGINT, signal.SIGTERM):
            signal.signal(signum, _exit_at_once)
        stop_executor(executor)
        _settle_callbacks(executor, nodes[0])
        for node in nodes + quiet:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0


def _end(nodes: List[Node], bring_down: Optional[Callable[[List[Node]], Any]]) -> None:
    """Close the nodes' transitions, then bring them down: SIGINT or SIGTERM came."""
    for node in close_transitions(nodes):
        node.get_logger().warning(
            f'a transition still under way {TRANSITION_GRACE:g} s after the signal: '
            'the node ends in it')
    if bring_down is not None:
        bring_down(nodes)


def spin(executor: Any, stopped: Optional[Future[None]] = None) -> None:
    """
    Spin until shutdown, through an entity destroyed while the executor gathered its wait set.

    The spin ends with the context, or once the executor is shut down, or
    once stopped is done (:func:`end_spin`). The executor then stays whole
    while the callbacks under way end (:func:`stop_executor`): rclpy's
    shutdown() drops what they wake it with, and rclpy 7.1 (Jazzy) returns
    before they end.

    A transition (cleanup, shutdown) destroys a node's ports in one of the
    executor's threads while the spinning thread may be gathering them: rclpy
    then raises InvalidHandle out of spin (ros2/rclpy#1142, #1206), which ended
    the process and every node it held; an action server's request taken just
    before raises a RuntimeError (:func:`destroyed_meanwhile`). The next spin
    leaves the entity out.

    rclpy's EventsExecutor (7.1.6, 9.1.2 of the ros-* wheels) runs nothing in
    an untimed ``spin()``: it turns on one CPU without calling back. It is
    spun for a long while at a time, until the context ends. It serves a
    request that came before a transition destroyed its service after it, and
    ``send_response`` raises InvalidHandle out of its spin: the request goes
    unanswered (its service is gone) and the executor spins on.
    """
    while True:
        try:
            if not isinstance(executor, Executor):  # the EventsExecutor is none
                _spin_events(executor, stopped or Future())
            elif stopped is None:
                executor.spin()
            else:
                executor.spin_until_future_complete(stopped)
            return
        except (InvalidHandle, RuntimeError) as error:
            if not executor.context.ok() or not destroyed_meanwhile(error):
                raise


def destroyed_meanwhile(error: BaseException) -> bool:
    """
    Say whether an error out of spin is about an entity destroyed while the executor used it.

    rclpy says so with InvalidHandle; rcl_action with a RuntimeError, when a
    port released (an event server) had a request taken for it and not yet
    processed: 'Failed to process cancel request: action server pointer is
    invalid' (seen once in CI, Kilted, rclpy 9.1.2).
    """
    return isinstance(error, InvalidHandle) or (
        isinstance(error, RuntimeError) and
        ('action server pointer is invalid' in str(error) or
         'action client pointer is invalid' in str(error)))


def spin_until_signal(executor: Any, bring_down: Callable[[], Any]) -> None:
    """
    Spin until SIGINT or SIGTERM, then call bring_down() and stop the executor.

    Python runs a signal's handler in the main thread only, between two of
    its instructions, never while that thread waits in rcl: the executor
    spins in a thread of its own, and the main thread waits for the signal
    (``signal.set_wakeup_fd``) or for the spin to end (a callback raised,
    or the context was shut down): what ended the spin is raised here.

    The executor's threads end here, the context still up: the nodes are
    destroyed after, and the context shut down last. rclpy 9 (Kilted)
    destroys every node of a context as it shuts it down, which under
    threads still spinning them is what rclpy does not support (ros2/rclpy#663).
    """
    reading, writing = os.pipe()
    os.set_blocking(writing, False)
    ended: List[BaseException] = []
    done = threading.Event()
    stopped: Future[None] = Future()

    def spin_here() -> None:
        try:
            spin(executor, stopped)
        except BaseException as failure:  # noqa: B902 - raised in the main thread
            ended.append(failure)
        finally:
            done.set()
            os.write(writing, b'.')

    previous = signal.set_wakeup_fd(writing)
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, _asked)
    spinner = threading.Thread(target=spin_here, name='spin', daemon=True)
    spinner.start()
    try:
        while not _asked_to_end and not done.is_set():
            select.select([reading], [], [])
            os.read(reading, 512)
        if _asked_to_end and not done.is_set():
            try:
                bring_down()
            finally:
                report_if_still_ending()
                end_spin(stopped)
        # the spin ends (the pipe is not closed under it); the callbacks under
        # way end in run_nodes (stop_executor)
        spinner.join()
    finally:
        signal.set_wakeup_fd(previous)
        os.close(reading)
        os.close(writing)
    if ended:
        raise ended[0]


def report_if_still_ending(after: float = ENDING_REPORT) -> None:
    """
    Have the process print where its threads are if it is still there after some seconds.

    What is left of the process's end once its nodes are brought down (the
    callbacks under way, its threads joined, its nodes destroyed, rclpy shut
    down, the interpreter's own end) takes well under a second. A process
    that hangs there would be killed by whoever asked it to end, and say
    nothing: faulthandler's own thread prints the Python stack of each
    thread to stderr, even while one holds the GIL.
    """
    try:
        faulthandler.dump_traceback_later(after, exit=False)
    except (OSError, RuntimeError, ValueError):
        pass  # stderr has no file descriptor (closed, or replaced in a test)


def _spin_events(executor: Any, stopped: Future[None]) -> None:
    while executor.context.ok() and not stopped.done():
        executor.spin_until_future_complete(stopped, timeout_sec=EVENTS_SPIN_PERIOD)


def end_spin(stopped: Future[None]) -> None:
    """
    End the spin of :func:`spin` given stopped, the executor whole.

    Its spin_until_future_complete() returns: the future wakes the executor
    (an events one too). Waking it alone does not end rclpy's spin_once().
    """
    stopped.set_result(None)


def stop_executor(executor: Any) -> None:
    """
    Wait for the callbacks the executor is running to end, then shut it down (its spin ended).

    The callbacks of a MultiThreadedExecutor run on its threads: they end
    first, the executor whole. rclpy's shutdown() destroys the guard condition
    a callback that ends wakes the executor with (an action's goal done:
    AttributeError, Jazzy), and rclpy 7.1 (Jazzy) returns from it before the
    callbacks end, which would then meet their nodes destroyed. A second
    SIGINT or SIGTERM still ends the process at once.
    """
    pool = getattr(executor, '_executor', None)
    if pool is not None:
        pool.shutdown(wait=True)
    executor.shutdown()


def _settle_callbacks(executor: Any, node: Node) -> None:
    """
    Take the outcome of the callbacks that ended after the executor's last spin.

    rclpy would print each failure when it collects the task ("exception was
    never retrieved"). One that failed because the context went down (a
    callback failed and ended the spin, others still running) is the
    shutdown; any other is logged.
    rclpy keeps the tasks of a MultiThreadedExecutor in ``_futures`` (7.1, 9.1).
    """
    for task in list(getattr(executor, '_futures', ())):
        if not task.done():
            continue
        failure = task.exception()
        if failure is not None and rclpy.ok():
            node.get_logger().error(f'a callback failed: {failure!r}')
