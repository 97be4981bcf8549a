"""The result type every model returns: a :class:`Run` along a trajectory.

Both models (and any engine added later) fill the same fields, each with what
it computed itself: the slider motion, the motor torques split into the parts
of spec §4.4, the singularity measure and, when the model has them, the joint
reaction forces. The CSV columns of spec §7.5 and the summary come from here,
so they are the same whichever model ran.

Units: SI inside (m, s, rad, N, N·m); :meth:`Run.columns` and
:meth:`Run.summary` convert to the report units named in their keys.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import numpy as np

from .arrays import check_shapes
from .exceptions import ArgumentError, MissingDependencyError
from .files import write_columns
from .machine.parameters import Parameters
from .motion.trajectories import Trajectory
from .physics.units import RPM_PER_RAD_S
from .records import Record, optional

__all__ = [
    "ExactSum",
    "JointForces",
    "JointPeaks",
    "MotorPeaks",
    "Run",
    "RunSummary",
    "SliderPeaks",
    "Summary",
    "Torques",
    "column_names",
    "peak_and_rms",
    "rms_and_signed_peak",
]


def peak_and_rms(values: np.ndarray, axis: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Peak of |values| and root mean square along ``axis`` (the sample axis), in the values' unit.

    Args:
        values: samples, e.g. (N, 3) torques in [N·m].
        axis: the axis to reduce.

    Returns:
        (peak, rms), each the shape of ``values`` without ``axis``.
    """
    values = np.asarray(values, dtype=float)
    # The mean square from a correctly rounded sum (math.fsum), the one a run in pieces gets
    # from ExactSum: a long run and its pieces then report the same RMS to the last digit.
    squares = np.moveaxis(values**2, axis, -1)
    sums = np.array([math.fsum(row) for row in squares.reshape(-1, squares.shape[-1])]).reshape(squares.shape[:-1])
    return np.abs(values).max(axis=axis), np.sqrt(sums / values.shape[axis])


def rms_and_signed_peak(t: np.ndarray, values: np.ndarray) -> tuple[float, float, float]:
    """(RMS, the value of largest magnitude with its sign, its time) of one series, e.g. an error in [deg].

    The law of every per-platform-and-angle error a run reports (``stations``, a plant-and-model run, a log's sensors
    against the prediction).

    Args:
        t: sample times in [s], (N,).
        values: the series, (N,).

    Returns:
        (RMS in the values' unit, the peak in it, when it occurs in [s]: the first of equal magnitudes).
    """
    peak = int(np.argmax(np.abs(values)))
    return float(np.sqrt(np.mean(values**2))), float(values[peak]), float(t[peak])


@dataclass(frozen=True, eq=False)
class Torques:
    """Motor torques and their parts along a trajectory (spec §4.4), (N, 3) per motor.

    Attributes:
        total: motor torque in [N·m]; the sum of the five parts below.
        platforms: moving platforms' inertia (both platforms) in [N·m] (τ_m).
        levers: levers' gravity and inertia in [N·m] (τ_l).
        sliders: sliders' gravity and inertia in [N·m] (τ_s).
        screws: lead screws' rotor inertia in [N·m] (τ_L).
        friction: all friction in [N·m] (τ_f).
        motor_speed: θ̇_i = 2π·L̇_i/p in [rad/s].
        friction_moment: magnitude of each platform's central-chain friction moment in [N·m], (N,).
        friction_power: power lost in all friction in [W], (N,), ≥ 0.
    """

    total: np.ndarray
    platforms: np.ndarray
    levers: np.ndarray
    sliders: np.ndarray
    screws: np.ndarray
    friction: np.ndarray
    motor_speed: np.ndarray
    friction_moment: np.ndarray
    friction_power: np.ndarray

    #: The five parts, in the order of spec §4.4.
    PARTS = ("platforms", "levers", "sliders", "screws", "friction")
    #: Each field's name in the CSV columns of spec §7.5 (``tau_m_1_Nmm`` …).
    COLUMN = {
        "total": "tau",
        "platforms": "tau_m",
        "levers": "tau_l",
        "sliders": "tau_s",
        "screws": "tau_L",
        "friction": "tau_f",
    }

    def __post_init__(self):
        shapes = {name: ("N", 3) for name in ("total", *self.PARTS, "motor_speed")}
        check_shapes(self, shapes | {"friction_moment": ("N",), "friction_power": ("N",)})


