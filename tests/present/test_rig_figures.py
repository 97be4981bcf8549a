"""The comparison page's own text (hipsim.present.rig_figures): the verdict block against --accept with the worst
motor by its relative error, and the table's rows, from summaries made by hand. The figures and the folder:
rig/test_compare.py."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

from hipsim.present.rig_figures import _rows, comparison_verdict


def motor(rms_error, measured_rms, away=None):
    return SimpleNamespace(
        measured_rms_Nmm=measured_rms,
        measured_peak_Nmm=2 * measured_rms,
        rms_error_Nmm=rms_error,
        relative_rms_error=rms_error / measured_rms,
        peak_error_Nmm=3 * rms_error,
        relative_peak_error=1.5 * rms_error / measured_rms,
        peak_error_t_s=0.1234,
        rms_error_away_from_reversals_Nmm=rms_error if away is None else away,
    )


# motor 1 has the largest error in N·mm, motor 2 the largest share of its torque: motor 2 is the worst
SUMMARY: Any = SimpleNamespace(motors={"1": motor(6.0, 200.0), "2": motor(5.0, 100.0, 4.0), "3": motor(1.0, 100.0)})


def test_without_a_threshold_nothing_is_judged_but_the_worst_motor_is_named():
    verdict = comparison_verdict(SUMMARY)
    assert (verdict.state, verdict.word) == ("open", "NOT JUDGED")
    assert verdict.lines == (
        "No acceptance threshold given (--accept PERCENT).",
        "Worst: motor 2, RMS error 5.00 N·mm = 5.00 % of its measured RMS torque (4.00 N·mm away from reversals).",
    )


def test_a_threshold_at_the_worst_error_passes_and_just_below_it_fails():
    passed = comparison_verdict(SUMMARY, accept=0.05)  # motor 2 at exactly 5 %
    assert (passed.state, passed.word) == ("pass", "PASS")
    assert passed.lines[0] == "Every motor's RMS error is within 5 % of its measured RMS torque."
    failed = comparison_verdict(SUMMARY, accept=0.0499)
    assert (failed.state, failed.word) == ("fail", "FAIL")
    assert failed.lines[0] == "1 of 3 motors exceed the accepted 4.99 % RMS error."


def test_the_rows_per_motor_in_newton_millimetres_and_percent():
    rows = _rows(SUMMARY)
    assert [r[0] for r in rows] == ["M1", "M2", "M3"]
    assert rows[1] == ["M2", "100.0", "200.0", "5.00", "5.00", "15.0", "7.50", "0.123", "4.00"]
