"""The compare page's verdict block, rendered from the acceptance verdict (hipsim/present/rig_figures.py), by hand."""

from __future__ import annotations

import math

import pytest

from hipsim.present.rig_figures import comparison_block
from hipsim.records import Level
from hipsim.rig.compare_summary import ComparisonSummary, MotorError
from hipsim.rig.compare_verdict import acceptance_verdict


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
