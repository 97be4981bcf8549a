"""The documents of size, sweep, workspace, the wear test and the plant-and-model simulate (hipsim.cli.documents_more):
listed by ``hipsim schema``, valid schemas, and a document keyed by name (size's) described as such."""

from __future__ import annotations

from dataclasses import dataclass

import jsonschema
import pytest

from hipsim.cli.documents import SCHEMAS, schema
from hipsim.cli.documents_more import MORE_SCHEMAS, SizeRun
from hipsim.present.pages import Verdict as PageVerdict
from hipsim.records import SCHEMA_VERSION, Level, Record, Verdict


def test_every_document_is_listed_and_its_schema_is_valid():
    for name in MORE_SCHEMAS:
        assert SCHEMAS[name] is MORE_SCHEMAS[name]
        document = schema(name)
        jsonschema.Draft202012Validator.check_schema(document)
        version = "2" if name == "wear-test" else SCHEMA_VERSION  # 2: the wear test's verdict a records.Verdict
        assert document["version"] == version and document["$id"].endswith(f"/{name}/v{version}.json")


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


@dataclass(frozen=True)
class _BlockAndVerdict(Record):
    """A page's Verdict block beside a records.Verdict: two records of one class name."""

    block: PageVerdict
    verdict: Verdict


def test_two_records_of_one_class_name_get_apart_definitions():
    """Each its own $defs entry, the second prefixed with its module's name; a document of both validates."""
    both = _BlockAndVerdict.json_schema()
    assert set(both["$defs"]) == {"Verdict", "records_Verdict"}
    assert both["properties"]["block"] == {"$ref": "#/$defs/Verdict"}
    assert both["properties"]["verdict"] == {"$ref": "#/$defs/records_Verdict"}
    assert (
        "level" in both["$defs"]["records_Verdict"]["properties"] and "word" in both["$defs"]["Verdict"]["properties"]
    )
    document = _BlockAndVerdict(PageVerdict("open", "NOT RATED", ("No drive.",)), Verdict(Level.NOT_MADE, "none"))
    jsonschema.Draft202012Validator(both).validate(document.to_json())
    # report's JSON now holds one kind: the drive's verdict at the top is the sizing's own (records.Verdict)
    report = schema("report")
    assert report["properties"]["verdict"] == {"$ref": "#/$defs/Verdict"}
    assert report["$defs"]["SizingSummary"]["properties"]["verdict"] == {"$ref": "#/$defs/Verdict"}
