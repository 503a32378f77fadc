# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The model of a running system: the graph, this host's processes, installed models."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from colcon_robmosys.check import load_model_file
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.check.underlays import installed_model_paths
from colcon_robmosys.errors import Diagnostic, Location, RobmosysError
from colcon_robmosys.importer.graph import COMPONENT, import_graph
from colcon_robmosys.importer.graph_read import read_graph
from colcon_robmosys.importer.interfaces import package_metadata
from colcon_robmosys.importer.processes import node_processes
from colcon_robmosys.model.components import Component


def import_running_system(system: str, index: InterfaceIndex, *, namespace: str | None,
                          timeout: float, domain: str, license_: str = '',
                          maintainers: list[dict[str, str]] | None = None) -> str:
    """Return the model of the system the ROS graph of this domain runs.

    :raises RobmosysError: if rclpy is missing, no node is found, or the
      system's license and maintainers are neither given nor found
    """
    def running() -> set[str]:
        # a node this host runs under a name its command line gives is waited for
        return {p.named_node for p in node_processes(domain)} - {''}
    try:
        nodes = read_graph(namespace, timeout, expected=running)
    except ImportError:
        raise RobmosysError([Diagnostic(Location('rclpy'), 'rclpy, which reads the ROS '
                                        'graph, is not installed: source a ROS 2 '
                                        'installation first')])
    where = f'under the namespace {namespace}' if namespace else ''
    if not nodes:
        raise RobmosysError([Diagnostic(Location(f'ROS domain {domain}'), ' '.join(
            f'no node found {where} within {timeout:g} s (is the system running, '
            'with the same ROS_DOMAIN_ID and discovery settings?)'.split()))])
    announced = {node.parameter(COMPONENT) for node in nodes} - {None}
    components, external = _installed_components(index, announced)
    return import_graph(
        nodes, system, components, external, node_processes(domain),
        lambda package: _metadata(index, package),
        header=' '.join(f'Imported by colcon robmosys-import graph from the running ROS '
                        f'graph {where}'.split()) + '.',
        license_=license_, maintainers=maintainers)


def _installed_components(index: InterfaceIndex, packages: set[str]
                          ) -> tuple[dict[str, Component], dict[str, Component]]:
    """Return the installed models of these component packages, and every external one.

    External components are described by the models of the systems that run
    them: the first description of each counts (package/executable).
    """
    found: dict[str, Component] = {}
    external: dict[str, Component] = {}
    for package, paths in sorted(installed_model_paths(index, set()).items()):
        try:
            model_file = load_model_file(paths[0])
        except RobmosysError:
            continue  # a broken installed model: its nodes are imported as external
        for component in model_file.components:
            if component.external:
                external.setdefault(f'{component.package}/{component.executable}', component)
            elif component.package == package and package in packages:
                found[package] = component
    return found, external


def _metadata(index: InterfaceIndex, package: str) -> tuple[str, list[tuple[str, str]]] | None:
    share = index.package_share(package)
    if share is None or not (share / 'package.xml').is_file():
        return None
    data: dict[str, Any] = package_metadata(Path(share) / 'package.xml')
    return data['license'], [(m['name'], m['email']) for m in data['maintainers']]
