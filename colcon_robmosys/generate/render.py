# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The one Jinja environment, and where the templates are found."""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path
from typing import Any, Mapping

import jinja2

from colcon_robmosys.generate.filters import FILTERS


def templates_dir() -> Path:
    """Return the templates folder of the installed package.

    In a source checkout the folder is ``templates/`` at the top level; an
    installed package carries it as ``colcon_robmosys/templates``.
    """
    package_dir = Path(__file__).resolve().parent.parent
    installed = package_dir / 'templates'
    if installed.is_dir():
        return installed
    return package_dir.parent / 'templates'


@lru_cache(maxsize=1)
def environment() -> jinja2.Environment:
    """Return the Jinja environment shared by every generator."""
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(templates_dir())),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
        autoescape=False,
    )
    env.filters.update(FILTERS)
    return env


def render(template: str, context: Mapping[str, Any]) -> str:
    """Render one template with its variables."""
    return environment().get_template(template).render(**context)
