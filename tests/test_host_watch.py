# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The watch on a real site: a camera on a robot, the manager on a base station.

A robot (a network namespace of colcon_robmosys/devtools/netns.py) streams 100 kB frames
at 20 Hz, 2 MB/s, to a viewer on the same robot; the system manager runs on
``base``. The conformance watch listens to the stream on the robot, where the
robot's ``bringup --host`` runs, and tells the manager only how long ago it
carried a frame: the base station's link carries no frame for the watch
(docs/runtime.md, "The conformance watch"). A drift on the robot is reported
by the manager at the model's line all the same.
"""

from __future__ import annotations

import contextlib
import json
import re
import signal
import sys
import time
from typing import Iterator

import pytest
import yaml

from colcon_robmosys.devtools import netns
from colcon_robmosys.devtools.ros_env import Background, free_domain_id
from colcon_robmosys.devtools.system import wait_until
from conftest import (
    assert_no_traceback, build_workspace, BuiltWorkspace, hosts_of, requires_ros)

pytestmark = [pytest.mark.integration, requires_ros]

METADATA = {'license': 'Apache-2.0', 'maintainers': [{'name': 'A', 'email': 'a@example.com'}]}
#: a frame: 100 kB, 20 a second
FRAME = 100_000
PERIOD = 0.05
CAMERA = {
    'name': 'Camera', 'package': 'site_camera', 'language': 'python',
    'ports': {'pFrame': {'pattern': 'push', 'role': 'provided',
                         'type': 'sensor_msgs/msg/Image', 'qos': {'depth': 1}}},
    'activities': {'Grab': {'period': PERIOD, 'functions': ['fGrab']}},
    'functions': {
        'fInit': {'code': (f'self.frame = Image(height=100, width={FRAME // 100}, '
                           f"encoding='mono8', step={FRAME // 100}, data=bytes({FRAME}))\n")},
        'fGrab': {'code': 'if self.params.streaming:\n    self.pFrame.publish(self.frame)\n'}},
    'lifecycle': {'on_configure': ['fInit']},
    'parameters': {'streaming': {'type': 'bool', 'default': True,
                                 'description': 'Whether frames are sent.'}}}
VIEWER = {
    'name': 'Viewer', 'package': 'site_viewer', 'language': 'python',
    'ports': {'rFrame': {'pattern': 'push', 'role': 'required',
                         'type': 'sensor_msgs/msg/Image', 'qos': {'depth': 1}}},
    'activities': {'Show': {'trigger': 'rFrame', 'functions': ['fShow']}},
    'functions': {'fShow': {'code': (
        "self.shown = getattr(self, 'shown', 0) + 1\n"
        'if self.shown % 40 == 0:\n'
        '    self.get_logger().info(\n'
        "        f'shown {self.shown} frames of {len(commobj.data)} bytes')\n")}}}
SYSTEM = {
    'name': 'Site', 'package': 'site_system',
    'instances': {'camera': {'component': 'site_camera', 'host': 'robot'},
                  'viewer': {'component': 'site_viewer', 'host': 'robot',
                             'after': ['camera']}},
    'connections': [{'from': 'camera.pFrame', 'to': 'viewer.rFrame', 'topic': 'frames'}]}
#: the conformance watch's check period (bringup's default)
CHECK_PERIOD = 1.0
#: what DDS discovery adds to a report between hosts, at most (docs/runtime.md)
DISCOVERY = 3.5
#: what the watch may add to the base station's link, at most (issue 41)
WATCH_BUDGET = 10 * 1024

#: sets a parameter of a node: node, name, value as JSON
SET_PARAMETER = """
import json, sys, rclpy
from rcl_interfaces.srv import SetParameters
from rclpy.parameter import Parameter
rclpy.init()
node = rclpy.create_node('site_operator')
client = node.create_client(SetParameters, sys.argv[1] + '/set_parameters')
assert client.wait_for_service(timeout_sec=20)
request = SetParameters.Request(parameters=[
    Parameter(sys.argv[2], value=json.loads(sys.argv[3])).to_parameter_msg()])
