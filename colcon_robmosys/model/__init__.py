# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""RobMoSys models: loading, validation and the typed model."""

from colcon_robmosys.model.types import *  # noqa: F401,F403
from colcon_robmosys.model.workspace import (  # noqa: F401
    find_model_files, load_model_file, load_workspace, LoadResult,
    model_dependencies, MODEL_FILE_NAME)
