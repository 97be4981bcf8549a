"""Design reports: figures of motion, torque, load and joint forces, a sizing table, one HTML page (issue 7).

:func:`write_report` runs the models along a trajectory and writes a folder a
designer can hand on: every figure as PNG and SVG, ``index.html`` (one
self-contained page: the PNGs are embedded as data URIs, so it works offline
and after the folder is moved or the page is mailed alone), ``report.json``
(the summary and sizing numbers) and ``torques.csv`` (the columns of spec §7.5).

Sizing (:func:`sizing`), per linear module i:

* peak and RMS motor torque τ_i [N·mm] (RMS over the samples: the cycle RMS
  on a periodic trajectory);
* peak motor speed [rpm];
* peak mechanical power max|τ_i·θ̇_i| [W], θ̇_i = 2π·L̇_i/p;
* peak **axial screw force** [N], defined as the force the nut pushes on the
  carriage (both sliders S_1i and S_2i together), positive upward:

      F_axial,i = 2π·(τ_i − τ_L,i − τ_sf,i)/p

  with τ_L,i = (2π·I_L/p)·L̈_i the screw rotor's inertia torque and
  τ_sf,i = c·ŝ(θ̇_i) + b·θ̇_i the screw's own friction torque (spec §4.3; zero
  with the published parameters): what is left of the motor torque once the
  rotor is accelerated and the screw's losses are paid is turned into thrust
  by an ideal screw. It carries the levers' forces, the sliders' weight and
  inertia and the guide friction;
* the carriage stroke (max − min slider height) [mm];

and per joint (Pinocchio model only) the peak reaction force at the spherical
joints a_ji and the central joints o_j [N]. Optionally each figure is checked
against a motor and module rating (:func:`load_ratings`, a small TOML file
with a ``[motor]`` table) with pass/fail and margin.
"""

from __future__ import annotations

import dataclasses

import base64
import html
import io
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np

from ..analytic.virtual_work import Torques, screw_friction_torque
from ..exceptions import HipsimError, ParameterError
from ..machine.parameters import SCHEMA, Parameters, check_entry, read_toml
from ..files import check_folder, output_folder, write_atomic
from ..analysis.runs import Result, analyse
from ..motion.trajectories import Trajectory

__all__ = [
    "FIGURE_CAPTIONS",
    "JointSizing",
    "ModuleSizing",
    "MotorRatings",
    "RATING_KEYS",
    "RatingCheck",
    "ReportFiles",
    "Sizing",
    "axial_screw_force",
    "load_ratings",
    "plot_joint_forces",
    "plot_load_friction",
    "plot_singularity",
    "plot_slider_motion",
    "plot_torque_parts",
    "plot_tracking",
    "save_figure",
    "sizing",
    "write_report",
]

_RPM = 60.0 / (2.0 * math.pi)
_MODULE_COLOURS = ("tab:blue", "tab:orange", "tab:green")
_PART_STYLE = {
    "tau_m": ("platforms", "tab:blue"),
    "tau_l": ("levers", "tab:orange"),
    "tau_s": ("sliders", "tab:green"),
    "tau_L": ("screws", "tab:purple"),
    "tau_f": ("friction", "tab:red"),
}
_ANGLE_LABELS = ("α flexion/extension", "β abduction/adduction", "γ internal/external rotation")

#: Each figure the report can hold, by file stem, with its caption.
FIGURE_CAPTIONS = {
    "slider_motion": "Slider displacement, velocity and acceleration over the cycle, per linear module, both platforms "
    "(the two sliders of a module share one carriage: equal velocity and acceleration, heights h₁ − h₂ apart).",
    "motor_torques": "Each motor's torque split into its five parts (platforms, levers, sliders, screws, friction) and the total.",
    "load_friction": "The applied hydraulic load and the friction moment of each platform's central chain (hip joint + thrust bearing).",
    "joint_forces": "Reaction forces at the spherical joints a_ji and the central joints o_j (Pinocchio closed-chain model).",
    "singularity": "The singularity measure (inverse condition number of J) along the trajectory.",
    "tracking_errors": "Tracking errors of the platform angles under each controller (closed-loop simulation).",
}


# ---------------------------------------------------------------------------
# Figures