future = client.call_async(request)
rclpy.spin_until_future_complete(node, future, timeout_sec=20)
print(json.dumps(future.result().results[0].successful), flush=True)
"""
#: publishes another type than the model's on a topic until stopped
FOREIGN = """
import sys, rclpy
from std_msgs.msg import String
rclpy.init()
node = rclpy.create_node('intruder')
publisher = node.create_publisher(String, sys.argv[1], 1)
node.create_timer(0.2, lambda: publisher.publish(String(data='not a frame')))
print('publishing', flush=True)
rclpy.spin(node)
"""


@pytest.fixture(scope='module')
def built(tmp_path_factory) -> BuiltWorkspace:
    """Build the camera, the viewer and the system, once."""
    src = tmp_path_factory.mktemp('site') / 'src'
    for folder, key, model in (('site_camera', 'components', CAMERA),
                               ('site_viewer', 'components', VIEWER),
                               ('site_system', 'systems', SYSTEM)):
        path = src / folder / 'robmosys.yaml'
        path.parent.mkdir(parents=True)
        path.write_text(yaml.safe_dump({'robmosys': 1, 'defaults': METADATA, key: [model]},
                                       sort_keys=False))
    return build_workspace(src, tmp_path_factory.mktemp('site_ws'))


@pytest.fixture(scope='module')
def network(tmp_path_factory) -> Iterator[netns.Network]:
    """Return the base station and the robot, made once for the module."""
    yield from hosts_of(('base', 'robot'), tmp_path_factory)


class Site:
    """The robot's bringup and the manager on base, for a with block."""

    def __init__(self, network: netns.Network, built: BuiltWorkspace,
                 stack: contextlib.ExitStack) -> None:
        self.network = network
        self.built = built
        self._stack = stack
        base = built.env(free_domain_id())
        self.env = {h: network.env(h, base) for h in network.hosts}
        bringup = built.install / 'site_system' / 'lib' / 'site_system' / 'bringup'
        self.bringup = [sys.executable, str(bringup)]
        self.robot = stack.enter_context(network.background(
            'robot', [*self.bringup, '--host', 'robot'], self.env['robot']))
        self.manager: Background | None = None
        self.description = json.loads((built.share('site_system') / 'bringup.json').read_text())

    def start_manager(self, *args: str) -> Background:
        """Start the manager on base; return it once every instance is active."""
        manager = self.manager = self._stack.enter_context(self.network.background(
            'base', [*self.bringup, *args], self.env['base']))
        assert wait_until(lambda: 'bringup: 2 of 2 managed instances active' in
                          manager.output(), 120), self.output()
        return manager

    def stop_manager(self) -> None:
        """Stop the manager with Ctrl-C (its instances are the robot's: they run on)."""
        assert self.manager is not None
        self.manager.proc.send_signal(signal.SIGINT)
        assert self.manager.proc.wait(timeout=60) == 0, self.output()

    def received(self, host: str) -> int:
        """Return the bytes a host's link has received so far."""
        result = self.network.run(host, ['cat', '/sys/class/net/eth0/statistics/rx_bytes'],
                                  self.env[host], timeout=30)
        return int(result.stdout)

    def rate(self, host: str, seconds: float) -> float:
        """Return the bytes a second a host's link receives, over some seconds."""
        start, first = time.monotonic(), self.received(host)
        time.sleep(seconds)
        return (self.received(host) - first) / (time.monotonic() - start)

    def on_robot(self, script: str, *args: str) -> str:
        """Run a script on the robot to its end; return what it printed."""
        result = self.network.run('robot', [sys.executable, '-c', script, *args],
                                  self.env['robot'], timeout=60)
        assert result.returncode == 0, result.stdout + result.stderr
        return result.stdout

    def output(self) -> str:
        parts = [('robot', self.robot), ('base', self.manager)]
        return '\n'.join(f'--- {h}:\n{p.output()}' for h, p in parts if p is not None)


@pytest.fixture
def site(network, built) -> Iterator[Site]:
    with contextlib.ExitStack() as stack:
        yield Site(network, built, stack)


def _fqn(site: Site, instance: str) -> str:
    return next(i['fqn'] for i in site.description['instances'] if i['instance'] == instance)


def _location(site: Site, what: str) -> str:
    """Return how a report names the model's place of an instance or of the connection.

    The file is the user's model, or its installed copy (docs/runtime.md): both
    have the same lines.
    """
    if what == 'connection':
        location = site.description['connections'][0]['location']
    else:
        location = next(i['location'] for i in site.description['instances']
                        if i['instance'] == what)
    return 'robmosys.yaml:' + location.split(':', 1)[1] + ':'


def _reported(manager: Background, mark: int, location: str, text: str) -> bool:
    return any(location in line and text in line
               for line in manager.output()[mark:].splitlines() if ': difference: ' in line)


