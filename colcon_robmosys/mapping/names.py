# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""ROS 2 names of nodes and connections."""

from __future__ import annotations


def node_name(namespace: str, name: str) -> str:
    """Return the fully qualified name of a node, ``/<namespace>/<name>``.

    :param namespace: a namespace as the model holds it: empty, or starting
      with ``/`` and not ending with one
    """
    return f'{namespace}/{name}'


def connection_name(namespace: str, instance: str, port: str,
                    topic: str | None) -> str:
    """Return the ROS 2 name both ends of a connection are remapped to.

    The provided end names a connection: ``/<namespace>/<instance>/<port>``
    unless the model gives a ``topic``; a relative topic lies in the
    namespace of the provided end.

    :param namespace: the namespace of the provided end's instance
    :param instance: the provided end's instance
    :param port: the provided end's port
    """
    if topic is None:
        return f'{node_name(namespace, instance)}/{port}'
    if topic.startswith('/'):
        return topic
    return f'{namespace}/{topic}'
