# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The launch files of a system: the instances each starts, and which it activates."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, replace

from colcon_robmosys.mapping.common import Banner, unique
from colcon_robmosys.model.types import System

#: where the system package installs its parameter file
PARAMS_FILE = 'cfg/params.yaml'
#: where it installs what ``bringup`` and the shared Python process read
DESCRIPTION_FILE = 'bringup.json'
#: a system that does not say ``processes`` shares them from this many instances on
#: one host: one process per instance, 20 Python instances came up through
#: ``ros2 launch`` in 1 run of 3 and through ``bringup`` in 8.9x the time of one
#: (issue 28, docs/performance.md); the systems below keep a process per instance
SHARED_FROM = 20


def process_layout(system: System) -> str:
    """Return how a system runs its instances: what it says, or by its size."""
    if system.processes:
        return system.processes
    on_one_host = Counter(i.host for i in system.instances).values()
    return 'shared' if max(on_one_host, default=0) >= SHARED_FROM else 'per_instance'


@dataclass(frozen=True)
class SystemNode:
    """An instance as a lifecycle node of the launch files."""

    instance: str
    package: str
    executable: str
    name: str
    namespace: str
    #: (port, ROS 2 name) for each connected port
    remappings: tuple[tuple[str, str], ...]
    activate: bool
    after: tuple[str, ...]
    fqn: str
    #: the instances of the same launch file it waits for
    activate_after: tuple[str, ...] = ()
    #: started again when its process ends
    respawn: bool = False
    #: seconds for each lifecycle transition; None: the bring-up's default
    timeout: float | None = None
    #: the host it runs on; '' for the manager's
    host: str = ''
    #: module:class of a Python component (``bringup`` runs shared processes with it)
    python_class: str = ''
    #: the rclcpp_components plugin of a C++ component (its shared container loads it)
    plugin: str = ''
    #: the executor threads its node needs at least (a shared container adds them up)
    threads: int = 1
    #: a lifecycle node (LifecycleNode in the launch files); a plain external node is not
    lifecycle: bool = True


@dataclass(frozen=True)
class LaunchAlias:
    """A launch file under its name of the last release, including its new one."""

    banner: Banner
    package: str
    old: str
    new: str


