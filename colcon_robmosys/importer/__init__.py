# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Models from what already exists: installed interface packages, running systems."""
