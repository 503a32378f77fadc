# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The loopback ROS 2 environment of the tests really carries messages."""

from __future__ import annotations

import contextlib
import ipaddress
import os
from pathlib import Path
import socket
import subprocess
import sys
import time

import pytest

from colcon_robmosys.devtools import ros_env
from colcon_robmosys.devtools.system import wait_until

PUBLISHER = """
import rclpy
from rclpy.executors import ExternalShutdownException
from std_msgs.msg import String
rclpy.init()
node = rclpy.create_node('loopback_talker')
pub = node.create_publisher(String, 'chatter', 10)
count = 0
def tick():
    global count
    count += 1
    pub.publish(String(data=f'hello {count}'))
node.create_timer(0.1, tick)
try:
    rclpy.spin(node)
except (KeyboardInterrupt, ExternalShutdownException):
    pass
"""

# Exits 0 after three messages; its own deadline keeps it from outliving the test.
SUBSCRIBER = """
import sys, time
import rclpy
from std_msgs.msg import String
rclpy.init()
node = rclpy.create_node('loopback_listener')
received = []
def on_message(msg):
    received.append(msg.data)
    print('received', msg.data, flush=True)
node.create_subscription(String, 'chatter', on_message, 10)
deadline = time.monotonic() + float(sys.argv[1])
while len(received) < 3 and time.monotonic() < deadline:
    rclpy.spin_once(node, timeout_sec=0.1)
sys.exit(0 if received else 1)
"""


def test_loopback_env_sets_the_variables(tmp_path: Path) -> None:
    base = {'PATH': '/usr/bin', 'ROS_LOCALHOST_ONLY': '1', 'AMENT_PREFIX_PATH': '/opt/other'}
    env = ros_env.loopback_env(42, base=base, underlays=[tmp_path])

    prefix = str(ros_env.ros_prefix())
    assert env['ROS_DOMAIN_ID'] == '42'
    assert env['RMW_IMPLEMENTATION'] == 'rmw_fastrtps_cpp'
    assert env['ROS_AUTOMATIC_DISCOVERY_RANGE'] == 'SYSTEM_DEFAULT'
    assert Path(env['FASTDDS_DEFAULT_PROFILES_FILE']).is_file()
    assert 'ROS_LOCALHOST_ONLY' not in env
    assert env['AMENT_PREFIX_PATH'].split(os.pathsep) == [str(tmp_path), prefix, '/opt/other']
    assert env['CMAKE_PREFIX_PATH'].split(os.pathsep) == [str(tmp_path), prefix]
    path = env['PATH'].split(os.pathsep)
    assert path[0] == os.path.join(prefix, 'bin') and path[-1] == '/usr/bin'
    assert env['PYTHONUNBUFFERED'] == '1'
    assert env['RCUTILS_COLORIZED_OUTPUT'] == '0'
    assert base['ROS_LOCALHOST_ONLY'] == '1', 'the base mapping must not change'


def test_free_domain_ids_are_distinct_and_in_range() -> None:
    ids = [ros_env.free_domain_id() for _ in range(5)]
    assert len(set(ids)) == 5
    assert all(1 <= i <= 101 for i in ids)


def test_a_free_domain_id_is_never_one_ros_2_test_isolation_takes() -> None:
    # `colcon test` of a generated smoke test runs it under ament_cmake_ros's
    # isolation, which sets a ROS_DOMAIN_ID of its own choosing: it must not be
    # the domain of a system another test runs (CI: two managers, one domain)
    ros_env.free_domain_id()
    held = set(ros_env._domain_locks)
    for domain_id in held:
        for address in ('127.0.0.1', ''):
            with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as taking:
                with pytest.raises(OSError):
                    taking.bind((address, 32768 + domain_id))
    isolated = Path(sys.prefix) / 'lib' / 'rmw_test_fixture_implementation' / 'run_rmw_isolated'
    if not isolated.is_file():
        pytest.skip(f'no {isolated.name} here (Kilted has it): the ports are checked above')
    chosen = set()
    for _ in range(20):
        result = ros_env.run([str(isolated), 'sh', '-c', 'echo "$ROS_DOMAIN_ID"'],
                             env=ros_env.loopback_env(0), timeout=60)
        assert result.returncode == 0, result.stdout + result.stderr
        chosen.add(int(result.stdout.split()[-1]))
    assert not chosen & held, (chosen, held)


def test_workspace_env_sources_local_setup(tmp_path: Path) -> None:
    (tmp_path / 'local_setup.sh').write_text(
        'export ROBMOSYS_TEST_PREFIX="$COLCON_CURRENT_PREFIX"\n')
    env = ros_env.workspace_env(tmp_path, {'PATH': os.environ['PATH'], 'KEEP': 'a b\nc'})
    assert env['ROBMOSYS_TEST_PREFIX'] == str(tmp_path.resolve())
    assert env['KEEP'] == 'a b\nc'
    assert 'COLCON_CURRENT_PREFIX' not in env


def test_run_kills_a_command_at_its_timeout() -> None:
    started = time.monotonic()
    with pytest.raises(subprocess.TimeoutExpired):
        ros_env.run(['sh', '-c', 'sleep 30 & sleep 30'], env=os.environ, timeout=0.5)
    assert time.monotonic() - started < 10


