# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
Hosts as Linux network namespaces, for the tests of a system on several hosts.

:class:`Network` makes one namespace per host and one more for the link they
share: a bridge (``br0``) in the link's namespace, and a veth pair per host
(``eth0`` in the host, ``port<n>`` on the bridge). Each host has its address
in 10.213.0.0/24 on ``eth0``, loopback up, and no route but its subnet's:
nothing it sends can leave the namespaces the test made, and since each
network has a bridge of its own, two test runs at once never meet.

DDS in a host: the Fast DDS profile of :meth:`Network.env` has one transport,
UDPv4, on the host's interfaces (``lo`` and ``eth0``: the namespace is what
keeps the traffic in). No shared memory, and no data sharing, which would
carry data between processes of one machine past the link the test cuts;
``ROS_AUTOMATIC_DISCOVERY_RANGE=SUBNET``, so that discovery reaches the other
hosts (by multicast, or the ``ROS_STATIC_PEERS`` the test gives). No
interface whitelist either: Fast DDS takes participants of one machine (one
machine id, whatever their namespace) for local ones, and with a whitelist
that leaves loopback out it discovered none of the other hosts.

Every name starts with :data:`PREFIX` and the pid of the process that made
it: namespaces left behind by a test process that was killed are removed by
the next one (:func:`remove_leftovers`), those of live processes are not.
"""

from __future__ import annotations

import contextlib
import os
from pathlib import Path
import shutil
import signal
import subprocess
import sys
from typing import Any, Iterator, Mapping, Sequence

from colcon_robmosys.devtools import ros_env

#: every namespace of these tests is named <PREFIX><pid>-<n>
PREFIX = 'robmosys-hosts-'

#: the subnet of the hosts (private, and only inside the namespaces)
SUBNET = '10.213.0'

#: seconds after which a host's participant that was not heard from is forgotten by
#: the others (Fast DDS's lease duration; its default is 20 s): a test that cuts a link
#: for longer makes the hosts discover each other again, as a long loss of Wi-Fi does
LEASE = 8

#: a Fast DDS profile for one host: UDPv4 on its interfaces, no shared memory, no data
#: sharing; the lease of LEASE, announced every LEASE / 4 s (Fast DDS: 20 s and 3 s)
_PROFILE = """<?xml version="1.0" encoding="UTF-8"?>
<!-- a host of colcon_robmosys/devtools/netns.py ({address}): UDPv4 only, no shared memory -->
<dds xmlns="http://www.eprosima.com">
  <profiles>
    <transport_descriptors>
      <transport_descriptor>
        <transport_id>host_udp</transport_id>
        <type>UDPv4</type>
      </transport_descriptor>
    </transport_descriptors>
    <participant profile_name="host_participant" is_default_profile="true">
      <rtps>
        <builtin>
          <discovery_config>
            <leaseDuration><sec>{lease}</sec></leaseDuration>
            <leaseAnnouncement><sec>{announcement}</sec></leaseAnnouncement>
          </discovery_config>
        </builtin>
        <userTransports>
          <transport_id>host_udp</transport_id>
        </userTransports>
        <useBuiltinTransports>false</useBuiltinTransports>
      </rtps>
    </participant>
    <data_writer profile_name="host_writer" is_default_profile="true">
      <qos><data_sharing><kind>OFF</kind></data_sharing></qos>
    </data_writer>
    <data_reader profile_name="host_reader" is_default_profile="true">
      <qos><data_sharing><kind>OFF</kind></data_sharing></qos>
    </data_reader>
  </profiles>
</dds>
"""

#: sends to a multicast group from one host, or listens on another (multicast_passes)
_MULTICAST = """
import socket, sys, time
group, port = '239.255.0.213', 7213
mode, address = sys.argv[1], sys.argv[2]
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
if mode == 'listen':
    s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    s.bind(('', port))
    s.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP,
                 socket.inet_aton(group) + socket.inet_aton(address))
    s.settimeout(float(sys.argv[3]))
    print('ready', flush=True)
    try:
        s.recvfrom(64)
        print('received', flush=True)
    except socket.timeout:
        print('nothing', flush=True)
