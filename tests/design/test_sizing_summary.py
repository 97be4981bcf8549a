"""The records of a sizing and a catalogue's ranking (hipsim.design.sizing_summary), and the ranking's verdict at
its boundaries; checks made by hand."""

from __future__ import annotations

from typing import cast

import numpy as np
import pytest

from hipsim.design.checks import Check
from hipsim.design.demand import Duty
from hipsim.design.ranking import Candidate
from hipsim.design.sizing import JointSizing, MarginBand, ModuleSizing, Sizing
from hipsim.design.sizing_summary import (
    CheckSummary,
    RulesSummary,
    ScrewChecks,
    candidate_summary,
    check_summary,
    drive_summary,
    ranking_summary,
    ranking_verdict,
    sizing_summary,
)
from hipsim.machine.drive_parts import Amplifier, Drive, Gearbox, LeadScrew, Motor, SizingRules, TorqueSpeedCurve
from hipsim.records import Level, Verdict, exit_status


def _candidate(name: str, *passed: bool | None) -> Candidate:
    """A combination whose checks pass, fail or were not made as given (margins +0.2, −0.1, none)."""
    margins = {True: 0.2, False: -0.1, None: None}
    checks = tuple(Check(1, "max_speed", 1.0, None if p is None else 1.0, margins[p], p, "", "iso") for p in passed)
    return Candidate(Drive(Motor(name, rotor_inertia=2e-5, cost=3.0)), checks)


def test_the_ranking_verdict_at_its_boundaries():
    one_passes = [_candidate("a", False), _candidate("b", True, None)]
    assert ranking_verdict(one_passes).level is Level.FEASIBLE
    assert ranking_verdict(one_passes).numbers == {"combinations": 2.0, "passing": 1.0, "checked": 2.0}
    none_passes = [_candidate("a", False), _candidate("b", True, False)]  # one failing check fails the combination
    assert ranking_verdict(none_passes).level is Level.NOT_FEASIBLE and exit_status([ranking_verdict(none_passes)]) == 1
    unchecked = [_candidate("a", None), _candidate("b")]
    verdict = ranking_verdict(unchecked)
    assert verdict.level is Level.NOT_MADE and exit_status([verdict]) == 0
    mixed = ranking_verdict([_candidate("a", None), _candidate("b", False)])
    assert mixed.level is Level.NOT_FEASIBLE and mixed.not_judged == "1 combination(s) with no check made"


def test_a_check_and_a_candidate_as_records():
    c = check_summary(Check(2, "max_speed", 3000.0, 6000.0, 0.5, True, "d", "iso"))
    assert (c.module, c.label, c.unit, c.bound, c.margin) == (2, "peak motor speed", "rpm", "max", 0.5)
    shown = [_candidate("b", True), _candidate("a", False)]
    summary = ranking_summary(shown, shown[:1], SizingRules(), "size", [(None, ())], ["why"])
    (first,) = summary.candidates
    assert first.motor == "b" and first.rotor_inertia_kgcm2 == 0.2 and first.cost == 3.0 and first.passed is True
    assert first.first_failure is None and first.first_failure_text == "why"
    document = summary.to_json()
    assert document["screw_checks"] == [{"screw": None, "checks": []}] and document["verdict"]["level"] == "FEASIBLE"
    assert "screw_checks" not in ranking_summary(shown, shown, SizingRules(), "margin").to_json()
    assert "first_failure_text" not in ranking_summary(shown, shown, SizingRules(), "margin").to_json()["candidates"][0]


def test_a_drive_is_echoed_as_given():
    drive = drive_summary(Drive(Motor("m", rotor_inertia=1.4e-5)))
    assert drive.name == "m" and drive.motor is not None and drive.motor["rotor_inertia"] == 1.4e-5
    assert drive.amplifier is None and drive.screw is None


def _module(i: int) -> ModuleSizing:
    """A module's demands (the summary echoes them; figures chosen apart so that a swap shows)."""
    return ModuleSizing(i, 100.0 * i, 50.0 * i, 1000.0, 500.0, 20.0, 300.0, 310.0, 200.0, 12.0, 4.0, 1.5, 80.0)