@dataclass(frozen=True, eq=False)
class JointForces:
    """Reaction force magnitudes in the passive spherical joints, in [N].

    Attributes:
        Fa: at each lever's platform joint a_ji, (N, 2, 3) [platform j, leg i].
        Fo: through each platform's central joint o_j, (N, 2), load F_e and platform weight included.
    """

    Fa: np.ndarray
    Fo: np.ndarray

    def __post_init__(self):
        check_shapes(self, {"Fa": ("N", 2, 3), "Fo": ("N", 2)})


def column_names(joint_forces: bool = False) -> list[str]:
    """The CSV columns of spec §7.5, in order; ``joint_forces`` adds ``Fa_ji_N`` and ``Fo_j_N``."""
    names = ["t_s", "alpha_deg", "beta_deg", "gamma_deg", "Fe_N"]
    for quantity, unit in (("L", "mm"), ("Ld", "mm_s"), ("Ldd", "mm_s2")):
        names += [f"{quantity}_{j}{i}_{unit}" for j in (1, 2) for i in (1, 2, 3)]
    for field in ("total", *Torques.PARTS):
        names += [f"{Torques.COLUMN[field]}_{i}_Nmm" for i in (1, 2, 3)]
    names += [f"speed_{i}_rpm" for i in (1, 2, 3)] + ["cond_inv"]
    if joint_forces:
        names += [f"Fa_{j}{i}_N" for j in (1, 2) for i in (1, 2, 3)] + ["Fo_1_N", "Fo_2_N"]
    return names