def save_figure(fig, out_dir: str | Path, stem: str, dpi: int = 120) -> tuple[Path, Path]:
    """Write a figure as ``stem.png`` and ``stem.svg`` in ``out_dir``, each atomically.

    The SVG is made reproducible (no date, fixed id salt) so reruns of the same
    input give the same bytes.

    Args:
        fig: a matplotlib Figure.
        out_dir: an existing folder.
        stem: file name without extension.
        dpi: PNG resolution in dots per inch.

    Returns:
        The PNG and SVG paths.
    """
    import matplotlib

    out = Path(out_dir)
    paths = []
    with matplotlib.rc_context({"svg.hashsalt": "hipsim", "svg.fonttype": "path"}):
        for fmt, metadata in (("png", {"Software": None}), ("svg", {"Date": None, "Creator": None})):
            buffer = io.BytesIO()
            fig.savefig(buffer, format=fmt, dpi=dpi, metadata=metadata)
            paths.append(write_atomic(out / f"{stem}.{fmt}", buffer.getvalue()))
    return paths[0], paths[1]


def _figure(rows: int, height: float = 2.6, width: float = 10.0):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height * rows + 0.6), layout="constrained")
    axes = fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0]
    for ax in axes:
        ax.grid(alpha=0.3)
    return fig, axes


def plot_slider_motion(result: Result):
    """Slider heights L_ji [mm], velocities [mm/s] and accelerations [mm/s²] over time [s].

    One colour per linear module i; solid platform 1 (upper), dashed platform 2 (lower).
    """
    fig, axes = _figure(3)
    t = result.trajectory.t
    for quantity, unit, ax in (("L", "mm", axes[0]), ("Ld", "mm/s", axes[1]), ("Ldd", "mm/s²", axes[2])):
        values = getattr(result, quantity) * 1e3
        for j, style in ((0, "-"), (1, "--")):
            for i in range(3):
                ax.plot(t, values[:, j, i], ls=style, color=_MODULE_COLOURS[i], lw=1.4 if j == 0 else 1.1, label=f"S{j + 1}{i + 1}")
        name = {"L": "height L_ji", "Ld": "velocity L̇_ji", "Ldd": "acceleration L̈_ji"}[quantity]
        ax.set_ylabel(f"slider {name} [{unit}]")
    axes[0].legend(ncol=6, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, 1.32), title="slider S_ji (platform j, module i)", title_fontsize=8)
    axes[-1].set_xlabel("time t [s]")
    fig.suptitle(f"Slider motion: {result.trajectory.name}")
    return fig


def plot_torque_parts(result: Result):
    """Per motor: the five torque parts and the total in [N·mm] over time [s]."""
    fig, axes = _figure(3, height=2.8)
    t = result.trajectory.t
    torques = result.torques
    for i, ax in enumerate(axes):
        for part, (label, colour) in _PART_STYLE.items():
            ax.plot(t, getattr(torques, part)[:, i] * 1e3, color=colour, lw=1.1, label=label)
        ax.plot(t, torques.tau[:, i] * 1e3, color="black", lw=2.0, label="total")
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.set_ylabel(f"motor {i + 1} torque [N·mm]")
    axes[0].legend(ncol=6, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, 1.25))
    axes[-1].set_xlabel("time t [s]")
    fig.suptitle(f"Motor torques and their parts ({result.model} model): {result.trajectory.name}")
    return fig


def plot_load_friction(result: Result):
    """The applied load F_e [N] and each platform's central-chain friction moment [N·mm] over time [s]."""
    fig, axes = _figure(2)
    t = result.trajectory.t
    axes[0].plot(t, result.trajectory.Fe, color="tab:brown", lw=1.6, label="hydraulic load F_e")
    axes[0].set_ylabel("load F_e [N]")
    axes[0].set_ylim(bottom=0.0)
    axes[0].legend(fontsize=8, loc="upper right")
    axes[1].plot(t, result.torques.friction_moment * 1e3, color="tab:red", lw=1.6, label="|τ_mf|, each platform (hip joint + thrust bearing)")
    axes[1].set_ylabel("friction moment [N·mm]")
    axes[1].set_ylim(bottom=0.0)
    axes[1].legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("time t [s]")
    fig.suptitle(f"Applied load and central-chain friction: {result.trajectory.name}")
    return fig


