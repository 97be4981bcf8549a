"""Figures (issue 14): the sizing figures show the cycle's own numbers, the tracking errors each on their own scale."""

import math
import re
from types import SimpleNamespace

import numpy as np
import pytest

import hipsim
import hipsim.present.figures as figures
from hipsim.design.sizing import axial_screw_load, sizing
from hipsim.machine.drive import Drive, Motor, TorqueSpeedCurve
from hipsim.motion.trajectories import iso14242

RPM = 60 / (2 * math.pi)


@pytest.fixture(scope="module")
def run():
    return hipsim.analyse(hipsim.load_parameters(), iso14242(rate=200))


def drive():
    rpm = 2 * math.pi / 60
    return Drive(
        Motor(
            "m",
            continuous=TorqueSpeedCurve(np.array([0, 3000 * rpm]), np.array([0.64, 0.6])),
            peak=TorqueSpeedCurve(np.array([0, 3000 * rpm, 5000 * rpm]), np.array([1.9, 1.9, 1.0])),
        )
    )


def test_torque_speed_cloud_is_the_cycle_over_the_curves(run):
    fig = figures.plot_torque_speed(sizing(run, drive()))
    assert len(fig.axes) == 3
    for i, ax in enumerate(fig.axes):
        lines = {line.get_label(): line for line in ax.get_lines()}
        cloud = lines["cycle samples"]
        # Direct drive, no rotor inertia given: the motor's points are the run's own.
        np.testing.assert_allclose(cloud.get_xdata(), np.abs(run.torques.motor_speed[:, i]) * RPM)
        np.testing.assert_allclose(cloud.get_ydata(), np.abs(run.torques.total[:, i]) * 1e3)
        s1, peak = lines["S1 (continuous)"], lines["peak"]
        assert np.interp(1500.0, s1.get_xdata(), s1.get_ydata()) == pytest.approx(620.0, rel=1e-3)
        assert np.interp(4000.0, peak.get_xdata(), peak.get_ydata()) == pytest.approx(1450.0, rel=1e-3)
        assert "[rpm]" in ax.get_xlabel()
    assert "[N·mm]" in fig.axes[0].get_ylabel()


def test_axial_load_histogram_weighs_revolutions(run):
    fig = figures.plot_axial_load_histogram(sizing(run))
    load = np.abs(axial_screw_load(run))
    revolutions = np.abs(run.torques.motor_speed)
    for i, ax in enumerate(fig.axes):
        (patch,) = ax.patches
        heights = patch.get_path().vertices[:, 1]
        edges = np.linspace(0.0, load.max() * 1.02, 41)
        expected = np.histogram(load[:, i], edges, weights=revolutions[:, i])[0] / revolutions[:, i].sum() * 100
        assert heights.max() == pytest.approx(expected.max(), rel=1e-9)
        assert "[%]" in ax.get_ylabel()
        cubic = (np.sum(load[:, i] ** 3 * revolutions[:, i]) / revolutions[:, i].sum()) ** (1 / 3)
        (mean_line,) = [line for line in ax.get_lines() if line.get_label().startswith("cubic mean")]
        assert mean_line.get_xdata()[0] == pytest.approx(cubic, rel=1e-9)
    assert "[N]" in fig.axes[-1].get_xlabel()


def test_tracking_panels_have_their_own_scales(run):
    t = run.t
    wave = np.sin(2 * np.pi * t)[:, None] * np.ones(3)
    sims = {
        "pd": SimpleNamespace(t=t, err=np.radians(0.2) * wave),
        "augmented-pd": SimpleNamespace(t=t, err=np.radians(2e-5) * wave),
    }
    fig = figures.plot_tracking(sims)
    assert len(fig.axes) == 6
    pd, augmented = fig.axes[0], fig.axes[1]  # row α: PD, then augmented PD
    assert pd.get_ylim()[1] > 0.19 and augmented.get_ylim()[1] < 1e-3  # the small errors fill their own panel
    assert augmented.get_ylim()[1] > 1.9e-5


def test_input_motion_shows_the_angles_and_load(run):
    fig = figures.plot_input_motion(run)
    angles, load = fig.axes
    for k, line in enumerate(angles.get_lines()[:3]):
        np.testing.assert_allclose(line.get_ydata(), np.degrees(run.trajectory.q[:, k]))
    np.testing.assert_allclose(load.get_lines()[0].get_ydata(), run.trajectory.Fe)
    for ax in fig.axes:
        assert re.search(r"\[.+\]", ax.get_ylabel())
    assert "[s]" in fig.axes[-1].get_xlabel()


def test_coinciding_platform_curves_are_named_and_drawn_apart(run):
    """Platform 2's joint forces equal to platform 1's (as the machine gives them): every legend entry stays visible."""
    n = len(run.trajectory)
    Fa = np.empty((n, 2, 3))
    Fa[:, 0, :] = 100.0 + 50.0 * np.sin(2 * np.pi * run.trajectory.t)[:, None] * [1.0, 2.0, 3.0]
    Fa[:, 1, :] = Fa[:, 0, :]
    Fa[:, 1, 2] += 40.0  # this pair differs
    Fo = np.column_stack([run.trajectory.Fe + 200.0] * 2)
    fig = figures.plot_joint_forces(dataclasses_replace(run, joint_forces=hipsim.JointForces(Fa, Fo)))
    labels = [text.get_text() for ax in fig.axes if ax.get_legend() for text in ax.get_legend().get_texts()]
    assert "a_21 = a_11" in labels and "a_22 = a_12" in labels and "a_23" in labels and "o_2 = o_1" in labels
    for ax in fig.axes:
        styles = [
            (line.get_color(), str(line.get_linestyle()), line.get_linewidth())
            for line in ax.get_lines()
            if not line.get_label().startswith("_")
        ]
        assert len(set(styles)) == len(styles), styles  # no two entries drawn alike


def dataclasses_replace(obj, **changes):
    import dataclasses

    return dataclasses.replace(obj, **changes)
