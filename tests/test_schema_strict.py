# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The JSON Schema alone is as strict as the checks, wherever a schema can be.

An editor validates with the schema only: every rule about the shape of one
model (keys, kinds of values, names, which keys go together) is in it, so
that what the editor accepts the check stage does not refuse for a reason
the editor could have shown. Rules that compare models, look into the
workspace or compare two values are the check stage's alone
(:data:`CHECK_ONLY`, each with its reason); this test keeps that list exact.
"""

from __future__ import annotations

import json
from pathlib import Path
import re
from typing import Any

from jsonschema import Draft202012Validator
import pytest
import yaml

from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.mapping.portkinds import PORT_KINDS
from colcon_robmosys.model import names, schema
from colcon_robmosys.model.base import Pattern, PATTERN_INTERFACE
from colcon_robmosys.model.loader import load_file

ROOT = Path(__file__).resolve().parent.parent
INVALID = sorted((ROOT / 'tests' / 'models' / 'invalid').glob('*.yaml'))
VALID = sorted((ROOT / 'tests' / 'models' / 'valid').glob('*.yaml'))
EXAMPLES = sorted((ROOT / 'test_workspace' / 'src').glob('*/robmosys.yaml'))
DOCS = sorted((ROOT / 'docs').glob('*.md')) + [ROOT / 'README.md']

_CROSS = 'names or compares another model, a package or a port elsewhere'
_VALUES = 'compares two values of the model (JSON Schema has no $data)'
_FIELD_VALUE = ('a field value against the type written in another key: fixed sizes '
                'and string bounds written in the type text cannot be compared')
_CODE = 'reads the embedded code or the signatures of functions'
_MAPPED = 'compares a parameter with the array parameter its for_each names'

#: corpus cases whose rule no schema can express, and why
CHECK_ONLY = {
    'activity_trigger_delivers_nothing': _CROSS,
    'activity_trigger_unknown_port': _CROSS,
    'activity_unknown_function': _CROSS,
    'component_depends_unknown_on_its_line': _CROSS,
    'component_lifecycle_unknown_function': _CROSS,
    'component_port_and_function_same_name': 'keys of two mappings must differ',
    'definition_external_not_installed': _CROSS,
    'duplicate_package': _CROSS,
    'duplicate_package_across_files': _CROSS,
    'executor_events_blocking_call': _CODE,
    'executor_single_threaded_user_code': _CODE,
    'executor_system_shared_blocking': _CROSS,
    'field_default_array_item_out_of_range_block': _FIELD_VALUE,
    'field_default_array_item_out_of_range_flow': _FIELD_VALUE,
    'field_default_escaped_over_bound': _FIELD_VALUE,
    'field_default_out_of_range': _FIELD_VALUE,
    'function_periodic_and_triggered': _CODE,
    'function_python_syntax_error': _CODE,
    'function_triggers_deliver_differently_cpp': _CODE,
    'function_triggers_deliver_differently_python': _CODE,
    'multiple_errors_function_and_type': _CROSS,
    'parameter_default_element_not_listed_block': _VALUES,
    'parameter_default_element_not_listed_flow': _VALUES,
    'parameter_default_outside_range': _VALUES,
    'parameter_for_each_array_is_mapped': _MAPPED,
    'parameter_for_each_array_not_read_only': _MAPPED,
    'parameter_for_each_entry_clashes': _MAPPED,
    'parameter_for_each_entry_not_a_name': _MAPPED,
    'parameter_for_each_not_a_string_array': _MAPPED,
    'parameter_for_each_typed_access_clash': _MAPPED,
    'parameter_for_each_unknown_array': _MAPPED,
    'parameter_group_and_parameter': 'compares two keys of one mapping (a name, a group)',
    'parameter_one_of_default_not_listed': _VALUES,
    'parameter_size_default_too_long': _VALUES,
    'parameter_size_min_above_max': _VALUES,
    'parameter_validate_unknown_function': _CROSS,
    'parameter_validator_also_periodic': _CODE,
    'parameter_range_inverted': _VALUES,
    'port_event_names_action': _CROSS,
    'port_unknown_type': _CROSS,
    'port_unknown_type_package': _CROSS,
    'query_port_without_handler': _CROSS,
    'service_definition_broken_no_cascade': _FIELD_VALUE,
    'service_dependency_cycle': _CROSS,
    'servicedef_message_contains_itself': _CROSS,
    'servicedef_message_cycle': _CROSS,
    'servicedef_same_name_message_and_query': 'keys of two mappings must differ',
    'servicedef_string_constant_with_newline': _FIELD_VALUE,
    'servicedef_string_default_with_hash': _FIELD_VALUE,
    'system_activation_cycle': _CROSS,
    'system_activation_cycle_block': _CROSS,
    'system_after_a_plain_external_node': _CROSS,
    'system_after_inactive_instance': _CROSS,
    'system_after_inactive_instance_block': _CROSS,
    'system_after_unknown_instance': _CROSS,
    'system_after_unknown_instance_block': _CROSS,
    'system_everywhere_values': _CROSS,
    'system_incompatible_qos': _CROSS,
    'system_instance_named_after_a_host': _VALUES,
    'system_instance_not_a_component': _CROSS,
    'system_instance_of_itself': _CROSS,
    'system_mapped_parameter_values': _CROSS,
    'system_mode_after_inactive': _CROSS,
    'system_mode_initial_unknown': _VALUES,
    'system_mode_subsystem_unknown': _CROSS,
    'system_mode_unknown_instance': _CROSS,
    'system_mode_unknown_parameter': _CROSS,
    'system_mode_value_refused': _CROSS,
    'system_one_name_two_types': _CROSS,
    'system_outside_name_of_another_type': _CROSS,
    'system_override_array_element_block': _CROSS,
    'system_override_array_element_flow': _CROSS,
    'system_override_breaks_one_of': _CROSS,
    'system_override_out_of_range': _CROSS,
    'system_port_two_topics': _CROSS,
    'system_port_type_typo_no_cascade': _CROSS,
    'system_qos_deadline': _CROSS,
    'system_qos_override_breaks_connection': _CROSS,
    'system_qos_override_depth_of_keep_all': _CROSS,
    'system_qos_override_event_port': _CROSS,
    'system_qos_override_of_external_node': _CROSS,
    'system_qos_override_query_port': _CROSS,
    'system_qos_override_reader_breaks_connection': _CROSS,
    'system_qos_override_unknown_port': _CROSS,
    'system_qos_transient_local_from_volatile': _CROSS,
    'system_query_to_action': _CROSS,
    'system_query_type_mismatch': _CROSS,
    'system_quiet_not_a_provided_push_port': _CROSS,
    'system_required_parameter_unset': _CROSS,
    'system_required_port_two_providers': _CROSS,
    'system_send_qos_writer_is_required': _CROSS,
    'system_subsystem_cycle': _CROSS,
    'system_subsystem_named_as_an_instance': 'keys of two mappings must differ',
    'system_subsystem_not_a_system': _CROSS,
    'system_subsystems_one_namespace': _CROSS,
    'system_two_provided_ports': _CROSS,
    'system_two_query_servers': _CROSS,
    'system_two_required_ports': _CROSS,
    'system_type_mismatch': _CROSS,
    'system_unconnected_port_is_connected': _CROSS,
    'system_unconnected_provided_port': _CROSS,
    'system_unconnected_unknown_port': _CROSS,
    'system_unknown_component': _CROSS,
    'system_unknown_instance': _CROSS,
    'system_unknown_parameter_override': _CROSS,
    'system_unknown_port': _CROSS,
    'system_wrong_pattern_pair': _CROSS,
}


def _validator() -> Any:
    # jsonschema, with '$' ending the text as in ECMA-262 (what editors run):
    # Python's '$' would also match before a final newline
    return schema._Validator(schema.schema())


def _rejects(data: Any) -> bool:
    return any(True for _ in _validator().iter_errors(data))


def test_the_schema_is_a_valid_2020_12_schema():
    Draft202012Validator.check_schema(schema.schema())


@pytest.mark.parametrize('path', INVALID, ids=[p.stem for p in INVALID])
def test_invalid_model(path: Path):
    try:
        data = load_file(path).data
    except RobmosysError:
        pytest.skip('not YAML a schema could read')
    reason = CHECK_ONLY.get(path.stem)
    if reason is None:
        assert _rejects(data), f'the schema accepts {path.name}'
    else:
        # listed as beyond a schema: the schema must not catch it after all
        assert not _rejects(data), f'{path.name} is check-only ({reason}), ' \
            'but the schema rejects it: drop it from CHECK_ONLY'


def _doc_models() -> list[tuple[str, str]]:
    """Return the YAML blocks of the docs that are whole models, with where they are."""
    found = []
    for doc in DOCS:
        text = doc.read_text(encoding='utf-8')
        for match in re.finditer(r'```yaml\n(.*?)```', text, re.DOTALL):
            block = match.group(1)
            if re.search(r'^robmosys:', block, re.MULTILINE):
                line = text.count('\n', 0, match.start()) + 1
                found.append((f'{doc.name}:{line}', block))
    return found


DOC_MODELS = _doc_models()


def test_docs_have_models():
    assert len(DOC_MODELS) >= 5


@pytest.mark.parametrize('path', VALID + EXAMPLES,
                         ids=[str(p.relative_to(ROOT)) for p in VALID + EXAMPLES])
def test_valid_model_file(path: Path):
    errors = list(_validator().iter_errors(load_file(path).data))
    assert errors == []


@pytest.mark.parametrize('where,block', DOC_MODELS, ids=[w for w, _ in DOC_MODELS])
def test_valid_model_of_the_docs(where: str, block: str):
    errors = list(_validator().iter_errors(yaml.safe_load(block)))
    assert errors == []


def test_the_id_is_versioned_like_the_format():
    definition = schema.schema()
    identifier = definition['$id']
    version = definition['properties']['robmosys']['const']
    assert re.fullmatch(r'https://[a-z0-9.-]+/schema/robmosys-[0-9]+\.schema\.json', identifier)
    assert identifier.endswith(f'/robmosys-{version}.schema.json')
    # the installed file is named as its $id ends
    assert schema.schema_path().name == identifier.rsplit('/', 1)[1]
    assert json.loads(schema.schema_path().read_text())['$id'] == identifier


def test_models_refer_to_the_published_schema():
    """Every model of test_workspace and the docs names the schema by its $id."""
    modeline = f"# yaml-language-server: $schema={schema.schema()['$id']}"
    texts = [(str(p.relative_to(ROOT)), p.read_text()) for p in EXAMPLES] + DOC_MODELS
    assert len(texts) >= len(EXAMPLES) + 5
    for where, text in texts:
        assert text.splitlines()[0] == modeline, where


def test_reserved_names_are_those_of_the_checks():
    defs = schema.schema()['$defs']
    assert set(defs['reserved_word']['enum']) == names.CPP_KEYWORDS | names.PYTHON_KEYWORDS
    assert set(defs['node_member']['enum']) == names.NODE_MEMBERS


def _port_rules() -> list[tuple[set[str], dict[str, Any]]]:
    return [(set(rule['if']['properties']['pattern']['enum']), rule['then']['properties'])
            for rule in schema.schema()['$defs']['port']['allOf']]


def test_qos_is_refused_where_the_port_kinds_have_no_topic():
    without = {k.pattern.value for k in PORT_KINDS.values() if not k.topic_qos}
    refused = set().union(*(p for p, then in _port_rules() if 'qos' in then))
    assert refused == without


def test_port_types_are_of_the_kind_the_pattern_exchanges():
    kinds = {p.value: kind.value for p, kind in PATTERN_INTERFACE.items()}
    for patterns, then in _port_rules():
        if 'type' in then:
            name = then['type']['$ref'].rsplit('/', 1)[1]
            pattern = schema.schema()['$defs'][name]['pattern']
            for written in patterns:
                assert f'{kinds[written]}/' in pattern, (written, name)
    assert {p.value for p in Pattern} == set().union(
        *(p for p, then in _port_rules() if 'type' in then))
