"""The comparison page's own text (hipsim.present.rig_figures): the verdict block, rendered from the acceptance
verdict against --accept, with the worst motor by its relative error, and the table's rows, from summaries made by hand. The figures and the folder:
rig/test_compare.py."""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any

import pytest

from hipsim import records
from hipsim.present import pages
from hipsim.present.rig_figures import _rows, comparison_block
from hipsim.records import Level
from hipsim.rig.compare_summary import ComparisonSummary, MotorError
from hipsim.rig.compare_verdict import acceptance_verdict


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


def comparison_verdict(summary: Any, accept: float | None = None) -> pages.Verdict:
    """The page's block of the acceptance verdict on ``summary``, as write_comparison makes it."""
    verdict: records.Verdict = acceptance_verdict({i: m.relative_rms_error for i, m in summary.motors.items()}, accept)
    return comparison_block(summary, verdict)


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


def _motor(rms_error_Nmm: float, measured_rms_Nmm: float) -> MotorError:
    relative = rms_error_Nmm / measured_rms_Nmm
    return MotorError(
        rms_error_Nmm, relative, 0.1, rms_error_Nmm, 2 * rms_error_Nmm, 0.5, measured_rms_Nmm, 300.0, relative, 0.1, {}
    )


def _summary(errors: dict[str, float]) -> ComparisonSummary:
    """Motors whose measured RMS torque is 200 N·mm, with these RMS errors in [N·mm]."""
    motors = {i: _motor(e, 200.0) for i, e in errors.items()}
    return ComparisonSummary("log.csv", 10, 100.0, None, "log", "published", True, motors, 0.1, None, [])


@pytest.mark.parametrize(
    ("worst_Nmm", "word", "state"),
    [(10.0, "PASS", "pass"), (math.nextafter(10.0, 11.0), "FAIL", "fail")],  # 10 N·mm of 200: exactly 5 %
)
def test_the_block_at_the_accepted_share_is_the_verdicts(worst_Nmm, word, state):
    summary = _summary({"1": 2.0, "2": worst_Nmm, "3": 4.0})
    verdict = acceptance_verdict({i: m.relative_rms_error for i, m in summary.motors.items()}, 0.05)
    block = comparison_block(summary, verdict)
    assert (block.word, block.state, verdict.level.value) == (word, state, word)
    assert block.lines[0] == verdict.judged[0].upper() + verdict.judged[1:] + "."
    assert block.lines[1].startswith("Worst: motor 2, RMS error 10.0 N·mm = 5.00 % of its measured RMS torque")


def test_no_threshold_is_not_judged_on_the_page_and_not_made_in_the_verdict():
    summary = _summary({"1": 30.0, "2": 2.0, "3": 4.0})
    verdict = acceptance_verdict({i: m.relative_rms_error for i, m in summary.motors.items()}, None)
    block = comparison_block(summary, verdict)
    assert verdict.level == Level.NOT_MADE and (block.word, block.state, block.symbol) == ("NOT JUDGED", "open", "–")
    assert block.lines[0] == "No acceptance threshold given (--accept PERCENT)."
    assert block.lines[1].startswith("Worst: motor 1, RMS error 30.0 N·mm = 15.0 %")
