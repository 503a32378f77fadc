# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Work shared by forked processes: the CPU time of many model files on every core.

Checking, planning and rendering are Python's CPU time; one process keeps
one core busy. A forked worker inherits what this process holds (the checked
models, the compiled schema): only its share of the work goes to it and only
its results come back, pickled.
"""

from __future__ import annotations

import gc
import multiprocessing
import os
import traceback
from typing import Any, Callable, Sequence, TypeVar

Share = TypeVar('Share')
Result = TypeVar('Result')

#: The fewest model files a worker is forked for: below, forking costs more
#: than it spares.
MIN_FILES_PER_WORKER = 16


def available_cpus() -> int:
    """Return how many CPUs this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def fork_map(function: Callable[[Share], Result],
             shares: Sequence[Share]) -> list[Result]:
    """Return ``[function(share) for share in shares]``, all but the last share forked.

    The last share runs here meanwhile: this process has a CPU's work too,
    and its result needs no pickling. The function is not pickled: each
    process inherits it, and everything it reads, at the fork; the results
    come back pickled. Called with no thread running beside this one (a
    fork copies only the calling thread, and a lock another thread holds
    stays locked in the copy).

    :raises: what the function raised, here or in a process
    """
    if len(shares) < 2:
        return [function(share) for share in shares]
    context = multiprocessing.get_context('fork')
    workers: list[tuple[Any, Any]] = []
    # what this process holds stays where it is: no collection in a worker
    # touches (and so copies) the pages of objects it only reads; nor, here,
    # goes through them again while this process does its own share
    gc.freeze()
    try:
        for share in shares[:-1]:
            receiver, sender = context.Pipe(duplex=False)
            process = context.Process(target=_work, args=(function, share, sender),
                                      daemon=True)
            process.start()
            sender.close()
            workers.append((process, receiver))
        own = function(shares[-1])
        return [*_receive(workers), own]
    finally:
        gc.unfreeze()
        for process, receiver in workers:
            receiver.close()
            if process.is_alive():
                process.terminate()
            process.join()


def _receive(workers: list[tuple[Any, Any]]) -> list[Any]:
    """Return the results of the forked processes, in order.

    Unpickled with the collector off: the results are trees of new objects,
    and a collection every few thousand of them took half of the time.
    """
    enabled = gc.isenabled()
    gc.disable()
    try:
        results = []
        for process, receiver in workers:
            try:
                done, value = receiver.recv()
            except EOFError:
                process.join()
                raise RuntimeError(
                    f'a worker ended with code {process.exitcode} before its result') from None
            if not done:
                raise value
            results.append(value)
        return results
    finally:
        if enabled:
            gc.enable()


def _work(function: Callable[[Share], Result], share: Share, sender: Any) -> None:
    """Run the inherited function on a share, in a forked process; send what came of it."""
    try:
        try:
            result = function(share)
        except BaseException as error:  # noqa: B902 - whatever it is, the caller raises it
            _send(sender, (False, error), error)
        else:
            _send(sender, (True, result), None)
    finally:
        sender.close()


def _send(sender: Any, outcome: tuple[bool, Any], error: BaseException | None) -> None:
    """Send an outcome; an exception or result that does not pickle, as a text."""
    try:
        sender.send(outcome)
    except Exception:  # noqa: B902 - whatever does not pickle
        text = ''.join(traceback.format_exception(error)) if error is not None \
            else 'a result that does not pickle'
        sender.send((False, RuntimeError(text)))
