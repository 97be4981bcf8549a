"""The records of a sizing and a catalogue's ranking (hipsim.design.sizing_summary), and the ranking's verdict at
its boundaries; checks made by hand."""

from __future__ import annotations

from hipsim.design.checks import Check
from hipsim.design.ranking import Candidate
from hipsim.design.sizing_summary import check_summary, drive_summary, ranking_summary, ranking_verdict
from hipsim.machine.drive_parts import Drive, Motor, SizingRules
from hipsim.records import Level, exit_status


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
