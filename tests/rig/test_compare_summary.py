"""A model-versus-rig comparison's summary as a record (hipsim/rig/compare_summary.py): built by hand, its JSON keys
(``from`` for the phases' origin, the phases left out when the log does not repeat) and its schema."""

from __future__ import annotations

import math

import jsonschema

from hipsim.rig.compare_summary import ComparisonSummary, MotorError, Phases


def _motor(rms: float) -> MotorError:
    return MotorError(
        rms, rms / 10, 0.25, rms, 2 * rms, 0.5, 10 * rms, 20 * rms, 0.1, 0.1, {"tau_m": 1.0, "tau_f": math.nan}
    )


def _summary(phases: Phases | None) -> ComparisonSummary:
    motors = {str(i): _motor(float(i)) for i in (1, 2, 3)}
    return ComparisonSummary(
        "rig.csv", 1000, 500.0, None, "log", "published", True, motors, 0.3, 1.0, ["a note"], phases
    )


def test_the_json_of_a_comparison_with_and_without_phases():
    phases = Phases([0.0, 0.5, 1.0], "heel strike", 0.12, ["stance", "swing"], {"1": [1.0, 2.0]})
    doc = _summary(phases).to_json()
    assert doc["phases"] == {
        "edges": [0.0, 0.5, 1.0],
        "from": "heel strike",
        "heel_strike_s": 0.12,
        "labels": ["stance", "swing"],
        "rms_error_Nmm": {"1": [1.0, 2.0]},
    }
    assert doc["motors"]["2"]["rms_error_Nmm"] == 2.0 and doc["motors"]["1"]["model_parts_rms_Nmm"]["tau_f"] is None
    assert doc["cutoff_Hz"] is None and doc["notes"] == ["a note"]
    jsonschema.validate(doc, ComparisonSummary.json_schema())
    plain = _summary(None).to_json()
    assert "phases" not in plain
    jsonschema.validate(plain, ComparisonSummary.json_schema())
    assert "from" in ComparisonSummary.json_schema()["$defs"]["Phases"]["required"]
