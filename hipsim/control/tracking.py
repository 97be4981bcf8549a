"""A closed-loop run on the machine as built: its per-sample record and its summary per platform and angle.

:class:`MachineRun` is what :func:`hipsim.control.machine_loop.run_machine`
returns: at each servo instant the carriages as the encoders read them, both
platforms' true attitudes and their errors against the desired motion, what
the controller saw, the motor torques and the load. Its columns are the
stations' contract (``t_s``, ``L_11_mm`` …, ``alpha_1_deg`` … ``gamma_2_deg``,
``err_alpha_1_deg`` …, ``Fe_N``, as ``hipsim stations`` writes them) plus
today's ``hipsim simulate`` columns (``alpha_des_deg``, ``alpha_deg`` and
``err_alpha_deg`` are the *controlled* platform's, torques, speeds,
saturation) and what the controller measured (``alpha_meas_deg`` …).

:class:`TrackingSummary` is the run's summary as a typed record: per platform
and angle the RMS and peak error in [deg] and when it peaks, the torques and
speeds per motor, and (asked for) each station's ISO 14242-1 verdict on the
motion it truly went through (:func:`hipsim.motion.iso_verdict.station_iso`,
both platforms being asked for the desired motion).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..arrays import check_shapes
from ..motion.iso_compliance import DEFAULT_TOLERANCES, Tolerances
from ..motion.iso_verdict import StationIso, station_iso
from ..motion.trajectories import Trajectory
from ..physics.units import RPM_PER_RAD_S
from ..records import Record, optional
from ..results import peak_and_rms, rms_and_signed_peak

__all__ = ["ANGLES", "AngleError", "MachineRun", "MotorLoad", "TrackingSummary", "attitude_columns", "error_columns"]

#: The angles, as the columns name them.
ANGLES = ("alpha", "beta", "gamma")


def attitude_columns() -> list[str]:
    """``alpha_1_deg`` … ``gamma_2_deg`` (platform 1's, then platform 2's): the names ``hipsim stations`` writes."""
    return [f"{a}_{j}_deg" for j in (1, 2) for a in ANGLES]


def error_columns() -> list[str]:
    """``err_alpha_1_deg`` … ``err_gamma_2_deg``."""
    return [f"err_{name}" for name in attitude_columns()]


@dataclass(frozen=True)
class AngleError(Record):
    """One platform's tracking error in one angle over a run.

    Attributes:
        platform: 1 (m_1) or 2 (m_2).
        angle: "alpha", "beta" or "gamma".
        controlled: True for the platform the loop closes on.
        rms_deg: RMS of desired − true in [deg].
        peak_deg: the error of largest magnitude in [deg] (signed).
        peak_at_s: when it occurs in [s].
    """

    platform: int
    angle: str
    controlled: bool
    rms_deg: float
    peak_deg: float
    peak_at_s: float


@dataclass(frozen=True)
class MotorLoad(Record):
    """One motor over a run: torque peak and RMS in [N·mm], speed peak in [rpm]."""

    motor: int
    torque_peak_Nmm: float
    torque_rms_Nmm: float
    speed_peak_rpm: float


@dataclass(frozen=True)
class TrackingSummary(Record):
    """A closed-loop run on the machine as built, summarised.

    Attributes:
        plant: the plant's name (pinocchio, mujoco, analytic).
        controller: "pd", "augmented-pd" or the caller's name.
        feedback: "encoders" or "sensors".
        control: the controlled platform (1 or 2).
        duration_s: simulated time in [s]; step_s: the RK4 step in [s].
        errors: per platform and angle (platform 1's α, β, γ, then platform 2's).
        motors: per motor.
        saturated_samples: servo periods whose torque was limited.
        stations: each platform's ISO 14242-1 verdict (m_1's, then m_2's); None when not asked for.
    """

    plant: str
    controller: str
    feedback: str
    control: int
    duration_s: float
    step_s: float
    errors: tuple[AngleError, ...]
    motors: tuple[MotorLoad, ...]
    saturated_samples: int
    stations: tuple[StationIso, ...] | None = optional()

    def error(self, platform: int, angle: str) -> AngleError:
        """The entry of one platform (1, 2) and angle ("alpha", "beta", "gamma")."""
        return self.errors[3 * (platform - 1) + ANGLES.index(angle)]


@dataclass(frozen=True, eq=False)
class MachineRun:
    """A closed-loop run of a plant that is not (necessarily) the controller's model, at the servo instants.

    Attributes:
        t: servo instants in [s], (n,).
        desired: the desired motion of the controlled platform (its load is the plant's).
        carriages: the carriages as the encoders read them in [m], (n, 3).
        attitudes: both platforms' true gait angles in [rad], (n, 2, 3).
        rates: their rates in [rad/s], (n, 2, 3).
        measured: the controlled platform's attitude as the controller saw it in [rad], (n, 3).
        tau: motor torques applied in [N·m], (n, 3); tau_requested: before the limit.
        saturated: periods whose torque was limited, (n,).
        motor_speed: motor speeds in [rad/s], (n, 3).
        plant, controller, feedback: names; control: the controlled platform (1, 2); step: the RK4 step in [s].
    """

    t: np.ndarray
    desired: Trajectory
    carriages: np.ndarray
    attitudes: np.ndarray
    rates: np.ndarray
    measured: np.ndarray
    tau: np.ndarray
    tau_requested: np.ndarray
    saturated: np.ndarray
    motor_speed: np.ndarray
    plant: str
    controller: str
    feedback: str
    control: int
    step: float = math.nan

    def __post_init__(self):
        check_shapes(
            self,
            {
                "t": ("N",),
                "carriages": ("N", 3),
                "attitudes": ("N", 2, 3),
                "rates": ("N", 2, 3),
                "measured": ("N", 3),
                "tau": ("N", 3),
                "tau_requested": ("N", 3),
                "saturated": ("N",),
                "motor_speed": ("N", 3),
            },
            samples=len(self.t),
        )

    @property
    def errors(self) -> np.ndarray:
        """desired − true per platform in [rad], (n, 2, 3)."""
        return self.desired.q[:, None, :] - self.attitudes

    def summary(
        self, tolerances: Tolerances = DEFAULT_TOLERANCES, periodic: bool = False, iso: bool = False
    ) -> TrackingSummary:
        """Per platform and angle the RMS and peak error and its time; per motor the torque and speed; with ``iso``
        each station's ISO 14242-1 verdict (``tolerances``; ``periodic``: the run covers whole periods)."""
        e = np.degrees(self.errors)
        errors = tuple(
            AngleError(j + 1, angle, j + 1 == self.control, *rms_and_signed_peak(self.t, e[:, j, k]))
            for j in range(2)
            for k, angle in enumerate(ANGLES)
        )
        tau_peak, tau_rms = peak_and_rms(self.tau * 1e3)
        speed_peak, _ = peak_and_rms(self.motor_speed * RPM_PER_RAD_S)
        motors = tuple(MotorLoad(i + 1, float(tau_peak[i]), float(tau_rms[i]), float(speed_peak[i])) for i in range(3))
        return TrackingSummary(
            plant=self.plant,
            controller=self.controller,
            feedback=self.feedback,
            control=self.control,
            duration_s=float(self.t.size * (self.t[1] - self.t[0])),
            step_s=float(self.step),
            errors=errors,
            motors=motors,
            saturated_samples=int(np.count_nonzero(self.saturated)),
            stations=self.station_verdicts(tolerances, periodic) if iso else None,
        )

    def station_verdicts(
        self, tolerances: Tolerances = DEFAULT_TOLERANCES, periodic: bool = False
    ) -> tuple[StationIso, StationIso]:
        """Each station's ISO 14242-1 verdict on the motion its platform truly went through, asked for the desired
        motion under the desired load (NOT MADE when the run holds no whole cycle)."""
        verdicts = [
            station_iso(
                f"m_{j}",
                self.t,
                self.attitudes[:, j - 1],
                self.desired.q,
                self.desired.Fe,
                tolerances,
                source=f"m_{j} under {self.controller}",
                periodic=periodic,
            )
            for j in (1, 2)
        ]
        return verdicts[0], verdicts[1]

    def columns(self) -> dict[str, np.ndarray]:
        """The per-sample table in the file's units (s, mm, deg, N·mm, rpm, N); module docstring."""
        n, c = len(self.t), self.control - 1
        out = {"t_s": self.t}
        out |= {f"L_1{i + 1}_mm": self.carriages[:, i] * 1e3 for i in range(3)}
        q, e = np.degrees(self.attitudes).reshape(n, 6), np.degrees(self.errors).reshape(n, 6)
        out |= {name: q[:, k] for k, name in enumerate(attitude_columns())}
        out |= {name: e[:, k] for k, name in enumerate(error_columns())}
        for k, a in enumerate(ANGLES):
            out[f"{a}_des_deg"] = np.degrees(self.desired.q[:, k])
            out[f"{a}_deg"] = np.degrees(self.attitudes[:, c, k])
            out[f"err_{a}_deg"] = np.degrees(self.errors[:, c, k])
            out[f"{a}_meas_deg"] = np.degrees(self.measured[:, k])
        out |= {f"tau_{i + 1}_Nmm": self.tau[:, i] * 1e3 for i in range(3)}
        out |= {f"tau_req_{i + 1}_Nmm": self.tau_requested[:, i] * 1e3 for i in range(3)}
        out |= {f"speed_{i + 1}_rpm": self.motor_speed[:, i] * RPM_PER_RAD_S for i in range(3)}
        out["saturated"] = self.saturated.astype(float)
        out["Fe_N"] = np.asarray(self.desired.Fe, dtype=float)
        return out

    def write(self, path) -> Path:
        """Write :meth:`columns` to ``path`` atomically, CSV or Parquet by its suffix. Returns the path."""
        from ..files import ColumnWriter

        with ColumnWriter(path) as writer:
            writer.write(self.columns())
            return writer.close()
