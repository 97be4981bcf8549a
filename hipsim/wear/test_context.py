"""What a station went through beside its wear, for the test's report: its motion's error against ISO and its friction.

- Motion: the error of each of α, β, γ against the commanded ISO motion
  (a ``stations`` output's ``err_alpha_J_deg`` … columns, or a logged motion
  against the built-in cycle at the same gait phase, :func:`iso_error`), RMS
  and largest, in [deg] (:func:`motion_error`).
- Friction: the monitor's table (``hipsim monitor --out``) at its last
  snapshot: the change of the hip friction coefficient since the baseline (the
  station's own column when the monitor separated the stations, else the two
  stations' mean) and the monitor's flag (:func:`friction_state`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..motion.gait_events import gait_cycles, gait_phase
from ..motion.trajectories import Trajectory, iso14242, iso14242_angles
from ..records import Record

__all__ = ["FrictionState", "MotionError", "StationContext", "friction_state", "iso_error", "motion_error"]


@dataclass(frozen=True)
class MotionError(Record):
    """A station's angle errors against ISO: RMS and largest |error| of α, β, γ in [deg], and where from."""

    source: str
    rms_deg: tuple[float, float, float]
    max_deg: tuple[float, float, float]


def motion_error(errors_deg: np.ndarray, source: str) -> MotionError:
    """RMS and largest |error| per angle of (N, 3) errors in [deg]."""
    e = np.asarray(errors_deg, dtype=float)
    rms = np.sqrt(np.mean(e**2, axis=0))
    top = np.max(np.abs(e), axis=0)
    return MotionError(
        source, (float(rms[0]), float(rms[1]), float(rms[2])), (float(top[0]), float(top[1]), float(top[2]))
    )


#: How far [cycles] the phase from heel strikes may be shifted to match the built-in cycle's angles (a heel strike is
#: found to a sample, and a low-passed load crosses its threshold a little off).
PHASE_SEARCH = 0.02


def iso_error(trajectory: Trajectory) -> np.ndarray:
    """A logged motion's angles minus the built-in ISO cycle's at the same gait phase, in [deg], (N, 3).

    The phase runs from each heel strike of the motion's load (:func:`hipsim.motion.gait_events.gait_phase`), the
    built-in cycle's own heel strike (found by the same rule on its load) its phase 0; then the one constant shift
    (within ±:data:`PHASE_SEARCH` cycles) that best matches the angles (least squares) is taken out: a timing offset
    of the heel strike is not an error of the motion.

    Raises:
        TrajectoryError: fewer than two heel strikes in the load.
    """
    from scipy.optimize import minimize_scalar

    phase, _ = gait_phase(trajectory.t, gait_cycles(trajectory))
    reference = gait_cycles(iso14242(rate=1000.0, cycles=2))
    start = float(reference.t_heel_strikes[0]) % 1.0 + phase / 100.0

    def error(shift: float) -> np.ndarray:
        return trajectory.q - iso14242_angles(np.mod(start + shift, 1.0))[0]

    best = minimize_scalar(
        lambda shift: float(np.sum(error(shift) ** 2)),
        bounds=(-PHASE_SEARCH, PHASE_SEARCH),
        method="bounded",
        options={"xatol": 1e-9},
    )
    return np.degrees(error(float(best.x)))


@dataclass(frozen=True)
class FrictionState:
    """The monitor's last word on a station: the hip μ change since the baseline, its standard deviation, whether
    it is the station's own or the stations' mean, the flag, and the snapshots and cycles the table covers."""

    source: str
    snapshots: int
    last_cycle: int
    hip_mu_change: float
    hip_mu_change_std: float
    own: bool
    flag: str

    def describe(self) -> str:
        whose = "this station's" if self.own else "the two stations' mean"
        return (
            f"hip μ change {self.hip_mu_change:+.4f} ± {self.hip_mu_change_std:.4f} ({whose}) at cycle "
            f"{self.last_cycle} over {self.snapshots} snapshots; monitor: {self.flag or 'no flag'}"
        )


def _last_finite(values: Sequence[Any]) -> tuple[float, int]:
    for k in range(len(values) - 1, -1, -1):
        try:
            x = float(values[k])
        except (TypeError, ValueError):
            continue
        if math.isfinite(x):
            return x, k
    return math.nan, len(values) - 1


def _number(values: Sequence[Any], k: int) -> float:
    try:
        return float(values[k])
    except (TypeError, ValueError, IndexError):
        return math.nan


def friction_state(table: Mapping[str, Sequence[Any]], j: int | None, source: str) -> FrictionState | None:
    """Station j's (1 or 2; None: the mean) friction at the table's last snapshot with an estimate: the station's own
    column when it has a value there (the monitor separated the stations), else the two stations' mean; None for no
    rows."""
    cycles = table.get("cycle", ())
    if not len(cycles):
        return None
    _, k = _last_finite(table.get("hip_mu_change", ()))
    if k < 0:  # no column of estimates: the last row
        k = len(cycles) - 1
    own = j is not None and math.isfinite(_number(table.get(f"hip_mu_change_{j}", ()), k))
    key = f"hip_mu_change_{j}" if own else "hip_mu_change"
    flags = table.get("flag", ())
    return FrictionState(
        source,
        len(cycles),
        int(float(cycles[k])),
        _number(table.get(key, ()), k),
        _number(table.get(f"{key}_std", ()), k),
        bool(own),
        str(flags[k]) if len(flags) > k else "",
    )


@dataclass(frozen=True)
class StationContext:
    """A station's motion and friction beside its wear (either None when not known)."""

    station: str
    motion: MotionError | None
    friction: FrictionState | None
