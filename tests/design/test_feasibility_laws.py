"""hipsim.design.feasibility pinned on runs written by hand: each limit, when it is first crossed, by how much.

The runs are stand-ins with the fields :func:`check_feasibility` reads (three
samples at t = 0, 0.01, 0.02 s), so every crossing's time, worst value and
excess is known: needed/allowed for a ceiling, allowed/needed for a floor.
"""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
from support import given

from hipsim.design.feasibility import (
    DEFAULT_COND_INV_FLOOR,
    DEFAULT_LOAD_RANGE,
    Crossing,
    Limits,
    check_feasibility,
    fitting_speed,
    time_scaled,
)
from hipsim.motion.trajectories import Trajectory

T = np.array([0.0, 0.01, 0.02])


def fake_run(L=None, Ld=None, Ldd=None, speed=None, tau=None, cond_inv=None, Fe=None):
    """A run of three samples; each given column is motor 1's (the others 0), shapes as a Run's."""

    def sliders(column):
        out = np.zeros((3, 2, 3))
        if column is not None:
            out[:, 0, 0] = column
            out[:, 1, 0] = column
        return out

    def motors(column):
        out = np.zeros((3, 3))
        if column is not None:
            out[:, 0] = column
        return out

    return SimpleNamespace(
        t=T,
        L=sliders(L),
        Ld=sliders(Ld),
        Ldd=sliders(Ldd),
        torques=SimpleNamespace(motor_speed=motors(speed), total=motors(tau)),
        cond_inv=np.full(3, 0.5) if cond_inv is None else np.asarray(cond_inv),
        trajectory=SimpleNamespace(Fe=np.full(3, 1000.0) if Fe is None else np.asarray(Fe)),
    )


def only(crossings):
    (crossing,) = crossings
    return crossing


def test_the_defaults():
    assert DEFAULT_COND_INV_FLOOR == 0.05 and DEFAULT_LOAD_RANGE == (0.0, 3000.0)
    assert check_feasibility(fake_run(), Limits()) == []


def test_stroke_is_the_travel_from_the_lowest_position():
    # Positions 100, 130, 120 mm: the travel from 100 mm reaches 30 mm at t = 0.01 s; stroke 25 mm.
    c = only(check_feasibility(fake_run(L=[0.10, 0.13, 0.12]), Limits(stroke=0.025)))
    assert (c.limit, c.motor, c.t) == ("stroke", 1, 0.01)
    assert c.needed == pytest.approx(0.03) and c.allowed == 0.025 and c.excess == pytest.approx(1.2)
    # A 30 mm stroke holds it, whatever the absolute position.
    assert check_feasibility(fake_run(L=[0.10, 0.13, 0.12]), Limits(stroke=0.03 + 1e-12)) == []


@pytest.mark.parametrize(
    ("field", "limit"), [("Ld", "slider_speed"), ("Ldd", "slider_acceleration"), ("speed", "motor_speed")]
)
def test_ceilings_on_the_absolute_value(field, limit):
    # Values 0.1, −0.5, 0.3 against 0.4: first over at 0.01 s (|−0.5|), worst 0.5, excess 1.25.
    ceiling: dict[str, Any] = {limit: 0.4}  # keyword arguments of Limits' several field types
    c = only(check_feasibility(fake_run(**{field: [0.1, -0.5, 0.3]}), Limits(**ceiling)))
    assert (c.limit, c.motor, c.t, c.needed, c.allowed) == (limit, 1, 0.01, 0.5, 0.4)
    assert c.excess == pytest.approx(1.25)
    # The first crossing's time is not the worst's: 0.45 at 0 s, 0.5 at 0.01 s.
    c = only(check_feasibility(fake_run(**{field: [0.45, -0.5, 0.3]}), Limits(**ceiling)))
    assert (c.t, c.needed) == (0.0, 0.5)
    # At the limit: not crossed.
    assert check_feasibility(fake_run(**{field: [0.4, -0.4, 0.1]}), Limits(**ceiling)) == []


def test_a_torque_against_a_number_and_against_a_torque_speed_curve():
    c = only(check_feasibility(fake_run(tau=[1.0, -2.0, 0.5]), Limits(motor_torque=1.5)))
    assert (c.limit, c.motor, c.t, c.needed, c.allowed) == ("motor_torque", 1, 0.01, 2.0, 1.5)
    # Peak torque 2 − 0.01·|speed| N·m: at 50 rad/s 1.5 N·m, at 150 rad/s 0.5 N·m, at 250 rad/s nothing
    # (beyond the curve's end: the speed's crossing, not the torque's). Torques 1.0, 0.6, 5.0:
    # only the second (0.6 > 0.5) is a torque crossing, allowed 0.5, excess 1.2.
    curve = lambda w: np.maximum(2.0 - 0.01 * np.abs(w), -1.0)
    run = fake_run(speed=[50.0, -150.0, 250.0], tau=[1.0, 0.6, 5.0])
    c = only(check_feasibility(run, Limits(motor_torque=curve)))
    assert (c.limit, c.motor, c.t, c.needed, c.allowed) == ("motor_torque", 1, 0.01, 0.6, pytest.approx(0.5))
    assert c.excess == pytest.approx(1.2)


