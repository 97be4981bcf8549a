"""Figures of a run (matplotlib, no pyplot state): slider motion, torque parts, load and friction, joint forces, singularity, tracking."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ..exceptions import HipsimError
from ..files import write_atomic
from ..results import Run

__all__ = [
    "FIGURE_CAPTIONS",
    "plot_joint_forces",
    "plot_load_friction",
    "plot_singularity",
    "plot_slider_motion",
    "plot_torque_parts",
    "plot_tracking",
    "save_figure",
    "tracking_arrays",
]


_MODULE_COLOURS = ("tab:blue", "tab:orange", "tab:green")


_PART_COLOURS = {"platforms": "tab:blue", "levers": "tab:orange", "sliders": "tab:green", "screws": "tab:purple", "friction": "tab:red"}


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


def plot_slider_motion(run: Run):
    """Slider heights L_ji [mm], velocities [mm/s] and accelerations [mm/s²] over time [s].

    One colour per linear module i; solid platform 1 (upper), dashed platform 2 (lower).
    """
    fig, axes = _figure(3)
    t = run.trajectory.t
    for quantity, unit, ax in (("L", "mm", axes[0]), ("Ld", "mm/s", axes[1]), ("Ldd", "mm/s²", axes[2])):
        values = getattr(run, quantity) * 1e3
        for j, style in ((0, "-"), (1, "--")):
            for i in range(3):
                ax.plot(t, values[:, j, i], ls=style, color=_MODULE_COLOURS[i], lw=1.4 if j == 0 else 1.1, label=f"S{j + 1}{i + 1}")
        name = {"L": "height L_ji", "Ld": "velocity L̇_ji", "Ldd": "acceleration L̈_ji"}[quantity]
        ax.set_ylabel(f"slider {name} [{unit}]")
    axes[0].legend(ncol=6, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, 1.32), title="slider S_ji (platform j, module i)", title_fontsize=8)
    axes[-1].set_xlabel("time t [s]")
    fig.suptitle(f"Slider motion: {run.trajectory.name}")
    return fig


def plot_torque_parts(run: Run):
    """Per motor: the five torque parts and the total in [N·mm] over time [s]."""
    fig, axes = _figure(3, height=2.8)
    t = run.trajectory.t
    torques = run.torques
    for i, ax in enumerate(axes):
        for part, colour in _PART_COLOURS.items():
            ax.plot(t, getattr(torques, part)[:, i] * 1e3, color=colour, lw=1.1, label=part)
        ax.plot(t, torques.total[:, i] * 1e3, color="black", lw=2.0, label="total")
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.set_ylabel(f"motor {i + 1} torque [N·mm]")
    axes[0].legend(ncol=6, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, 1.25))
    axes[-1].set_xlabel("time t [s]")
    fig.suptitle(f"Motor torques and their parts ({run.model} model): {run.trajectory.name}")
    return fig


def plot_load_friction(run: Run):
    """The applied load F_e [N] and each platform's central-chain friction moment [N·mm] over time [s]."""
    fig, axes = _figure(2)
    t = run.trajectory.t
    axes[0].plot(t, run.trajectory.Fe, color="tab:brown", lw=1.6, label="hydraulic load F_e")
    axes[0].set_ylabel("load F_e [N]")
    axes[0].set_ylim(bottom=0.0)
    axes[0].legend(fontsize=8, loc="upper right")
    axes[1].plot(t, run.torques.friction_moment * 1e3, color="tab:red", lw=1.6, label="|τ_mf|, each platform (hip joint + thrust bearing)")
    axes[1].set_ylabel("friction moment [N·mm]")
    axes[1].set_ylim(bottom=0.0)
    axes[1].legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("time t [s]")
    fig.suptitle(f"Applied load and central-chain friction: {run.trajectory.name}")
    return fig


def plot_joint_forces(run: Run):
    """Reaction force magnitudes at the spherical joints a_ji and central joints o_j in [N] over time [s].

    Raises:
        HipsimError: if the run has no joint forces (only the Pinocchio model gives them).
    """
    if run.joint_forces is None:
        raise HipsimError(f"the {run.model} model gives no joint reaction forces; run the Pinocchio model")
    Fa, Fo = run.joint_forces.Fa, run.joint_forces.Fo
    fig, axes = _figure(2)
    t = run.trajectory.t
    for j, style in ((0, "-"), (1, "--")):
        for i in range(3):
            axes[0].plot(t, Fa[:, j, i], ls=style, color=_MODULE_COLOURS[i], lw=1.2, label=f"a_{j + 1}{i + 1}")
        axes[1].plot(t, Fo[:, j], ls=style, color="black", lw=1.4, label=f"o_{j + 1}")
    axes[0].set_ylabel("spherical joint force |F_a| [N]")
    axes[1].set_ylabel("central joint force |F_o| [N]")
    axes[0].legend(ncol=6, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, 1.3))
    axes[1].legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("time t [s]")
    fig.suptitle(f"Joint reaction forces ({run.model} model): {run.trajectory.name}")
    return fig


def plot_singularity(run: Run):
    """The inverse condition number of J [–] over time [s], its minimum marked."""
    fig, axes = _figure(1, height=3.0)
    ax = axes[0]
    t, c = run.trajectory.t, run.cond_inv
    ax.plot(t, c, color="tab:blue", lw=1.6, label="inverse condition number of J")
    k = int(np.nanargmin(c))
    ax.plot(t[k], c[k], marker="*", ms=14, color="tab:orange", mec="black", label=f"minimum {c[k]:.4f} at t = {t[k]:.4g} s")
    ax.set_ylim(0.0, max(1e-3, float(np.nanmax(c))) * 1.1)
    ax.set_ylabel("inverse condition number [–]\n(0 singular, 1 isotropic)")
    ax.set_xlabel("time t [s]")
    ax.legend(fontsize=8, loc="lower right")
    fig.suptitle(f"Distance from singularity: {run.trajectory.name}")
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
        t, err = tracking_arrays(name, sim)
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


def tracking_arrays(name: str, sim) -> tuple[np.ndarray, np.ndarray]:
    try:
        t = np.asarray(sim.t, dtype=float)
        err = np.asarray(sim.err, dtype=float)
    except AttributeError:
        raise HipsimError(f"simulation '{name}': expected an object with t (N,) in s and err (N, 3) in rad") from None
    if t.ndim != 1 or err.shape != (t.size, 3):
        raise HipsimError(f"simulation '{name}': t has shape {t.shape} and err {err.shape}; expected (N,) and (N, 3)")
    return t, err
