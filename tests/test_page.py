# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The system manager's page in a real browser: the model drawn, coloured by what runs.

``dummy_robot_bringup`` runs under its manager with ``--web 0``; the
distribution's Chromium (``/usr/bin/chromium``, driven by Selenium through
``chromium-driver``, headless) opens the address the manager prints. Every
instance and connection of the model is drawn; a foreign type published on a
connection's topic turns that connection's colour within 2 s of the manager
seeing it, and back after the repair; a click shows an instance's parameter
values; a change without the token is refused; instances brought down turn;
the page is live again once a manager is back on its port.
With ``ROBMOSYS_SCREENSHOT=<file>`` the test saves what the browser shows
(docs/page.png is made so).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
import re
import shutil
import socket
import subprocess
import sys
import time
from typing import Iterator
import urllib.error
import urllib.request

import pytest

from colcon_robmosys.devtools.ros_env import background, free_domain_id
from colcon_robmosys.devtools.system import wait_until
from conftest import requires_ros

CHROMIUM = Path('/usr/bin/chromium')
DRIVER = shutil.which('chromedriver') or '/usr/bin/chromedriver'


def _browser_missing() -> str | None:
    if not CHROMIUM.is_file() or not Path(DRIVER).is_file():
        return ('no /usr/bin/chromium with its driver (apt-get install chromium '
                'chromium-driver; .ci/run does)')
    try:
        import selenium  # noqa: F401
    except ImportError:
        return 'selenium is not installed (requirements/ros.txt)'
    return None


pytestmark = [pytest.mark.integration, requires_ros]
needs_browser = pytest.mark.skipif(_browser_missing() is not None,
                                   reason=_browser_missing() or '')

SYSTEM = 'dummy_robot_bringup'
#: how soon the page shows what the manager knows (the issue's bound)
SHOWN_WITHIN = 2.0
#: red and green of page.css, as the browser computes them
RED, GREEN = 'rgb(176, 0, 32)', 'rgb(46, 125, 50)'


@pytest.fixture(scope='module')
def browser() -> Iterator[object]:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    options = webdriver.ChromeOptions()
    options.binary_location = str(CHROMIUM)
    for argument in ('--headless=new', '--no-sandbox', '--disable-gpu',
                     '--disable-dev-shm-usage', '--window-size=1500,1000'):
        options.add_argument(argument)
    # the distribution's driver: Selenium Manager downloads nothing
    os.environ['SE_OFFLINE'] = 'true'
    driver = webdriver.Chrome(service=Service(DRIVER), options=options)
    driver.set_script_timeout(10)
    try:
        yield driver
    finally:
        driver.quit()


def _page_url(output: str) -> str | None:
    found = re.search(r'^bringup: the page of the system: (http://\S+)$', output, re.MULTILINE)
    return found.group(1) if found else None


def _colour(browser, selector: str) -> str:
    return browser.execute_script(
        'const e = document.querySelector(arguments[0]);'
        'return e ? getComputedStyle(e).stroke : null;', selector)


def _status(browser, index: int) -> str | None:
    return browser.execute_script(
        'const g = document.querySelector(`g.connection[data-connection="${arguments[0]}"]`);'
        'return g ? g.dataset.status || null : null;', index)


