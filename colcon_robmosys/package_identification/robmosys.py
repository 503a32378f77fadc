# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

from pathlib import Path

from colcon_core.package_identification import IgnoreLocationException
from colcon_core.package_identification import \
    PackageIdentificationExtensionPoint
from colcon_core.plugin_system import satisfies_version
from colcon_ros.package_identification.ros import get_package_with_build_type

from colcon_robmosys.mapping.common import RUNTIME_PACKAGE
from colcon_robmosys.model.files import MODEL_FILE_NAME


class RobmosysPackageIdentification(PackageIdentificationExtensionPoint):
    """Record the folders that hold a robmosys.yaml model file.

    A model file generates one package or several, so this extension
    identifies no package itself: it records the file for
    :class:`RobmosysPackageDiscovery`, like colcon-cargo does for
    workspaces.
    """

    # before ros (150): a model folder is not searched for package.xml
    PRIORITY = 160

    def __init__(self):  # noqa: D107
        super().__init__()
        satisfies_version(
            PackageIdentificationExtensionPoint.EXTENSION_POINT_VERSION,
            '^1.0')
        self.model_files = set()
        # folders of the workspace that hold robmosys_runtime itself: then
        # discovery does not add the copy of our package data
        self.runtime_folders = set()

    def identify(self, metadata):  # noqa: D102
        if metadata.type is not None and \
                not metadata.type.startswith('robmosys.'):
            return
        model_file = Path(metadata.path) / MODEL_FILE_NAME
        if not model_file.is_file():
            # colcon-ros reads the package.xml of every folder with catkin_pkg
            # and keeps what it read: asked first, it reads nothing twice
            package, _ = get_package_with_build_type(str(metadata.path))
            if package is not None and package.name == RUNTIME_PACKAGE:
                self.runtime_folders.add(Path(metadata.path).resolve())
            return
        self.model_files.add(model_file.resolve())
        # the folder belongs to the model: the user's implementation files
        # below it are no packages of their own
        raise IgnoreLocationException()
