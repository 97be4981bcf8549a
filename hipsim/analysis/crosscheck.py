"""The engines side by side (``hipsim check``): the analytic and Pinocchio models, and the MuJoCo engine against both.

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

MuJoCo's inverse dynamics (:func:`compare_mujoco`, ``hipsim check --engine
mujoco``: M and bias from MuJoCo, the rigid closure solved with MuJoCo's
constraint Jacobian, friction as applied forces) describes the same machine
as the other two, the levers' universal-joint spin included. So it must agree
column by column, within :data:`TOLERANCE` of each column's peak, with the
analytic model given that spin (``lever_spin=True``) and with the Pinocchio
model, for any lever inertia and any friction coefficients. The compared
columns are every output of the spec §7.5 contract (slider motion, torques
and their parts, motor speeds, the singularity measure, which MuJoCo's engine
computes from its own Jacobians, and, against Pinocchio, the joint forces);
the inputs (time, angles, load) are the same by construction.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..exceptions import HipsimError
from ..machine.parameters import Parameters, slender_levers
from ..motion.sources import TrajectorySource, pieces
from ..motion.trajectories import Trajectory
from ..physics import laws
from ..results import Run
from .runs import analyse
from .streaming import CHUNK, PieceRunner, as_source

__all__ = [
    "CONFIGURATIONS",
    "Comparison",
    "Differences",
    "TOLERANCE",
    "compare_models",
    "compare_mujoco",
    "differences",
]

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


class Differences:
    """The largest absolute difference and the reference's peak per column, gathered over pieces of two runs."""

    def __init__(self):
        self.largest: dict[str, float] = {}
        self.peaks: dict[str, float] = {}

    def add(self, run: Run, reference: Run) -> Differences:
        """Take in one piece of both runs (the same samples). Returns self."""
        if run.trajectory.t.shape != reference.trajectory.t.shape or np.any(run.trajectory.t != reference.trajectory.t):
            raise HipsimError(f"the {run.model} and {reference.model} runs are not along the same trajectory")
        a, b = run.columns(), reference.columns()
        for name, values in a.items():
            if name in _INPUTS or name not in b:
                continue
            absolute = float(np.max(np.abs(values - b[name])))
            peak = float(np.max(np.abs(b[name])))
            self.largest[name] = max(self.largest.get(name, absolute), absolute)
            self.peaks[name] = max(self.peaks.get(name, peak), peak)
        return self

    def rows(self) -> tuple[tuple[str, float, float], ...]:
        """(column, largest absolute difference, relative to the reference column's peak)."""
        return tuple((name, a, a / self.peaks[name] if self.peaks[name] > 0 else a) for name, a in self.largest.items())


def differences(run: Run, reference: Run) -> tuple[tuple[str, float, float], ...]:
    """Column by column, the largest absolute difference and that difference relative to the reference column's peak.

    Args:
        run, reference: two runs along the same trajectory; only the columns
            both have and that a model computes are compared.

    Returns:
        (column, largest absolute difference in the column's unit, relative difference).
    """
    return Differences().add(run, reference).rows()


#: The three comparisons: name, description, whether required (of the machine), the run and its reference.
CONFIGURATIONS = (
    (
        "exact",
        "spec §7.4: slender-rod levers, spin-free analytic levers",
        lambda params: not laws.lever_joint_friction_on(params.friction),
        "analytic slender",
        "pinocchio slender",
    ),
    (
        "published",
        "published lever inertia, spin-free analytic levers (the paper model's error)",
        lambda params: False,
        "analytic published",
        "pinocchio published",
    ),
    (
        "published+spin",
        "published lever inertia, analytic levers with the universal joints' spin",
        lambda params: True,
        "analytic spin",
        "pinocchio published",
    ),
)


def compare_models(
    params: Parameters,
    trajectory: Trajectory | TrajectorySource,
    *,
    chunk: int = CHUNK,
    progress: Callable[[int, int], None] | None = None,
) -> list[Comparison]:
    """Run both models in the three configurations of the module docstring, a piece at a time.

    Args:
        params: the machine (published lever inertia or the user's).
        trajectory: the motion and load (a Trajectory or a :mod:`~hipsim.motion.sources` source).
        chunk: samples per piece (memory is set by it; the result is that of one piece).
        progress: called with (samples done, samples in all) after each piece.

    Returns:
        The three comparisons, exact first.
    """
    source = as_source(trajectory)
    slender = slender_levers(params)
    # The analytic model first on every piece: it checks every pose and names the first one out of reach.
    runners = {
        "analytic slender": PieceRunner(slender, source, "analytic"),
        "analytic published": PieceRunner(params, source, "analytic"),
        "analytic spin": PieceRunner(params, source, "analytic", lever_spin=True),
        "pinocchio slender": PieceRunner(slender, source, "pinocchio"),
        "pinocchio published": PieceRunner(params, source, "pinocchio"),
    }
    gathered = {name: Differences() for name, *_ in CONFIGURATIONS}
    for start, stop in pieces(source, chunk):
        piece = source.piece(start, stop)
        runs = {name: runner.run(start, piece) for name, runner in runners.items()}
        for name, _, _, run, reference in CONFIGURATIONS:
            gathered[name].add(runs[run], runs[reference])
        if progress is not None:
            progress(stop, len(source))
    return [
        Comparison(name, description, required(params), gathered[name].rows())
        for name, description, required, _, _ in CONFIGURATIONS
    ]


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
            "mujoco-analytic",
            "MuJoCo inverse dynamics vs the analytic model with the universal joints' lever spin",
            True,
            differences(mujoco, analyse(params, trajectory, lever_spin=True)),
        ),
        Comparison(
            "mujoco-pinocchio",
            "MuJoCo inverse dynamics vs the Pinocchio closed-chain model",
            True,
            differences(mujoco, analyse(params, trajectory, model="pinocchio")),
        ),
    ]
