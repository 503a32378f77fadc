# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The ROS 2 distributions the generated code is for, and the shell's.

The generated packages are the same for every supported distribution
(docs/distributions.md): what follows the shell's ``ROS_DISTRO`` is whether
they can build there at all. A distribution older than Jazzy lacks APIs they
use, and its compiler or interpreter would say so only deep in a package's
build; this says it first, once, in the user's terms.
"""

from __future__ import annotations

from typing import Mapping

#: the distributions the generated code is tested on
SUPPORTED = ('jazzy', 'kilted')

#: distributions before Jazzy -> what of theirs the generated code cannot use
#: (the first missing API; docs/distributions.md lists the rest)
TOO_OLD = {
    'humble': 'rclcpp_lifecycle managed entities and post-set parameter callbacks '
              'came in Iron',
    'iron': "rclpy's create_timer(autostart=False) came in Jazzy",
}
TOO_OLD.update((name, 'it is older than Humble') for name in (
    'ardent', 'bouncy', 'crystal', 'dashing', 'eloquent', 'foxy', 'galactic'))


def distribution_problem(environ: Mapping[str, str]) -> str | None:
    """Return why the shell's ROS 2 distribution cannot build generated code, or None.

    An unset ``ROS_DISTRO`` (the PyPI wheels set none) and any distribution
    not known to be older than Jazzy (Rolling, those after Kilted) pass.
    """
    name = environ.get('ROS_DISTRO', '').strip().lower()
    if name not in TOO_OLD:
        return None
    return (f"ROS_DISTRO is '{name}': the generated code needs ROS 2 Jazzy or newer "
            f'({TOO_OLD[name]}; see docs/distributions.md of colcon-robmosys)')