@dataclass(frozen=True, eq=False)
class Run:
    """One model run along one trajectory: what every model returns.

    Attributes:
        model: the model that ran ("analytic", "pinocchio", …).
        params: the machine.
        trajectory: the motion and load.
        L, Ld, Ldd: slider motion in [m], [m/s], [m/s²], (N, 2, 3) [platform j, module i].
        torques: motor torques and their parts.
        cond_inv: singularity measure, the inverse condition number of J (0 = singular), (N,).
        flagged: samples out of reach or singular, carried as NaN, (N,) bool
            (only a model asked to flag rather than raise has any).
        joint_forces: the joint reaction forces, or None when the model has none.
    """

    model: str
    params: Parameters
    trajectory: Trajectory
    L: np.ndarray
    Ld: np.ndarray
    Ldd: np.ndarray
    torques: Torques
    cond_inv: np.ndarray
    flagged: np.ndarray
    joint_forces: JointForces | None = None

    def __post_init__(self):
        n = len(self.trajectory.t)
        check_shapes(self, {"L": (n, 2, 3), "Ld": (n, 2, 3), "Ldd": (n, 2, 3), "cond_inv": (n,), "flagged": (n,)})
        if self.torques.total.shape[0] != n:
            raise ArgumentError("Run.torques", self.torques.total, f"{n} samples, one per trajectory sample")

    @property
    def t(self) -> np.ndarray:
        """Sample times in [s], (N,)."""
        return self.trajectory.t

    def slice(self, index: slice) -> Run:
        """The samples selected by ``index`` (a slice), every field cut alike."""
        torques = Torques(**{name: getattr(self.torques, name)[index] for name in Torques.__dataclass_fields__})
        forces = (
            None if self.joint_forces is None else JointForces(self.joint_forces.Fa[index], self.joint_forces.Fo[index])
        )
        return Run(
            self.model,
            self.params,
            self.trajectory.slice(index),
            self.L[index],
            self.Ld[index],
            self.Ldd[index],
            torques,
            self.cond_inv[index],
            self.flagged[index],
            forces,
        )

    def columns(self) -> dict[str, np.ndarray]:
        """The spec §7.5 columns, in their units, by name (``flagged`` added when any sample is)."""
        out: dict[str, np.ndarray] = {"t_s": self.trajectory.t}
        for k, name in enumerate(("alpha", "beta", "gamma")):
            out[f"{name}_deg"] = np.degrees(self.trajectory.q[:, k])
        out["Fe_N"] = self.trajectory.Fe
        for quantity, unit in (("L", "mm"), ("Ld", "mm_s"), ("Ldd", "mm_s2")):
            values = getattr(self, quantity) * 1e3
            for j in (1, 2):
                for i in (1, 2, 3):
                    out[f"{quantity}_{j}{i}_{unit}"] = values[:, j - 1, i - 1]
        for field in ("total", *Torques.PARTS):
            values = getattr(self.torques, field) * 1e3
            for i in (1, 2, 3):
                out[f"{Torques.COLUMN[field]}_{i}_Nmm"] = values[:, i - 1]
        for i in (1, 2, 3):
            out[f"speed_{i}_rpm"] = self.torques.motor_speed[:, i - 1] * RPM_PER_RAD_S
        out["cond_inv"] = self.cond_inv
        if self.joint_forces is not None:
            for j in (1, 2):
                for i in (1, 2, 3):
                    out[f"Fa_{j}{i}_N"] = self.joint_forces.Fa[:, j - 1, i - 1]
            for j in (1, 2):
                out[f"Fo_{j}_N"] = self.joint_forces.Fo[:, j - 1]
        if np.any(self.flagged):
            out["flagged"] = self.flagged.astype(float)
        return out

    def summary(self) -> RunSummary:
        """Per slider its extreme motion, per motor its torque parts, speed and RMS, and the worst singularity margin.

        Values in mm, mm/s, mm/s², N·mm, rpm (keys say which), over the samples
        that are not flagged. RMS values are over the samples, which is the
        cycle RMS when the trajectory is periodic. The same as a
        :class:`Summary` fed this run in any number of pieces.
        """
        return Summary(self.model, self.params, self.trajectory.name, self.joint_forces is not None).add(self).result()

    def to_dataframe(self):
        """:meth:`columns` as a pandas DataFrame (needs the ``pandas`` extra).

        Raises:
            MissingDependencyError: pandas is not installed (the message has the install line).
        """
        try:
            import pandas
        except ImportError:
            raise MissingDependencyError("pandas", "pandas", "Run.to_dataframe()") from None
        return pandas.DataFrame(self.columns())

    def write_csv(self, path: str | Path) -> Path:
        """Write :meth:`columns` to ``path`` atomically (a complete file or none). Returns the path."""
        return write_columns(path, self.columns())


class ExactSum:
    """The exact sum of float64 values fed in pieces, so the result does not depend on where the pieces are cut.

    Each value is split into two 27-bit integer halves of its mantissa,
    summed per binary exponent (exact in float64 for up to 2²⁶ values a
    piece) and carried in Python integers; :meth:`total` rounds once.

    Args:
        width: how many sums side by side (the columns of what :meth:`add` gets).
    """

    _SHIFT = 1200  # 2^-1200 is below the smallest float64 mantissa bit (2^-1074)
    _SPAN = 2200  # binary exponents of float64 values, from the subnormals up

    def __init__(self, width: int):
        self.width = width
        self._sums = [0] * width

    def add(self, values: np.ndarray) -> None:
        """Add ``values`` (M, width) column by column (non-finite values are the caller's to drop)."""
        values = np.asarray(values, dtype=float).reshape(-1, self.width)
        if values.shape[0] > 2**26:
            for start in range(0, values.shape[0], 2**26):
                self.add(values[start : start + 2**26])
            return
        mantissa, exponent = np.frexp(values)  # values = mantissa·2^exponent, mantissa·2^53 an integer
        whole = mantissa * 2.0**53
        high = np.floor(whole / 2.0**27)
        low = whole - high * 2.0**27
        bins = (np.arange(self.width) * self._SPAN + (exponent + 1100)).ravel()
        size = self.width * self._SPAN
        high_sums = np.bincount(bins, high.ravel(), size)
        low_sums = np.bincount(bins, low.ravel(), size)
        for index in np.flatnonzero((high_sums != 0) | (low_sums != 0)):
            column, e = divmod(int(index), self._SPAN)
            integer = (int(high_sums[index]) << 27) + int(low_sums[index])
            self._sums[column] += integer << (e - 1100 - 53 + self._SHIFT)

    def total(self) -> np.ndarray:
        """The sums, each rounded once to float64, (width,)."""
        return np.array([float(Fraction(s, 1 << self._SHIFT)) for s in self._sums])


