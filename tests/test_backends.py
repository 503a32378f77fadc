# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Every language backend spells every entity, return and template it may meet.

A new pattern adds rows to the port-kind table (mapping/portkinds.py); these
tests name the backend that lacks the row for it.
"""

from __future__ import annotations

from dataclasses import fields, is_dataclass

import pytest

from colcon_robmosys.generators.render import templates_dir
from colcon_robmosys.mapping.backends import BACKENDS
from colcon_robmosys.mapping.backends.cpp.spelling import PARAMETERS
from colcon_robmosys.mapping.portkinds import Delivery, Entity, PORT_KINDS, Returns
from colcon_robmosys.model.types import Language

LANGUAGES = sorted(BACKENDS, key=lambda language: language.value)


def test_every_language_has_a_backend():
    assert set(BACKENDS) == set(Language)
    assert all(BACKENDS[language].language is language for language in Language)


@pytest.mark.parametrize('language', LANGUAGES, ids=lambda language: language.value)
def test_every_entity_has_a_row_in_every_language(language):
    entities = BACKENDS[language].entities
    assert sorted(set(Entity) - set(entities)) == []
    assert {kind.entity for kind in PORT_KINDS.values()} <= set(entities)


@pytest.mark.parametrize('language', LANGUAGES, ids=lambda language: language.value)
def test_every_return_has_a_type_in_every_language(language):
    assert sorted(set(Returns) - set(BACKENDS[language].return_types)) == []


def test_every_delivery_has_parameters_in_cpp():
    assert sorted(set(Delivery) - set(PARAMETERS)) == []


@pytest.mark.parametrize('language', LANGUAGES, ids=lambda language: language.value)
def test_the_templates_of_a_backend_exist(language):
    backend = BACKENDS[language]
    named = [row.template for row in backend.files + backend.user_files] + [backend.starter]
    for row in backend.entities.values():
        assert is_dataclass(row)
        named += [getattr(row, f.name) for f in fields(row) if f.name == 'template']
    assert [t for t in named if not (templates_dir() / t).is_file()] == []
