"""The identification's records by hand: the held-out note's keys, ``identify --base``'s listing in file units, and
the document's schema (the whole summary of a fit by hand: tests/rig/identification/test_fit_laws.py)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from hipsim.rig.compare_summary import MotorError
from hipsim.rig.identification.summary import (
    HeldOutLog,
    IdentificationSummary,
    PhaseNote,
    base_listing,
    phase_note,
)


def test_a_note_has_its_phases_only_with_all_three_arrays():
    edges, a, b = np.array([0.0, 50.0, 100.0]), np.array([[1.0, 2.0, 3.0], [4.0, np.nan, 6.0]]), np.ones((2, 3))
    full = phase_note(["load 1 to 2 N"], edges, a, b)
    assert full.to_json() == {
        "envelope_warnings": ["load 1 to 2 N"],
        "gait_phase_edges_percent": [0.0, 50.0, 100.0],
        "identified_phase_rms_error_Nmm": [[1.0, 2.0, 3.0], [4.0, None, 6.0]],  # a bin without samples: null
        "starting_phase_rms_error_Nmm": [[1.0] * 3] * 2,
    }
    for missing in ((None, a, b), (edges, None, b), (edges, a, None)):
        assert phase_note(("w",), *missing) == PhaseNote(("w",))


def test_a_held_out_log_lays_its_note_beside_its_errors():
    motor = MotorError(0.1, 0.01, 0.2, 1.5, 3.0, 0.25, 100.0, 200.0, 0.015, 0.015, {"tau_m": 1.0})
    entry = HeldOutLog("h.csv", {"1": motor}, {"1": motor}, PhaseNote(("x",)))
    assert list(entry.to_json()) == ["log", "identified", "starting", "envelope_warnings"]
    assert entry.to_json()["identified"]["1"]["rms_error_Nmm"] == 1.5
    assert list(HeldOutLog("h.csv", {}, {}).to_json()) == ["log", "identified", "starting"]


def test_the_base_listing_in_file_units():
    """Prior mean and std in SI divided by each base parameter's scale (kg·mm² is 1e-6 kg·m²)."""
    parameters = (
        SimpleNamespace(label="I_L", key="screw.inertia_kgmm2", unit="kg·mm²", definition="I_L"),
        SimpleNamespace(label="m_L", key="slider.mass_kg", unit="kg", definition="m_L + 0.5·m_l"),
    )
    base = SimpleNamespace(parameters=parameters, scale=np.array([1e-6, 1.0]))
    listing = base_listing(base, np.array([5e-5, 3.7]), np.array([1.5e-5, 0.9]))  # type: ignore[arg-type]
    rows = listing.to_json()["base_parameters"]
    assert [r["name"] for r in rows] == ["I_L", "m_L"] and rows[1]["definition"] == "m_L + 0.5·m_l"
    assert [r["key"] for r in rows] == ["screw.inertia_kgmm2", "slider.mass_kg"]
    assert rows[0]["prior"] == pytest.approx(50.0, rel=1e-12) and rows[0]["prior_std"] == pytest.approx(15.0)
    assert (rows[1]["prior"], rows[1]["prior_std"], rows[1]["unit"]) == (3.7, 0.9, "kg")


def test_the_summary_schema_has_validation_only_sometimes():
    schema = IdentificationSummary.json_schema("identify")
    assert "validation" in schema["properties"] and "validation" not in schema["required"]
    assert {"logs", "rows", "base_parameters", "identified", "held", "residual_rms_Nmm"} <= set(schema["required"])
    note = schema["$defs"]["HeldOutLog"]
    assert "envelope_warnings" in note["properties"] and "envelope_warnings" not in note["required"]
