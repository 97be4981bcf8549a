"""Every command's ``--summary-format json`` output validates against the schema ``hipsim schema COMMAND`` prints,
and the exit status follows the one rule (docs/guide/outputs.md): 0 PASS/OK/ALIKE, 1 FAIL/ALARM/DIFFERENT/NOT
FEASIBLE, 2 refused input."""

from __future__ import annotations

import json
import re
from pathlib import Path

import jsonschema
import pytest

from hipsim.cli.documents import COMMAND_LINES, SCHEMAS
from hipsim.cli.main import main
from hipsim.records import EXIT_RULE, SCHEMA_VERSION

LEVER = "geometry.lever_offset_mm=[0.3, 0, 0, 0, -0.2, 0]"


def _json(capsys, argv: list[str]) -> tuple[int, dict]:
    status = main(argv)
    captured = capsys.readouterr()
    text = captured.out if captured.out.strip().startswith("{") else captured.err[captured.err.index("{") :]
    return status, json.loads(text)


def _schema(capsys, command: str) -> dict:
    assert main(["schema", command]) == 0
    schema = json.loads(capsys.readouterr().out)
    jsonschema.Draft202012Validator.check_schema(schema)
    assert (
        schema["version"] == SCHEMAS[command].schema_version
        and schema["title"] == f"hipsim {COMMAND_LINES[command]} --summary-format json"
    )
    return schema


def _valid(capsys, command: str, document: dict) -> None:
    jsonschema.Draft202012Validator(_schema(capsys, command)).validate(document)


@pytest.fixture(scope="module")
def stations_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("stations")
    return out


def test_stations_modes(tmp_path, capsys):
    argv = ["stations", "--set", LEVER, "--control", "2", "--rate", "100", "--summary-format", "json"]
    status, document = _json(capsys, [*argv, "--out", str(tmp_path / "run")])
    assert status == 0 and document["summary"]["platforms"][0]["iso"]["verdict"] == "PASS"
    assert document["verdict"]["level"] == "PASS" and document["verdict"]["judged"].startswith("ISO 14242-1")
    _valid(capsys, "stations", document)
    sliders = ["stations", "--set", LEVER, "--sliders", str(tmp_path / "run" / "stations.csv"), "--out"]
    status, document = _json(capsys, [*sliders, str(tmp_path / "sl"), "--summary-format", "json"])
    assert status == 0
    _valid(capsys, "stations-sliders", document)
    tolerance = ["stations", "--bands", "all=0.05", "--draws", "3", "--workers", "1", "--rate", "20"]
    status, document = _json(capsys, [*tolerance, "--out", str(tmp_path / "tol"), "--summary-format", "json"])
    assert status == 0 and len(document["tolerance"]["controls"][0]["platforms"]) == 2
    _valid(capsys, "stations-tolerance", document)


def test_a_failing_station_exits_1(tmp_path, capsys):
    """m_1's lever 15 mm off the drawing while m_2 is commanded: the follower leaves ISO 14242-1's ±3°."""
    argv = ["stations", "--set", "geometry.lever_offset_mm=[15, 0, 0, 0, 0, 0]", "--control", "2", "--rate", "100"]
    status, document = _json(capsys, [*argv, "--out", str(tmp_path / "f"), "--summary-format", "json"])
    verdicts = [p["iso"]["verdict"] for p in document["summary"]["platforms"]]
    assert verdicts == ["FAIL", "PASS"] and status == 1 and document["verdict"]["level"] == "FAIL"
    _valid(capsys, "stations", document)
    assert main([*argv, "--out", str(tmp_path / "g")]) == 1
    text = capsys.readouterr().out
    assert "station 1: ISO 14242-1: FAIL" in text and "station 2: ISO 14242-1: PASS" in text


def test_iso_check(tmp_path, capsys):
    status, document = _json(capsys, ["iso-check", "--out", str(tmp_path / "iso"), "--summary-format", "json"])
    assert status == 0 and document["verdict"]["level"] == "PASS"
    _valid(capsys, "iso-check", document)
    strict = ["iso-check", "--tolerance", "alpha=0.000001", "--out", str(tmp_path / "iso2"), "--summary-format", "json"]
    status, document = _json(capsys, strict)
    assert status == 1 and document["failing"] == ["alpha"] and document["verdict"]["level"] == "FAIL"
    _valid(capsys, "iso-check", document)


def test_wear_and_its_comparison(tmp_path, capsys):
    base = ["wear", "--grid", "8x16", "--rate", "100", "--summary-format", "json"]
    status, document = _json(capsys, [*base, "--out", str(tmp_path / "w.csv")])
    assert status == 0 and document["verdict"]["level"] == "NOT MADE"  # one run: not rated
    _valid(capsys, "wear", document)
    compare = [*base, "--compare", "iso", "iso", "--report", str(tmp_path / "cmp"), "--out", str(tmp_path / "c.csv")]
    status, document = _json(capsys, compare)
    assert (
        status == 0
        and document["verdict"]["level"] == "ALIKE"
        and document["verdict"]["numbers"]["sliding_mm_mean"] == 0
    )
    _valid(capsys, "wear-compare", document)