def plot_joint_forces(result: Result):
    """Reaction force magnitudes at the spherical joints a_ji and central joints o_j in [N] over time [s].

    Raises:
        HipsimError: if the result has no joint forces (only the Pinocchio model gives them).
    """
    if result.joint_forces is None:
        raise HipsimError(f"the {result.model} model gives no joint reaction forces; run the Pinocchio model")
    Fa, Fo = result.joint_forces
    fig, axes = _figure(2)
    t = result.trajectory.t
    for j, style in ((0, "-"), (1, "--")):
        for i in range(3):
            axes[0].plot(t, Fa[:, j, i], ls=style, color=_MODULE_COLOURS[i], lw=1.2, label=f"a_{j + 1}{i + 1}")
        axes[1].plot(t, Fo[:, j], ls=style, color="black", lw=1.4, label=f"o_{j + 1}")
    axes[0].set_ylabel("spherical joint force |F_a| [N]")
    axes[1].set_ylabel("central joint force |F_o| [N]")
    axes[0].legend(ncol=6, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, 1.3))
    axes[1].legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("time t [s]")
    fig.suptitle(f"Joint reaction forces ({result.model} model): {result.trajectory.name}")
    return fig


def plot_singularity(result: Result):
    """The inverse condition number of J [–] over time [s], its minimum marked."""
    fig, axes = _figure(1, height=3.0)
    ax = axes[0]
    t, c = result.kin.t, result.kin.cond_inv
    ax.plot(t, c, color="tab:blue", lw=1.6, label="inverse condition number of J")
    k = int(np.nanargmin(c))
    ax.plot(t[k], c[k], marker="*", ms=14, color="tab:orange", mec="black", label=f"minimum {c[k]:.4f} at t = {t[k]:.4g} s")
    ax.set_ylim(0.0, max(1e-3, float(np.nanmax(c))) * 1.1)
    ax.set_ylabel("inverse condition number [–]\n(0 singular, 1 isotropic)")
    ax.set_xlabel("time t [s]")
    ax.legend(fontsize=8, loc="lower right")
    fig.suptitle(f"Distance from singularity: {result.trajectory.name}")
    return fig


def plot_tracking(simulations: Mapping[str, Any]):
    """Tracking errors of α, β, γ in [deg] over time [s], one line per controller.

    Args:
        simulations: {controller name: object with ``t`` (N,) in [s] and ``err``
            (N, 3) in [rad], the desired minus the actual angles}.
    """
    fig, axes = _figure(3)
    colours = ("tab:blue", "tab:red", "tab:green", "tab:purple", "tab:brown")
    for n, (name, sim) in enumerate(simulations.items()):
        t, err = _tracking_arrays(name, sim)
        for k, ax in enumerate(axes):
            ax.plot(t, np.degrees(err[:, k]), color=colours[n % len(colours)], lw=1.3, label=name)
    for k, ax in enumerate(axes):
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.set_ylabel(f"{_ANGLE_LABELS[k].split()[0]} error [deg]")
        ax.set_title(_ANGLE_LABELS[k], fontsize=9, loc="left")
    axes[0].legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("time t [s]")
    fig.suptitle("Tracking errors (desired − actual)")
    return fig


def _tracking_arrays(name: str, sim) -> tuple[np.ndarray, np.ndarray]:
    try:
        t = np.asarray(sim.t, dtype=float)
        err = np.asarray(sim.err, dtype=float)
    except AttributeError:
        raise HipsimError(f"simulation '{name}': expected an object with t (N,) in s and err (N, 3) in rad") from None
    if t.ndim != 1 or err.shape != (t.size, 3):
        raise HipsimError(f"simulation '{name}': t has shape {t.shape} and err {err.shape}; expected (N,) and (N, 3)")
    return t, err


# ---------------------------------------------------------------------------
# Sizing


#: Keys of the ``[motor]`` table of a ratings file, with their units and what each is checked against.
RATING_KEYS = {
    "rated_torque_Nmm": ("N·mm", "RMS motor torque"),
    "peak_torque_Nmm": ("N·mm", "peak motor torque"),
    "max_speed_rpm": ("rpm", "peak motor speed"),
    "stroke_mm": ("mm", "carriage stroke"),
    "axial_force_N": ("N", "peak axial screw force"),
}


@dataclass(frozen=True)
class MotorRatings:
    """A motor and linear module to check the demands against; None for a figure not given.

    Attributes:
        rated_torque_Nmm: continuous (rated) motor torque in [N·mm], checked against the RMS torque.
        peak_torque_Nmm: peak motor torque in [N·mm], checked against the peak torque.
        max_speed_rpm: maximum motor speed in [rpm].
        stroke_mm: usable stroke of the linear module in [mm], checked against the carriage stroke.
        axial_force_N: permissible axial load of the screw in [N].
        source: the file they came from.
    """

    rated_torque_Nmm: float | None = None
    peak_torque_Nmm: float | None = None
    max_speed_rpm: float | None = None
    stroke_mm: float | None = None
    axial_force_N: float | None = None
    source: str = "<given>"


