# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The page's server: changes need the token, what is not understood is 4xx, changes only."""

import http.client
import json
import threading
import time

import pytest
from robmosys_runtime.watch.conformance import Difference
from robmosys_runtime.web.server import Page
from robmosys_runtime.web.view import Source, View

DESCRIPTION = {
    'package': 'demo_system',
    'instances': [
        {'instance': 'talker', 'fqn': '/talker', 'managed': True, 'location': 'm.yaml:3:5',
         'parameters': [{'name': 'rate', 'value': 2.0, 'location': 'm.yaml:4:9'}]},
        {'instance': 'listener', 'fqn': '/listener', 'managed': True, 'location': 'm.yaml:6:5'},
    ],
    'connections': [{'from': 'talker.out', 'to': 'listener.in', 'name': '/chatter',
                     'type': 'std_msgs/msg/String', 'location': 'm.yaml:9:9'}],
}


class Watched:
    """What the manager's watch answers the view (the view reads nothing else of it)."""

    ready = True

    def __init__(self) -> None:
        self.differences = []

    def by_subject(self):
        subjects = {}
        for difference in self.differences:
            subjects.setdefault(difference.subject, []).append(difference)
        return subjects

    def parameter_values(self):
        return {'/talker': {'rate': 5.0}}


@pytest.fixture
def page(tmp_path, capsys):
    (tmp_path / 'doc').mkdir()
    (tmp_path / 'doc' / 'demo_system.svg').write_text('<svg xmlns="http://www.w3.org/2000/svg"/>')
    states = {'talker': 'active', 'listener': 'active'}
    watch = Watched()
    asked = []
    served = Page('127.0.0.1', 0, str(tmp_path), 'demo_system')
    view = View(Source(DESCRIPTION, lambda: dict(states), dict, lambda: watch, lambda: True))
    served.serve(view, 0.05, {
        'bring_down': lambda arguments: asked.append(arguments) or (True, 'brought down')})
    served.states, served.watch, served.asked = states, watch, asked
    yield served
    served.close()


def _request(page, method, path, headers=None, body=None):
    host, port = page.server.server_address[:2]
    connection = http.client.HTTPConnection(host, port, timeout=5)
    connection.request(method, path, body=body, headers=headers or {})
    response = connection.getresponse()
    return response.status, response.read()


def test_a_change_needs_the_token(page, capsys):
    status, body = _request(page, 'POST', '/action/bring_down', body=b'{}')
    assert status == 403
    assert page.asked == []
    status, body = _request(page, 'POST', '/action/bring_down',
                            {'X-Robmosys-Token': 'not-it'}, b'{}')
    assert status == 403
    status, body = _request(page, 'POST', '/action/bring_down',
                            {'X-Robmosys-Token': page.token}, b'{"why": "test"}')
    assert status == 200
    assert json.loads(body) == {'success': True, 'message': 'brought down'}
    assert page.asked == [{'why': 'test'}]
    out = capsys.readouterr()
    assert out.out.count('the page refused 127.0.0.1: POST /action/bring_down: 403') == 2


def test_a_request_naming_another_host_is_refused(page, capsys):
    # a site of the browser's that names its own host at this address (DNS rebinding)
    assert _request(page, 'GET', '/state', {'Host': 'evil.example:80'})[0] == 403
    assert _request(page, 'GET', '/state', {'Host': 'localhost:1'})[0] == 200
    assert 'refused 127.0.0.1: GET /state: 403' in capsys.readouterr().out


def test_what_is_not_understood_is_4xx_and_one_line(page, capsys):
    for method, path, headers, body, status in (
            ('GET', '/nothing', {}, None, 404),
            ('POST', '/action/nothing', {'X-Robmosys-Token': page.token}, b'{}', 404),
            ('POST', '/action/bring_down', {'X-Robmosys-Token': page.token}, b'[1', 400),
            ('POST', '/elsewhere', {}, b'', 404),
            ('PUT', '/', {}, b'', 405)):
        assert _request(page, method, path, headers, body)[0] == status, (method, path)
    out = capsys.readouterr()
    lines = [x for x in out.out.splitlines() if 'the page of the system' not in x]
    assert len(lines) == 5, out.out
    assert all(' refused 127.0.0.1: ' in x for x in lines), out.out
    assert 'Traceback' not in out.out + out.err
    assert page.asked == []


def test_the_page_its_diagram_and_the_state_are_served(page):
    assert b'page.js' in _request(page, 'GET', '/')[1]
    assert b'EventSource' in _request(page, 'GET', '/page.js')[1]
    assert _request(page, 'GET', '/diagram.svg')[1].startswith(b'<svg')
    time.sleep(0.2)
    state = json.loads(_request(page, 'GET', '/state')[1])['entries']
    assert state['i:talker']['parameters'] == [['rate', 2.0, 5.0, 'm.yaml:4:9']]
    assert state['c:0']['status'] == 'conforms'
    assert state['system'] == {'package': 'demo_system', 'up': True, 'mode': None,
                               'modes': [], 'watch': 'ready'}


def test_the_events_send_everything_then_only_what_changed(page):
    host, port = page.server.server_address[:2]
    connection = http.client.HTTPConnection(host, port, timeout=5)
    connection.request('GET', '/events')
    stream = connection.getresponse()
    assert stream.getheader('Content-Type') == 'text/event-stream'
    events = []

    def read():
        lines = []
        for raw in stream:
            line = raw.decode().rstrip('\n')
            if line:
                lines.append(line)
            elif any(x.startswith('data: ') for x in lines):
                events.append({k: v for k, _, v in (x.partition(': ') for x in lines)})
                lines = []
    threading.Thread(target=read, daemon=True).start()
    deadline = time.monotonic() + 5
    while not events and time.monotonic() < deadline:
        time.sleep(0.02)
    assert events[0]['event'] == 'state'
    page.watch.differences = [Difference('foreign', 'm.yaml:9:9', 'connection 0', 'foreign')]
    page.states['listener'] = 'inactive'
    changed = {}
    while set(changed) != {'c:0', 'i:listener'} and time.monotonic() < deadline:
        time.sleep(0.02)
        changed = {k: v for e in events[1:] for k, v in json.loads(e['data'])['entries'].items()}
    # what did not change is not sent again
    assert set(changed) <= {'c:0', 'i:listener'}
    assert changed['c:0']['status'] == 'differs'
    assert changed['c:0']['differences'] == ['m.yaml:9:9: error: foreign']
    assert changed['i:listener']['state'] == 'inactive'
    connection.close()


def test_a_port_in_use_is_refused_before_anything_starts(page):
    host, port = page.server.server_address[:2]
    with pytest.raises(OSError):
        Page(host, port, '/nowhere', 'demo_system')
