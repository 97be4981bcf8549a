"""The documents of size, sweep, workspace, the wear test and the plant-and-model simulate (hipsim.cli.documents_more):
listed by ``hipsim schema``, valid schemas, and a document keyed by name (size's) described as such."""

from __future__ import annotations

import jsonschema
import pytest

from hipsim.cli.documents import SCHEMAS, schema
from hipsim.cli.documents_more import MORE_SCHEMAS, SizeRun
from hipsim.records import SCHEMA_VERSION


def test_every_document_is_listed_and_its_schema_is_valid():
    for name in MORE_SCHEMAS:
        assert SCHEMAS[name] is MORE_SCHEMAS[name]
        document = schema(name)
        jsonschema.Draft202012Validator.check_schema(document)
        assert document["version"] == SCHEMA_VERSION and document["$id"].endswith(f"/{name}/v{SCHEMA_VERSION}.json")


def test_a_document_keyed_by_trajectory_name_takes_any_name_and_only_sizings():
    """size's JSON is keyed by the trajectory's name: any key is allowed, each value must be a sizing."""
    size = SizeRun.json_schema("size")
    assert size["properties"] == {} and size["required"] == []
    assert size["additionalProperties"] == {"$ref": "#/$defs/SizingSummary"}
    validator = jsonschema.Draft202012Validator(size)
    validator.validate({})
    with pytest.raises(jsonschema.ValidationError):
        validator.validate({"ISO 14242-1": {"modules": []}})  # a sizing lacks most of its keys
    assert SizeRun({}).to_json() == {}


def test_two_records_of_one_class_name_get_apart_definitions():
    """report's JSON holds the page's Verdict and, in its sizing, a records.Verdict: each its own $defs entry."""
    report = schema("report")
    assert {"Verdict", "pages_Verdict"} <= set(report["$defs"])
    assert report["properties"]["verdict"] == {"$ref": "#/$defs/pages_Verdict"}
    assert report["$defs"]["SizingSummary"]["properties"]["verdict"] == {"$ref": "#/$defs/Verdict"}
    assert "level" in report["$defs"]["Verdict"]["properties"]