@dataclass(frozen=True)
class SliderPeaks(Record):
    """One slider's extreme motion over a run: L highest and lowest, the stroke between, |Ld| and |Ldd| at most."""

    L_max_mm: float
    L_min_mm: float
    stroke_mm: float
    Ld_max_mm_s: float
    Ldd_max_mm_s2: float


@dataclass(frozen=True)
class MotorPeaks(Record):
    """One motor over a run: each torque part's largest |value|, the total's peak and RMS, the peak speed."""

    tau_m_max_Nmm: float
    tau_l_max_Nmm: float
    tau_s_max_Nmm: float
    tau_L_max_Nmm: float
    tau_f_max_Nmm: float
    tau_peak_Nmm: float
    tau_rms_Nmm: float
    speed_peak_rpm: float


@dataclass(frozen=True)
class JointPeaks(Record):
    """One joint force over a run: its peak |value| and RMS in [N]."""

    peak_N: float
    rms_N: float


@dataclass(frozen=True)
class RunSummary(Record):
    """What :meth:`Run.summary` reports (``hipsim torques``), over the samples that are not flagged.

    Attributes:
        model, trajectory, parameters: the model's name, the motion's, where the machine's values came from.
        samples: samples of the run; flagged_samples: those out of reach or singular (left out).
        sliders: per slider "11" … "23" its extreme motion.
        motors: per motor "1" … "3" its torques and speed.
        cond_inv_min: the smallest inverse condition number of J; cond_inv_min_t_s: when, the first such sample.
        joints: per joint force (Fa_11 … Fo_2) its peak and RMS, for a model that gives them.
    """

    model: str
    trajectory: str
    parameters: str
    samples: int
    flagged_samples: int
    sliders: dict[str, SliderPeaks]
    motors: dict[str, MotorPeaks]
    cond_inv_min: float
    cond_inv_min_t_s: float
    joints: dict[str, JointPeaks] | None = optional()