@dataclass(frozen=True)
class LaunchFile:
    """A launch file, and its activate twin: all instances or one.

    Named as ROS 2 names launch files, ``<name>.launch.py``: the system's
    ``<system>.launch.py`` starts and activates every instance,
    ``<system>.nodes.launch.py`` only starts them; each instance has
    ``<system>.<instance>.launch.py`` and ``<system>.<instance>.nodes.launch.py``
    (an instance may not be called ``nodes``). The names of the last release,
    ``launch{suffix}.py`` and ``activate{suffix}.py``, stay as aliases.
    """

    suffix: str
    banner: Banner
    package: str
    params_file: str
    nodes: tuple[SystemNode, ...]
    what: str
    #: instances it activates that the launch file of their host starts
    remote: tuple[SystemNode, ...] = ()
    #: whether the Python instances share one process (``processes: shared``)
    shared: bool = False
    #: whether its C++ instances share a container, when shared (the file of a host,
    #: or the manager's: not the file of one instance)
    containers: bool = False
    #: the host of the file's instances, '' for the manager's
    host: str = ''

    @property
    def stem(self) -> str:
        """Return the name the launch files share: the system's, or with an instance."""
        return f'{self.package}{self.suffix}'

    @property
    def activate_file(self) -> str:
        """Return the file name of the launch file that also activates."""
        return f'{self.stem}.launch.py'

    @property
    def nodes_file(self) -> str:
        """Return the file name of the launch file that only starts the nodes."""
        return f'{self.stem}.nodes.launch.py'

    @property
    def has_manager(self) -> bool:
        """Tell whether the file starts the system manager: the system's own file does."""
        return self.suffix == ''

    # The processes of its instances, as bringup's (robmosys_runtime.hosting.processes,
    # plan_processes) from the same bringup.json: one per instance, or with
    # processes: shared one for the Python instances and a component container
    # for the C++ instances of the manager's host. templates/system/processes.jinja
    # starts them, the one list of nodes of every launch file.

    @property
    def together(self) -> tuple[SystemNode, ...]:
        """Return the Python instances that share one process."""
        return tuple(n for n in self.nodes if self.shared and n.python_class)

    @property
    def loaded(self) -> tuple[SystemNode, ...]:
        """Return the C++ instances loaded into the system's component container."""
        return tuple(n for n in self.nodes if self.shared and self.containers and n.plugin)

    @property
    def alone(self) -> tuple[SystemNode, ...]:
        """Return the instances that run in a process of their own."""
        grouped = {n.instance for n in self.together + self.loaded}
        return tuple(n for n in self.nodes if n.instance not in grouped)

    @property
    def together_respawn(self) -> bool:
        """Tell whether the shared Python process starts again when it ends (as bringup)."""
        return any(n.respawn for n in self.together)

    @property
    def loaded_respawn(self) -> bool:
        """Tell whether the component container starts again when it ends (as bringup)."""
        return any(n.respawn for n in self.loaded)

    @property
    def description_file(self) -> str:
        """Return where the system package installs its description (the shared process)."""
        return DESCRIPTION_FILE

    @property
    def node_classes(self) -> str:
        """Return the launch_ros actions that start its processes."""
        return ', '.join(self._ros_actions())

    @property
    def launch_actions(self) -> str:
        """Return the launch.actions of its processes: ExecuteProcess, or none."""
        return ', '.join(self._launch_actions())

    @property
    def manager_actions(self) -> str:
        """
        Return the launch.actions of the file that also starts the manager (ExecuteProcess).

        The manager is a plain process, as the shared ones: a file whose
        instances all share processes imports no launch_ros, which took a
        launch 0.3 to 0.5 s to import before it started anything (issue 28).
        """
        return ', '.join(self._launch_actions('ExecuteProcess'))

    @property
    def activate_actions(self) -> str:
        """Return the launch.actions of a file that activates its instances itself."""
        return ', '.join(self._launch_actions('OpaqueFunction', 'RegisterEventHandler'))

    def _ros_actions(self) -> list[str]:
        return sorted({'LifecycleNode' if n.lifecycle else 'Node' for n in self.alone})

    def _launch_actions(self, *more: str) -> list[str]:
        return sorted(set(more) | ({'ExecuteProcess'} if self.together or self.loaded else set()))

    @property
    def activates_itself(self) -> bool:
        """Tell whether the file activates its instances itself (one instance, a host)."""
        return not self.has_manager

    @property
    def has_aliases(self) -> bool:
        """Tell whether the last release had the file: the files of hosts are new."""
        return not self.suffix.startswith('.on_')

    @property
    def activate_alias(self) -> LaunchAlias:
        """Return the alias of the activating file under its former name."""
        return LaunchAlias(self.banner, self.package, f'activate{self.suffix}.py',
                           self.activate_file)

    @property
    def nodes_alias(self) -> LaunchAlias:
        """Return the alias of the starting file under its former name."""
        return LaunchAlias(self.banner, self.package, f'launch{self.suffix}.py',
                           self.nodes_file)


def launch_files(system: System, nodes: tuple[SystemNode, ...],
                 banner: Banner) -> tuple[LaunchFile, ...]:
    """Return the launch files of a system: every instance, each, each host."""
    local = tuple(n for n in nodes if not n.host)
    remote = tuple(n for n in nodes if n.host)
    # each file: its suffix, its instances, those it activates on other hosts, what
    # it starts, its host (None: one instance's file, which no container serves);
    # the system's files start the instances of the manager's host, and
    # activate those of every host
    Variant = tuple[str, tuple[SystemNode, ...], tuple[SystemNode, ...], str, str | None]
    variants: list[Variant] = [('', local, remote, f'every instance of the system {system.name}'
                                + (' that runs on no host of its own' if remote else ''), '')]
    variants += [(f'.{n.instance}', (n,), (), f'the instance {n.instance} '
                  f'of the system {system.name}', None) for n in nodes]
    variants += [(f'.on_{host}', tuple(n for n in remote if n.host == host), (),
                  f'the instances of the system {system.name} on the host {host}', host)
                 for host in unique(n.host for n in remote)]
    files = []
    for suffix, selected, elsewhere, what, host in variants:
        # a file waits only for instances it activates itself: an instance
        # started by another file, or left unmanaged, would never be seen
        managed = {n.instance for n in selected + elsewhere if n.activate}

        def waiting(chosen: tuple[SystemNode, ...]) -> tuple[SystemNode, ...]:
            return tuple(replace(n, activate_after=tuple(a for a in n.after if a in managed))
                         for n in chosen)
        # as bringup: the instances of one file share processes, C++ ones a
        # container of their host (not of one instance). The system's own file
        # does so for one instance too, as bringup does: its manager waits for
        # the shared process to tell what it brought up (10 s, where a process
        # of its own ran the instance and told nothing); the file of one
        # instance has no manager, and needs no shared process.
        shared = process_layout(system) == 'shared' and (len(selected) > 1 or suffix == '')
        files.append(LaunchFile(suffix, banner, system.package, PARAMS_FILE,
                                waiting(selected), what, waiting(elsewhere), shared=shared,
                                containers=host is not None, host=host or ''))
    return tuple(files)
