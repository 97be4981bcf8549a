"""A station run's typed summary and verdict, by hand-computed cases (hipsim/stations/summary.py).

The motions are made here sample by sample, not by the carriage commands: each
platform's error is a short series whose RMS, peak and its time are worked out
by hand below.
"""

from __future__ import annotations

import math

import jsonschema
import numpy as np
import pytest

from hipsim.motion.trajectories import iso14242
from hipsim.records import Level, exit_status
from hipsim.stations.commands import StationMotion
from hipsim.stations.summary import StationSummary, station_summary, stations_verdict


def _motion(errors_deg: np.ndarray, desired: np.ndarray | None = None, t=None, control="2") -> StationMotion:
    n = errors_deg.shape[0]
    t = np.arange(n) * 0.5 if t is None else t
    desired = np.zeros((n, 3)) if desired is None else desired
    attitudes = desired[:, None, :] + np.radians(errors_deg)
    return StationMotion(t, desired, np.zeros((n, 3)), attitudes, control)


#: Four samples; platform 1 errs in alpha only, platform 2 in gamma only, so a swap of platforms shows.
ERRORS = np.zeros((4, 2, 3))
ERRORS[:, 0, 0] = [1.0, -3.0, 2.0, 0.0]  # m_1 alpha: RMS √(14/4), peak −3 at t = 0.5 s
ERRORS[:, 1, 2] = [0.0, 0.0, 2.0, -2.0]  # m_2 gamma: RMS √(8/4) = √2, peak +2 at t = 1.0 s (the first of equals)


def test_rms_peak_and_its_time_per_platform_and_angle():
    summary = station_summary(_motion(ERRORS))
    m1, m2 = summary.platforms
    assert (m1.platform, m2.platform) == (1, 2)
    assert (m1.controlled, m2.controlled) == (False, True)  # --control 2
    assert m1.angles["alpha"].rms_deg == pytest.approx(math.sqrt(14 / 4), rel=1e-12)
    assert m1.angles["alpha"].peak_deg == pytest.approx(-3.0, rel=1e-12)  # signed, picked by magnitude
    assert m1.angles["alpha"].peak_at_s == 0.5
    assert m1.angles["gamma"].rms_deg == 0.0 and m2.angles["alpha"].rms_deg == 0.0
    assert m2.angles["gamma"].rms_deg == pytest.approx(math.sqrt(2.0), rel=1e-12)
    assert m2.angles["gamma"].peak_deg == pytest.approx(2.0, rel=1e-12) and m2.angles["gamma"].peak_at_s == 1.0
    # Σ e² = 14 + 8 over 4 samples × 2 platforms × 3 angles = 24 values
    assert summary.sum_squared_error_deg2 == pytest.approx(22.0, rel=1e-12)
    assert summary.rms_error_deg == pytest.approx(math.sqrt(22.0 / 24), rel=1e-12)
    assert summary.samples == 4 and summary.duration_s == 1.5 and summary.control == "2"
    platform, angle, worst = summary.worst
    assert (platform, angle, worst.peak_deg) == (1, "alpha", pytest.approx(-3.0))  # by |peak|, not the signed value


def test_the_json_keeps_its_keys_and_matches_its_schema():
    summary = station_summary(_motion(ERRORS))
    document = summary.to_json()
    assert list(document) == [
        "control",
        "weights",
        "samples",
        "duration_s",
        "sum_squared_error_deg2",
        "rms_error_deg",
        "platforms",
    ]
    assert list(document["platforms"][0]) == ["platform", "angles", "controlled"]  # no "iso" without a load
    assert document["platforms"][1]["angles"]["gamma"] == {
        "rms_deg": pytest.approx(math.sqrt(2)),
        "peak_deg": pytest.approx(2.0),
        "peak_at_s": 1.0,
    }
    jsonschema.validate(document, StationSummary.json_schema())


def _iso_run(offset_deg: tuple[float, float]) -> StationSummary:
    """Two ISO cycles tracked perfectly by m_2; m_1 off by a constant on beta."""
    iso = iso14242(rate=100.0, cycles=2)
    errors = np.zeros((len(iso.t), 2, 3))
    errors[:, 0, 1], errors[:, 1, 1] = offset_deg
    return station_summary(_motion(errors, iso.q, iso.t), iso.Fe, "ISO", periodic=True)


def test_each_station_is_judged_on_its_own_platform():
    """m_1 4° off, m_2 exact: station 1 FAILs and station 2 PASSes; platforms swapped, the words would swap."""
    summary = _iso_run((4.0, 0.0))
    iso1, iso2 = (p.iso for p in summary.platforms)
    assert iso1 is not None and iso2 is not None
    assert iso1.verdict == Level.FAIL and iso1.failing == ("beta",)
    assert iso1.worst_deg is not None and iso1.worst_deg["beta"] == pytest.approx(4.0, abs=0.03)
    assert iso2.verdict == Level.PASS and iso2.worst_deg is not None and iso2.worst_deg["beta"] < 0.05
    assert iso1.judged.startswith("m_1's motion against") and iso2.judged.startswith("m_2's motion against")
    verdict = stations_verdict(summary)
    assert verdict.level == Level.FAIL and exit_status(summary.verdicts) == 1
    assert verdict.judged == "ISO 14242-1 (tolerances assumed): station 1 FAIL, station 2 PASS"
    assert verdict.numbers["worst_beta_1_deg"] == pytest.approx(4.0, abs=0.03)
    assert verdict.numbers["worst_peak_deg"] == pytest.approx(4.0)
    jsonschema.validate(summary.to_json(), StationSummary.json_schema())


def test_stations_passing_exit_0_and_no_load_is_no_verdict():
    summary = _iso_run((1.0, -1.0))
    assert stations_verdict(summary).level == Level.PASS and exit_status(summary.verdicts) == 0
    bare = station_summary(_motion(ERRORS))
    assert bare.verdicts == () and stations_verdict(bare).level == Level.NOT_MADE


def test_the_sliders_attitudes_state_no_verdict():
    from hipsim.stations.summary import SlidersSummary, sliders_verdict

    verdict = sliders_verdict(SlidersSummary("log.csv", 12, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
    assert verdict.level == Level.NOT_MADE and exit_status([verdict]) == 0
    assert (
        verdict.judged
        == "both platforms' attitudes from the carriages of log.csv (12 samples): how far apart they turn"
    )
    assert verdict.not_judged == "the attitudes against an acceptance limit (none is set)" and not verdict.numbers