_DEAF = """
import signal, time
signal.signal(signal.SIGINT, signal.SIG_IGN)
print('ready', flush=True)

def stuck_in_shutdown():
    time.sleep(60)

stuck_in_shutdown()
"""


def test_a_python_process_deaf_to_sigint_is_killed_and_says_where_it_hung(capfd) -> None:
    started = time.monotonic()
    with ros_env.background([sys.executable, '-c', _DEAF], env=os.environ,
                            stop_timeout=0.5) as deaf:
        assert wait_until(lambda: 'ready' in deaf.output(), timeout=20)
    assert deaf.proc.returncode is not None
    assert time.monotonic() - started < 20
    said = capfd.readouterr().err
    assert 'did not end within 0.5 s of SIGINT; killed' in said, said
    assert 'in stuck_in_shutdown' in said, said


def test_publisher_reaches_subscriber_on_loopback() -> None:
    pytest.importorskip('rclpy', reason='ROS 2 (rclpy) is not installed in this interpreter')
    env = ros_env.loopback_env(ros_env.free_domain_id())

    with ros_env.background([sys.executable, '-c', PUBLISHER], env=env) as talker:
        listener = ros_env.run([sys.executable, '-c', SUBSCRIBER, '20'], env=env, timeout=60)
        talker_output = talker.output()
        addresses = _udp_addresses(talker.proc.pid)
        shared = _shared_memory(talker.proc.pid)

    output = listener.stdout + listener.stderr + talker_output
    assert listener.returncode == 0, output
    assert 'received hello' in listener.stdout
    # Fast DDS reports a profile it cannot parse but carries on with defaults.
    assert 'XMLPARSER' not in output and 'XMLPROFILES' not in output, output
    # DDS of the tests stays on loopback: every socket the talker bound is on
    # 127.0.0.1 (or a multicast group, joined on 127.0.0.1 alone), and no shared
    # memory segment of Fast DDS is mapped, which a process killed could leave behind
    # for a later one to crash on (rmw_fastrtps adds both at LOCALHOST, see ros_env)
    assert addresses and all(a == '127.0.0.1' or _multicast(a) for a in addresses), addresses
    assert not shared, shared


# Prints how many nodes it saw (all of them, or at its deadline), then stays in the
# graph until its stdin closes, so that the others can see it as long as they look.
_PEER = """
import sys, time, rclpy
rclpy.init()
node = rclpy.create_node(f'peer_{sys.argv[1]}')
deadline = time.monotonic() + float(sys.argv[3])
while len(node.get_node_names()) < int(sys.argv[2]) and time.monotonic() < deadline:
    rclpy.spin_once(node, timeout_sec=0.1)
print(len(node.get_node_names()), flush=True)
sys.stdin.read()
"""


def test_every_process_of_a_domain_sees_every_other() -> None:
    # Fast DDS sends its first announcements to the initial peer's ports of
    # participants 0 to 3 only, unless told more (the profile): the fifth process
    # of a system and those after it then never saw each other
    pytest.importorskip('rclpy', reason='ROS 2 (rclpy) is not installed in this interpreter')
    env = ros_env.loopback_env(ros_env.free_domain_id())
    count = 8
    peers = [subprocess.Popen([sys.executable, '-c', _PEER, str(i), str(count), '30'], env=env,
                              stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
             for i in range(count)]
    try:
        seen = [int(peer.stdout.readline() or 0) for peer in peers]
    finally:
        for peer in peers:
            peer.stdin.close()
        for peer in peers:
            try:
                peer.wait(timeout=10)
            except subprocess.TimeoutExpired:
                peer.kill()
                peer.wait()
    assert seen == [count] * count, seen


def _udp_addresses(pid: int) -> set[str]:
    """Return the local IPv4 and IPv6 addresses of process pid's UDP sockets."""
    inodes = set()
    for fd in Path(f'/proc/{pid}/fd').iterdir():
        with contextlib.suppress(OSError):
            target = os.readlink(fd)
            if target.startswith('socket:['):
                inodes.add(target[len('socket:['):-1])
    addresses = set()
    for table, family in (('udp', socket.AF_INET), ('udp6', socket.AF_INET6)):
        lines = Path(f'/proc/{pid}/net/{table}').read_text().splitlines()[1:]
        for fields in (line.split() for line in lines):
            if fields[9] in inodes:
                # the address is hex of its bytes in host (little-endian) order, per 32 bits
                packed = bytes.fromhex(fields[1].split(':')[0])
                raw = b''.join(packed[i:i + 4][::-1] for i in range(0, len(packed), 4))
                addresses.add(socket.inet_ntop(family, raw))
    return addresses


def _multicast(address: str) -> bool:
    """Return whether address is an IPv4 multicast group."""
    group = ipaddress.ip_address(address)
    return group.version == 4 and group.is_multicast


def _shared_memory(pid: int) -> set[str]:
    """Return the Fast DDS segments in /dev/shm that process pid maps."""
    maps = Path(f'/proc/{pid}/maps').read_text().splitlines()
    return {line.split()[-1] for line in maps if '/dev/shm/fastdds' in line}
