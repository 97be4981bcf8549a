"""The demand along a run (hipsim.design.demand): the two forces along a screw, the motor's duty through a gearbox, the reflected inertia against the kinetic energy."""

import math

import numpy as np
import pytest
from drive_support import constant_side

import hipsim
from hipsim.analytic import kinematics, mechanical_energy
from hipsim.analytic.inverse_kinematics import slider_heights
from hipsim.design.demand import axial_screw_load, motor_duty, motor_thrust, reflected_inertia
from hipsim.machine.drive_parts import Drive, Gearbox, Motor
from hipsim.motion.trajectories import Trajectory, iso14242


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


@pytest.fixture(scope="module")
def run(params):
    return hipsim.analyse(params, iso14242(rate=100))  # 100 samples, 1 s, periodic


# ---------------------------------------------------------------------------
# The two forces along a screw


def test_motor_thrust_and_axial_screw_load_differ_by_the_screw_rotor_and_friction(params):
    rough = params.replace(screw_coulomb=0.05, screw_viscous=2e-4)
    run = hipsim.analyse(rough, iso14242(rate=200))
    thrust, load = motor_thrust(run), axial_screw_load(run)
    t = run.torques
    speed = t.motor_speed
    friction = 0.05 * speed / np.sqrt(speed**2 + rough.friction.epsilon**2) + 2e-4 * speed
    np.testing.assert_allclose(
        (thrust - load) * rough.lead / (2 * math.pi), t.screws + friction, rtol=1e-10, atol=1e-12
    )
    assert (
        np.abs(thrust - load).max() > 20.0
    )  # the difference is not small on this machine: 50 N·mm of friction alone is 31 N


# ---------------------------------------------------------------------------
# The motor's duty through a gearbox


def test_motor_torque_through_a_gearbox_with_rotor_inertia(run):
    motor = Motor("m", rotor_inertia=2e-5)
    gearbox = Gearbox("g", ratio=2.0, efficiency=0.9, inertia=1e-5)
    driving = motor_duty(constant_side(run, speed=100.0, torque=0.4, acceleration=50.0), Drive(motor, gearbox=gearbox))
    # Driving: τ_m = τ/(i·η) + (J_m + J_g)·i·θ̈ = 0.4/1.8 + 3e-5·2·50.
    assert driving.torque == pytest.approx(np.full((100, 3), 0.4 / 1.8 + 3e-3))
    assert driving.speed == pytest.approx(np.full((100, 3), 200.0))
    # Driven back (torque against the motion): τ_m = τ·η/i.
    regenerating = motor_duty(constant_side(run, speed=100.0, torque=-0.4), Drive(motor, gearbox=gearbox))
    assert regenerating.torque == pytest.approx(np.full((100, 3), -0.4 * 0.9 / 2))
    assert regenerating.power == pytest.approx(np.full((100, 3), -0.18 * 200.0))


# ---------------------------------------------------------------------------
# Reflected inertia


def test_reflected_inertia_is_the_kinetic_energy_inertia_along_the_cycle(params):
    trajectory = iso14242(rate=200)
    M = reflected_inertia(params, trajectory)
    np.testing.assert_allclose(M, np.swapaxes(M, 1, 2), rtol=0, atol=1e-12 * np.abs(M).max())
    speed = hipsim.analyse(params, trajectory).torques.motor_speed
    kinetic, _ = mechanical_energy(params, kinematics(params, trajectory), lever_spin=True)
    np.testing.assert_allclose(0.5 * np.einsum("ni,nij,nj->n", speed, M, speed), kinetic, rtol=1e-10)


def test_each_modules_load_inertia_is_the_energy_of_moving_that_motor_alone(params):
    """M_θ,ii = 2·KE when only screw i turns at 1 rad/s: q̇ from finite differences of the slider heights."""
    q = iso14242(rate=8).q
    h = 1e-6
    G = np.stack(
        [
            (slider_heights(params, q + h * e)[:, 0] - slider_heights(params, q - h * e)[:, 0]) / (2 * h)
            for e in np.eye(3)
        ],
        axis=-1,
    )
    G *= 2 * math.pi / params.lead
    M = reflected_inertia(
        params, Trajectory(np.arange(8) * 0.1, q, np.zeros_like(q), np.zeros_like(q), np.full(8, 300.0))
    )
    for i in range(3):
        qd = np.linalg.solve(G, np.eye(3)[i])
        alone = Trajectory(np.arange(8) * 0.1, q, qd, np.zeros_like(q), np.full(8, 300.0))
        kinetic, _ = mechanical_energy(params, kinematics(params, alone), lever_spin=True)
        np.testing.assert_allclose(M[:, i, i], 2 * kinetic, rtol=1e-7)
