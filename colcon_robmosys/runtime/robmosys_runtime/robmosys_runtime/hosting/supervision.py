# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The processes of a host's instances, started, watched and stopped.

Each in a session of its own (a Ctrl-C reaches only bringup), ending with
the bringup that started it, even killed; one that ends is reported; at the
end each is asked to end (SIGINT), and one that does not is made to say where
it hangs (SIGABRT) before it is killed.
"""

from __future__ import annotations

import os
from pathlib import Path
import queue
import shutil
import signal
import subprocess
import sys
import threading
import time
from typing import Any, Callable, Dict, List, Optional, Sequence, Set

from robmosys_runtime.hosting.output import say
from robmosys_runtime.hosting.processes import NotInstalled
from robmosys_runtime.hosting.running import look, MARK, wait_gone
from robmosys_runtime.sends import send_directory, SENDS

#: seconds each process has to end after SIGINT, before SIGABRT and SIGKILL
STOP_TIMEOUT = 10.0
#: seconds a process that did not end of SIGINT has, after SIGABRT, to print
#: where its threads are (Python's faulthandler), before SIGKILL
ABORT_GRACE = 3.0


def _ending_with_parent() -> Optional[Callable[[], None]]:
    """
    Return what a child calls to get SIGTERM when the thread that started it ends (Linux).

    prctl(PR_SET_PDEATHSIG): the instances of a ``bringup`` end with it, even
    when it is killed. Otherwise they would live on unsupervised, and the
    ``bringup`` started again would start a second node of each name. The
    signal comes when the *thread* that forked ends, not the process: every
    process is started from one thread that lives as long as the process
    (:class:`Processes`). The function is looked up here, in the parent: the
    child only calls it.
    """
    if not sys.platform.startswith('linux'):
        return None
    import ctypes  # here: bringup starts the instances before anything else
    try:
        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None
    parent = os.getpid()

    def end_with_parent() -> None:
        prctl(_PR_SET_PDEATHSIG, int(signal.SIGTERM))
        if os.getppid() != parent:
            # the parent died before prctl: no signal would ever come
            os._exit(1)
    return end_with_parent


_PR_SET_PDEATHSIG = 1


class Processes:
    """
    The processes of the instances, watched: one that ends is reported.

    :param end_with_parent: whether each process gets SIGTERM when this
        process ends, even killed; they are then all started from a thread of
        their own, which lives as long as this process: PR_SET_PDEATHSIG
        signals when the thread that started a process ends (the manager
        starts them from its main thread, and respawns from short threads)
    :param mark: the value of :data:`~robmosys_runtime.hosting.running.MARK`
        in each process's environment (:func:`~robmosys_runtime.hosting.running.mark`):
        a ``bringup`` started again finds what this one left
    :param sends: whether the components keep the time of their sends
        (:mod:`robmosys_runtime.sends`) for the watch, in a directory of this
        object's (:attr:`sends`), removed by :meth:`stop`
    """

    def __init__(self, on_exit: Any, end_with_parent: bool = False, mark: str = '',
                 sends: bool = False) -> None:
        self._preexec = _ending_with_parent() if end_with_parent else None
        self._environment = {MARK: mark} if mark else {}
        #: the directory of the send files, if they are kept
        self.sends: Optional[Path] = send_directory() if sends else None
        if self.sends is not None:
            self._environment[SENDS] = str(self.sends)
        #: what the starting thread runs, each with where its outcome goes
        self._starts: Optional[queue.Queue[Any]] = None
        if self._preexec is not None:
            self._starts = queue.Queue()
            threading.Thread(target=self._starting, daemon=True,
                             name='starting processes').start()
        self._processes: Dict[str, subprocess.Popen[bytes]] = {}
        #: called with (name, exit code) once a process ends, while watched
        self.on_exit = on_exit
        self._stopping = threading.Event()
        #: the processes asked to end already (interrupt): asked once only
        self._interrupted: Set[str] = set()
        self._watch = threading.Thread(target=self._watch_loop, daemon=True)

    def start(self, name: str, args: Sequence[str], pass_fds: Sequence[int] = ()) -> None:
        """
        Start an instance in a session of its own: a Ctrl-C reaches only bringup.

        :param pass_fds: file descriptors the process inherits (``--report-fd``)
        """
        def popen() -> subprocess.Popen[bytes]:
            return subprocess.Popen(
                list(args), stdin=subprocess.DEVNULL, start_new_session=True,
                preexec_fn=self._preexec, pass_fds=tuple(pass_fds),
                # a Python process that hangs prints its threads' stacks at SIGABRT
                env={'PYTHONFAULTHANDLER': '1', **os.environ, **self._environment})
        if self._starts is None:
            self._processes[name] = popen()
            return
        outcome: queue.Queue[Any] = queue.Queue(maxsize=1)
        self._starts.put((popen, outcome))
        process = outcome.get()
        if isinstance(process, BaseException):
            raise process
        self._processes[name] = process

    def _starting(self) -> None:
        """Start each process asked for, for as long as this process lives (a thread's target)."""
        assert self._starts is not None
        while True:
            popen, outcome = self._starts.get()
            try:
                outcome.put(popen())
            except BaseException as error:  # noqa: B902 - raised in the asking thread
                outcome.put(error)

    def started(self) -> bool:
        """Tell whether a process was started."""
        return bool(self._processes)

    def watch(self) -> None:
        """Start watching the processes."""
        self._watch.start()

    def state(self, name: str) -> str:
        """
        Return the state of the process of an instance: starting, running or exited.

        The manager's services answer from the start, before every process
        is started: one not started yet is starting.
        """
        process = self._processes.get(name)
        if process is None:
            return 'starting'
        return 'running' if process.poll() is None else 'exited'

    def _watch_loop(self) -> None:
        reported: Dict[str, subprocess.Popen[bytes]] = {}
        while not self._stopping.wait(0.1):
            for name, process in list(self._processes.items()):
                code = process.poll()
                # a process started again is watched again
                if code is not None and reported.get(name) is not process:
                    reported[name] = process
                    self.on_exit(name, code)

    def interrupt(self, name: str) -> None:
        """
        Ask one process to end (SIGINT) now, the system being stopped; stop() waits for it.

        A second SIGINT would tell it to end at once: it gets none from stop().
        """
        self._stopping.set()
        self._interrupted.add(name)
        process = self._processes.get(name)
        if process is not None and process.poll() is None:
            self._signal(process, signal.SIGINT)

    def stop(self, timeout: float = STOP_TIMEOUT) -> bool:
        """
        Ask every process to end (SIGINT), then kill what is left after timeout.

        A process left gets SIGABRT first: a Python one prints where each of
        its threads is (``PYTHONFAULTHANDLER``), which names the hang.

        :returns: whether every process ended of SIGINT, none needing SIGKILL
        """
        self._stopping.set()
        for name in self._processes:
            if name not in self._interrupted:
                self.interrupt(name)
        late = self._wait(self._processes, timeout)
        # never expected: a process ends within a few seconds of SIGINT. One
        # at a time, so that the stacks do not run into each other; those
        # left after twice ABORT_GRACE are killed as they are
        deadline = time.monotonic() + 2 * ABORT_GRACE
        for name in late:
            if time.monotonic() >= deadline:
                say('error', f'{name} did not end within {timeout:g} s of SIGINT: SIGKILL')
                continue
            say('error', f'{name} did not end within {timeout:g} s of SIGINT: SIGABRT, '
                'for the stacks of its threads, then SIGKILL')
            self._signal(self._processes[name], signal.SIGABRT)
            self._wait({name: self._processes[name]},
                       min(ABORT_GRACE, deadline - time.monotonic()))
        if late:
            self.kill()
        if self.sends is not None:
            shutil.rmtree(self.sends, ignore_errors=True)
        return not late

    @staticmethod
    def _wait(processes: Dict[str, subprocess.Popen[bytes]], timeout: float) -> List[str]:
        """Wait for the processes to end within timeout; return the names of those that did not."""
        deadline = time.monotonic() + timeout
        late = []
        for name, process in processes.items():
            try:
                process.wait(max(0.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                late.append(name)
        return late

    @staticmethod
    def _signal(process: subprocess.Popen[bytes], signum: int) -> None:
        try:
            os.killpg(process.pid, signum)
        except ProcessLookupError:
            pass

    def kill(self) -> None:
        """End every process at once."""
        self._stopping.set()
        for process in self._processes.values():
            self._signal(process, signal.SIGKILL)


#: the host of an instance whose node runs already, started otherwise: no host's own
ELSEWHERE = ' running already'


def before_start(description: Dict[str, Any], host: str,
                 stopped: Callable[[], bool]) -> Optional[Dict[str, Any]]:
    """
    Look at what runs on this host already, before the instances of a host are started.

    What a ``bringup`` of the system that ended left is waited for (it got
    SIGTERM as that one died). An instance whose node runs already, started
    otherwise (by hand, a launch file left running), is taken as it is: not
    started here, never respawned nor ended here, brought up and down by the
    manager as an instance of another host is. A second node of one name
    would break every tool that looks a node up by its name.

    :returns: the description to plan this host's processes from, where the
        instances taken as they are run on no host of the model
        (:data:`ELSEWHERE`); None if another ``bringup`` of the system runs
        on this host for the same host and namespace: nothing may be started
    """
    found = look(description, host)
    who = f'bringup --host {host}' if host else 'manager'
    if found.bringups:
        pids = ', '.join(str(p) for p in found.bringups)
        say('error', f'a {who} of this system runs on this host already (process {pids}); '
            'nothing was started')
        return None
    if found.left:
        say('info', f'waiting for the {len(found.left)} processes that a {who} of this system '
            'which ended left to end')
        for killed in wait_gone(found.left, STOP_TIMEOUT, stopped):
            say('error', f'process {killed} did not end within {STOP_TIMEOUT:g} s: SIGKILL')
    taken = set()
    for instance in description['instances']:
        pid = found.nodes.get(instance['fqn'])
        if pid is None or instance.get('host', '') != host:
            continue
        taken.add(instance['instance'])
        where = f"{instance['location']}: " if instance.get('location') else ''
        say('info', f"{where}warning: instance {instance['instance']}: node {instance['fqn']} "
            f'runs already (process {pid}), not started by this {who.split()[0]}: taken as '
            'it is')
    return dict(description, instances=[
        dict(i, host=ELSEWHERE) if i['instance'] in taken else i
        for i in description['instances']])


def not_installed(error: NotInstalled) -> int:
    """Report the packages that instances need and do not find; return the exit status."""
    for problem in error.problems:
        say('error', f'{problem}; nothing was started')
    return 1
