"""The MuJoCo engine against the analytic and Pinocchio models (``hipsim check --engine mujoco``).

MuJoCo's inverse dynamics (``hipsim.analyse(..., model="mujoco")``: M and bias
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

from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from .crosscheck import Comparison, differences
from .runs import analyse

__all__ = ["compare_mujoco"]


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
    mujoco = analyse(params, trajectory, model="mujoco")
    return [
        Comparison(
            "mujoco-analytic", "MuJoCo inverse dynamics vs the analytic model with the universal joints' lever spin", True,
            differences(mujoco, analyse(params, trajectory, lever_spin=True)),
        ),
        Comparison(
            "mujoco-pinocchio", "MuJoCo inverse dynamics vs the Pinocchio closed-chain model", True,
            differences(mujoco, analyse(params, trajectory, model="pinocchio")),
        ),
    ]