def test_simulate(tmp_path, capsys):
    argv = ["simulate", "--plant", "analytic", "--controller", "pd", "--cycles", "0.02", "--summary-format", "json"]
    status, document = _json(capsys, [*argv, "--out", str(tmp_path / "s.csv")])
    assert status == 0 and document["simulations"][0]["iso"]["verdict"] == "NOT MADE"  # no whole cycle
    _valid(capsys, "simulate", document)


def test_a_document_whose_keys_changed_has_its_own_version():
    """compare, report, wear --compare, and since this round iso-check, stations, monitor, wear and the wear test carry
    a records.Verdict since version 2 (under the key verdict); the others are at version 1."""
    changed = {"compare", "report", "wear-compare", "iso-check", "stations", "monitor", "wear", "wear-test"}
    for name, record in SCHEMAS.items():
        assert record.schema_version == ("2" if name in changed else SCHEMA_VERSION), name
        assert record.json_schema(name)["$id"].endswith(f"/{name}/v{record.schema_version}.json")
    for name in changed:
        verdict = SCHEMAS[name].json_schema(name)["properties"]["verdict"]
        assert verdict == {"$ref": "#/$defs/Verdict"}, name


def test_the_exit_rule_table_in_the_docs_is_the_codes():
    page = (Path(__file__).resolve().parents[1] / "docs" / "guide" / "outputs.md").read_text()
    for status, levels in EXIT_RULE.items():
        row = next(line for line in page.splitlines() if re.match(rf"\|\s*{status}\s*\|", line))
        for level in levels if status != 2 else ():
            assert f"`{level}`" in row, (status, level)
    for name in SCHEMAS:
        assert f"`hipsim schema {name}`" in page, name


def test_feasible(tmp_path, capsys):
    status, document = _json(capsys, ["feasible", "--summary-format", "json"])
    assert status == 0 and document["crossings"] == []
    _valid(capsys, "feasible", document)
    fast = ["feasible", "--set", "motor.max_speed_rpm=100", "--summary-format", "json"]
    status, document = _json(capsys, fast)
    assert status == 1 and document["feasible"] is False and document["crossings"][0]["limit"] == "motor_speed"
    _valid(capsys, "feasible", document)


def test_torques(tmp_path, capsys):
    argv = ["torques", "--rate", "50", "--cycles", "2", "--summary-format", "json", "--out", str(tmp_path / "t.csv")]
    status, document = _json(capsys, argv)
    assert status == 0 and document["cond_inv_min_cycle"] in (1, 2) and document["csv"].endswith("t.csv")
    assert "joints" not in document  # the analytic model gives no joint forces
    _valid(capsys, "torques", document)
    one = ["torques", "--rate", "50", "--model", "pinocchio", "--summary-format", "json", "--out"]
    status, document = _json(capsys, [*one, str(tmp_path / "p.parquet")])
    assert (
        status == 0 and "cond_inv_min_cycle" not in document and "parquet" in document and "Fo_1" in document["joints"]
    )
    _valid(capsys, "torques", document)


def test_every_schema_is_validated_by_a_test_of_its_command():
    """Each document of ``hipsim schema`` has a test that runs its command and validates the output against it."""
    tests = Path(__file__).resolve().parent
    text = "\n".join(path.read_text(encoding="utf-8") for path in tests.rglob("test_*.py"))  # every folder of tests/
    for name in SCHEMAS:
        assert f'_valid(capsys, "{name}"' in text or f'schema("{name}")' in text, name


# --- the fits and their motions: identify (its run in tests/rig/identification/test_identified_file.py), calibrate (in
# tests/stations/test_calibration.py), identify --base, excite ----------------------------------------------------


def test_identify_base(capsys):
    status, document = _json(capsys, ["identify", "--base", "--summary-format", "json"])
    assert status == 0 and document["base_parameters"][0]["name"] == "I_m,xx"
    _valid(capsys, "identify-base", document)


def test_excite_both_kinds(tmp_path, capsys):
    """One harmonic of 1 Hz and two optimiser steps: the smallest design; its peaks within the default limits."""
    small = ["--harmonics", "1", "--frequency", "1", "--duration", "1", "--rate", "100", "--summary-format", "json"]
    argv = ["excite", *small, "--iterations", "2", "--out", str(tmp_path / "e.csv")]
    status, document = _json(capsys, argv)
    assert status == 0 and document["verdict"]["level"] == "PASS" and document["peaks"]["torque_Nmm"] <= 600.0
    assert document["csv"].endswith("e.csv") and document["harmonics"] == 1
    _valid(capsys, "excite", document)
    status, document = _json(capsys, ["excite", *small, "--for", "calibration", "--out", str(tmp_path / "c.csv")])
    assert status == 0 and document["for"] == "calibration" and "torque_Nmm" not in document["peaks"]
    assert document["verdict"]["level"] == "PASS" and "torque" in document["verdict"]["not_judged"]
    _valid(capsys, "excite-calibration", document)


def test_the_exit_section_says_when_the_fits_and_their_motions_exit_1():
    page = (Path(__file__).resolve().parents[1] / "docs" / "guide" / "outputs.md").read_text(encoding="utf-8")
    section = page.split("## Exit status")[1].split("\n## ")[0]
    for command in ("identify", "calibrate", "excite"):
        assert f"`{command}`" in section, command
    assert "written with\n`--force`" in section or "written with `--force`" in section