def test_the_worst_is_the_largest_ratio_to_a_varying_limit():
    # Allowed 1.5, 0.5 (speeds 50, 150): torques 1.8 (ratio 1.2) and 0.9 (ratio 1.8): the worst is 0.9.
    curve = lambda w: 2.0 - 0.01 * np.abs(w)
    c = only(check_feasibility(fake_run(speed=[50.0, 150.0, 0.0], tau=[1.8, 0.9, 0.0]), Limits(motor_torque=curve)))
    assert (c.t, c.needed, c.allowed) == (0.0, 0.9, pytest.approx(0.5))


def test_the_singularity_floor_and_the_load_range():
    run = fake_run(cond_inv=[0.5, 0.04, 0.03], Fe=[100.0, 3100.0, -10.0])
    crossings = check_feasibility(run, Limits())
    by_limit = {c.limit: c for c in crossings}
    # Floor 0.05: first below at 0.01 s, worst 0.03, excess 0.05/0.03.
    assert (by_limit["cond_inv"].t, by_limit["cond_inv"].needed) == (0.01, 0.03)
    assert by_limit["cond_inv"].excess == pytest.approx(0.05 / 0.03)
    # Load above 3000 N at 0.01 s (3100 N, excess 31/30); below 0 N at 0.02 s (a floor of 0: infinite excess).
    assert (by_limit["load_max"].t, by_limit["load_max"].needed, by_limit["load_max"].allowed) == (0.01, 3100.0, 3000.0)
    assert (by_limit["load_min"].t, by_limit["load_min"].needed) == (0.02, -10.0)
    assert by_limit["load_min"].excess == math.inf
    # Ordered by excess, the largest first.
    assert [c.limit for c in crossings] == ["load_min", "cond_inv", "load_max"]
    assert all(c.motor is None for c in crossings)
    # Another floor and range: nothing crossed.
    assert check_feasibility(run, Limits(cond_inv_floor=0.03, load_range=(-10.0, 3100.0))) == []


def test_the_message():
    # 300 rad/s is 300·60/2π = 2864.8 rpm; 250 rad/s 2387.3 rpm; excess 1.2.
    c = Crossing("motor_speed", 2, 0.412, 300.0, 250.0)
    assert c.message() == "motor 2 needs a speed of 2,865 rpm at t = 0.412 s; the limit is 2,387 rpm (1.2×)"
    floor = Crossing("cond_inv", None, 0.5, 0.04, 0.05)
    assert floor.message() == (
        "the run needs a singularity measure of 0.04 at t = 0.5 s; the lowest allowed is 0.05 (1.25×)"
    )
    assert Crossing("stroke", 1, 0.0, 0.05, 0.04).message() == (
        "motor 1 needs a stroke of 50 mm at t = 0 s; the limit is 40 mm (1.25×)"
    )


def test_the_message_of_a_near_miss_shows_the_digits_that_differ():
    # 40.01 mm against 40 mm: excess 1.00025 < 1.0005, so 10 significant digits and the relative excess
    # 0.01/40 = 2.5e-4 (not "1×", and not 1 + 2.5e-4).
    near = Crossing("stroke", 3, 1.5, 0.04001, 0.04)
    assert near.message() == (
        "motor 3 needs a stroke of 40.01 mm at t = 1.5 s; the limit is 40 mm (0.00025 beyond it, relative)"
    )
    # From an excess of 1.0005 on (here exactly: 1.0005 m against 1 m), four digits and the ratio.
    assert Crossing("stroke", 1, 0.0, 1.0005, 1.0).message() == (
        "motor 1 needs a stroke of 1,000 mm at t = 0 s; the limit is 1,000 mm (1×)"
    )


def test_which_limits_a_verdict_covers():
    # The singularity floor and the load range have defaults; the motor's figures come from a machine.
    assert Limits().checked() == ["singularity measure", "load range"]
    assert Limits().unchecked() == ["stroke", "motor speed", "motor torque"]
    some = Limits(stroke=0.1, motor_torque=2.0, slider_speed=0.3, cond_inv_floor=None, load_range=None)  # type: ignore[arg-type]  # both off
    # The verdict's own order; the slider's speed and acceleration are covered when given but never "unchecked".
    assert some.checked() == ["stroke", "motor torque", "slider speed"]
    assert some.unchecked() == ["motor speed", "singularity measure", "load range"]


