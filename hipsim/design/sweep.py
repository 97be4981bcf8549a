"""Design sweeps: each variant of a machine along one trajectory → one row of metrics.

Pure: :func:`evaluate` turns one variant's values into a row (peak and RMS
torque and peak speed per motor, stroke per slider, the smallest singularity
measure, joint forces with the Pinocchio model, the rating check);
:func:`run_sweep` runs batches of variants through dask.distributed (a
``LocalCluster`` of worker processes, or a cluster at a scheduler's address),
or in this process for one worker, with the same :func:`evaluate_batch` on
either path, so the rows are the same to the last bit.

A variant that cannot be built (:class:`~hipsim.exceptions.ParameterError`:
a lever that does not reach, a negative mass) or whose motion leaves the
workspace (:class:`~hipsim.exceptions.PoseError`,
:class:`~hipsim.exceptions.ClosureError`) is a row too, with its status and
reason: a sweep maps where designs stop working.

Example:
    >>> import hipsim
    >>> from hipsim.design.sweep import SweepSetup, run_sweep
    >>> from hipsim.design.variants import grid
    >>> setup = SweepSetup(hipsim.load_parameters(), hipsim.iso14242(rate=100))
    >>> variants = grid({"lever.length_mm": (320.0, 340.0, 10.0)})
    >>> rows = [row for batch in run_sweep(setup, variants, workers=1) for _, row in batch]
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..analysis.cluster import batch_size as _batch_size
from ..analysis.cluster import run_batches
from ..analysis.registry import engine_entry, engine_names
from ..analysis.runs import analyse
from ..exceptions import ArgumentError, ClosureError, ParameterError, PoseError
from ..fingerprint import part_fingerprints
from ..machine.drive import Drive, drive_from_motor_table
from ..machine.parameters import Parameters, file_values, override_parameters
from ..motion.trajectories import Trajectory
from ..physics.units import RPM_PER_RAD_S
from ..results import peak_and_rms
from .checks import drive_checks
from .demand import screw_side
from .ranking import Candidate
from .variants import KeyRef, Variants

__all__ = [
    "OBJECTIVES",
    "STATUSES",
    "TEXT_COLUMNS",
    "SweepSetup",
    "batches",
    "evaluate",
    "evaluate_batch",
    "metric_columns",
    "pareto_front",
    "parse_objective",
    "run_sweep",
    "variant_id",
]

#: A row's status: computed, a machine that cannot be built, or a motion out of its workspace.
STATUSES = ("ok", "cannot_assemble", "out_of_workspace")
#: Columns holding text; every other column is a number (NaN where there is none).
TEXT_COLUMNS = ("status", "reason", "rating", "binding")
#: The objectives the summary names the best variant of, and whether larger is better.
OBJECTIVES = {
    "tau_peak_max_Nmm": False,
    "tau_rms_max_Nmm": False,
    "speed_peak_max_rpm": False,
    "stroke_max_mm": False,
    "cond_inv_min": True,
}


@dataclass(frozen=True, eq=False)
class SweepSetup:
    """What every variant shares: the machine they start from, the keys, the motion, the model and the ratings.

    Attributes:
        base: the machine the variants change (``--params``, ``--set``).
        trajectory: the motion and load every variant runs (reused, never copied per variant).
        keys: the swept keys (columns of :class:`~hipsim.design.variants.Variants`).
        model: "analytic" or "pinocchio" (adds the joint forces).
        drive: the drive to check every variant against; None for each
            variant's own ``[motor]`` table (when it has one; else no check).
        cycles: test cycles the trajectory holds (for the checks' energy per cycle).
    """

    base: Parameters
    trajectory: Trajectory
    keys: tuple[KeyRef, ...] = ()
    model: str = "analytic"
    drive: Drive | None = None
    cycles: float = 1.0
    _lists: dict = field(default_factory=dict, repr=False)

    def __post_init__(self):
        installed = engine_names(optional=False)
        if self.model not in installed:
            raise ArgumentError("model", self.model, " or ".join(repr(name) for name in installed))
        if not (math.isfinite(self.cycles) and self.cycles > 0):
            raise ArgumentError("cycles", self.cycles, "a positive number of test cycles")
        screw = None if self.drive is None else self.drive.screw
        if self.drive is not None and screw is not None and screw.lead is not None:
            swept = [k.name for k in self.keys if k.dotted in ("screw.lead_mm", "screw.inertia_kgmm2")]
            if swept:
                raise ArgumentError(
                    "keys",
                    swept,
                    f"no screw key: the drive ({self.drive.source}) names its screw's lead, which is the machine's",
                )
        # A list key's other numbers stay the base machine's: keep the whole lists once, in the file's units.
        listed = [k.dotted for k in self.keys if k.index is not None]
        values = file_values(self.base) if listed else {}
        lists = {dotted: list(values[dotted]) for dotted in listed}
        object.__setattr__(self, "_lists", lists)

    @property
    def joint_forces(self) -> bool:
        return engine_entry(self.model).joint_forces

    def fingerprints(self) -> dict[str, str]:
        """The fingerprint of everything that determines a row, per part and whole (``"setup"``; :mod:`hipsim.fingerprint`).

        Parts: the machine's values (``--params`` and ``--set``, not the
        file's name or comments), the trajectory's samples (file, rate,
        frequency, cycles all end up there), the model, the drive's values,
        the test cycles and the swept keys.
        """
        t = self.trajectory
        return part_fingerprints(
            {
                "parameters": self.base,
                "trajectory": {"t": t.t, "q": t.q, "qd": t.qd, "qdd": t.qdd, "Fe": t.Fe, "periodic": bool(t.periodic)},
                "model": self.model,
                "drive": self.drive,
                "cycles": self.cycles,
                "keys": [k.name for k in self.keys],
            }
        )

    def overrides(self, values: Sequence[float] | np.ndarray) -> dict[str, Any]:
        """One variant's values as parameter overrides (a list key gets its whole list, one number changed)."""
        out: dict[str, Any] = {}
        for key, value in zip(self.keys, values):
            if key.index is None:
                out[key.dotted] = float(value)
            else:
                numbers = out.setdefault(key.dotted, list(self._lists[key.dotted]))
                numbers[key.index] = float(value)
        return out


def metric_columns(joint_forces: bool = False) -> list[str]:
    """The columns of a row after the swept keys, in order (units in the names, as the CSV of spec §7.5)."""
    names = ["status", "reason"]
    for quantity, unit in (("tau_peak", "Nmm"), ("tau_rms", "Nmm"), ("speed_peak", "rpm")):
        names += [f"{quantity}_{i}_{unit}" for i in (1, 2, 3)] + [f"{quantity}_max_{unit}"]
    names += [f"stroke_{j}{i}_mm" for j in (1, 2) for i in (1, 2, 3)] + ["stroke_max_mm", "cond_inv_min"]
    if joint_forces:
        names += [f"Fa_{j}{i}_peak_N" for j in (1, 2) for i in (1, 2, 3)] + [
            "Fo_1_peak_N",
            "Fo_2_peak_N",
            "Fa_peak_max_N",
            "Fo_peak_max_N",
        ]
    return names + ["rating", "margin", "binding"]


def _drive(setup: SweepSetup, params: Parameters) -> Drive | None:
    if setup.drive is not None:
        return setup.drive
    return drive_from_motor_table(params.motor, params.source) if params.motor else None


def evaluate(setup: SweepSetup, values: Sequence[float] | np.ndarray) -> dict[str, Any]:
    """One variant's row: its metrics, or its status and the reason it has none.

    Args:
        setup: what the variants share.
        values: the variant's values, one per key of ``setup.keys``, in the file's units.

    Returns:
        The row by column (:func:`metric_columns`): numbers in the units their
        names give, NaN where not computed; ``rating`` is "pass", "fail",
        "unchecked" (no ratings given) or empty (no metrics); ``margin`` the
        smallest margin of the checks and ``binding`` the check it belongs to.
    """
    row: dict[str, Any] = {name: math.nan for name in metric_columns(setup.joint_forces)}
    row |= {"reason": "", "rating": "", "binding": ""}
    try:
        params = override_parameters(setup.base, setup.overrides(values), overrides_source="variant")
        drive = _drive(setup, params)
        if (
            drive is not None and drive.screw is not None
        ):  # the drive's screw, when it names one, is the machine's (as hipsim size)
            screw = {"lead": drive.screw.lead, "screw_inertia": drive.screw.inertia}
            params = params.replace(**{k: v for k, v in screw.items() if v is not None})
    except ParameterError as error:
        return row | {"status": "cannot_assemble", "reason": _reason(error)}
    try:
        run = analyse(params, setup.trajectory, model=setup.model)
    except (PoseError, ClosureError) as error:
        return row | {"status": "out_of_workspace", "reason": _reason(error)}
    row["status"] = "ok"
    # The same reductions as Run.summary, so a variant equal to the base gives its numbers to the last bit.
    ok = (
        ~run.flagged
    )  # none are (the run raises instead); indexing copies as Run.summary's does, so the sums round alike
    tau_peak, tau_rms = peak_and_rms(run.torques.total[ok] * 1e3)
    speed_peak, _ = peak_and_rms(run.torques.motor_speed[ok] * RPM_PER_RAD_S)
    for quantity, unit, numbers in (
        ("tau_peak", "Nmm", tau_peak),
        ("tau_rms", "Nmm", tau_rms),
        ("speed_peak", "rpm", speed_peak),
    ):
        for i in range(3):
            row[f"{quantity}_{i + 1}_{unit}"] = float(numbers[i])
        row[f"{quantity}_max_{unit}"] = float(numbers.max())
    L = run.L * 1e3
    stroke = L.max(axis=0) - L.min(axis=0)
    for j in range(2):
        for i in range(3):
            row[f"stroke_{j + 1}{i + 1}_mm"] = float(stroke[j, i])
    row["stroke_max_mm"] = float(stroke.max())
    row["cond_inv_min"] = float(run.cond_inv.min())
    if setup.joint_forces and run.joint_forces is not None:  # the setup asks the model for them
        Fa_peak, _ = peak_and_rms(run.joint_forces.Fa)
        Fo_peak, _ = peak_and_rms(run.joint_forces.Fo)
        for j in range(2):
            for i in range(3):
                row[f"Fa_{j + 1}{i + 1}_peak_N"] = float(Fa_peak[j, i])
            row[f"Fo_{j + 1}_peak_N"] = float(Fo_peak[j])
        row["Fa_peak_max_N"], row["Fo_peak_max_N"] = float(Fa_peak.max()), float(Fo_peak.max())
    if drive is None:
        row["rating"] = "unchecked"
        return row
    # The reflected inertia costs several model runs; only a motor with a rotor inertia is checked against it.
    side = screw_side(run, setup.cycles, load_inertia=drive.motor.rotor_inertia is not None)
    candidate = Candidate(drive, tuple(drive_checks(side, drive)))
    binding = candidate.binding
    row["rating"] = {True: "pass", False: "fail", None: "unchecked"}[candidate.passed]
    if binding is not None and binding.margin is not None:  # the binding check is one made: it has a margin
        row["margin"] = float(binding.margin)
        row["binding"] = f"{binding.name} LN{binding.module}"
    return row


def _reason(error: Exception) -> str:
    """The error without the place every row shares (the parameter file and the variant's values are in the row)."""
    if isinstance(error, ParameterError):
        text = error.args[0].removeprefix(f"{error.source}, ") if error.source else error.args[0]
    elif isinstance(error, PoseError):
        text = f"t = {error.time:.6g} s: {error.reason}"
    else:
        text = str(error)
    return " ".join(text.split())


def evaluate_batch(batch: tuple[np.ndarray, np.ndarray], setup: SweepSetup) -> list[tuple[int, dict[str, Any]]]:
    """The rows of a batch of variants: (index, row) pairs, ``batch`` = (indices (m,), values (m, k)).

    The task each worker runs; a batch of many variants keeps the scheduler's
    cost per variant small.
    """
    indices, values = batch
    return [(int(index), evaluate(setup, row)) for index, row in zip(indices, values)]


def batches(
    variants: Variants, indices: Sequence[int] | np.ndarray | None = None, size: int = 100
) -> list[tuple[np.ndarray, np.ndarray]]:
    """The variants (or those at ``indices``) in batches of at most ``size``: (indices, values) pairs."""
    if size < 1:
        raise ArgumentError("size", size, "at least 1 variant a batch")
    chosen = np.arange(len(variants)) if indices is None else np.asarray(indices, dtype=int)
    return [(chosen[k : k + size], variants.values[chosen[k : k + size]]) for k in range(0, chosen.size, size)]


#: The largest batch of variants a task gets.
MOST_PER_BATCH = 200


def run_sweep(
    setup: SweepSetup,
    variants: Variants,
    indices: Sequence[int] | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    batch_size: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Iterator[list[tuple[int, dict[str, Any]]]]:
    """Evaluate variants on dask.distributed, yielding each batch's rows as it completes.

    Args:
        setup: what the variants share (sent to each worker once).
        variants: the variants.
        indices: which of them to run (default all), e.g. those a previous run has not.
        workers: worker processes of a local cluster (default: the cores); 1
            without ``scheduler`` runs in this process, through the same batches.
        scheduler: a dask scheduler's address (``tcp://host:8786``) to run on
            its cluster instead of a local one.
        batch_size: variants per task (default: about eight tasks a worker, at most 200 variants each).
        progress: called with (variants done, variants to do) after each batch.

    Yields:
        Lists of (variant index, row) pairs, in the order the batches complete.

    Raises:
        MissingDependencyError: dask.distributed is not installed (``pip install 'hipsim[sweep]'``).
        ArgumentError: a worker count below 1, or a scheduler that cannot be reached.
    """
    if workers is not None and (not isinstance(workers, (int, np.integer)) or workers < 1):
        raise ArgumentError("workers", workers, "a whole number of worker processes, at least 1")
    workers = int(workers) if workers is not None else (os.cpu_count() or 1)
    chosen = np.arange(len(variants)) if indices is None else np.asarray(indices, dtype=int)
    size = batch_size if batch_size is not None else _batch_size(chosen.size, workers, MOST_PER_BATCH)
    work = batches(variants, chosen, size)
    done, total = 0, int(chosen.size)
    for rows in run_batches(evaluate_batch, work, setup, workers, scheduler, "hipsim sweep"):
        done += len(rows)
        if progress is not None:
            progress(done, total)
        yield rows


def variant_id(values: Sequence[float]) -> tuple[float, ...]:
    """A variant's identity from its values, robust to how a file printed them (12 significant digits)."""
    return tuple(float(f"{float(v):.12g}") for v in values)


def parse_objective(text: str, columns: Sequence[str] | None = None) -> tuple[str, bool]:
    """``"tau_peak_max_Nmm"`` (smaller is better) or ``"-cond_inv_min"`` (larger is better) → (column, maximise).

    Raises:
        ArgumentError: the column is not one of ``columns`` (when given) or holds text.
    """
    text = text.strip()
    maximise = text.startswith("-")
    name = text.lstrip("+-").strip()
    if not name or name in TEXT_COLUMNS or (columns is not None and name not in columns):
        known = [c for c in (columns or []) if c not in TEXT_COLUMNS]
        raise ArgumentError(
            "objective",
            text,
            "a numeric column" + (f" ({', '.join(known)})" if known else "") + ", with a leading - to maximise it",
        )
    return name, maximise


def pareto_front(values: np.ndarray, maximise: Sequence[bool]) -> np.ndarray:
    """Which points no other point dominates: at least as good in every objective and better in one.

    Args:
        values: (n, m) objective values; NaN rows are never on the front.
        maximise: per objective, True if larger is better.

    Returns:
        (n,) bool, True on the front.
    """
    values = np.asarray(values, dtype=float)
    signs = np.where(np.asarray(maximise, dtype=bool), -1.0, 1.0)
    cost = values * signs  # smaller is better everywhere
    valid = np.all(np.isfinite(cost), axis=1)
    front = valid.copy()
    points = cost[valid]
    where = np.flatnonzero(valid)
    for k, point in zip(where, points):
        dominated = np.all(points <= point, axis=1) & np.any(points < point, axis=1)
        front[k] = not np.any(dominated)
    return front