#: The drive of the tests: every part fitted, an S1 curve, a catalogue's rated power.
DRIVE = Drive(
    Motor(
        "m",
        continuous=TorqueSpeedCurve(np.array([0.0, 300.0]), np.array([1.2, 1.0])),
        rotor_inertia=2e-5,
        rated_power=400.0,
        cost=120.0,
    ),
    Amplifier(peak_current=10.0),
    Gearbox("g5", ratio=5.0, efficiency=0.9),
    LeadScrew("s10", lead=0.01),
    source="drives.toml",
)
#: Rules away from the defaults, each its own figure.
RULES = SizingRules(5.0, 1e7, 80.0, 90.0, 0.7, 0.4)


def test_a_check_is_echoed_whole_with_its_kind():
    c = check_summary(Check(3, "screw_life", 1e6, 5e6, -0.8, False, "at module 3", "iso"))
    assert c == CheckSummary(
        3,
        "screw_life",
        1e6,
        5e6,
        -0.8,
        False,
        "at module 3",
        "iso",
        "lead screw L10 life",
        "cycles",
        "min",
        "ISO 3408-5: L10 = (C_a/F_m)³·10⁶ rev, F_m the cubic mean over revolutions",
    )


def test_the_sizing_summary_of_a_hand_made_sizing_with_its_bands():
    """Binding: the smallest margin (LN2's 0.1, not LN1's 0.5); bands: margin ± 1.96σ, confident when margin ≥ 1.645σ
    (0.5 with σ = 0.1 is, 0.1 is not); a check not made has no band."""
    fast = Check(1, "max_speed", 3000.0, 6000.0, 0.5, True, "at 0.2 s", "iso")
    rms = Check(2, "s1_rms", 900.0, 1000.0, 0.1, True, "", "iso")
    life = Check(3, "screw_life", None, None, None, None, "no dynamic load rating", "iso")
    modules = (_module(1), _module(2), _module(3))
    joints = (JointSizing("a_11", 800.0, 400.0),)
    size = Sizing(modules, joints, (fast, rms, life), DRIVE, RULES, cast(Duty, None))  # the duty is not summarised
    bands = (MarginBand(fast, 0.1), MarginBand(rms, 0.1), MarginBand(life, None))
    summary = sizing_summary(size, bands)
    assert summary.modules == modules and summary.joints == joints
    assert summary.checks == tuple(check_summary(c) for c in (fast, rms, life))
    assert summary.binding == check_summary(rms) and summary.passed is True
    assert summary.verdict.level is Level.PASS and "checks of m + g5 + s10 pass" in summary.verdict.judged
    assert summary.rules.to_json() == {
        "inertia_ratio_max": 5.0,
        "life_target_cycles": 1e7,
        "winding_rise_max": 80.0,
        "rated_winding_rise": 90.0,
        "critical_speed_factor": 0.7,
        "buckling_factor": 0.4,
    }
    assert summary.margin_bands is not None
    first, second, third = (b.to_json() for b in summary.margin_bands)
    assert first == {
        "module": 1,
        "name": "max_speed",
        "margin": 0.5,
        "margin_std": 0.1,
        "margin_lo95": pytest.approx(0.5 - 0.196, abs=1e-4),
        "margin_hi95": pytest.approx(0.5 + 0.196, abs=1e-4),
        "passes_with_95_confidence": True,
    }
    assert (second["module"], second["name"], second["passes_with_95_confidence"]) == (2, "s1_rms", False)
    assert third == {
        "module": 3,
        "name": "screw_life",
        "margin": None,
        "margin_std": None,
        "margin_lo95": None,
        "margin_hi95": None,
        "passes_with_95_confidence": None,
    }
    drive = summary.drive
    assert drive is not None and (drive.name, drive.source) == ("m + g5 + s10", "drives.toml")
    assert drive.motor is not None and drive.motor["continuous"] == {
        "speed_rad_s": [0.0, 300.0],
        "torque_Nm": [1.2, 1.0],
    }
    assert drive.motor["peak"] is None and drive.motor["rated_power"] == 400.0
    assert drive.amplifier is not None and drive.amplifier["peak_current"] == 10.0
    assert drive.gearbox == {"name": "g5", "ratio": 5.0, "efficiency": 0.9, "inertia": 0.0}
    assert drive.screw is not None and (drive.screw["name"], drive.screw["lead"]) == ("s10", 0.01)
    assert "margin_bands" not in sizing_summary(size).to_json()


