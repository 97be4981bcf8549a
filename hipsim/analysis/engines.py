"""The MuJoCo engine against the analytic and Pinocchio models (``hipsim check --engine mujoco``).

MuJoCo's inverse dynamics (:func:`hipsim.mujoco_engine.analyse`: M and bias
from MuJoCo, the rigid closure solved with MuJoCo's constraint Jacobian,
friction as applied forces) describes the same machine as the other two, the
levers' universal-joint spin included. So it must agree column by column,
within :data:`hipsim.analysis.crosscheck.TOLERANCE` of each column's peak,
with the analytic model given that spin (``lever_spin=True``) and with the
Pinocchio model, for any lever inertia and any friction coefficients.

The compared columns are every output of the spec §7.5 contract (slider
motion, torques and their parts, motor speeds, the singularity measure, which
MuJoCo's engine computes from its own Jacobians, and, against Pinocchio, the
joint forces); the inputs (time, angles, load) are the same by construction.
"""

from __future__ import annotations

from typing import Mapping

import numpy as np

from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from .crosscheck import Comparison
from .runs import analyse

__all__ = ["column_differences", "compare_mujoco"]

_INPUTS = ("t_s", "alpha_deg", "beta_deg", "gamma_deg", "Fe_N", "flagged")


def column_differences(candidate: Mapping[str, np.ndarray], reference: Mapping[str, np.ndarray]) -> tuple[tuple[str, float, float], ...]:
    """Per output column both tables have: (name, largest |difference| in the column's unit, that over the reference's peak).

    Args:
        candidate, reference: column name → values, as ``Result.columns()`` gives them.
    """
    rows = []
    for name, values in reference.items():
        if name in _INPUTS or name not in candidate:
            continue
        absolute = float(np.max(np.abs(np.asarray(candidate[name]) - values)))
        peak = float(np.max(np.abs(values)))
        rows.append((name, absolute, absolute / peak if peak > 0 else absolute))
    return tuple(rows)


def compare_mujoco(params: Parameters, trajectory: Trajectory) -> list[Comparison]:
    """MuJoCo's inverse dynamics against the analytic model (with lever spin) and the Pinocchio model.

    Args:
        params: the machine (any lever inertia, any friction).
        trajectory: the motion and load.

    Returns:
        Two comparisons, both required to agree.

    Raises:
        MissingDependencyError: ``mujoco`` is not installed.
    """
    from ..mujoco_engine import analyse as mujoco_analyse

    mujoco = mujoco_analyse(params, trajectory).columns()
    return [
        Comparison(
            "mujoco-analytic", "MuJoCo inverse dynamics vs the analytic model with the universal joints' lever spin", True,
            column_differences(mujoco, analyse(params, trajectory, lever_spin=True).columns()),
        ),
        Comparison(
            "mujoco-pinocchio", "MuJoCo inverse dynamics vs the Pinocchio closed-chain model", True,
            column_differences(mujoco, analyse(params, trajectory, model="pinocchio").columns()),
        ),
    ]
