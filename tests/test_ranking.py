"""Choosing from catalogues (hipsim.design.ranking): each screw lead reruns the model; candidates rank with the binding constraint named."""

import math

import numpy as np
import pytest

import hipsim
from hipsim.design.ranking import rank_drives
from hipsim.design.sizing import sizing
from hipsim.machine.drive_parts import Drive, LeadScrew, Motor, TorqueSpeedCurve
from hipsim.motion.trajectories import iso14242

from drive_support import curve, only


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


# ---------------------------------------------------------------------------
# The lead: recomputed, not rescaled


def test_each_screw_lead_reruns_the_model(params):
    trajectory = iso14242(rate=100)
    motor = (Motor("m", peak=TorqueSpeedCurve([0.0], [5.0]), rotor_inertia=1e-4), None)
    screws = [LeadScrew("p5", lead=0.005), LeadScrew("p20", lead=0.020, inertia=80e-6)]
    candidates = rank_drives(params, [(trajectory, 1.0)], [motor], screws)
    by_screw = {c.drive.screw.name: c for c in candidates}
    for screw in screws:
        machine = params.replace(lead=screw.lead, **({"screw_inertia": screw.inertia} if screw.inertia else {}))
        direct = sizing(hipsim.analyse(machine, trajectory), Drive(motor[0], screw=screw))
        expected = {(c.module, c.name): c.value for c in direct.checks if c.value is not None}
        got = {(c.module, c.name): c.value for c in by_screw[screw.name].checks if c.value is not None}
        assert got == pytest.approx(expected, rel=1e-12, nan_ok=True)
    peak5 = only(by_screw["p5"].checks, "peak_curve").value
    peak20 = only(by_screw["p20"].checks, "peak_curve").value
    # Rescaling the 20 mm torques by 5/20 would miss the screw inertia and the changed reflected inertia.
    assert abs(peak5 - peak20 * 5 / 20) > 0.01 * peak5


# ---------------------------------------------------------------------------
# Ranking


def test_an_undersized_and_a_right_motor_rank_with_the_binding_constraint_named(params):
    small = Motor("small", continuous=curve([0, 3000], [1.0, 1.0]), peak=curve([0, 3000], [0.25, 0.25]), rotor_inertia=1e-4)
    right = Motor("right", continuous=curve([0, 3000], [1.3, 1.2]), peak=curve([0, 5000], [3.8, 3.0]), rotor_inertia=1e-4)
    trajectory = iso14242(rate=200)
    candidates = rank_drives(params, [(trajectory, 1.0)], [(small, None), (right, None)])
    assert [c.drive.motor.name for c in candidates] == ["right", "small"]
    assert candidates[0].passed is True and candidates[1].passed is False
    binding = candidates[1].binding
    assert binding.name == "peak_curve" and binding.module == 1  # motor 1 needs over 431 N·mm, 250 N·mm on offer
    run = hipsim.analyse(params, trajectory)
    rotor = 1e-4 * 2 * math.pi / params.lead * run.Ldd[:, 0, 0]  # the motor also turns its own rotor
    assert binding.value == pytest.approx(np.abs(run.torques.total[:, 0] + rotor).max() * 1e3, rel=1e-12)
    assert binding.limit == pytest.approx(250.0) and binding.margin == pytest.approx(1 - binding.value / 250.0)
    assert candidates[0].margin > 0 > candidates[1].margin
