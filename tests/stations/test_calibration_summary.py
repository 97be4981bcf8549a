"""The calibration's records by hand: units (m to mm, rad to deg), the held-out RMS over its samples, the keys."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from hipsim.stations import calibration_summary as module
from hipsim.stations import deviations as dv
from hipsim.stations.calibration import Confounding
from hipsim.stations.calibration_summary import HeldOutResidual, calibration_summary, held_out_residual


def test_a_held_out_log_rms_over_its_samples_in_degrees(monkeypatch):
    """Errors of 3° and 4° on two samples: RMS √12.5°; the starting machine's 1° and 1°: 1°."""
    errors = {
        "calibrated": np.radians(np.stack([np.full((2, 3), 3.0), np.full((2, 3), 4.0)])),
        "start": np.radians(np.ones((2, 2, 3))),
    }
    monkeypatch.setattr(module, "prediction_errors", lambda machine, log, offsets: (errors[machine], None, None))
    calibration = SimpleNamespace(machine="calibrated")
    got = held_out_residual(calibration, "start", SimpleNamespace(name="h.csv"), False)  # type: ignore[arg-type]
    assert got.log == "h.csv"
    np.testing.assert_allclose(got.rms_deg, np.full((2, 3), math.sqrt(12.5)), rtol=1e-12)
    np.testing.assert_allclose(got.start_rms_deg, np.ones((2, 3)), rtol=1e-12)


def test_the_summary_in_mm_and_degrees():
    names = dv.names()
    n = len(names)
    theta = np.zeros(n)
    theta[0], theta[-1] = 1e-3, -2.5e-4  # 1 mm, -0.25 mm
    calibration = SimpleNamespace(
        theta=theta,
        theta_std=np.full(n, 5e-5),
        determined=np.arange(n) % 2 == 0,
        logs=("a.csv",),
        samples=300,
        iterations=4,
        noise=np.radians(np.full((2, 3), 0.01)),
        residual_rms=np.radians(np.full((1, 2, 3), 0.02)),
        start_rms=np.radians(np.full((1, 2, 3), 0.5)),
        offsets=np.zeros((1, 2, 3)),
        unseen=["x"],
        weak=[],
        structure=SimpleNamespace(definitions=lambda: ["a + 1·b"]),
        confounded=(Confounding("alpha_1", 0.99, ("u", "v"), (1.0, -0.5)),),
    )
    held = HeldOutResidual("h.csv", [[0.1] * 3] * 2, [[0.2] * 3] * 2)
    document = calibration_summary(calibration, [held]).to_json()  # type: ignore[arg-type]
    values = document["values"]
    assert values[0] == {"value": names[0], "deviation_mm": pytest.approx(1.0), "std_mm": 0.05, "determined": True}
    assert values[-1]["deviation_mm"] == pytest.approx(-0.25) and values[1]["determined"] is False
    assert np.allclose(document["noise_deg"], 0.01) and np.allclose(document["start_residual_rms_deg"], 0.5)
    assert np.shape(document["residual_rms_deg"]) == (1, 2, 3) and document["offsets_deg"] == [[[0.0] * 3] * 2]
    assert document["confounded"][0]["values"] == ["u", "v"] and document["validation"][0]["log"] == "h.csv"
    assert (document["samples"], document["iterations"], document["unseen"]) == (300, 4, ["x"])
