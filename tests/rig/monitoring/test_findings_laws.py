"""hipsim.rig.monitoring.findings pinned by hand: the load-cell alternative, the flags' words, notes and duplicates.

The chart is the one of tests/rig/monitoring/test_control_chart_laws.py: baseline 10.0, 10.2, 9.8 mm (μ₀ = 10, σ₀ = 0.2), then
10.5, 11.0, 10.4 mm: z = 10.1, 10.28, 10.304 against the upper limits 10.12, 10.1537, 10.1718 (λ = 0.2, L = 3).
With r_h = 25 mm the changes of μ_h are 0.02, 0.04, 0.016; against D = 0.03 the second is an alarm, the third a
notice. Its standard deviation √(0.1² + 0.2²/3)/25 = 0.0061101.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import pytest
from support import given

from hipsim.rig.monitoring import findings
from hipsim.rig.monitoring.findings import (
    INCOMPLETE,
    LOAD_GAIN_DRIFT,
    change_text,
    duplicates,
    load_cell_text,
    missing_cycles,
)
from hipsim.rig.monitoring.snapshots import Skipped

CYCLES = [100_000, 500_000, 750_000, 1_000_000, 1_100_000, 1_200_000, 1_300_000]
ESTIMATE = [20.0, 10.0, 10.2, 9.8, 10.5, 11.0, 10.4]
R_H = 25.0
BASELINE = (500_000, 1_000_000)
STD = math.sqrt(0.01 + 0.04 / 3) / 25.0
NAN = math.nan


def find(*args: Any, **options: Any) -> findings.Findings:
    """The findings with the three-snapshot baseline these hand values are of (the default needs five)."""
    return findings.find(*args, **({"baseline_min": 3} | options))


def rows(estimate=ESTIMATE, station_1=None, station_2=None, separated=False, gain=None, samples=None, notes=None):
    """The monitor's rows (cycle, file, …) of one estimate per snapshot, errors 0.1 mm."""
    n = len(estimate)
    out = []
    for k in range(n):
        out.append(
            {
                "cycle": CYCLES[k],
                "last_cycle": CYCLES[k] + 999,
                "file": f"s{k}.csv",
                "samples": (samples or [1000] * n)[k],
                "load_friction_mm": estimate[k],
                "load_friction_mm_std": 0.1,
                "load_friction_1_mm": (station_1 or [NAN] * n)[k],
                "load_friction_1_mm_std": 0.1,
                "load_friction_2_mm": (station_2 or [NAN] * n)[k],
                "load_friction_2_mm_std": 0.1,
                "stations": "separated" if separated else "shared",
                "load_gain": (gain or [NAN] * n)[k],
                "note": (notes or [""] * n)[k],
            }
        )
    return out


def test_the_constants():
    assert (INCOMPLETE, LOAD_GAIN_DRIFT) == (0.9, 0.01)


def test_the_load_cell_alternative_by_hand():
    # a₀ = 10 mm, r_h = 25 mm: a rise of μ_h by 0.04 is Δa = 1 mm, which a gain g = 10/11 − 1 = −9.1 % alone reads
    # as; ±3 % reads as ∓0.03/1.03·10/25 = ∓0.011650.
    start = (
        "or the load cell's calibration: the load term cannot tell friction from a load-cell gain drift, and a drift "
        "of -9.1 % alone reads as this change (±3 % reads as ∓0.0117); "
    )
    assert load_cell_text(0.04, 10.0, R_H) == start + (
        "tell them apart by checking the load cell against a reference load, or log the commanded load "
        "(Fe_cmd_N) to compare with the measured one per snapshot"
    )
    for gain, signed in ((0.02, "+2.0"), (-0.02, "-2.0")):
        assert load_cell_text(0.04, 10.0, R_H, gain) == start + (
            f"the commanded load logged with it says the measured load drifted by {signed} % since the baseline: "
            "check the load cell's calibration"
        )
    for gain in (0.005, 0.01):  # a drift of 1 % exactly is within 1 %
        assert load_cell_text(0.04, 10.0, R_H, gain) == start + (
            "the commanded load logged with it agrees with the measured one within 1% of the baseline's ratio: "
            "not the load cell"
        )
    assert "drifted by +10.0 % since" in load_cell_text(0.04, 10.0, R_H, 0.1)
    # A fall: g = 10/9 − 1 = +11.1 %.
    assert "a drift of +11.1 % alone" in load_cell_text(-0.04, 10.0, R_H)