def test_limits_from_the_machine_and_a_drive():
    motor = {"stroke_mm": 120.0, "max_speed_rpm": 3000.0, "peak_torque_Nmm": 2500.0}
    limits = Limits.from_machine(SimpleNamespace(motor=motor))
    # 120 mm → 0.12 m; 3000 rpm → 100π rad/s; 2500 N·mm → 2.5 N·m.
    assert limits.stroke == pytest.approx(0.12) and limits.motor_speed == pytest.approx(100 * math.pi)
    assert limits.motor_torque == pytest.approx(2.5)
    assert Limits.from_machine(SimpleNamespace(motor={})) == Limits()
    # A drive's figures win; an infinite top speed is no figure.
    peak = SimpleNamespace(at=lambda w: 3.0 - w)
    drive = SimpleNamespace(motor=SimpleNamespace(top_speed=400.0, peak=peak), screw=SimpleNamespace(stroke=0.2))
    limits = Limits.from_machine(SimpleNamespace(motor=motor), drive)
    assert (limits.stroke, limits.motor_speed, limits.motor_torque) == (0.2, 400.0, peak.at)
    endless = SimpleNamespace(motor=SimpleNamespace(top_speed=math.inf, peak=None), screw=None)
    limits = Limits.from_machine(SimpleNamespace(motor=motor), endless, cond_inv_floor=0.1)
    assert limits.motor_speed == pytest.approx(100 * math.pi) and limits.motor_torque == pytest.approx(2.5)
    assert limits.stroke == pytest.approx(0.12) and limits.cond_inv_floor == 0.1
    no_stroke = SimpleNamespace(motor=SimpleNamespace(top_speed=None, peak=None), screw=SimpleNamespace(stroke=None))
    assert Limits.from_machine(SimpleNamespace(motor=motor), no_stroke).stroke == pytest.approx(0.12)


def protocol():
    t = np.linspace(0.0, 1.0, 5)
    q = np.zeros((5, 3))
    qd = np.column_stack([np.sin(2 * np.pi * t), np.zeros(5), np.zeros(5)])
    return Trajectory(t, q, qd, 2.0 * qd, np.full(5, 1000.0), name="walk", periodic=True, lines=np.arange(2, 7))


def test_time_scaled():
    # Twice the speed: half the times, twice the rates, four times the accelerations; the same load.
    tr = protocol()
    fast = time_scaled(tr, 2.0)
    np.testing.assert_allclose(fast.t, tr.t / 2)
    np.testing.assert_allclose(fast.qd, 2 * tr.qd)
    np.testing.assert_allclose(fast.qdd, 4 * tr.qdd)
    np.testing.assert_array_equal(fast.Fe, tr.Fe)
    assert fast.name == "walk at 2× speed"
    # Still periodic, each sample still on its file line.
    assert fast.periodic
    np.testing.assert_array_equal(fast.lines, [2, 3, 4, 5, 6])


def test_fitting_speed_by_bisection():
    # The model: motor 1's speed is 1000·q̇_α, at most 1000 rad/s at full speed. With a 250 rad/s limit
    # the protocol fits at a quarter of its speed: k → 0.25 from below, within the tolerance 1e-3.
    def run_at(tr):
        run = fake_run()
        run.torques.motor_speed = np.column_stack([1000.0 * tr.qd[:, 0], np.zeros(5), np.zeros(5)])
        run.t = tr.t
        run.L, run.Ld, run.Ldd = (np.zeros((5, 2, 3)),) * 3
        run.cond_inv = np.full(5, 0.5)
        run.trajectory = SimpleNamespace(Fe=tr.Fe)
        return run

    tr = protocol()
    k = given(fitting_speed(run_at, tr, Limits(motor_speed=250.0)))
    assert 0.25 * (1 - 1e-3) <= k <= 0.25
    assert fitting_speed(run_at, tr, Limits(motor_speed=250.0), tolerance=0.1) == pytest.approx(0.25, rel=0.1)
    assert fitting_speed(run_at, tr, Limits(motor_speed=2000.0)) == 1.0
    # Not even at 1/1000 of the speed (0.5 rad/s needed, 0.1 allowed): None.
    assert fitting_speed(run_at, tr, Limits(motor_speed=0.1)) is None
    # A limit speed cannot help (the load): None.
    assert fitting_speed(run_at, tr, Limits(motor_speed=250.0, load_range=(0.0, 500.0))) is None
