# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A component's publishers keep the time of their last send where bringup asks."""

import time

from conftest import wait_until
from rclpy.lifecycle import LifecycleNode
from robmosys_runtime.node import ComponentNode
from robmosys_runtime.sends import count_sends, SENDS, Sends, topic_key
from std_msgs.msg import Int32


def test_the_key_of_a_topic_is_fnv_1a_as_the_cpp_side_computes_it():
    assert topic_key('') == 'cbf29ce484222325'
    assert topic_key('a') == 'af63dc4c8601ec8c'
    assert topic_key('/robot1/publisher/pMap') != topic_key('/robot2/publisher/pMap')


class _Ticker(ComponentNode):

    def __init__(self, name, **kwargs):
        super().__init__(name, ports=['pTick'], **kwargs)

    def create_ports(self):
        self.add_publisher('pTick', Int32, 10)


def test_a_port_keeps_its_last_send_only_while_active(spinning, tmp_path, monkeypatch):
    monkeypatch.setenv(SENDS, str(tmp_path))
    node = spinning.add(_Ticker('ticker', context=spinning.context))
    node.trigger_configure()
    sends = Sends(tmp_path)
    assert sends.latest(['/pTick', '/other']) == {'/pTick': None}
    node.pTick.publish(Int32(data=1))  # inactive: dropped, not counted
    assert sends.latest(['/pTick']) == {'/pTick': None}
    node.trigger_activate()
    before = time.monotonic()
    node.pTick.publish(Int32(data=2))
    last = sends.latest(['/pTick'])['/pTick']
    assert last is not None and before <= last <= time.monotonic()
    # a second node of the same topic: the latest of both
    other = spinning.add(_Ticker('ticker2', context=spinning.context))
    other.trigger_configure()
    other.trigger_activate()
    assert wait_until(lambda: len(list(tmp_path.iterdir())) == 2)
    other.pTick.publish(Int32(data=3))
    assert sends.latest(['/pTick'])['/pTick'] > last
    sends.close()


def test_without_the_variable_nothing_is_kept(spinning, tmp_path, monkeypatch):
    monkeypatch.delenv(SENDS, raising=False)
    node = spinning.add(LifecycleNode('plain', context=spinning.context))
    publisher = node.create_lifecycle_publisher(Int32, 'plain', 10)
    count_sends(publisher)
    assert 'publish' not in vars(publisher)
    assert not list(tmp_path.iterdir())
