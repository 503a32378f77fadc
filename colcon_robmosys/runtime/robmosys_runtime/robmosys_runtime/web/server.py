# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The system manager's page, served over HTTP: ``bringup --web PORT``.

Python's own :class:`http.server.ThreadingHTTPServer`: the page is a handful of
files and one stream of server-sent events per browser, which a thread each
serves well; it is in every Python, so a robot needs nothing more. The page
itself (``page.html``, ``page.js``, ``page.css``, written for it, no library)
draws the system's installed diagram (``doc/<system>.svg``, laid out at build
time) and colours it with what :class:`~robmosys_runtime.web.view.View` sends.

Reading is open to whoever reaches the address (127.0.0.1 by default); what
changes the system (``POST /action/<name>``: bring_up, bring_down, and the
actions a caller adds) needs the token the manager prints at start, as Jupyter
does. A request not understood is answered 4xx and said in one line.
"""

from __future__ import annotations

import argparse
import hmac
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
import ipaddress
import json
import os
import secrets
import threading
from typing import Any, Callable, Dict, Optional, Tuple
from urllib.parse import parse_qs, urlsplit

from robmosys_runtime.hosting.output import say
from robmosys_runtime.web.view import run, View

#: an action: its arguments (the request's JSON object) -> success, message
Action = Callable[[Dict[str, Any]], Tuple[bool, str]]

#: the page's own files, beside this module: path -> (file, content type)
FILES = {
    '/': ('page.html', 'text/html; charset=utf-8'),
    '/page.js': ('page.js', 'text/javascript; charset=utf-8'),
    '/page.css': ('page.css', 'text/css; charset=utf-8'),
}
#: seconds between two comments on a quiet stream: a proxy or browser keeps it open
KEEPALIVE = 15.0
#: the longest request body read (an action's arguments)
MOST_BODY = 65536


def add_options(parser: argparse.ArgumentParser) -> None:
    """Add bringup's options of the page."""
    parser.add_argument('--web', type=_port, default=None, metavar='PORT',
                        help='serve a page of the running system on this port (0: any free '
                        'one); it prints the address, with the token that changes need')
    parser.add_argument('--web-address', default='127.0.0.1', metavar='ADDRESS',
                        help='the address the page listens on (default: 127.0.0.1, this '
                        'machine only)')


def _port(text: str) -> Optional[int]:
    if text == '':
        return None  # the launch files' default: no page
    if not text.isdigit() or int(text) > 65535:
        raise argparse.ArgumentTypeError(f'{text}: is not a port (0 to 65535)')
    return int(text)


class Page:
    """
    The page of one system manager: its socket, bound before anything starts.

    :meth:`serve` starts serving once the manager exists; until then the
    socket holds the connections that arrive.
    """

    def __init__(self, address: str, port: int, share: str, package: str) -> None:
        self.token = os.environ.get('ROBMOSYS_WEB_TOKEN') or secrets.token_urlsafe(24)
        self.diagram = os.path.join(share, 'doc', f'{package}.svg')
        self.actions: Dict[str, Action] = {}
        self.view: Optional[View] = None
        self.stopping = threading.Event()
        self.server = _Server((address, port), _Handler)
        self.server.page = self
        # (host, port) of an AF_INET or AF_INET6 socket, the port the system gave for 0
        bound: Any = self.server.server_address
        host, port = bound[0], bound[1]
        shown = f'[{host}]' if ':' in host else host
        #: whether only this machine reaches it
        self.loopback = ipaddress.ip_address(host).is_loopback
        #: where the page is, with its token
        self.url = f'http://{shown}:{port}/?token={self.token}'

    def serve(self, view: View, period: float, actions: Dict[str, Action]) -> None:
        """Serve the page, the view updated every period, in threads of their own."""
        self.view = view
        self.actions.update(actions)
        threading.Thread(target=run, args=(view, period, self.stopping,
                                           lambda text: say('error', text)),
                         daemon=True, name='page view').start()
        threading.Thread(target=self.server.serve_forever, kwargs={'poll_interval': 0.2},
                         daemon=True, name='page').start()
        say('info', f'the page of the system: {self.url}')

    def close(self) -> None:
        """Stop serving; the streams of the browsers end (they reconnect to the next one)."""
        self.stopping.set()
        if self.view is not None:
            self.view.wake()
            self.server.shutdown()
        self.server.server_close()

    def allowed(self, token: str) -> bool:
        """Tell whether a request's token is this page's."""
        return hmac.compare_digest(token.encode('utf-8'), self.token.encode('utf-8'))


class _Server(ThreadingHTTPServer):
    daemon_threads = True
    page: Page

    def handle_error(self, request: Any, client_address: Any) -> None:
        # socketserver prints a traceback: one line is what the manager says
        import sys
        error = sys.exc_info()[1]
        if not isinstance(error, (BrokenPipeError, ConnectionResetError)):
            say('error', f'the page: a request of {client_address[0]} failed: '
                f'{type(error).__name__}: {error}')


