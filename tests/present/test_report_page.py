"""The design report's verdict block, rendered from the drive's verdict (hipsim/present/report_page.py), by hand."""

from __future__ import annotations

from typing import cast

from hipsim.design.checks import Check, _check, checks_verdict
from hipsim.design.demand import Duty
from hipsim.design.sizing import ModuleSizing, Sizing
from hipsim.machine.drive_parts import SizingRules
from hipsim.present.report_page import report_block
from hipsim.records import Level


def _module(i: int, peak_Nmm: float, rms_Nmm: float, speed_rpm: float) -> ModuleSizing:
    return ModuleSizing(i, peak_Nmm, rms_Nmm, speed_rpm, 0.5 * speed_rpm, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 10.0)


def _sizing(checks: tuple[Check, ...]) -> Sizing:
    modules = (_module(1, 431.1, 216.6, 950.0), _module(2, 500.0, 100.0, 40.0), _module(3, 20.0, 10.0, 30.0))
    return Sizing(modules, None, checks, None, SizingRules(), cast(Duty, None))  # the block reads no duty


MISSING = Check(2, "max_speed", None, None, None, None, "no top speed given")


def test_a_check_at_its_limit_passes_and_binds():
    size = _sizing((_check(1, "peak_curve", 300.0, 300.0), _check(2, "s1_rms", 200.0, 250.0), MISSING))
    block = report_block(size, checks_verdict(size.checks))
    assert (block.word, block.state, block.symbol) == ("PASS", "pass", "✔")
    assert block.lines == (
        "the drive passes all 2 rating checks made; 1 not made for want of data.",
        "Binding: torque under the peak curve (worst point), LN1: 300.0 N·mm against ≤ 300.0 N·mm (margin +0.0 %).",
    )


def test_a_check_beyond_its_limit_fails_and_is_named_worst():
    size = _sizing((_check(1, "peak_curve", 303.0, 300.0), _check(2, "s1_rms", 200.0, 250.0)))
    verdict = checks_verdict(size.checks)
    block = report_block(size, verdict)
    assert verdict.level == Level.FAIL and (block.word, block.state, block.symbol) == ("FAIL", "fail", "✘")
    assert block.lines[0] == "the drive fails 1 of the 2 rating checks made."
    assert block.lines[1] == (
        "Worst: torque under the peak curve (worst point), LN1: 303.0 N·mm against ≤ 300.0 N·mm (margin −1.0 %)."
    )


def test_no_check_made_is_not_rated_with_what_the_cycle_asks():
    size = _sizing((MISSING,))
    verdict = checks_verdict(size.checks)
    block = report_block(size, verdict)
    assert verdict.level == Level.NOT_MADE and (block.word, block.state, block.symbol) == ("NOT RATED", "open", "–")
    assert block.lines[1] == (
        "The cycle asks at most 500.0 N·mm peak (LN2), 216.6 N·mm RMS (LN1) and 950.0 rpm (LN1) at the screw shafts."
    )