def test_a_sizing_without_a_drive_or_a_check_made():
    size = Sizing((_module(1),), None, (), None, SizingRules(), cast(Duty, None))
    summary = sizing_summary(size)
    assert summary.drive is None and summary.binding is None and summary.passed is None and summary.joints is None
    assert summary.verdict.level is Level.NOT_MADE and summary.verdict.judged == "no check of the drive could be made"


def test_a_candidate_names_its_binding_its_motors_binding_and_its_first_failure():
    """The screw's life fails (margin −0.8): the binding check and the first failure; among the motor's own checks the
    RMS torque binds (0.1 below the speed's 1/3); the winding's rise was not checked."""
    life = Check(1, "screw_life", 1e6, 5e6, -0.8, False)
    fast = Check(2, "max_speed", 2000.0, 3000.0, 1 / 3, True)
    rms = Check(1, "s1_rms", 450.0, 500.0, 0.1, True)
    hot = Check(1, "winding_rise", None, 100.0, None, None, "no thermal data")
    c = candidate_summary(Candidate(DRIVE, (life, fast, rms, hot)), "the screw wears out")
    assert (c.drive, c.motor, c.gearbox, c.screw) == ("m + g5 + s10", "m", "g5", "s10")
    assert c.passed is False and c.margin == -0.8 and c.unchecked == ("winding_rise",)
    assert c.binding == check_summary(life) and c.first_failure == check_summary(life)
    assert c.motor_binding == check_summary(rms)
    assert c.checks == tuple(check_summary(x) for x in (life, fast, rms, hot))
    assert (c.rated_power_W, c.rated_power_source) == (400.0, "catalogue")
    assert c.rotor_inertia_kgcm2 == pytest.approx(0.2, rel=1e-12) and c.cost == 120.0
    assert c.first_failure_text == "the screw wears out"
    bare = candidate_summary(Candidate(Drive(Motor("n")), ()))
    assert (bare.gearbox, bare.screw, bare.rotor_inertia_kgcm2, bare.cost, bare.passed) == (
        None,
        None,
        None,
        None,
        None,
    )
    assert bare.rated_power_W is None and bare.rated_power_source.startswith("unknown")


def test_the_ranking_verdicts_words_whole():
    assert ranking_verdict([_candidate("a", True), _candidate("b", False)]) == Verdict(
        Level.FEASIBLE,
        "1 of 2 combinations pass every check",
        "",
        {"combinations": 2.0, "passing": 1.0, "checked": 2.0},
    )
    assert ranking_verdict([_candidate("a", None), _candidate("b")]) == Verdict(
        Level.NOT_MADE,
        "no check of any of 2 combinations could be made",
        "",
        {"combinations": 2.0, "passing": 0.0, "checked": 0.0},
    )
    assert ranking_verdict([_candidate("a", False), _candidate("b", False), _candidate("c", None)]) == Verdict(
        Level.NOT_FEASIBLE,
        "0 of 3 combinations pass every check",
        "1 combination(s) with no check made",
        {"combinations": 3.0, "passing": 0.0, "checked": 2.0},
    )


def test_a_ranking_summary_keeps_its_rules_order_and_screws_names():
    both = [_candidate("b", True), _candidate("a", False)]
    life = Check(1, "screw_life", 1e6, 5e6, -0.8, False)
    summary = ranking_summary(both, both, RULES, "margin", [("s10", (life,)), (None, ())])
    assert summary.rank == "margin" and summary.rules == RulesSummary.of(RULES) and summary.rules.buckling_factor == 0.4
    assert summary.screw_checks == (ScrewChecks("s10", (check_summary(life),)), ScrewChecks(None, ()))
    assert [c.motor for c in summary.candidates] == ["b", "a"]
    with pytest.raises(ValueError, match="zip"):  # a failure text for each combination shown, no fewer
        ranking_summary(both, both, RULES, "size", failure_texts=["why"])