class _Handler(BaseHTTPRequestHandler):
    server: _Server
    server_version = 'robmosys'
    protocol_version = 'HTTP/1.1'

    def log_message(self, format: str, *args: Any) -> None:  # noqa: A002 - the base's name
        # requests served are not told; what is refused is (log_error, send_error)
        pass

    def log_error(self, format: str, *args: Any) -> None:  # noqa: A002 - the base's name
        say('info', f'the page refused {self.address_string()}: {format % args}')

    def refuse(self, status: HTTPStatus, why: str) -> None:
        """Answer a request not understood, or not allowed: 4xx, and one line."""
        self.log_error('%s %s: %d %s', self.command, urlsplit(self.path).path, status, why)
        # the body of a refused request is not read: the connection ends with it,
        # or what is left of the body would be read as the next request
        self.close_connection = True
        self._send(status, json.dumps({'success': False, 'message': why}).encode(),
                   'application/json', close=True)

    def _send(self, status: HTTPStatus, body: bytes, content_type: str,
              close: bool = False) -> None:
        self.send_response(status)
        if close:
            self.send_header('Connection', 'close')
        self.send_header('Content-Type', content_type)
        self.send_header('Content-Length', str(len(body)))
        self.send_header('Cache-Control', 'no-store')
        self.send_header('X-Content-Type-Options', 'nosniff')
        self.end_headers()
        if self.command != 'HEAD':
            self.wfile.write(body)

    def _host_refused(self) -> bool:
        """
        Refuse a request to a page on loopback that names another host (403); tell if so.

        A web site the browser visits may name its own host at this address (DNS
        rebinding) and read the page: a browser sends the name it asked for.
        """
        if not self.server.page.loopback:
            return False
        host = urlsplit(f"//{self.headers.get('Host', '')}").hostname or ''
        if host in ('127.0.0.1', 'localhost', '::1'):
            return False
        self.refuse(HTTPStatus.FORBIDDEN, f'a request for host {host!r} on 127.0.0.1')
        return True

    def do_GET(self) -> None:  # noqa: N802 - the base's name
        page = self.server.page
        path = urlsplit(self.path).path
        if self._host_refused():
            return
        if path in FILES:
            name, content_type = FILES[path]
            with open(os.path.join(os.path.dirname(__file__), name), 'rb') as stream:
                self._send(HTTPStatus.OK, stream.read(), content_type)
        elif path == '/diagram.svg':
            if not os.path.isfile(page.diagram):
                self.refuse(HTTPStatus.NOT_FOUND, f'{page.diagram}: no such file (build the '
                            'system package again)')
                return
            with open(page.diagram, 'rb') as stream:
                self._send(HTTPStatus.OK, stream.read(), 'image/svg+xml')
        elif path == '/state' and page.view is not None:
            self._send(HTTPStatus.OK, json.dumps(page.view.snapshot(), default=str).encode(),
                       'application/json')
        elif path == '/events' and page.view is not None:
            self._events(page)
        else:
            self.refuse(HTTPStatus.NOT_FOUND, 'no such page')

    do_HEAD = do_GET  # noqa: N815 - the base's name

    def do_POST(self) -> None:  # noqa: N802 - the base's name
        page = self.server.page
        parts = urlsplit(self.path)
        if self._host_refused():
            return
        token = self.headers.get('X-Robmosys-Token') or \
            parse_qs(parts.query).get('token', [''])[0]
        if not parts.path.startswith('/action/'):
            self.refuse(HTTPStatus.NOT_FOUND, 'no such page')
            return
        if not page.allowed(token):
            self.refuse(HTTPStatus.FORBIDDEN, 'a change needs the token the manager printed')
            return
        action = page.actions.get(parts.path[len('/action/'):])
        if action is None:
            self.refuse(HTTPStatus.NOT_FOUND, f'no action {parts.path[len("/action/"):]!r}')
            return
        try:
            length = int(self.headers.get('Content-Length') or 0)
        except ValueError:
            length = -1
        if not 0 <= length <= MOST_BODY:
            self.refuse(HTTPStatus.BAD_REQUEST, 'a body of an unknown or too large length')
            return
        try:
            arguments = json.loads(self.rfile.read(length) or b'{}')
        except ValueError:
            arguments = None
        if not isinstance(arguments, dict):
            self.refuse(HTTPStatus.BAD_REQUEST, 'the body is not a JSON object')
            return
        success, message = action(arguments)
        say('info', f'the page: {parts.path[len("/action/"):]} asked by '
            f'{self.address_string()}')
        self._send(HTTPStatus.OK, json.dumps({'success': success, 'message': message}).encode(),
                   'application/json')

    def _not_allowed(self) -> None:
        self.refuse(HTTPStatus.METHOD_NOT_ALLOWED, f'{self.command} is not served')

    do_PUT = do_DELETE = do_PATCH = do_OPTIONS = _not_allowed  # noqa: N815 - the base's names

    def _events(self, page: Page) -> None:
        """Stream every entry, then each change, until the browser or the page goes."""
        view = page.view
        assert view is not None
        self.send_response(HTTPStatus.OK)
        self.send_header('Content-Type', 'text/event-stream')
        self.send_header('Cache-Control', 'no-store')
        self.send_header('Connection', 'close')
        self.end_headers()
        self.close_connection = True
        # a browser reconnects a second after the stream ends (the manager restarted)
        version, text = view.everything()
        self.wfile.write(b'retry: 1000\n\n' + text)
        self.wfile.flush()
        while not page.stopping.is_set():
            version, changes = view.since(version, KEEPALIVE)
            if page.stopping.is_set():
                return
            self.wfile.write(changes if changes is not None else b': quiet\n\n')
            self.wfile.flush()