def test_the_change_in_words():
    assert change_text(0.0074, 2.0, "the two stations' mean") == (
        "+0.0074 in the two stations' mean: up to +0.0148 in one of them"
    )
    assert change_text(-0.015, 1.0, "station 2") == "-0.0150 in station 2"


def test_one_station_an_alarm_then_a_notice():
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no NumPy warning (a mean of no commanded loads) reaches the user
        f = find(rows(), R_H, False, BASELINE, 0.03)
    assert f.stations is None and f.mean.mean == pytest.approx(10.0) and f.mean.worst == 1.0
    assert f.flag == ["", "", "", "", "", "alarm: the station rises", "notice: the station rises"]
    assert list(f.alarm) == [0, 0, 0, 0, 0, 1, 0] and f.alarm.dtype.kind == "i"
    text = "the hip friction coefficient rose by +0.0400 in the station ± 0.0061: the specimen's friction, "
    assert given(f.first).to_json() == {
        "cycle": 1_200_000,
        "file": "s5.csv",
        "kind": "alarm",
        "where": "the station",
        "direction": "rise",
        "hip_mu_change": pytest.approx(0.04, abs=1e-12),
        "hip_mu_change_std": pytest.approx(STD, rel=1e-12),
        "worst_case_change": pytest.approx(0.04, abs=1e-12),
        "load_friction_mm": 11.0,
        "load_friction_change_mm": pytest.approx(1.0, abs=1e-12),
        "text": "alarm: " + text + load_cell_text(0.04, 10.0, R_H),
    }
    assert given(f.latest_notice).cycle == 1_300_000 and given(f.latest_notice).kind == "notice"
    assert given(f.latest_notice).hip_mu_change == pytest.approx(0.016, abs=1e-12)
    assert given(f.latest_notice).text.startswith(
        "notice: the hip friction coefficient rose by +0.0160 in the station ± "
    )
    # Without the commanded load there is no gain to compare: NaN, and no note.
    assert np.isnan(f.load_gain_change).all() and f.notes == [""] * 7


def test_the_first_alarm_is_kept_and_a_fall_is_said():
    # Falls of 0.04 and 0.06: two alarms, the first described; the words say "falls" and "fell".
    f = find(rows([20.0, 10.0, 10.2, 9.8, 9.5, 9.0, 8.5]), R_H, False, BASELINE, 0.03)
    assert f.flag[5:] == ["alarm: the station falls", "alarm: the station falls"]
    assert given(f.first).cycle == 1_200_000 and given(f.first).direction == "fall" and f.latest_notice is None
    assert given(f.first).text.startswith("alarm: the hip friction coefficient fell by -0.0400 in the station ± 0.0061")
    assert given(f.first).load_friction_change_mm == pytest.approx(-1.0, abs=1e-12)


def test_two_stations_sharing_a_load_are_judged_by_their_mean_at_twice():
    # The mean of two stations: its change 0.016 is up to 0.032 in one of them, beyond D = 0.03: both alarms.
    f = find(rows(), R_H, True, BASELINE, 0.03)
    assert f.stations is None
    said = "alarm: the two stations' mean rises (up to twice in one station)"
    assert f.flag[5:] == [said, said]
    assert given(f.first).where == "the two stations' mean" and given(f.first).worst_case_change == pytest.approx(0.08)
    assert "rose by +0.0400 in the two stations' mean: up to +0.0800 in one of them ± 0.012: " in given(f.first).text


def test_separated_stations_are_judged_each_by_its_own_chart():
    # Station 1 stays at the baseline, station 2 moves as the mean did: only station 2 is flagged, at full threshold.
    still = [20.0, 10.0, 10.2, 9.8, 10.0, 10.0, 10.0]
    f = find(rows(station_1=still, station_2=ESTIMATE, separated=True), R_H, True, BASELINE, 0.03)
    assert f.stations is not None
    assert f.flag[5:] == ["alarm: station 2 rises", "notice: station 2 rises"]
    assert given(f.first).where == "station 2" and given(f.first).worst_case_change == pytest.approx(0.04)
    # Separated rows on a one-station machine: the station's chart only.
    assert find(rows(station_1=still, station_2=ESTIMATE, separated=True), R_H, False, BASELINE, 0.03).stations is None


