"""The analytic and Pinocchio models side by side (``hipsim check``).

Three comparisons along one trajectory, column by column of the CSV contract:

1. **exact** — spec §7.4: slender-rod levers, I_l = diag(I_t, I_t, 0). The
   analytic lever has no spin about its axis, the universal joint gives it one,
   and with no inertia about the axis the spin carries no energy: the two
   models describe the same physics and must agree to 1e-8 of each column's
   peak. (Friction in the levers' own joints acts on the spin too, so when the
   U- or S-joint friction is non-zero this comparison is shown, not required.)
2. **published, spin-free** — the published I_l with the paper's lever: the
   difference is the paper model's error, shown as a result.
3. **published, with spin** — the published I_l with the analytic model given
   the universal joint's spin (``lever_spin=True``): the difference vanishes
   again, which shows that the spin is the whole of (2). Required to 1e-8.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..analytic import laws
from ..machine.parameters import Parameters, slender_levers
from .runs import analyse
from ..motion.trajectories import Trajectory

__all__ = ["Comparison", "TOLERANCE", "compare_models"]

#: Largest allowed difference, relative to each column's peak, where the models must agree.
TOLERANCE = 1e-8

#: Columns both models compute (the others — time, angles, load, singularity measure — they share).
_SHARED_INPUTS = ("t_s", "alpha_deg", "beta_deg", "gamma_deg", "Fe_N", "cond_inv")


@dataclass(frozen=True)
class Comparison:
    """One configuration's column-by-column differences.

    Attributes:
        name: short name of the configuration.
        description: what is compared.
        required: whether the models must agree to :data:`TOLERANCE`.
        rows: (column, largest absolute difference in the column's unit,
            largest difference relative to the column's peak).
    """

    name: str
    description: str
    required: bool
    rows: tuple[tuple[str, float, float], ...]

    @property
    def worst(self) -> float:
        """The largest relative difference over all columns."""
        return max(relative for _, _, relative in self.rows)

    @property
    def ok(self) -> bool:
        """True if every column is within tolerance."""
        return self.worst <= TOLERANCE


def _differences(analytic, pinocchio) -> tuple[tuple[str, float, float], ...]:
    a, b = analytic.columns(), pinocchio.columns()
    rows = []
    for name, values in a.items():
        if name in _SHARED_INPUTS or name == "flagged":
            continue
        absolute = float(np.max(np.abs(values - b[name])))
        peak = float(np.max(np.abs(b[name])))
        rows.append((name, absolute, absolute / peak if peak > 0 else absolute))
    return tuple(rows)


def compare_models(params: Parameters, trajectory: Trajectory) -> list[Comparison]:
    """Run both models in the three configurations of the module docstring.

    Args:
        params: the machine (published lever inertia or the user's).
        trajectory: the motion and load.

    Returns:
        The three comparisons, exact first.
    """
    lever_joint_friction = laws.lever_joint_friction_on(params.friction)
    slender = slender_levers(params)
    pinocchio_slender = analyse(slender, trajectory, model="pinocchio")
    pinocchio = analyse(params, trajectory, model="pinocchio")
    return [
        Comparison(
            "exact", "spec §7.4: slender-rod levers, spin-free analytic levers", not lever_joint_friction,
            _differences(analyse(slender, trajectory), pinocchio_slender),
        ),
        Comparison(
            "published", "published lever inertia, spin-free analytic levers (the paper model's error)", False,
            _differences(analyse(params, trajectory), pinocchio),
        ),
        Comparison(
            "published+spin", "published lever inertia, analytic levers with the universal joints' spin", True,
            _differences(analyse(params, trajectory, lever_spin=True), pinocchio),
        ),
    ]
