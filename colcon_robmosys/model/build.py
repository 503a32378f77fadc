# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Turn the checked data of one model file into typed models, model by model."""

from __future__ import annotations

from typing import Callable

from colcon_robmosys.model.build_base import BuilderBase, MODEL_SECTIONS
from colcon_robmosys.model.build_components import ComponentBuilder
from colcon_robmosys.model.build_definitions import DefinitionBuilder
from colcon_robmosys.model.build_systems import SystemBuilder
from colcon_robmosys.model.loader import NodePath, RawData
from colcon_robmosys.model.types import Model


class FileBuilder(BuilderBase):
    """Build the typed models of one loaded file, each kind by its builder.

    A model whose part of the file broke the schema is skipped; the others
    are built, so that the checks of the workspace see them. The builders
    record their problems here (``diagnostics``, ``broken_models``).
    """

    def build_models(self, skip: frozenset[tuple[str, int]] = frozenset()
                     ) -> list[tuple[tuple[str, int], Model]]:
        """Return the models of the file, each with its (section, index)."""
        data = self.loaded.data
        defaults = data.get('defaults', {})
        shared = (self.loaded, self.diagnostics, self.broken_models)
        builders: dict[str, Callable[[NodePath, RawData, RawData], Model]] = {
            'service_definitions': DefinitionBuilder(*shared).service_definition,
            'components': ComponentBuilder(*shared).component,
            'systems': SystemBuilder(*shared).system}
        models: list[tuple[tuple[str, int], Model]] = []
        for section in MODEL_SECTIONS:
            for index, raw in enumerate(data.get(section, [])):
                if (section, index) not in skip:
                    models.append(((section, index), builders[section](
                        (section, index), raw, defaults)))
        return models