def test_stations_without_a_baseline_fall_back_to_the_mean():
    # Station 2 has no estimate in the baseline: its chart has a note, and the mean judges every snapshot.
    nothing = [NAN] * 7
    f = find(rows(station_1=ESTIMATE, station_2=nothing, separated=True), R_H, True, BASELINE, 0.03)
    assert f.stations is None
    assert f.flag[5].startswith("alarm: the two stations' mean rises")


def test_the_notes_incomplete_and_load_cell():
    # Median 1000 samples: 899 is incomplete (below 0.9·1000), 900 is not. Gains: baseline 2.0 (mean), then a
    # snapshot at 2.04 (+2.0 %, beyond 1 %) and one at 2.01 (+0.5 %).
    gain = [NAN, 2.0, 2.0, 2.0, 2.04, 2.01, 1.8]
    samples = [1000, 1000, 899, 1000, 900, 1000, 890]
    notes = ["", "", "", "", "", "cut at line 7", "cut at line 9"]
    f = find(rows(gain=gain, samples=samples, notes=notes), R_H, False, BASELINE, 0.03)
    np.testing.assert_allclose(f.load_gain_change[1:], [0.0, 0.0, 0.0, 0.02, 0.005, -0.1], atol=1e-12)
    assert math.isnan(f.load_gain_change[0])
    assert f.notes == [
        "",
        "",
        "incomplete: 899 of 1,000 samples",
        "",
        "load cell: measured over commanded load +2.0 % since the baseline",
        "cut at line 7",
        "cut at line 9; incomplete: 890 of 1,000 samples; load cell: measured over commanded load -10.0 % since the "
        "baseline",
    ]
    # The alarm's sentence quotes the snapshot's gain change: +0.5 % agrees with the commanded load.
    assert given(f.first).text.endswith("within 1% of the baseline's ratio: not the load cell")


def test_both_stations_flagged_are_both_said():
    f = find(rows(station_1=ESTIMATE, station_2=ESTIMATE, separated=True), R_H, True, BASELINE, 0.03)
    assert f.flag[5] == "alarm: station 1 rises; alarm: station 2 rises"
    assert given(f.first).where == "station 1"


@pytest.mark.parametrize(
    ("cycles", "missing"),
    [
        ([0, 100, 300], [200]),  # three are enough
        ([0, 300], []),  # two are not
        # Spacing 100 (a third of the steps or more are within 1.5 times the smallest): a gap of 250 misses one
        # snapshot (at 400; 500 is within half a spacing of 550).
        ([0, 100, 200, 300, 550], [400]),
        ([0, 100, 600, 1100], [200, 300, 400, 500, 700, 800, 900, 1000]),  # one step of three is a third
        # Two steps of seven are fewer than a third: the spacing is the median step (500), no gap beyond 750.
        ([0, 100, 200, 700, 1200, 1700, 2200, 2700], []),
        # Steps of 100, 100 and three of 150 (1.5 times the smallest, included): spacing 150; the gap of 400
        # misses two (800, 950).
        ([0, 100, 200, 350, 500, 650, 1050], [800, 950]),
    ],
)
def test_missing_cycles_by_hand(cycles, missing):
    assert missing_cycles(cycles) == missing


def test_no_rows_find_nothing():
    f = find([], R_H, False, BASELINE, 0.03)
    assert f.flag == [] and f.notes == [] and f.alarm.size == 0 and f.first is None


def test_duplicates_keep_the_first_of_a_cycle():
    rows_ = [
        {"cycle": 0, "last_cycle": 99, "file": "a.csv"},
        {"cycle": 99, "last_cycle": 149, "file": "b.csv"},
        {"cycle": 100, "last_cycle": 199, "file": "c.csv"},
        {"cycle": 150, "last_cycle": 199, "file": "c.csv"},  # a window of the same file: kept
    ]
    rows_[1] |= {"bytes": 120, "sha256": "5e"}  # the copy's identity, kept with its reason
    kept, left = duplicates(rows_, {"b.csv": "/logs/b.csv"})
    assert [r["file"] for r in kept] == ["a.csv", "c.csv", "c.csv"]
    assert left == [
        Skipped(
            "b.csv",
            "/logs/b.csv",
            "/logs/b.csv: covers cycles 99-149, as does a.csv (0-99): each cycle in one snapshot only (a copied file?)",
            "duplicate",
            size=120,
            sha256="5e",
        )
    ]
    # A file not among the paths is named by its name.
    _, (only,) = duplicates(rows_[:2], {})
    assert only.path == "b.csv" and only.reason.startswith("b.csv: covers cycles 99-149")
