"""What each command prints with --summary-format json (hipsim.cli.documents): the documents' schemas, their
summaries flattened into the top level, optional parts not required. Each command's JSON validated against its
schema: tests/test_schemas.py."""

from __future__ import annotations

import dataclasses

import pytest

from hipsim.cli.documents import SCHEMAS, CompareRun, ReportFiles, schema
from hipsim.rig.compare_summary import ComparisonSummary


def test_a_flattened_summarys_fields_are_the_documents_own():
    document = schema("compare")
    assert document["title"] == "hipsim compare --summary-format json"
    comparison = {f.name for f in dataclasses.fields(ComparisonSummary)}
    assert comparison <= set(document["properties"]) and "comparison" not in document["properties"]
    assert {"verdict", "provenance", "model_band95"} <= set(document["properties"])
    assert "model_band95" not in document["required"] and "verdict" in document["required"]
    assert "phases" not in document["required"]  # optional in the summary itself


def test_the_report_document_requires_what_every_run_has():
    document = schema("report")
    assert {"index", "pdf", "verdict", "provenance", "model", "motors"} <= set(document["required"])
    assert "rating_check" not in document["properties"]  # version 2: the verdict's level says it
    assert document["properties"]["verdict"] == {"$ref": "#/$defs/Verdict"} and document["version"] == "2"
    assert "margin_bands" in document["properties"] and "margin_bands" not in document["required"]


def test_each_schema_is_named_by_its_key_and_versioned():
    for name in SCHEMAS:
        document = schema(name)
        assert document["title"] == f"hipsim {name} --summary-format json"
        assert document["$id"].endswith(f"/schemas/{name}/v{SCHEMAS[name].schema_version}.json")
    with pytest.raises(KeyError):
        schema("nothing")


def test_a_small_document_as_json():
    assert ReportFiles("page/index.html", None).to_json() == {"report": "page/index.html", "pdf": None}
    assert SCHEMAS["compare"] is CompareRun