def load_ratings(path: str | Path) -> MotorRatings:
    """Read a motor/module rating file: TOML with one ``[motor]`` table (or a parameter file, of which only ``[motor]`` is read).

    Example file::

        [motor]
        rated_torque_Nmm = 640      # continuous torque
        peak_torque_Nmm = 1910
        max_speed_rpm = 3000
        stroke_mm = 200             # linear module stroke
        axial_force_N = 2000        # optional: permissible screw load

    Every key is optional (at least one is needed); each must be a positive number.

    Raises:
        ParameterError: naming the file and key of anything missing, unknown or invalid.
    """
    source = str(path)
    raw = read_toml(path, "rating file")
    for section in raw:
        if section not in SCHEMA:  # the parameter file's other tables are allowed, and ignored here
            raise ParameterError("unknown section (expected one [motor] table)", key=section, source=source)
    table = raw.get("motor")
    if not isinstance(table, dict) or not table:
        raise ParameterError(f"expected a [motor] table with any of {', '.join(RATING_KEYS)}", key="motor", source=source)
    # The same keys, units and checks as the parameter file's optional [motor] table.
    values = {key: check_entry("motor", key, value, source) for key, value in table.items()}
    return MotorRatings(**values, source=source)


@dataclass(frozen=True)
class ModuleSizing:
    """The demands on linear module i (its motor and screw) along the trajectory.

    Attributes:
        module: i (1, 2, 3).
        tau_peak_Nmm: max |τ_i| in [N·mm].
        tau_rms_Nmm: RMS of τ_i in [N·mm].
        speed_peak_rpm: max |θ̇_i| in [rpm].
        power_peak_W: max |τ_i·θ̇_i| in [W].
        axial_force_peak_N: max |F_axial,i| in [N] (see :func:`axial_screw_force`).
        stroke_mm: carriage stroke max L − min L in [mm].
    """

    module: int
    tau_peak_Nmm: float
    tau_rms_Nmm: float
    speed_peak_rpm: float
    power_peak_W: float
    axial_force_peak_N: float
    stroke_mm: float


@dataclass(frozen=True)
class JointSizing:
    """Peak and RMS reaction force magnitude at one joint, in [N]; name ``a_ji`` or ``o_j``."""

    joint: str
    peak_N: float
    rms_N: float


@dataclass(frozen=True)
class RatingCheck:
    """One demand checked against one rating.

    Attributes:
        module: i (1, 2, 3).
        item: the rating key, e.g. ``"peak_torque_Nmm"``.
        demand: what the trajectory needs, in the key's unit.
        rating: what the motor or module offers.
        margin_pct: (rating − demand)/rating in [%]; negative when it fails.
        passed: demand ≤ rating.
    """

    module: int
    item: str
    demand: float
    rating: float
    margin_pct: float
    passed: bool


@dataclass(frozen=True)
class Sizing:
    """The sizing table: per module, per joint (when known), and the rating checks.

    Attributes:
        modules: one :class:`ModuleSizing` per linear module.
        joints: one :class:`JointSizing` per joint, or None when the model gives no joint forces.
        checks: the :class:`RatingCheck` list (empty without ratings).
        ratings: the ratings checked against, if any.
    """

    modules: tuple[ModuleSizing, ...]
    joints: tuple[JointSizing, ...] | None
    checks: tuple[RatingCheck, ...] = ()
    ratings: MotorRatings | None = None

    @property
    def passed(self) -> bool | None:
        """True if every check passed, False if any failed, None without ratings."""
        return None if not self.checks else all(c.passed for c in self.checks)

    def as_dict(self) -> dict[str, Any]:
        """Plain data for JSON."""
        from dataclasses import asdict

        return {
            "modules": [asdict(m) for m in self.modules],
            "joints": None if self.joints is None else [asdict(j) for j in self.joints],
            "checks": [asdict(c) for c in self.checks],
            "ratings": None if self.ratings is None else asdict(self.ratings),
            "passed": self.passed,
        }


def axial_screw_force(result: Result) -> np.ndarray:
    """F_axial = 2π·(τ − τ_L − τ_sf)/p: the force each nut pushes on its carriage, in [N], (N, 3), positive up.

    τ_L is the screw rotor's inertia torque and τ_sf the screw's own friction
    torque (Coulomb with the smooth sign on the motor speed, plus viscous, as
    in :func:`hipsim.dynamics.inverse_dynamics`).
    """
    params, torques = result.params, result.torques
    screw_friction = screw_friction_torque(params, torques.motor_speed)
    return 2.0 * math.pi * (torques.tau - torques.tau_L - screw_friction) / params.lead


