"""The analytic checks ``hipsim wear --self-check`` runs on the user's cup and grid, each with its number and tolerance.

- **Pure flexion** (the built-in cycle's α, β = γ = 0): the head slides along
  one line at every point, so CS = 0 everywhere.
- **Time reversal** (the built-in cycle run backwards): |v| and p are the same
  at each instant, so s, W and CS are the same at every point.
- **Flexion arc**: with β = γ = 0 the contact centre n = Rx(−α)·ẑ sweeps an
  arc out and back, so the force track is r·(range of α)·2 long.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..motion.trajectories import Trajectory, iso14242_angles, iso14242_load
from .kinematics import CupSetup
from .maps import wear_maps
from .points import CupPoints

__all__ = ["SelfCheck", "self_checks"]

#: Samples of the check motions (one 1 s cycle).
SAMPLES = 1000


@dataclass(frozen=True)
class SelfCheck:
    """One check: what it holds, the worst deviation found, the tolerance, and whether it held.

    Attributes:
        name: the check.
        law: what must hold, in words.
        deviation: the worst deviation found (unit in ``law``).
        tolerance: the largest deviation allowed.
    """

    name: str
    law: str
    deviation: float
    tolerance: float

    @property
    def passed(self) -> bool:
        return bool(self.deviation <= self.tolerance)


def _motion(times: np.ndarray, sign: float, flexion_only: bool, name: str) -> Trajectory:
    q, qd, qdd = iso14242_angles(times)
    if flexion_only:
        q[:, 1:] = qd[:, 1:] = qdd[:, 1:] = 0.0
    return Trajectory(times, q, sign * qd, qdd, iso14242_load(times), name=name, periodic=True)


def self_checks(setup: CupSetup, points: CupPoints) -> list[SelfCheck]:
    """Run the module's checks on ``setup`` (the head, the sequence, the mount, the moving part) and ``points``."""
    t = np.arange(SAMPLES) / SAMPLES
    forward = _motion(t, 1.0, False, "ISO 14242-1")
    # q_r(t) = q(T − t): the samples of the cycle in reverse order, the rates negated.
    reversed_ = _motion((1.0 - t) % 1.0, -1.0, False, "ISO 14242-1 reversed")
    reversed_ = Trajectory(t, reversed_.q, reversed_.qd, reversed_.qdd, reversed_.Fe, reversed_.name, periodic=True)
    flexion = _motion(t, 1.0, True, "flexion only")
    a, b, f = (wear_maps(m, 1.0, setup, points) for m in (forward, reversed_, flexion))
    checks = []
    loaded = f.loaded
    # Flexion alone is sliding along one line only when the platform's x axis is the head's: the moving head and a
    # mount keep it so (R_rel = Rx(±α)·M turns about M's image of x), and the sequence does not matter with β = γ = 0.
    checks.append(
        SelfCheck(
            "pure flexion",
            "CS = 0 at every loaded point",
            float(np.max(np.abs(f.cross_shear[loaded]))) if loaded.any() else 0.0,
            1e-9,
        )
    )

    def worst(x, y):
        scale = max(float(np.nanmax(np.abs(x))), 1e-300)
        same_nan = np.isnan(x) == np.isnan(y)
        return float(np.nanmax(np.abs(x - y)) / scale) if same_nan.all() else math.inf

    checks.append(
        SelfCheck(
            "time reversal",
            "the same s, W and CS at every point (largest difference relative to the largest value)",
            max(
                worst(a.sliding_mm, b.sliding_mm),
                worst(a.work_N_per_mm, b.work_N_per_mm),
                worst(a.cross_shear, b.cross_shear),
            ),
            1e-9,
        )
    )
    alpha = flexion.q[:, 0]
    arc = setup.radius_mm * (alpha.max() - alpha.min()) * 2
    expected = 0.0 if setup.moving == "head" else arc
    checks.append(
        SelfCheck(
            "flexion arc",
            f"force track = r·(range of α)·2 = {expected:.6g} mm (relative difference)"
            if setup.moving == "cup"
            else "force track = 0 mm with the head moving (mm)",
            abs(f.force_track_mm - expected) / (expected if expected else 1.0),
            1e-5,
        )
    )
    return checks
