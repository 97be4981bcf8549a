"""Feasibility: each limit a run crosses is named, first the one it misses most; time scaling that fits."""

from pathlib import Path

import hipsim.models
import numpy as np
import pytest

from hipsim import iso14242, load_parameters
from hipsim.analysis import analyse
from hipsim.design.feasibility import Limits, check_feasibility, fitting_speed, time_scaled
from hipsim.machine.drive import load_drive
from hipsim.motion.trajectories import Trajectory

PARAMS = load_parameters()
ISO = iso14242(rate=500)


@pytest.fixture(scope="module")
def iso_run():
    return analyse(PARAMS, ISO)


def needs(run):
    """What a run needs of each limit, computed here from the run's arrays."""
    L = run.L[:, 0, :]
    return {
        "stroke": np.ptp(L, axis=0).max(),
        "slider_speed": np.abs(run.Ld[:, 0, :]).max(),
        "slider_acceleration": np.abs(run.Ldd[:, 0, :]).max(),
        "motor_speed": np.abs(run.torques.motor_speed).max(),
        "motor_torque": np.abs(run.torques.total).max(),
    }


def test_the_built_in_cycle_on_the_published_machine_crosses_nothing(iso_run):
    assert check_feasibility(iso_run, Limits.from_machine(PARAMS)) == []
    drive = load_drive(
        Path(hipsim.models.__file__).with_name("drive_example.toml")
    )  # the example drive's motor and screw
    assert check_feasibility(iso_run, Limits.from_machine(PARAMS, drive)) == []


def amplified(trajectory, gain):
    """The angles' swing about their mean scaled by ``gain`` (derivatives with it): a larger motion, same timing."""
    mean = trajectory.q.mean(axis=0)
    return Trajectory(
        trajectory.t,
        mean + gain * (trajectory.q - mean),
        gain * trajectory.qd,
        gain * trajectory.qdd,
        trajectory.Fe,
        "amplified",
        trajectory.periodic,
    )


@pytest.mark.parametrize(
    ("limit", "scale"),
    [
        ("stroke", "amplitude"),
        ("slider_speed", "speed"),
        ("slider_acceleration", "speed"),
        ("motor_speed", "speed"),
        ("motor_torque", "speed"),
    ],
)
def test_a_motion_scaled_past_one_limit_names_that_limit_first(iso_run, limit, scale):
    need = needs(iso_run)
    # Every limit 10 % above what the ISO cycle needs; the scaled motion crosses the one under test most.
    limits = Limits(**{name: 1.1 * value for name, value in need.items()})
    run = analyse(PARAMS, amplified(ISO, 1.3) if scale == "amplitude" else time_scaled(ISO, 1.25))
    crossings = check_feasibility(run, limits)
    assert crossings, "the scaled motion crossed nothing"
    assert limit in [c.limit for c in crossings]
    only = Limits(**{limit: 1.1 * need[limit]})
    first = check_feasibility(run, only)[0]
    assert first.limit == limit
    assert first.needed > first.allowed and first.excess > 1.0


def test_the_message_names_motor_time_need_and_limit(iso_run):
    need = np.abs(iso_run.torques.motor_speed).max(axis=0)
    worst = int(np.argmax(need))
    crossing = check_feasibility(iso_run, Limits(motor_speed=0.5 * need[worst]))[0]
    assert crossing.motor == worst + 1
    text = crossing.message()
    assert f"motor {worst + 1} needs a speed of" in text and "rpm at t = " in text and "2×" in text
    first = np.flatnonzero(np.abs(iso_run.torques.motor_speed[:, worst]) > 0.5 * need[worst])[0]
    assert crossing.t == pytest.approx(ISO.t[first])


def test_floors_and_load_range(iso_run):
    kinds = {c.limit for c in check_feasibility(iso_run, Limits(cond_inv_floor=0.5, load_range=(400.0, 2500.0)))}
    assert kinds == {"cond_inv", "load_max", "load_min"}


def test_fitting_speed_is_where_the_speed_limit_binds(iso_run):
    need = needs(iso_run)
    run_at = lambda tr: analyse(PARAMS, tr)
    # Motor speed scales with k: a limit at 80 % of the need fits at k = 0.8.
    assert fitting_speed(run_at, ISO, Limits(motor_speed=0.8 * need["motor_speed"])) == pytest.approx(0.8, rel=2e-3)
    # Acceleration scales with k²: 64 % fits at k = 0.8.
    assert fitting_speed(run_at, ISO, Limits(slider_acceleration=0.64 * need["slider_acceleration"])) == pytest.approx(
        0.8, rel=2e-3
    )
    assert fitting_speed(run_at, ISO, Limits()) == 1.0
    # A stroke does not change with speed: no time scale helps.
    assert fitting_speed(run_at, ISO, Limits(stroke=0.5 * need["stroke"])) is None


def test_beyond_the_torque_curves_end_only_the_speed_is_crossed(iso_run):
    """A torque–speed curve gives no torque past its end: that is an overspeed, not a torque of 0 N·mm allowed."""
    speed = np.abs(iso_run.torques.motor_speed).max()
    curve = lambda w: np.where(w <= 0.5 * speed, 10.0, 0.0)  # 10 N·m up to half the speed the run needs
    kinds = {c.limit for c in check_feasibility(iso_run, Limits(motor_speed=0.5 * speed, motor_torque=curve))}
    assert kinds == {"motor_speed"}
    tight = lambda w: np.where(w <= 0.5 * speed, 1e-3, 0.0)  # a curve the run exceeds where it applies
    crossing = [c for c in check_feasibility(iso_run, Limits(motor_torque=tight)) if c.limit == "motor_torque"][0]
    assert crossing.allowed == pytest.approx(1e-3) and np.isfinite(crossing.excess)
