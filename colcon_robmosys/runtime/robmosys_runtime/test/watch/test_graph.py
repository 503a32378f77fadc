# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""When the graph reader reads through a participant made anew: only for a lasting loss."""

from rclpy.node import Node
from robmosys_runtime.watch import graph as graph_module
from robmosys_runtime.watch.conformance import Endpoint, Graph, Model
from robmosys_runtime.watch.graph import GraphReader, RENEW_AFTER, UNKNOWN_NODE

UNNAMED = Endpoint(UNKNOWN_NODE, 'writer', 'rcl_interfaces/msg/ParameterEvent', None, (1, 2))


class _Clock:
    now = 1000.0

    def __call__(self):
        return self.now


def _reader(spinning, monkeypatch, ends):
    clock = _Clock()
    monkeypatch.setattr(graph_module.time, 'monotonic', clock)
    node = spinning.add(Node('watching', context=spinning.context))
    reader = GraphReader(node, Model({'package': 'site', 'instances': [], 'connections': []}))
    monkeypatch.setattr(reader, '_topic_ends', lambda *args: list(ends))
    return reader, clock


def test_an_end_named_within_a_moment_makes_no_participant(spinning, monkeypatch):
    # a tool just started beside the manager: its names follow its ends
    ends = [UNNAMED]
    reader, clock = _reader(spinning, monkeypatch, ends)
    for _ in range(3):
        assert not reader._named(Graph())  # noqa: SLF001 - the decision under test
        clock.now += 1.0
    ends.clear()
    assert reader._named(Graph())  # noqa: SLF001
    assert reader._own is None  # noqa: SLF001


def test_an_end_unnamed_for_longer_is_read_through_a_participant_made_anew(spinning, monkeypatch):
    reader, clock = _reader(spinning, monkeypatch, [UNNAMED])
    assert not reader._named(Graph())  # noqa: SLF001
    clock.now += RENEW_AFTER
    assert not reader._named(Graph())  # noqa: SLF001
    assert reader._own is not None  # noqa: SLF001
    reader.close()