def sizing(result: Result, ratings: MotorRatings | None = None) -> Sizing:
    """The sizing table of a run, optionally checked against a motor and module rating.

    Args:
        result: a model run (:func:`hipsim.results.analyse`); joint forces are
            included when it has them (Pinocchio model).
        ratings: a motor and module to check against; None for no check.

    Returns:
        The :class:`Sizing`. Values are over the samples the run kept (flagged
        poses, if any, are left out, as in :meth:`Result.summary`).
    """
    ok = ~result.kin.flagged
    torques = result.torques
    tau = torques.tau[ok] * 1e3
    speed = torques.motor_speed[ok]
    power = torques.tau[ok] * speed
    force = axial_screw_force(result)[ok]
    stroke = np.ptp(result.L[ok, 0], axis=0) * 1e3
    modules = tuple(
        ModuleSizing(
            module=i + 1,
            tau_peak_Nmm=float(np.abs(tau[:, i]).max()),
            tau_rms_Nmm=float(np.sqrt(np.mean(tau[:, i] ** 2))),
            speed_peak_rpm=float(np.abs(speed[:, i]).max() * _RPM),
            power_peak_W=float(np.abs(power[:, i]).max()),
            axial_force_peak_N=float(np.abs(force[:, i]).max()),
            stroke_mm=float(stroke[i]),
        )
        for i in range(3)
    )
    joints = None
    if result.joint_forces is not None:
        Fa, Fo = (np.asarray(x)[ok] for x in result.joint_forces)
        joints = tuple(
            JointSizing(f"a_{j + 1}{i + 1}", float(Fa[:, j, i].max()), float(np.sqrt(np.mean(Fa[:, j, i] ** 2))))
            for j in range(Fa.shape[1]) for i in range(3)
        ) + tuple(
            JointSizing(f"o_{j + 1}", float(Fo[:, j].max()), float(np.sqrt(np.mean(Fo[:, j] ** 2)))) for j in range(Fo.shape[1])
        )
    checks: list[RatingCheck] = []
    if ratings is not None:
        demand_of = {
            "rated_torque_Nmm": "tau_rms_Nmm",
            "peak_torque_Nmm": "tau_peak_Nmm",
            "max_speed_rpm": "speed_peak_rpm",
            "stroke_mm": "stroke_mm",
            "axial_force_N": "axial_force_peak_N",
        }
        for module in modules:
            for key, attribute in demand_of.items():
                rating = getattr(ratings, key)
                if rating is None:
                    continue
                demand = getattr(module, attribute)
                checks.append(RatingCheck(module.module, key, demand, rating, 100.0 * (rating - demand) / rating, bool(demand <= rating)))
    return Sizing(modules, joints, tuple(checks), ratings)


# ---------------------------------------------------------------------------
# The report


@dataclass(frozen=True)
class ReportFiles:
    """What :func:`write_report` wrote.

    Attributes:
        folder: the output folder.
        index: the HTML page.
        figures: figure stem → (PNG path, SVG path).
        data: the other files (report.json, torques.csv).
        notes: the notes shown on the page (model fallbacks, estimates).
        sizing: the sizing table.
    """

    folder: Path
    index: Path
    figures: dict[str, tuple[Path, Path]]
    data: tuple[Path, ...]
    notes: tuple[str, ...] = field(default_factory=tuple)
    sizing: Sizing | None = None


def _joint_force_result(params: Parameters, trajectory: Trajectory, model: str) -> tuple[Result | None, str | None]:
    """The Pinocchio run (for joint forces), or None and the reason it is missing."""
    if model == "analytic":
        return None, "Joint reaction forces were not computed (analytic model only: it has no joint forces)."
    try:
        return analyse(params, trajectory, model="pinocchio"), None
    except (ImportError, AttributeError) as error:
        if model == "pinocchio":
            raise HipsimError(f"the Pinocchio model is not available ({error})") from None
        return None, f"Joint reaction forces are missing: the Pinocchio model is not available ({type(error).__name__}: {error}); torques are from the analytic model."


def _simulations(simulate, params: Parameters, trajectory: Trajectory) -> Mapping[str, Any] | None:
    if simulate is None:
        return None
    sims = simulate(params, trajectory) if callable(simulate) else simulate
    if not isinstance(sims, Mapping) or not sims:
        raise HipsimError("simulate must give a non-empty mapping {controller name: result with t and err}")
    for name, sim in sims.items():
        _tracking_arrays(name, sim)
    return sims


