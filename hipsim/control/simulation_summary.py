"""What a closed-loop run reports: per angle its tracking error, per motor its torque and speed, and the ISO 14242-1
verdict on the motion the platform went through (:mod:`hipsim.motion.iso_verdict`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from ..motion.iso_compliance import DEFAULT_TOLERANCES, Tolerances
from ..motion.iso_verdict import ANGLES, StationIso, station_iso
from ..motion.trajectories import Trajectory
from ..physics.units import RPM_PER_RAD_S
from ..records import Record, optional
from ..results import peak_and_rms


class Run(Protocol):
    """What a summary reads of a run (:class:`hipsim.control.simulation.Simulation`)."""

    @property
    def t(self) -> np.ndarray: ...

    @property
    def desired(self) -> Trajectory: ...

    @property
    def q(self) -> np.ndarray: ...

    @property
    def tau(self) -> np.ndarray: ...

    @property
    def saturated(self) -> np.ndarray: ...

    @property
    def motor_speed(self) -> np.ndarray: ...

    @property
    def plant(self) -> str: ...

    @property
    def controller(self) -> str: ...

    @property
    def step(self) -> float: ...

    @property
    def err(self) -> np.ndarray: ...


__all__ = ["PeakRms", "SimulationSummary", "simulation_summary"]


@dataclass(frozen=True)
class PeakRms(Record):
    """The largest magnitude and the RMS of a series, in the unit its key names."""

    peak: float
    rms: float


@dataclass(frozen=True)
class SimulationSummary(Record):
    """One closed-loop run.

    Attributes:
        plant, controller: their names.
        duration_s: the run's span in [s].
        errors_deg: per angle the tracking error's peak |q_d − q| and RMS in [deg].
        torques_Nmm: per motor ("1".."3") the applied torque's peak and RMS in [N·mm].
        speed_peak_rpm: per motor the peak speed in [rpm].
        saturated_samples: samples where a torque was limited.
        step_s: the integration step used in [s].
        iso: the ISO 14242-1 verdict on the tracked motion (None when not asked for).
    """

    plant: str
    controller: str
    duration_s: float
    errors_deg: dict[str, PeakRms]
    torques_Nmm: dict[str, PeakRms]
    speed_peak_rpm: dict[str, float]
    saturated_samples: int
    step_s: float
    iso: StationIso | None = optional()


def simulation_summary(
    sim: Run, tolerances: Tolerances | None = None, periodic: bool = False, iso: bool = False
) -> SimulationSummary:
    """The run's summary; with ``iso`` also the verdict on the motion it went through against its desired motion.

    Args:
        sim: the run.
        tolerances: the ISO 14242-1 limits (default: the assumed defaults).
        periodic: the desired motion covers whole periods (the check wraps around).
        iso: make the ISO verdict.
    """
    err_peak, err_rms = peak_and_rms(np.degrees(sim.err))
    tau_peak, tau_rms = peak_and_rms(sim.tau * 1e3)
    speed_peak, _ = peak_and_rms(sim.motor_speed * RPM_PER_RAD_S)
    verdict = None
    if iso:
        verdict = station_iso(
            sim.controller,
            sim.t,
            sim.q,
            sim.desired.q,
            sim.desired.Fe,
            tolerances or DEFAULT_TOLERANCES,
            sim.controller,
            periodic,
        )
    return SimulationSummary(
        plant=sim.plant,
        controller=sim.controller,
        duration_s=float(sim.t.size * (sim.t[1] - sim.t[0])),  # simulate() makes at least two samples
        errors_deg={n: PeakRms(float(err_peak[k]), float(err_rms[k])) for k, n in enumerate(ANGLES)},
        torques_Nmm={str(i + 1): PeakRms(float(tau_peak[i]), float(tau_rms[i])) for i in range(3)},
        speed_peak_rpm={str(i + 1): float(speed_peak[i]) for i in range(3)},
        saturated_samples=int(np.count_nonzero(sim.saturated)),
        step_s=sim.step,
        iso=verdict,
    )
