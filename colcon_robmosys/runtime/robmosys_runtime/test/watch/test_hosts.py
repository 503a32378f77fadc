# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Which watched names a host reads from its instances' own counts, and which it listens to."""

from robmosys_runtime.watch.conformance import Model
from robmosys_runtime.watch.hosts import counted_names, names_of, watched_names


def _instance(name, host, ports, **kind):
    return {'instance': name, 'fqn': f'/{name}', 'host': host, 'managed': True, 'after': [],
            'parameters': {}, 'ports': ports, **kind}


def _port(name, entity='publisher', period=0.1):
    return {'name': name, 'entity': entity, 'type': 'std_msgs/msg/Int32', 'period': period,
            'quiet': False, 'port': name.rsplit('/', 1)[-1]}


MODEL = Model({'package': 'site', 'connections': [], 'instances': [
    _instance('camera', 'robot', [_port('/frames')], python_class='c.C:C'),
    _instance('lidar', 'robot', [_port('/scan')], plugin='l::L'),
    _instance('driver', 'robot', [_port('/odom')], executable='driver'),
    # a second publisher of /scan, without a period, external
    _instance('replay', 'robot', [_port('/scan', period=None)], executable='replay'),
    _instance('viewer', '', [_port('/frames', 'subscription', None)], python_class='v.V:V'),
]})


def test_a_name_is_counted_when_every_publisher_is_a_generated_instance_started_here():
    names = names_of(watched_names(MODEL), 'robot')
    assert sorted(names) == ['/frames', '/odom', '/scan']
    everything = {'camera', 'lidar', 'driver', 'replay'}
    # an external component's name (driver, replay) is listened to
    assert counted_names(MODEL, names, everything) == {'/frames'}
    # an instance this bringup did not start (the launch file did) keeps no count for it
    assert counted_names(MODEL, names, {'lidar', 'driver'}) == set()
