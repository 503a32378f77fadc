# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

from pathlib import Path

from colcon_core.logging import colcon_logger
from colcon_core.plugin_system import satisfies_version
from colcon_core.task import TaskExtensionPoint
from colcon_ros.task.ament_cmake.test import AmentCmakeTestTask

from colcon_robmosys.task.build import GENERATED_DIR

logger = colcon_logger.getChild(__name__)


class RobmosysTestTask(TaskExtensionPoint):
    """Test a generated package the ament way: `colcon test` runs its CTest tests."""

    def __init__(self):  # noqa: D107
        super().__init__()
        satisfies_version(TaskExtensionPoint.EXTENSION_POINT_VERSION, '^1.0')

    async def test(self):  # noqa: D102
        pkg, args = self.context.pkg, self.context.args
        source_dir = Path(args.build_base) / GENERATED_DIR
        if not source_dir.is_dir():
            logger.error(
                f"cannot test '{pkg.name}': it has not been generated and "
                "built yet (run 'colcon build' first)")
            return 1
        # the generated tree is an ordinary ament_cmake package, as in build
        args.path = str(source_dir)
        extension = AmentCmakeTestTask()
        extension.set_context(context=self.context)
        return await extension.test()