else:
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_IF, socket.inet_aton(address))
    for _ in range(int(float(sys.argv[3]) / 0.1)):
        s.sendto(b'hello', (group, port))
        time.sleep(0.1)
"""


def _ip(*args: str, check: bool = True) -> subprocess.CompletedProcess[str]:
    result = subprocess.run(['ip', *args], capture_output=True, text=True, timeout=30)
    if check and result.returncode != 0:
        raise RuntimeError(f"ip {' '.join(args)}: {result.stderr.strip()}")
    return result


def unavailable_reason() -> str | None:
    """Return why network namespaces cannot be made here, or None if they can."""
    if sys.platform != 'linux':
        return 'hosts are network namespaces, which only Linux has'
    if shutil.which('ip') is None:
        return "hosts are network namespaces, made with 'ip netns': iproute2 is not installed"
    if os.geteuid() != 0:
        return 'hosts are network namespaces, which only root can make (CI runs as root)'
    name = f'{PREFIX}{os.getpid()}-probe'
    made = _ip('netns', 'add', name, check=False)
    if made.returncode != 0:
        return f"'ip netns add' fails here: {made.stderr.strip()}"
    _ip('netns', 'del', name, check=False)
    return None


def _pids(namespace: str) -> list[int]:
    result = _ip('netns', 'pids', namespace, check=False)
    return [int(p) for p in result.stdout.split()]


def _remove(namespace: str) -> None:
    """Kill every process of a namespace, then remove it (its veth ends go with it)."""
    for pid in _pids(namespace):
        with contextlib.suppress(ProcessLookupError):
            os.kill(pid, signal.SIGKILL)
    _ip('netns', 'del', namespace, check=False)


def remove_leftovers() -> None:
    """Remove the namespaces of test processes that no longer run."""
    listed = _ip('netns', 'list', check=False).stdout.split('\n')
    for line in listed:
        name = line.split(' ')[0]
        owner = name[len(PREFIX):].split('-')[0]
        if not name.startswith(PREFIX) or not owner.isdigit():
            continue
        if not Path(f'/proc/{owner}').exists() or int(owner) == os.getpid():
            _remove(name)


class Host:
    """One host of a :class:`Network`: a namespace with an address."""

    def __init__(self, name: str, namespace: str, address: str, port: str) -> None:
        self.name = name
        self.namespace = namespace
        self.address = address
        #: its end of the link, on the bridge
        self.port = port

    def command(self, args: Sequence[str | os.PathLike[str]]) -> list[str]:
        """Return a command line that runs args on this host."""
        return ['ip', 'netns', 'exec', self.namespace, *map(str, args)]


class Network:
    """
    Hosts joined by one link (a bridge), made on entry and removed on exit.

    :param names: the hosts, e.g. ``['base', 'robot1', 'robot2']``
    :param folder: where the hosts' Fast DDS profiles are written
    """

    def __init__(self, names: Sequence[str], folder: Path) -> None:
        base = f'{PREFIX}{os.getpid()}-'
        self._link = f'{base}link'
        self.hosts = {name: Host(name, f'{base}{n}', f'{SUBNET}.{10 + n}', f'port{n}')
                      for n, name in enumerate(names)}
        self._folder = folder

    def __enter__(self) -> 'Network':
        remove_leftovers()
        try:
            self._make()
        except BaseException:  # noqa: B902 - a half-made network is removed too
            self.close()
            raise
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def _make(self) -> None:
        _ip('netns', 'add', self._link)
        # no snooping: every multicast frame goes to every port that floods it
        _ip('-n', self._link, 'link', 'add', 'br0', 'type', 'bridge', 'mcast_snooping', '0')
        _ip('-n', self._link, 'link', 'set', 'br0', 'up')
        for host in self.hosts.values():
            _ip('netns', 'add', host.namespace)
            _ip('link', 'add', host.port, 'netns', self._link, 'type', 'veth',
                'peer', 'name', 'eth0', 'netns', host.namespace)
            _ip('-n', self._link, 'link', 'set', host.port, 'master', 'br0', 'up')
            _ip('-n', host.namespace, 'link', 'set', 'lo', 'up')
            _ip('-n', host.namespace, 'addr', 'add', f'{host.address}/24', 'dev', 'eth0')
            _ip('-n', host.namespace, 'link', 'set', 'eth0', 'up')
            (self._folder / f'{host.name}.xml').write_text(
                _PROFILE.format(address=host.address, lease=LEASE,
                                announcement=LEASE // 4), encoding='utf-8')

    def close(self) -> None:
        """Kill every process of the hosts, remove the namespaces."""
        for host in self.hosts.values():
            _remove(host.namespace)
        _remove(self._link)

    # what a test does to the network

    def set_link(self, host: str, up: bool) -> None:
        """Take a host's link down (its frames go nowhere, as out of Wi-Fi range) or up."""
        _ip('-n', self._link, 'link', 'set', self.hosts[host].port, 'up' if up else 'down')

    def set_multicast(self, passes: bool) -> None:
        """Let multicast pass between the hosts, or drop it on the bridge."""
        for host in self.hosts.values():
            result = subprocess.run(
                ['ip', 'netns', 'exec', self._link, 'bridge', 'link', 'set', 'dev', host.port,
                 'mcast_flood', 'on' if passes else 'off'],
                capture_output=True, text=True, timeout=30)
            if result.returncode != 0:
                raise RuntimeError(f'bridge link set: {result.stderr.strip()}')

    def multicast_passes(self, sender: str, receiver: str, timeout: float = 2.0) -> bool:
        """Tell whether a multicast datagram of one host reaches another."""
        listen = subprocess.Popen(
            self.hosts[receiver].command([sys.executable, '-c', _MULTICAST, 'listen',
                                          self.hosts[receiver].address, str(timeout)]),
            stdout=subprocess.PIPE, text=True)
        try:
            assert listen.stdout is not None
            assert listen.stdout.readline().strip() == 'ready'
            subprocess.run(self.hosts[sender].command(
                [sys.executable, '-c', _MULTICAST, 'send', self.hosts[sender].address,
                 str(timeout)]), timeout=timeout + 30, check=True)
            out, _ = listen.communicate(timeout=timeout + 30)
        finally:
            listen.kill()
            listen.wait()
        return out.strip() == 'received'

    def pids(self, host: str) -> list[int]:
        """Return the processes that run on a host."""
        return _pids(self.hosts[host].namespace)

    def kill(self, host: str) -> None:
        """End every process of a host at once, as a power cut does."""
        for pid in _pids(self.hosts[host].namespace):
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)

    # processes on the hosts

    def env(self, host: str, base: Mapping[str, str],
            static_peers: bool = False) -> dict[str, str]:
        """
        Return the environment of ROS 2 on a host: its own profile, discovery on its subnet.

        :param base: an environment of :mod:`colcon_robmosys.devtools.ros_env`
            (its domain, the workspace sourced)
        :param static_peers: whether ``ROS_STATIC_PEERS`` names the other hosts
            (where multicast does not pass)
        """
        env = dict(base)
        env['FASTDDS_DEFAULT_PROFILES_FILE'] = str(self._folder / f'{host}.xml')
        env['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'SUBNET'
        env.pop('ROS_STATIC_PEERS', None)
        if static_peers:
            env['ROS_STATIC_PEERS'] = ';'.join(
                h.address for h in self.hosts.values() if h.name != host)
        return env

    @contextlib.contextmanager
    def background(self, host: str, args: Sequence[str | os.PathLike[str]],
                   env: Mapping[str, str], stop_timeout: float = 30.0) -> Iterator[Any]:
        """Run a command on a host for a with block (ros_env.background: stopped after)."""
        with ros_env.background(self.hosts[host].command(args), env=env,
                                stop_timeout=stop_timeout) as process:
            yield process

    def run(self, host: str, args: Sequence[str | os.PathLike[str]], env: Mapping[str, str],
            timeout: float) -> subprocess.CompletedProcess[Any]:
        """Run a command on a host to its end, under a timeout (ros_env.run)."""
        return ros_env.run(self.hosts[host].command(args), env=env, timeout=timeout)
