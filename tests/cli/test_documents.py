"""What each command prints with --summary-format json (hipsim.cli.documents): the documents' schemas, their
summaries flattened into the top level, optional parts not required. Each command's JSON validated against its
schema: tests/test_schemas.py."""

from __future__ import annotations

import argparse
import dataclasses
import shlex
from pathlib import Path

import pytest

from hipsim.cli.documents import SCHEMAS, CompareRun, ReportFiles, schema
from hipsim.cli.main import build_parser
from hipsim.rig.compare_summary import ComparisonSummary


def test_a_flattened_summarys_fields_are_the_documents_own():
    document = schema("compare")
    assert document["title"] == "hipsim compare --log FILE --summary-format json"
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
        assert schema(name)["$id"].endswith(f"/schemas/{name}/v{SCHEMAS[name].schema_version}.json")
    with pytest.raises(KeyError):
        schema("nothing")


@pytest.fixture(scope="module")
def parser():
    return build_parser()


@pytest.mark.parametrize("name", list(SCHEMAS))
def test_each_schemas_title_is_a_command_line_the_parser_takes(parser, name):
    """``hipsim stations --sliders LOG --summary-format json``, not ``hipsim stations-sliders ...`` (no such
    command): the title parses with the real parser; a mode's (a name that is not a command) parses to its command
    with an option away from that command's defaults, the option that selects the mode."""
    title = schema(name)["title"]
    assert title.startswith("hipsim ") and title.endswith(" --summary-format json"), title
    words = shlex.split(title)[1:]
    args = parser.parse_args(words)
    assert args.summary_format == "json"
    commands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices
    if name in commands:
        assert args.command == name
    else:  # a mode: its command's own document's line, with the option that selects it
        assert name.startswith(f"{args.command}-"), (name, title)
        plain = parser.parse_args(shlex.split(schema(args.command)["title"])[1:])
        assert vars(args) != vars(plain), f"{title}: no option selects the mode {name}"


def test_a_small_document_as_json():
    assert ReportFiles("page/index.html", None).to_json() == {"report": "page/index.html", "pdf": None}
    assert SCHEMAS["compare"] is CompareRun


def test_the_guide_lists_each_schema_by_its_title():
    """docs/guide/outputs.md's table: each schema's row names the command line of its title."""
    page = (Path(__file__).parents[2] / "docs" / "guide" / "outputs.md").read_text()
    for name in SCHEMAS:
        assert f"| `hipsim schema {name}` | `{schema(name)['title']}`" in page, name