@needs_browser
def test_the_page_draws_the_model_and_colours_it_with_what_runs(
        test_workspace_built, browser, tmp_path):
    built = test_workspace_built
    env = built.env(free_domain_id())
    description = json.loads((built.share(SYSTEM) / 'bringup.json').read_text())
    instances = [i['instance'] for i in description['instances']]
    executable = built.install / SYSTEM / 'lib' / SYSTEM / 'bringup'
    with background([sys.executable, str(executable), '--check-period', '0.5', '--web', '0'],
                    env=env, cwd=built.root, stop_timeout=30) as manager:
        assert wait_until(lambda: re.search(r'bringup: (\d+) of \1 managed instances active',
                                            manager.output()) is not None,
                          timeout=120), manager.output()
        # said once the manager's node is made: after the report where shared processes
        # told the instances up by themselves
        assert wait_until(lambda: _page_url(manager.output()) is not None, timeout=30), \
            manager.output()
        url = _page_url(manager.output())
        assert url is not None and url.startswith('http://127.0.0.1:'), manager.output()
        base, token = url.split('/?token=')
        browser.get(url)
        # every instance and connection of the model, drawn
        assert wait_until(lambda: browser.execute_script(
            'return document.body.dataset.version !== undefined'), timeout=20)
        drawn = browser.execute_script(
            'return [...document.querySelectorAll("g.instance")].map(g => g.dataset.instance)')
        assert drawn == instances
        lines = browser.execute_script(
            'return [...document.querySelectorAll("g.connection")]'
            '.map(g => Number(g.dataset.connection))')
        assert lines == list(range(len(description['connections'])))
        # once the watch compared the whole system, every connection conforms
        assert wait_until(lambda: all(_status(browser, i) == 'conforms' for i in lines),
                          timeout=60), manager.output()[-4000:]
        joint_states = next(i for i, c in enumerate(description['connections'])
                            if c['name'] == '/dummy_robot/joint_states')
        path = f'g.connection[data-connection="{joint_states}"] path'
        assert _colour(browser, path) == GREEN
        assert all(browser.execute_script(
            'return document.querySelector(`g.instance[data-instance="${arguments[0]}"]`)'
            '.dataset.state', name) in ('active', 'running') for name in instances)

        # a foreign type on the connection's topic: red within 2 s of the manager's line
        from test_watch import PUBLISH_STRING
        # another type than the model's on joint_states, until SIGINT
        foreign = PUBLISH_STRING.format(node='intruder', topic='/dummy_robot/joint_states')
        with background([sys.executable, '-c', foreign], env=env, stop_timeout=10) as helper:
            assert wait_until(lambda: 'ready' in helper.output(), timeout=60), helper.output()
            assert wait_until(lambda: ': difference: ' in manager.output() and
                              'node /intruder' in manager.output(), timeout=30, period=0.02), \
                manager.output()[-4000:]
            seen = time.monotonic()
            assert wait_until(lambda: _colour(browser, path) == RED, timeout=SHOWN_WITHIN,
                              period=0.02), _colour(browser, path)
            took = time.monotonic() - seen
            browser.find_element(
                'css selector', f'g.connection[data-connection="{joint_states}"] text').click()
            assert wait_until(lambda: 'node /intruder has a publisher of type '
                              'std_msgs/msg/String' in browser.find_element(
                                  'id', 'details').text, timeout=SHOWN_WITHIN)
            screenshot = os.environ.get('ROBMOSYS_SCREENSHOT')
            if screenshot:
                browser.save_screenshot(str(Path(screenshot).resolve()))
            cleared_from = len(manager.output())
        assert wait_until(lambda: ': cleared: ' in manager.output()[cleared_from:],
                          timeout=30, period=0.02), manager.output()[-4000:]
        seen = time.monotonic()
        assert wait_until(lambda: _colour(browser, path) == GREEN, timeout=SHOWN_WITHIN,
                          period=0.02), _colour(browser, path)
        print(f'the page turned red {took:.2f} s after the manager saw the drift, '
              f'green {time.monotonic() - seen:.2f} s after it cleared')

        # a click on an instance: its parameters, the model's value beside the running one
        browser.find_element('css selector', 'g.instance[data-instance="map_server"]').click()
        rows = {}

        def read_rows() -> bool:
            rows.update({r.get_attribute('data-parameter'): r.text for r in
                         browser.find_elements('css selector', '#details tr[data-parameter]')})
            return rows.get('width') == 'width 40 40'
        assert wait_until(read_rows, timeout=10), rows
        assert rows['frame_id'] == 'frame_id "world" "world"'

        # a change without the token is refused, and changes nothing
        for headers in ({}, {'X-Robmosys-Token': token + 'x'}):
            request = urllib.request.Request(f'{base}/action/bring_down', data=b'{}',
                                             headers=headers, method='POST')
            with pytest.raises(urllib.error.HTTPError) as refused:
                urllib.request.urlopen(request, timeout=10)
            assert refused.value.code == 403
        assert 'refused 127.0.0.1: POST /action/bring_down: 403' in manager.output()
        assert 'Traceback' not in manager.output()
        time.sleep(1.0)
        assert browser.execute_script(
            'return document.querySelector(`g.instance[data-instance="joints"]`)'
            '.dataset.state') == 'active'

        # the page's button, with the token of its address: the instances turn
        browser.find_element('id', 'bring_down').click()
        managed = [i['instance'] for i in description['instances'] if i['managed']]

        def all_down() -> bool:
            return all(browser.execute_script(
                'const g = document.querySelector(`g.instance[data-instance="${arguments[0]}"]`);'
                'return g.classList.contains("state-inactive")', name) for name in managed)
        assert wait_until(all_down, timeout=30), manager.output()[-4000:]
        assert 'the page: bring_down asked by 127.0.0.1' in manager.output()

    # the manager ends: the page says so, and is live again once it is back on its port
    assert wait_until(lambda: browser.find_element('id', 'live').text == 'reconnecting',
                      timeout=10)
    port = base.rsplit(':', 1)[1]
    with background([sys.executable, str(executable), '--web', port], env=env, cwd=built.root,
                    stop_timeout=30) as manager:
        assert wait_until(lambda: browser.find_element('id', 'live').text == 'live' and
                          browser.execute_script(
                              'return document.querySelector(`g.instance[data-instance='
                              '"joints"]`).dataset.state') == 'active',
                          timeout=120), manager.output()[-4000:]


def test_a_port_in_use_is_one_line_and_nothing_starts(test_workspace_built):
    built = test_workspace_built
    executable = built.install / SYSTEM / 'lib' / SYSTEM / 'bringup'
    with socket.socket() as taken:
        taken.bind(('127.0.0.1', 0))
        taken.listen()
        port = taken.getsockname()[1]
        result = subprocess.run([sys.executable, str(executable), '--web', str(port)],
                                env=built.env(free_domain_id()), capture_output=True,
                                text=True, timeout=60, cwd=built.root)
    assert (result.returncode, result.stdout, result.stderr) == (
        2, '', f'bringup: error: --web {port}: 127.0.0.1: Address already in use; '
        'nothing was started\n')