def test_the_watch_adds_nothing_to_the_base_station_link(site):
    # the stream flows on the robot
    site.start_manager('--check-period', '0')
    assert wait_until(lambda: 'shown 40 frames of 100000 bytes' in site.robot.output(), 30), \
        site.output()
    off = site.rate('base', 10.0)
    site.stop_manager()
    manager = site.start_manager()
    conformance = f"/{site.description['package']}_bringup/conformance"
    assert wait_until(lambda: 'the conformance watch' not in _ask(site, conformance), 30), \
        site.output()
    on = site.rate('base', 10.0)
    print(f'base station link: {off / 1024:.1f} KiB/s with the watch off, '
          f'{on / 1024:.1f} KiB/s with it on (the stream: {FRAME / PERIOD / 1024:.0f} KiB/s)')
    assert on - off <= WATCH_BUDGET, (off, on)
    # and the watch sees the stream: no difference
    assert _ask(site, conformance) == '', site.output()
    # the robot's watch reads when the camera last sent, kept by the camera
    # itself: the viewer is the stream's only subscription, on the robot too
    topic = site.description['connections'][0]['name']
    assert json.loads(site.on_robot(SUBSCRIPTIONS, topic).splitlines()[-1]) == \
        [_fqn(site, 'viewer')], site.output()
    assert_no_traceback(manager.output())


#: prints the nodes of a topic's subscriptions, once the graph shows its publisher and a
#: subscription (on Jazzy under load a participant's endpoints can come seconds after it)
SUBSCRIPTIONS = """
import json, sys, time, rclpy
rclpy.init()
node = rclpy.create_node('site_graph')
deadline = time.monotonic() + 30
while not (node.get_publishers_info_by_topic(sys.argv[1])
           and node.get_subscriptions_info_by_topic(sys.argv[1])) \\
        and time.monotonic() < deadline:
    time.sleep(0.1)
time.sleep(3.0)  # the other endpoints of the participants it found
print(json.dumps(sorted(f"{i.node_namespace.rstrip('/')}/{i.node_name}"
                        for i in node.get_subscriptions_info_by_topic(sys.argv[1]))))
"""


def _ask(site: Site, service: str) -> str:
    """Return the message of a Trigger service of the manager, asked from base."""
    script = ('import json, sys; from robmosys_runtime.tools.smoke import Probe, spinning_node\n'
              'from std_srvs.srv import Trigger\n'
              "with spinning_node('site_probe') as node:\n"
              '    a = Probe(node).call(sys.argv[1], Trigger, Trigger.Request(), 20.0)\n'
              '    print(json.dumps(None if a is None else a.message))\n')
    result = site.network.run('base', [sys.executable, '-c', script, service],
                              site.env['base'], timeout=60)
    assert result.returncode == 0, result.stdout + result.stderr
    return json.loads(result.stdout.splitlines()[-1]) or ''


def test_a_drift_on_the_robot_is_reported_by_the_manager_at_the_model_s_line(site):
    manager = site.start_manager()
    topic = site.description['connections'][0]['name']
    connection = _location(site, 'connection')
    # a foreign type on the robot's topic: the graph tells base (discovery)
    mark = len(manager.output())
    with site.network.background('robot', [sys.executable, '-c', FOREIGN, topic],
                                 site.env['robot']) as intruder:
        assert wait_until(lambda: 'publishing' in intruder.output(), 30), intruder.output()
        started = time.monotonic()
        assert wait_until(lambda: _reported(manager, mark, connection, 'std_msgs/msg/String'),
                          3 * CHECK_PERIOD + DISCOVERY + 2.0, 0.05), site.output()
        print(f'a foreign type reported after {time.monotonic() - started:.1f} s')
    assert wait_until(lambda: re.search(r': cleared: .*std_msgs/msg/String',
                                        manager.output()[mark:]), 30), site.output()
    # the camera stops sending: its host's watch tells the manager
    mark = len(manager.output())
    assert site.on_robot(SET_PARAMETER, _fqn(site, 'camera'), 'streaming', 'false') \
        .strip() == 'true'
    stopped = time.monotonic()
    silence = max(5 * PERIOD, 2 * CHECK_PERIOD)
    assert wait_until(lambda: _reported(manager, mark, connection, 'sent nothing'),
                      silence + 3 * CHECK_PERIOD + 2.0, 0.05), site.output()
    print(f'a silent camera reported after {time.monotonic() - stopped:.1f} s')
    assert site.on_robot(SET_PARAMETER, _fqn(site, 'camera'), 'streaming', 'true') \
        .strip() == 'true'
    assert wait_until(lambda: re.search(r': cleared: .*sent nothing',
                                        manager.output()[mark:]), 30), site.output()
    assert_no_traceback(site.output())
