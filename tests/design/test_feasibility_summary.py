"""The feasibility summary and its verdict, by hand (hipsim/design/feasibility_summary.py)."""

from __future__ import annotations

import jsonschema
import pytest

from hipsim.design.feasibility import Crossing, Limits
from hipsim.design.feasibility_summary import FeasibilitySummary, feasibility_summary
from hipsim.records import Level, exit_status

ALL = Limits(stroke=0.1, slider_speed=1.0, slider_acceleration=10.0, motor_speed=300.0, motor_torque=2.0)


def _summary(limits=ALL, crossings=(), k=1.0, period=1.0, noisy=False):
    return feasibility_summary("iso", "published", limits, crossings, k, period, False, noisy)


def test_within_every_limit_is_feasible():
    s = _summary()
    assert s.feasible is True and s.level == Level.FEASIBLE and exit_status([s]) == 0
    assert s.not_checked == () and s.verdict.startswith("within every machine limit (")
    assert s.cycle_frequency_Hz == 1.0
    jsonschema.validate(s.to_json(), FeasibilitySummary.json_schema())


def test_a_crossing_is_not_feasible_and_the_speed_scales_the_frequency():
    crossing = Crossing("motor_speed", 2, 0.25, 600.0, 300.0)
    s = _summary(crossings=[crossing], k=0.5, period=2.0)
    assert s.feasible is False and s.level == Level.NOT_FEASIBLE and exit_status([s]) == 1
    assert s.crossings[0].excess == pytest.approx(2.0) and s.crossings[0].t_s == 0.25
    assert s.cycle_frequency_Hz == pytest.approx(0.25)  # 0.5× the speed of a 2 s cycle
    assert s.verdict.startswith("crosses 1 of the limits checked")
    assert _summary(crossings=[crossing], k=None).cycle_frequency_Hz is None  # fits at no speed


def test_limits_not_checked_leave_the_verdict_open_and_say_so():
    s = _summary(limits=Limits(stroke=0.1))
    assert s.feasible is None and s.level == Level.FEASIBLE and exit_status([s]) == 0
    assert "motor speed" in " ".join(s.not_checked) and "not checked:" in s.verdict
    assert s.verdict.endswith(
        "; not checked: motor speed, motor torque (no drive data: give --drive, or a [motor] table in the parameter file)"
    )
    assert "--cutoff" in _summary(noisy=True).verdict


def test_each_verdict_line_whole():
    names = "stroke, motor speed, motor torque, singularity measure, load range, slider speed, slider acceleration"
    assert _summary().verdict == f"within every machine limit ({names})"
    crossing = Crossing("motor_speed", 2, 0.25, 600.0, 300.0)
    assert _summary(crossings=[crossing, crossing]).verdict == f"crosses 2 of the limits checked ({names})"
    few = Limits(stroke=0.1, motor_speed=300.0)
    no_drive = "no drive data: give --drive, or a [motor] table in the parameter file"
    missing = "motor torque"
    covered = "stroke, motor speed, singularity measure, load range"
    assert _summary(limits=few).verdict == (
        f"within the limits checked ({covered}); not checked: {missing} ({no_drive})"
    )
    given = feasibility_summary("iso", "published", few, [crossing], 0.5, 1.0, True, True)
    assert given.verdict == (
        f"crosses 1 of the limits checked ({covered}); not checked: {missing} "
        "(not in the drive file or the parameter file's [motor] table); on a motion the noise check flagged: its "
        "speeds and accelerations carry the noise (filter it with --cutoff 6)"
    )
    assert given.noise_flagged is True and given.feasible is False and given.speed_factor == 0.5
    assert (given.trajectory, given.parameters) == ("iso", "published")
    assert given.checked == tuple(covered.split(", ")) and given.not_checked == ("motor torque",)


def test_a_crossing_s_record_is_the_crossing_s_figures():
    crossing = Crossing("motor_speed", 2, 0.25, 600.0, 300.0)
    record = _summary(crossings=[crossing]).crossings[0]
    assert (record.limit, record.motor, record.t_s, record.needed, record.allowed) == (
        "motor_speed",
        2,
        0.25,
        600.0,
        300.0,
    )
    assert record.message == crossing.message() and record.excess == crossing.excess
    assert _summary(k=0.7, period=None).cycle_frequency_Hz is None and _summary(k=0.7).speed_factor == 0.7
