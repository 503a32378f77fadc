# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The manager's page (``bringup --web PORT``): bound before anything starts, served once it runs.

:func:`open_page` binds the socket first, so that a port in use is one line
and exit 2 with nothing started; :func:`serve_page` gives the page what the
manager knows and what an operator may ask of it with the token: bring_up,
bring_down, and the actions given as ``extra``. Modes, once they exist, give
``extra={'mode': switch}`` (``switch({'mode': name})`` returns success and a
message) and the view's :class:`~robmosys_runtime.web.view.Source` its
``mode`` and ``modes``: the page then shows the mode and a button for each.
"""

from __future__ import annotations

import argparse
from types import SimpleNamespace
from typing import Any, Callable, Dict, List, Optional, Tuple

from robmosys_runtime.hosting.output import say
from robmosys_runtime.web.server import Action, Page
from robmosys_runtime.web.view import Source, View

#: the page's period when the watch is off or slower: a state shows within it
MOST_PERIOD = 0.5


def open_page(description: Dict[str, Any], args: argparse.Namespace) -> Optional[Page]:
    """
    Return the page, its socket bound, or None without ``--web``.

    :raises OSError: the address or port cannot be had (said by the caller)
    """
    if getattr(args, 'web', None) is None:
        return None
    from ament_index_python.packages import get_package_share_directory
    package = description['package']
    return Page(args.web_address, args.web, get_package_share_directory(package), package)


def serve_page(page: Page, manager: Any, args: argparse.Namespace,
               extra: Optional[Dict[str, Action]] = None,
               mode: Callable[[], Optional[str]] = lambda: None,
               modes: Callable[[], List[str]] = lambda: []) -> None:
    """Serve the page of a manager (robmosys_runtime.system.manager.Manager)."""
    watch_on = getattr(args, 'check_period', 0.0) > 0
    source = Source(manager.description, manager.states, manager.activation.failures,
                    lambda: manager.watch, lambda: manager.up, mode=mode, watch_on=watch_on,
                    modes=modes)
    period = min(args.check_period, MOST_PERIOD) if watch_on else MOST_PERIOD
    actions: Dict[str, Action] = {
        'bring_up': _trigger(manager._bring_up),  # noqa: SLF001 - the services' own answer
        'bring_down': _trigger(manager._bring_down),  # noqa: SLF001
    }
    actions.update(extra or {})
    page.serve(View(source), period, actions)


def _trigger(service: Callable[[Any, Any], Any]) -> Action:
    """Return an action that answers as the manager's Trigger service of the same name."""
    def act(arguments: Dict[str, Any]) -> Tuple[bool, str]:
        try:
            response = service(None, SimpleNamespace(success=False, message=''))
        except Exception as error:  # noqa: B902 - said, and the page answers
            say('error', f'the page: {type(error).__name__}: {error}')
            return False, f'{type(error).__name__}: {error}'
        return bool(response.success), str(response.message)
    return act
