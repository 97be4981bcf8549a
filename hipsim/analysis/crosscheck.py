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
from ..exceptions import HipsimError
from ..results import Run
from ..motion.trajectories import Trajectory

__all__ = ["Comparison", "TOLERANCE", "compare_models", "differences"]

#: Largest allowed difference, relative to each column's peak, where the models must agree.
TOLERANCE = 1e-8

#: Columns that are the trajectory itself, not computed by a model.
_INPUTS = ("t_s", "alpha_deg", "beta_deg", "gamma_deg", "Fe_N", "flagged")


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


def differences(run: Run, reference: Run) -> tuple[tuple[str, float, float], ...]:
    """Column by column, the largest absolute difference and that difference relative to the reference column's peak.

    Args:
        run, reference: two runs along the same trajectory; only the columns
            both have and that a model computes are compared.

    Returns:
        (column, largest absolute difference in the column's unit, relative difference).
    """
    if run.trajectory.t.shape != reference.trajectory.t.shape or np.any(run.trajectory.t != reference.trajectory.t):
        raise HipsimError(f"the {run.model} and {reference.model} runs are not along the same trajectory")
    a, b = run.columns(), reference.columns()
    rows = []
    for name, values in a.items():
        if name in _INPUTS or name not in b:
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
    # The analytic model first: it checks every pose and names the first one out of reach.
    analytic_slender = analyse(slender, trajectory)
    analytic = analyse(params, trajectory)
    analytic_spin = analyse(params, trajectory, lever_spin=True)
    pinocchio_slender = analyse(slender, trajectory, model="pinocchio")
    pinocchio = analyse(params, trajectory, model="pinocchio")
    return [
        Comparison(
            "exact", "spec §7.4: slender-rod levers, spin-free analytic levers", not lever_joint_friction,
            differences(analytic_slender, pinocchio_slender),
        ),
        Comparison(
            "published", "published lever inertia, spin-free analytic levers (the paper model's error)", False,
            differences(analytic, pinocchio),
        ),
        Comparison(
            "published+spin", "published lever inertia, analytic levers with the universal joints' spin", True,
            differences(analytic_spin, pinocchio),
        ),
    ]