def write_report(
    out_dir: str | Path,
    params: Parameters,
    trajectory: Trajectory,
    simulate: Mapping[str, Any] | Callable[[Parameters, Trajectory], Mapping[str, Any]] | None = None,
    ratings: MotorRatings | str | Path | None = None,
    model: str = "auto",
) -> ReportFiles:
    """Run the models along a trajectory and write the design report folder.

    Writes into ``out_dir`` (created if missing): ``slider_motion``,
    ``motor_torques``, ``load_friction``, ``singularity`` and, when available,
    ``joint_forces`` and ``tracking_errors``, each as ``.png`` and ``.svg``;
    ``index.html`` (self-contained: figures embedded as base64 PNG, with links
    to the SVG files beside it); ``report.json`` (summary and sizing) and
    ``torques.csv`` (spec §7.5 columns). Every file is written atomically.

    Args:
        out_dir: the folder to write.
        params: the machine (SI inside; reported in mm, N·mm, rpm).
        trajectory: the motion (angles in [rad]) and load F_e in [N].
        simulate: tracking simulations to plot: a mapping {controller name:
            object with ``t`` (N,) in [s] and ``err`` (N, 3) in [rad]}, or a callable
            ``(params, trajectory) -> mapping``; None for no tracking section.
        ratings: a motor/module rating (:class:`MotorRatings` or a TOML file for
            :func:`load_ratings`) to check the sizing against; None for no check.
        model: ``"auto"`` (torques from the analytic model, joint forces from
            the Pinocchio model when it is available, a note on the page when it
            is not), ``"analytic"`` (no joint forces) or ``"pinocchio"`` (joint
            forces required: an error if the model is missing).

    Returns:
        The :class:`ReportFiles`.

    Raises:
        PoseError: if the trajectory leaves the workspace or is singular.
        ParameterError: for an invalid rating file.
    """
    if model not in ("auto", "analytic", "pinocchio"):
        raise HipsimError(f"unknown model '{model}' (expected 'auto', 'analytic' or 'pinocchio')")
    if ratings is not None and not isinstance(ratings, MotorRatings):
        ratings = load_ratings(ratings)
    out = Path(out_dir)
    check_folder(out)  # fail now, not after the computing; but make it only when there is something to write

    result = analyse(params, trajectory)
    notes = []
    if params.platform_mass > 0:
        notes.append(f"The platform mass m_m = {params.platform_mass:g} kg is an estimate (not published); it enters only the thrust-bearing friction.")
    joint_result, missing = _joint_force_result(params, trajectory, model)
    if missing:
        notes.append(missing)
    if joint_result is not None:
        difference = np.abs(joint_result.torques.tau - result.torques.tau).max() / np.abs(result.torques.tau).max()
        notes.append(
            f"Torques are from the analytic model; joint forces from the Pinocchio closed-chain model, whose motor "
            f"torques differ from the analytic ones by at most {difference:.2e} of the peak (the analytic lever does not spin, spec §7.4)."
        )
    sims = _simulations(simulate, params, trajectory)

    # The analytic torques with the Pinocchio joint forces: one Result for the sizing and the figures.
    combined = dataclasses.replace(result, joint_forces=None if joint_result is None else joint_result.joint_forces)
    size = sizing(combined, ratings)

    figures: dict[str, tuple[Path, Path]] = {}
    plots = [
        ("slider_motion", lambda: plot_slider_motion(combined)),
        ("motor_torques", lambda: plot_torque_parts(combined)),
        ("load_friction", lambda: plot_load_friction(combined)),
        ("singularity", lambda: plot_singularity(combined)),
    ]
    if combined.joint_forces is not None:
        plots.append(("joint_forces", lambda: plot_joint_forces(combined)))
    if sims is not None:
        plots.append(("tracking_errors", lambda: plot_tracking(sims)))
    with output_folder(out):  # a failure from here on takes back the folder if this run made it and it is empty
        for stem, make in plots:
            figures[stem] = save_figure(make(), out, stem)

        summary = combined.summary()
        tracking = _tracking_table(sims) if sims is not None else None
        document = {"summary": summary, "sizing": size.as_dict(), "tracking": tracking, "notes": notes,
                    "figures": {stem: [p.name for p in paths] for stem, paths in figures.items()}}
        data = (
            write_atomic(out / "report.json", json.dumps(_finite(document), indent=2) + "\n"),
            combined.write_csv(out / "torques.csv"),
        )
        page = _html(combined, summary, size, tracking, figures, notes)
        index = write_atomic(out / "index.html", page)
    return ReportFiles(out, index, figures, data, tuple(notes), size)