class Summary:
    """What :meth:`Run.summary` reports, gathered from a run fed in pieces (a long run in chunks).

    Args:
        model: the model's name.
        params: the machine.
        trajectory: the trajectory's name.
        joint_forces: whether the runs carry joint forces.
    """

    def __init__(self, model: str, params: Parameters, trajectory: str, joint_forces: bool):
        self.model, self.params, self.trajectory, self.joint_forces = model, params, trajectory, joint_forces
        self.samples = self.flagged = self.kept = 0
        self._peaks: dict[str, np.ndarray] = {}
        self._lows: dict[str, np.ndarray] = {}
        self._squares = ExactSum(3 + (8 if joint_forces else 0))
        self._cond_inv_min, self._cond_inv_t = math.inf, math.nan

    def _fold(self, store: dict, key: str, values: np.ndarray, reduce) -> None:
        store[key] = values if key not in store else reduce(store[key], values)

    def add(self, run: Run) -> Summary:
        """Take in one piece of the run (pieces in time order). Returns self."""
        ok = ~run.flagged
        self.samples += run.t.size
        self.flagged += int(np.count_nonzero(run.flagged))
        if not ok.any():
            return self
        self.kept += int(np.count_nonzero(ok))
        if ok.all():  # the usual case: no copies through the mask
            ok = slice(None)  # type: ignore[assignment]
        peaks = {
            "L": run.L[ok].max(axis=0) * 1e3,
            "Ld": np.abs(run.Ld[ok]).max(axis=0) * 1e3,
            "Ldd": np.abs(run.Ldd[ok]).max(axis=0) * 1e3,
            "speed": np.abs(run.torques.motor_speed[ok]).max(axis=0) * RPM_PER_RAD_S,
        }
        total = run.torques.total[ok] * 1e3
        squares = [total**2]
        peaks["total"] = np.abs(total).max(axis=0)
        for field in Torques.PARTS:
            peaks[field] = np.abs(getattr(run.torques, field)[ok] * 1e3).max(axis=0)
        if self.joint_forces:
            if run.joint_forces is None:
                raise ArgumentError("run", run.model, "a run with joint forces, as the summary's first")
            Fa, Fo = run.joint_forces.Fa[ok].reshape(-1, 6), run.joint_forces.Fo[ok]
            peaks["Fa"], peaks["Fo"] = np.abs(Fa).max(axis=0), np.abs(Fo).max(axis=0)
            squares += [Fa**2, Fo**2]
        for key, values in peaks.items():
            self._fold(self._peaks, key, values, np.maximum)
        self._fold(self._lows, "L", run.L[ok].min(axis=0) * 1e3, np.minimum)
        self._squares.add(np.hstack(squares))
        k = int(np.nanargmin(run.cond_inv if isinstance(ok, slice) else np.where(ok, run.cond_inv, np.nan)))
        if run.cond_inv[k] < self._cond_inv_min:  # strictly: the first sample of the smallest value, as in one piece
            self._cond_inv_min, self._cond_inv_t = float(run.cond_inv[k]), float(run.t[k])
        return self

    def result(self) -> RunSummary:
        """The summary of everything added, as :meth:`Run.summary` gives it."""
        peaks = self._peaks
        if not self.kept:
            raise ArgumentError("Summary", self.samples, "at least one sample that is not flagged")
        rms, low = np.sqrt(self._squares.total() / self.kept), self._lows["L"]  # set by every add() that kept a sample
        sliders = {}
        for j in (1, 2):
            for i in (1, 2, 3):
                high, bottom = peaks["L"][j - 1, i - 1], low[j - 1, i - 1]
                sliders[f"{j}{i}"] = SliderPeaks(
                    float(high),
                    float(bottom),
                    float(high - bottom),
                    float(peaks["Ld"][j - 1, i - 1]),
                    float(peaks["Ldd"][j - 1, i - 1]),
                )
        motors = {
            str(i + 1): MotorPeaks(
                tau_m_max_Nmm=float(peaks["platforms"][i]),
                tau_l_max_Nmm=float(peaks["levers"][i]),
                tau_s_max_Nmm=float(peaks["sliders"][i]),
                tau_L_max_Nmm=float(peaks["screws"][i]),
                tau_f_max_Nmm=float(peaks["friction"][i]),
                tau_peak_Nmm=float(peaks["total"][i]),
                tau_rms_Nmm=float(rms[i]),
                speed_peak_rpm=float(peaks["speed"][i]),
            )
            for i in range(3)
        }
        joints = None
        if self.joint_forces:
            names = [f"Fa_{j}{i}" for j in (1, 2) for i in (1, 2, 3)] + ["Fo_1", "Fo_2"]
            values = np.concatenate([peaks["Fa"], peaks["Fo"]])
            joints = {name: JointPeaks(float(values[k]), float(rms[3 + k])) for k, name in enumerate(names)}
        return RunSummary(
            model=self.model,
            trajectory=self.trajectory,
            parameters=str(self.params.source),
            samples=self.samples,
            flagged_samples=self.flagged,
            sliders=sliders,
            motors=motors,
            cond_inv_min=self._cond_inv_min,
            cond_inv_min_t_s=self._cond_inv_t,
            joints=joints,
        )
