"""A closed-loop run's summary (hipsim.control.simulation_summary) by hand on a stand-in run of four samples, and the
ISO verdict it asks for."""

import math
from dataclasses import dataclass

import numpy as np
import pytest

import hipsim.control.simulation_summary as summary_module
from hipsim.control.simulation_summary import PeakRms, simulation_summary
from hipsim.motion.iso_compliance import DEFAULT_TOLERANCES, Tolerances
from hipsim.motion.trajectories import Trajectory
from hipsim.records import Level


@dataclass
class StandIn:
    t: np.ndarray
    desired: Trajectory
    q: np.ndarray
    tau: np.ndarray
    saturated: np.ndarray
    motor_speed: np.ndarray
    plant: str = "reduced"
    controller: str = "pd"
    step: float = 2.5e-4

    @property
    def err(self) -> np.ndarray:
        return self.desired.q - self.q


def _run() -> StandIn:
    t = np.array([0.0, 0.004, 0.008, 0.012])  # a 4 ms period: 16 ms in all
    z = np.zeros((4, 3))
    err = np.zeros((4, 3))
    err[:, 0] = [1.0, -3.0, 2.0, 0.0]  # α: the peak magnitude the negative sample's
    err[:, 2] = [0.0, 0.0, 0.0, -0.5]  # γ
    desired = Trajectory(t, np.radians(np.full((4, 3), 2.0)), z, z, np.full(4, 500.0))
    tau = np.array([[0.1, 0.0, -0.4], [-0.3, 0.0, 0.3], [0.2, 0.0, 0.0], [0.0, 0.0, 0.0]])  # N·m
    speed = np.array([[1.0, -2.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])  # rad/s
    return StandIn(t, desired, desired.q - np.radians(err), tau, np.array([False, True, True, False]), speed)


def test_the_summary_by_hand():
    s = simulation_summary(_run())
    assert (s.plant, s.controller, s.step_s, s.iso) == ("reduced", "pd", 2.5e-4, None)
    assert s.duration_s == pytest.approx(0.016, rel=1e-12)  # four samples of 4 ms, not the 12 ms their stamps span
    assert list(s.errors_deg) == ["alpha", "beta", "gamma"]
    assert (s.errors_deg["alpha"].peak, s.errors_deg["alpha"].rms) == pytest.approx((3.0, math.sqrt(14 / 4)), rel=1e-12)
    assert (s.errors_deg["beta"].peak, s.errors_deg["beta"].rms) == (0.0, 0.0)
    assert (s.errors_deg["gamma"].peak, s.errors_deg["gamma"].rms) == pytest.approx((0.5, 0.25), rel=1e-12)
    assert list(s.torques_Nmm) == ["1", "2", "3"]
    assert (s.torques_Nmm["1"].peak, s.torques_Nmm["1"].rms) == pytest.approx((300.0, 1e3 * math.sqrt(0.14 / 4)))
    assert s.torques_Nmm["2"] == PeakRms(0.0, 0.0)
    assert (s.torques_Nmm["3"].peak, s.torques_Nmm["3"].rms) == pytest.approx((400.0, 250.0))
    rpm = 60 / (2 * math.pi)
    assert s.speed_peak_rpm == pytest.approx({"1": rpm, "2": 2 * rpm, "3": 0.0}, rel=1e-12)
    assert s.saturated_samples == 2
    doc = s.to_json()
    assert "iso" not in doc and doc["errors_deg"]["gamma"] == pytest.approx({"peak": 0.5, "rms": 0.25}, rel=1e-12)


def test_the_iso_verdict_is_asked_for_with_the_run_s_names_and_limits(monkeypatch):
    calls = []

    def stand_in(*args):
        calls.append(args)
        return "verdict"

    monkeypatch.setattr(summary_module, "station_iso", stand_in)
    run = _run()
    assert simulation_summary(run).iso is None and not calls
    assert simulation_summary(run, iso=True).iso == "verdict"
    name, t, q, q_d, load, tolerances, source, periodic = calls[-1]
    assert (name, source, periodic, tolerances) == ("pd", "pd", False, DEFAULT_TOLERANCES)
    assert t is run.t and q is run.q and q_d is run.desired.q and load is run.desired.Fe
    tight = Tolerances(alpha=0.1)
    simulation_summary(run, tolerances=tight, periodic=True, iso=True)
    assert calls[-1][5] is tight and calls[-1][7] is True


def test_a_run_too_short_for_a_cycle_is_not_judged():
    s = simulation_summary(_run(), iso=True)
    assert s.iso is not None and s.iso.verdict == Level.NOT_MADE
    assert s.iso.judged == "pd's motion: no ISO 14242-1 check" and s.iso.reason
    assert s.to_json()["iso"]["verdict"] == "NOT MADE"
