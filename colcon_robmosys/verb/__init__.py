# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

import os


def display_path(path):
    """Return a path as the verbs print it: relative to here where it can be."""
    try:
        return os.path.relpath(path)
    except ValueError:
        return str(path)