def _tracking_table(sims: Mapping[str, Any]) -> dict[str, dict[str, float]]:
    """Per controller: peak and RMS error of each angle in [deg] (and torque when the result has ``tau``)."""
    table = {}
    for name, sim in sims.items():
        _, err = _tracking_arrays(name, sim)
        deg = np.degrees(err)
        row = {}
        for k, angle in enumerate(("alpha", "beta", "gamma")):
            row[f"{angle}_err_peak_deg"] = float(np.abs(deg[:, k]).max())
            row[f"{angle}_err_rms_deg"] = float(np.sqrt(np.mean(deg[:, k] ** 2)))
        tau = getattr(sim, "tau", None)
        if tau is not None and np.shape(tau) == (err.shape[0], 3):
            tau = np.asarray(tau, dtype=float) * 1e3
            row |= {f"tau_peak_{i + 1}_Nmm": float(np.abs(tau[:, i]).max()) for i in range(3)}
            row |= {f"tau_rms_{i + 1}_Nmm": float(np.sqrt(np.mean(tau[:, i] ** 2))) for i in range(3)}
        table[name] = row
    return table


def _finite(value):
    """NaN and infinity become None: JSON has neither."""
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


# ---------------------------------------------------------------------------
# HTML

_CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 2em auto; max-width: 1100px; color: #222; padding: 0 1em; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { font-size: 1.25em; border-bottom: 1px solid #ccc; padding-bottom: 0.2em; margin-top: 1.8em; }
table { border-collapse: collapse; margin: 0.6em 0 1em; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
th { background: #f0f0f0; }
th.l, td.l { text-align: left; }
.meta { color: #555; font-size: 0.9em; }
.note { background: #fff8e0; border-left: 4px solid #e0b000; padding: 0.4em 0.8em; margin: 0.4em 0; }
.pass { color: #0a7a0a; font-weight: bold; }
.fail { color: #c00000; font-weight: bold; }
figure { margin: 1em 0 2em; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.9em; color: #444; }
"""


def _esc(value) -> str:
    return html.escape(str(value))


def _table(header: list[str], rows: list[list], digits: int = 1, left: int = 1) -> str:
    """An HTML table; numbers right-aligned with ``digits`` decimals, the first ``left`` columns left-aligned."""

    def cell(value):
        if isinstance(value, str):
            return value  # already HTML (escaped by the caller)
        if value is None or (isinstance(value, float) and not math.isfinite(value)):
            return "—"
        return f"{value:,.{digits}f}" if isinstance(value, float) else _esc(value)

    def align(k):
        return " class='l'" if k < left else ""

    head = "".join(f"<th{align(k)}>{_esc(h)}</th>" for k, h in enumerate(header))
    body = "".join("<tr>" + "".join(f"<td{align(k)}>{cell(v)}</td>" for k, v in enumerate(row)) + "</tr>" for row in rows)
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def _html(result: Result, summary: dict, size: Sizing, tracking, figures, notes) -> str:
    from .. import __version__

    traj = result.trajectory
    parts = []
    parts.append("<h1>hipsim design report</h1>")
    parts.append(
        f"<p class='meta'>Trajectory: <b>{_esc(traj.name)}</b> ({len(traj)} samples, {traj.t[-1] - traj.t[0] + (traj.t[1] - traj.t[0] if len(traj) > 1 else 0):.4g} s)"
        f" &middot; parameters: {_esc(result.params.source)} &middot; platform offset δ = {math.degrees(result.params.home_offset):g}°"
        f" &middot; hipsim {_esc(__version__)}</p>"
    )
    for note in notes:
        parts.append(f"<p class='note'>{_esc(note)}</p>")

    # Summary
    parts.append("<h2>Summary</h2>")
    rows = [[f"S{name}", s["L_max_mm"], s["L_min_mm"], s["stroke_mm"], s["Ld_max_mm_s"], s["Ldd_max_mm_s2"]] for name, s in summary["sliders"].items()]
    parts.append("<h3>Sliders (S<sub>ji</sub>: platform j, module i)</h3>")
    parts.append(_table(["slider", "L max [mm]", "L min [mm]", "stroke [mm]", "|L̇| max [mm/s]", "|L̈| max [mm/s²]"], rows))
    parts.append("<h3>Motor torques [N·mm] (largest |part|; peak and RMS of the total)</h3>")
    rows = [
        [f"M{i}", *(m[f"{p}_max_Nmm"] for p in Torques.PARTS), m["tau_peak_Nmm"], m["tau_rms_Nmm"], m["speed_peak_rpm"]]
        for i, m in summary["motors"].items()
    ]
    parts.append(_table(["motor", "platforms", "levers", "sliders", "screws", "friction", "peak", "RMS", "peak speed [rpm]"], rows))
    parts.append(
        f"<p>Smallest singularity measure (inverse condition number of J): <b>{summary['cond_inv_min']:.4f}</b>"
        f" at t = {summary['cond_inv_min_t_s']:.4g} s (0 singular, 1 isotropic).</p>"
    )

    # Sizing
    parts.append("<h2>Sizing</h2>")
    rows = [[f"LN{m.module}", m.tau_peak_Nmm, m.tau_rms_Nmm, m.speed_peak_rpm, m.power_peak_W, m.axial_force_peak_N, m.stroke_mm] for m in size.modules]
    parts.append(_table(["linear module", "peak torque [N·mm]", "RMS torque [N·mm]", "peak speed [rpm]", "peak power [W]", "peak axial screw force [N]", "stroke [mm]"], rows))
    parts.append(
        "<p class='meta'>Peak power is max |τ·θ̇| of the motor. The axial screw force is the force the nut pushes on the "
        "carriage (both sliders of the module), F = 2π(τ − τ<sub>L</sub> − τ<sub>screw friction</sub>)/p: the motor torque "
        "less the screw rotor's inertia and the screw's own friction, turned into thrust by an ideal screw of lead p.</p>"
    )
    if size.joints is not None:
        parts.append("<h3>Joint reaction forces</h3>")
        parts.append(_table(["joint", "peak [N]", "RMS [N]"], [[j.joint, j.peak_N, j.rms_N] for j in size.joints]))
    else:
        parts.append("<p class='meta'>Joint reaction forces: not available in this report (see the note above).</p>")
    if size.ratings is not None:
        verdict = "<span class='pass'>PASS</span>" if size.passed else "<span class='fail'>FAIL</span>"
        parts.append(f"<h3>Rating check ({_esc(size.ratings.source)}): {verdict}</h3>")
        rows = []
        for c in size.checks:
            unit, meaning = RATING_KEYS[c.item]
            mark = "<span class='pass'>pass</span>" if c.passed else "<span class='fail'>FAIL</span>"
            rows.append([f"LN{c.module}", _esc(f"{meaning} vs {c.item}"), f"{c.demand:,.1f} {_esc(unit)}", f"{c.rating:,.1f} {_esc(unit)}", f"{c.margin_pct:+.1f} %", mark])
        parts.append(_table(["module", "check", "demand", "rating", "margin", "result"], rows, left=2))

    # Tracking
    if tracking is not None:
        parts.append("<h2>Tracking</h2>")
        rows = []
        for name, row in tracking.items():
            rows.append([_esc(name), *(row[f"{a}_err_{s}_deg"] for a in ("alpha", "beta", "gamma") for s in ("peak", "rms"))])
        parts.append(_table(["controller", "α peak [deg]", "α RMS [deg]", "β peak [deg]", "β RMS [deg]", "γ peak [deg]", "γ RMS [deg]"], rows, digits=4))
        with_torque = [(name, row) for name, row in tracking.items() if "tau_peak_1_Nmm" in row]
        if with_torque:
            rows = [[_esc(name), *(row[f"tau_{s}_{i}_Nmm"] for i in (1, 2, 3) for s in ("peak", "rms"))] for name, row in with_torque]
            header = ["controller"] + [f"M{i} {s} [N·mm]" for i in (1, 2, 3) for s in ("peak", "RMS")]
            parts.append(_table(header, rows))

    # Figures
    parts.append("<h2>Figures</h2>")
    for stem, (png, svg) in figures.items():
        data = base64.b64encode(png.read_bytes()).decode("ascii")
        caption = FIGURE_CAPTIONS.get(stem, stem)
        parts.append(
            f"<figure id='{stem}'><img src='data:image/png;base64,{data}' alt='{_esc(stem)}: {_esc(caption)}'>"
            f"<figcaption>{_esc(caption)} Files: <a href='{_esc(svg.name)}'>{_esc(svg.name)}</a>, "
            f"<a href='{_esc(png.name)}'>{_esc(png.name)}</a>.</figcaption></figure>"
        )
    body = "\n".join(parts)
    return (
        "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
        f"<meta name='viewport' content='width=device-width, initial-scale=1'><title>hipsim report: {_esc(traj.name)}</title>"
        f"<style>{_CSS}</style></head><body>\n{body}\n</body></html>\n"
    )
