# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
What the page shows of the system, computed once per period whatever the clients.

:class:`View` reads what the manager knows (each instance's state and why, the
conformance watch's differences, the parameter values it saw) into entries,
one per instance (``i:<name>``), one per connection (``c:<index>``, its index
in the model and in ``bringup.json``) and one for the system (``system``).
Each :meth:`View.update` compares them with the last and keeps only those that
changed, as one JSON text: every client is sent that same text (server-sent
events), so a period costs the manager one comparison, not one per client.
"""

from __future__ import annotations

import collections
import json
import threading
from typing import Any, Callable, Deque, Dict, List, Optional, Tuple

#: the changes kept for a client that is behind; one further behind gets everything
KEPT = 64


class Source:
    """
    What the view reads; the system manager gives it (robmosys_runtime.system.page).

    Each is a callable so that this room needs nothing of the manager's.
    """

    def __init__(self, description: Dict[str, Any], states: Callable[[], Dict[str, str]],
                 failures: Callable[[], Dict[str, str]], watch: Callable[[], Any],
                 up: Callable[[], bool], mode: Callable[[], Optional[str]] = lambda: None,
                 watch_on: bool = True,
                 modes: Callable[[], List[str]] = lambda: []) -> None:
        self.description = description
        self.states = states
        self.failures = failures
        #: the conformance watch (robmosys_runtime.watch.watcher.Watch), or None yet
        self.watch = watch
        self.up = up
        #: the mode the system is in, once modes exist (None: the system has none)
        self.mode = mode
        #: the modes an operator may switch to: the page shows a button each, which
        #: asks the action ``mode`` with ``{"mode": <name>}``
        self.modes = modes
        self.watch_on = watch_on


def _instance(instance: Dict[str, Any], state: str, why: str, lines: List[str],
              running: Dict[str, Any]) -> Dict[str, Any]:
    parameters = [[p['name'], p['value'], running.get(p['name']), p.get('location', '')]
                  for p in instance.get('parameters', ())]
    return {'state': state, 'why': why, 'differences': lines, 'parameters': parameters,
            'fqn': instance['fqn'], 'managed': instance['managed'],
            'host': instance.get('host', ''), 'location': instance.get('location', '')}


def entries(source: Source) -> Dict[str, Any]:
    """Return what the page shows now, by entry."""
    description = source.description
    states = source.states()
    failures = source.failures()
    watch = source.watch()
    subjects = watch.by_subject() if watch is not None else {}
    seen = watch.parameter_values() if watch is not None else {}
    found: Dict[str, Any] = {}
    for instance in description['instances']:
        name = instance['instance']
        lines = [d.line() for d in subjects.get(f'instance {name}', ())]
        found[f'i:{name}'] = _instance(instance, states.get(name, 'starting'),
                                       failures.get(name, ''), lines,
                                       seen.get(instance['fqn'], {}))
    for index, connection in enumerate(description.get('connections', ())):
        lines = [d.line() for d in subjects.get(f'connection {index}', ())]
        if lines:
            status = 'differs'
        elif watch is not None and watch.ready:
            status = 'conforms'
        else:
            status = 'unknown'
        found[f'c:{index}'] = {
            'status': status, 'differences': lines, 'from': connection['from'],
            'to': connection['to'] or connection['name'], 'name': connection['name'],
            'type': connection['type'], 'location': connection.get('location', '')}
    if not source.watch_on:
        watching = 'off'
    elif watch is None:
        watching = 'starting'
    else:
        watching = 'ready' if watch.ready else 'comparing'
    found['system'] = {'package': description['package'], 'up': bool(source.up()),
                       'mode': source.mode(), 'modes': list(source.modes()),
                       'watch': watching}
    return found


class View:
    """The page's entries, and their changes as server-sent events for every client."""

    def __init__(self, source: Source) -> None:
        self.source = source
        self._entries: Dict[str, Any] = {}
        self.version = 0
        self._changes: Deque[Tuple[int, bytes]] = collections.deque(maxlen=KEPT)
        self._changed = threading.Condition()

    def update(self) -> int:
        """Read the system once; keep what changed as the next event; return how many entries."""
        now = entries(self.source)
        changed = {k: v for k, v in now.items() if self._entries.get(k) != v}
        gone = [k for k in self._entries if k not in now]
        if not changed and not gone:
            return 0
        text = json.dumps({'version': self.version + 1, 'entries': changed, 'gone': gone},
                          separators=(',', ':'), default=str)
        with self._changed:
            self._entries = now
            self.version += 1
            self._changes.append((self.version, event('change', text, self.version)))
            self._changed.notify_all()
        return len(changed) + len(gone)

    def everything(self) -> Tuple[int, bytes]:
        """Return the version and every entry, as one event."""
        with self._changed:
            text = json.dumps({'version': self.version, 'entries': self._entries, 'gone': []},
                              separators=(',', ':'), default=str)
            return self.version, event('state', text, self.version)

    def snapshot(self) -> Dict[str, Any]:
        """Return every entry (GET /state)."""
        with self._changed:
            return {'version': self.version, 'entries': dict(self._entries)}

    def since(self, version: int, timeout: float) -> Tuple[int, Optional[bytes]]:
        """
        Wait until there is a version after ``version``; return it and the events to send.

        None when nothing changed within the timeout; every entry when the
        client is further behind than the changes kept.
        """
        with self._changed:
            if self.version == version:
                self._changed.wait(timeout)
            if self.version == version:
                return version, None
            kept = [text for v, text in self._changes if v > version]
            if len(kept) != self.version - version:
                return self.everything()
            return self.version, b''.join(kept)

    def wake(self) -> None:
        """Wake every waiting client (the page is closing)."""
        with self._changed:
            self._changed.notify_all()


def event(name: str, data: str, version: int) -> bytes:
    """Return the bytes of a server-sent event; its data is JSON without a newline."""
    return f'id: {version}\nevent: {name}\ndata: {data}\n\n'.encode('utf-8')


def run(view: View, period: float, stopping: threading.Event,
        report: Callable[[str], None]) -> None:
    """Update the view every period until stopping is set (a thread's target)."""
    told = set()
    while True:
        try:
            view.update()
        except Exception as error:  # noqa: B902 - the page goes on; each failure said once
            text = f'the page failed to read the system: {type(error).__name__}: {error}'
            if text not in told:
                told.add(text)
                report(text)
        if stopping.wait(period):
            return
