"""Figures of a run (matplotlib, no pyplot state): input motion, slider motion, torque parts, load and friction,
joint forces, singularity, tracking, and the sizing figures (torque–speed cloud, axial-load histogram)."""

from __future__ import annotations

import io
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..design.sizing import Sizing
from ..exceptions import HipsimError
from ..files import write_atomic
from ..physics.units import RPM_PER_RAD_S as _RPM_PER_RAD_S
from ..results import Run

__all__ = [
    "FIGURE_CAPTIONS",
    "plot_axial_load_histogram",
    "plot_input_motion",
    "plot_joint_forces",
    "plot_load_friction",
    "plot_singularity",
    "plot_slider_motion",
    "plot_torque_parts",
    "plot_torque_speed",
    "plot_tracking",
    "save_figure",
    "tracking_arrays",
]


_MODULE_COLOURS = ("tab:blue", "tab:orange", "tab:green")


_PART_COLOURS = {
    "platforms": "tab:blue",
    "levers": "tab:orange",
    "sliders": "tab:green",
    "screws": "tab:purple",
    "friction": "tab:red",
}


_ANGLE_LABELS = ("α flexion/extension", "β abduction/adduction", "γ internal/external rotation")


#: Each figure the report can hold, by file stem, with its caption.
FIGURE_CAPTIONS = {
    "input_motion": "The input: the platform angles α (flexion/extension), β (abduction/adduction), γ (internal/external "
    "rotation) and the hydraulic load F_e over the cycle.",
    "slider_motion": "Slider displacement, velocity and acceleration over the cycle, per linear module, both platforms "
    "(the two sliders of a module share one carriage: equal velocity and acceleration, heights h₁ − h₂ apart).",
    "motor_torques": "Each motor's torque split into its five parts (platforms, levers, sliders, screws, friction) and the total.",
    "load_friction": "The applied hydraulic load and the friction moment of each platform's central chain (hip joint + thrust bearing).",
    "joint_forces": "Reaction forces at the spherical joints a_ji and the central joints o_j (from the Pinocchio closed-chain model: "
    "the analytic model has none). Platform 2 is drawn dashed over platform 1; where its curve lies on platform 1's, "
    "the legend says so (a_2i = a_1i).",
    "torque_speed": "Each motor's operating points (|speed|, |torque|) over the cycle, with the S1 (continuous) and peak "
    "torque–speed curves of the drive checked and the RMS torque at the mean speed (★).",
    "axial_load": "Share of each screw's revolutions at each axial screw load 2π(τ − τ_L − τ_screw friction)/p: the "
    "load spectrum that sets the lead screw's L10 life (ISO 3408-5), its cubic mean marked.",
    "singularity": "The singularity measure (inverse condition number of J) along the trajectory.",
    "tracking_errors": "Tracking errors of the platform angles under each controller (closed-loop simulation), one column "
    "per controller, each on its own scale.",
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
                ax.plot(
                    t,
                    values[:, j, i],
                    ls=style,
                    color=_MODULE_COLOURS[i],
                    lw=1.4 if j == 0 else 1.1,
                    label=f"S{j + 1}{i + 1}",
                )
        name = {"L": "height L_ji", "Ld": "velocity L̇_ji", "Ldd": "acceleration L̈_ji"}[quantity]
        ax.set_ylabel(f"slider {name} [{unit}]")
    axes[0].legend(
        ncol=6,
        fontsize=8,
        loc="upper center",
        bbox_to_anchor=(0.5, 1.32),
        title="slider S_ji (platform j, module i)",
        title_fontsize=8,
    )
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
    axes[1].plot(
        t,
        run.torques.friction_moment * 1e3,
        color="tab:red",
        lw=1.6,
        label="|τ_mf|, each platform (hip joint + thrust bearing)",
    )
    axes[1].set_ylabel("friction moment [N·mm]")
    axes[1].set_ylim(bottom=0.0)
    axes[1].legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("time t [s]")
    fig.suptitle(f"Applied load and central-chain friction: {run.trajectory.name}")
    return fig


def plot_joint_forces(run: Run, model: str | None = None):
    """Reaction force magnitudes at the spherical joints a_ji and central joints o_j in [N] over time [s].

    Args:
        run: a run with joint forces.
        model: the model the joint forces came from, for the title (default: the run's model).

    Raises:
        HipsimError: if the run has no joint forces (only the Pinocchio model gives them).
    """
    if run.joint_forces is None:
        raise HipsimError(f"the {run.model} model gives no joint reaction forces; run the Pinocchio model")
    Fa, Fo = run.joint_forces.Fa, run.joint_forces.Fo
    fig, axes = _figure(2)
    t = run.trajectory.t
    # Platform 2's curves often lie exactly on platform 1's (the two platforms move alike): they are drawn
    # dashed and wider over the solid ones, and their legend entry says they coincide, so no entry hides.
    for j, style in ((0, "-"), (1, (0, (4, 3)))):
        for i in range(3):
            same = j == 1 and _coincide(Fa[:, 1, i], Fa[:, 0, i])
            label = f"a_2{i + 1} = a_1{i + 1}" if same else f"a_{j + 1}{i + 1}"
            axes[0].plot(
                t, Fa[:, j, i], ls=style, color=_MODULE_COLOURS[i], lw=1.2 if j == 0 else 2.0, label=label, zorder=2 + j
            )
        label = "o_2 = o_1" if j == 1 and _coincide(Fo[:, 1], Fo[:, 0]) else f"o_{j + 1}"
        axes[1].plot(
            t,
            Fo[:, j],
            ls=style,
            color="black" if j == 0 else "tab:grey",
            lw=1.4 if j == 0 else 2.0,
            label=label,
            zorder=2 + j,
        )
    axes[0].set_ylabel("spherical joint force |F_a| [N]")
    axes[1].set_ylabel("central joint force |F_o| [N]")
    axes[0].legend(ncol=6, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, 1.3), handlelength=3.0)
    axes[1].legend(fontsize=8, loc="upper right", handlelength=3.0)
    axes[-1].set_xlabel("time t [s]")
    source = model or run.model
    fig.suptitle(
        f"Joint reaction forces ({'Pinocchio closed-chain' if source == 'pinocchio' else source} model): {run.trajectory.name}"
    )
    return fig


def _coincide(a: np.ndarray, b: np.ndarray) -> bool:
    """True when two curves lie within a line's width of each other (0.2 % of their range) everywhere."""
    scale = max(float(np.nanmax(np.abs(a))), float(np.nanmax(np.abs(b))), 1e-12)
    return bool(np.nanmax(np.abs(a - b)) <= 2e-3 * scale)


def plot_singularity(run: Run):
    """The inverse condition number of J [–] over time [s], its minimum marked."""
    fig, axes = _figure(1, height=3.0)
    ax = axes[0]
    t, c = run.trajectory.t, run.cond_inv
    ax.plot(t, c, color="tab:blue", lw=1.6, label="inverse condition number of J")
    k = int(np.nanargmin(c))
    ax.plot(
        t[k], c[k], marker="*", ms=14, color="tab:orange", mec="black", label=f"minimum {c[k]:.4f} at t = {t[k]:.4g} s"
    )
    ax.set_ylim(0.0, max(1e-3, float(np.nanmax(c))) * 1.1)
    ax.set_ylabel("inverse condition number [–]\n(0 singular, 1 isotropic)")
    ax.set_xlabel("time t [s]")
    ax.legend(fontsize=8, loc="lower right")
    fig.suptitle(f"Distance from singularity: {run.trajectory.name}")
    return fig


def plot_tracking(simulations: Mapping[str, Any]):
    """Tracking errors of α, β, γ in [deg] over time [s]: one row per angle, one column per controller.

    Each panel has its own scale, so a controller whose errors are a hundred
    times smaller than another's still shows its curves.

    Args:
        simulations: {controller name: object with ``t`` (N,) in [s] and ``err``
            (N, 3) in [rad], the desired minus the actual angles}.
    """
    from matplotlib.figure import Figure

    names = list(simulations)
    fig = Figure(figsize=(5.0 * len(names) + 1.0, 7.6), layout="constrained")
    axes = fig.subplots(3, len(names), sharex=True, squeeze=False)
    colours = ("tab:blue", "tab:red", "tab:green", "tab:purple", "tab:brown")
    for n, name in enumerate(names):
        t, err = tracking_arrays(name, simulations[name])
        for k in range(3):
            ax = axes[k, n]
            ax.grid(alpha=0.3)
            peak = float(np.abs(np.degrees(err[:, k])).max())
            ax.plot(
                t, np.degrees(err[:, k]), color=colours[n % len(colours)], lw=1.3, label=f"{name} (peak {peak:.3g}°)"
            )
            ax.axhline(0.0, color="0.5", lw=0.6)
            ax.set_ylabel(f"{_ANGLE_LABELS[k].split()[0]} error [deg]")
            ax.legend(fontsize=8, loc="upper right")
            if k == 0:
                ax.set_title(name, fontsize=10)
        axes[-1, n].set_xlabel("time t [s]")
    for k in range(3):
        axes[k, 0].annotate(_ANGLE_LABELS[k], (0.01, 0.97), xycoords="axes fraction", fontsize=8, va="top")
    fig.suptitle("Tracking errors (desired − actual), each panel on its own scale")
    return fig


def tracking_arrays(name: str, sim) -> tuple[np.ndarray, np.ndarray]:
    """A simulation's times (N,) in [s] and angle errors (N, 3) in [rad], checked.

    Args:
        name: the simulation's name, for the message.
        sim: an object with ``t`` and ``err`` (a :class:`hipsim.control.Simulation`).

    Raises:
        HipsimError: ``sim`` has no ``t`` or ``err``, or they have other shapes.
    """
    try:
        t = np.asarray(sim.t, dtype=float)
        err = np.asarray(sim.err, dtype=float)
    except AttributeError:
        raise HipsimError(f"simulation '{name}': expected an object with t (N,) in s and err (N, 3) in rad") from None
    if t.ndim != 1 or err.shape != (t.size, 3):
        raise HipsimError(f"simulation '{name}': t has shape {t.shape} and err {err.shape}; expected (N,) and (N, 3)")
    return t, err


def plot_input_motion(run: Run):
    """The platform angles α, β, γ [deg] and the hydraulic load F_e [N] over time [s]: the input of every other figure."""
    fig, axes = _figure(2)
    t = run.trajectory.t
    for k, colour in enumerate(("tab:blue", "tab:orange", "tab:green")):
        axes[0].plot(t, np.degrees(run.trajectory.q[:, k]), color=colour, lw=1.5, label=_ANGLE_LABELS[k])
    axes[0].axhline(0.0, color="0.5", lw=0.6)
    axes[0].set_ylabel("platform angle [deg]")
    axes[0].legend(fontsize=8, loc="upper right")
    axes[1].plot(t, run.trajectory.Fe, color="tab:brown", lw=1.6, label="hydraulic load F_e")
    axes[1].set_ylim(bottom=0.0)
    axes[1].set_ylabel("load F_e [N]")
    axes[1].legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("time t [s]")
    fig.suptitle(f"Input motion and load: {run.trajectory.name}")
    return fig


def plot_torque_speed(size: Sizing):
    """Per module, the motor's (|speed| [rpm], |torque| [N·mm]) points over the cycle on the drive's S1 and peak curves.

    Without a drive the points are the screw shaft's (a direct drive, rotor not counted) and no curve is drawn.
    """
    from matplotlib.figure import Figure

    duty = size.duty
    ok = duty.side.weights > 0
    fig = Figure(figsize=(14.0, 4.6), layout="constrained")
    axes = fig.subplots(1, 3, sharey=True)
    motor = size.drive.motor if size.drive is not None else None
    top_speed = max(float(np.abs(duty.speed[ok]).max()) * _RPM_PER_RAD_S * 1.15, 1.0)
    for curve in () if motor is None else (motor.continuous, motor.peak):
        if curve is not None and not curve.flat:
            top_speed = max(top_speed, curve.end_speed * _RPM_PER_RAD_S * 1.05)
    speeds = np.linspace(0.0, top_speed / _RPM_PER_RAD_S, 400)
    weights = duty.side.weights
    for i, ax in enumerate(axes):
        ax.grid(alpha=0.3)
        speed = np.abs(duty.speed[ok, i]) * _RPM_PER_RAD_S
        torque = np.abs(duty.torque[ok, i]) * 1e3
        ax.plot(speed, torque, ".", ms=2.5, color=_MODULE_COLOURS[i], alpha=0.6, label="cycle samples")
        rms = np.sqrt(np.sum(duty.torque[:, i] ** 2 * weights) / weights.sum()) * 1e3
        mean_speed = np.sum(np.abs(duty.speed[:, i]) * weights) / weights.sum() * _RPM_PER_RAD_S
        ax.plot(
            mean_speed,
            rms,
            marker="*",
            ms=14,
            color="gold",
            mec="black",
            ls="none",
            label=f"RMS {rms:.0f} N·mm at mean {mean_speed:.0f} rpm",
        )
        if motor is not None:
            for curve, style, label in ((motor.continuous, "-", "S1 (continuous)"), (motor.peak, "--", "peak")):
                if curve is not None:
                    ax.plot(speeds * _RPM_PER_RAD_S, curve.at(speeds) * 1e3, style, color="black", lw=1.6, label=label)
        ax.set_xlim(0.0, top_speed)
        ax.set_ylim(bottom=0.0)
        ax.set_xlabel("motor speed |n| [rpm]")
        ax.set_title(f"motor {i + 1}", fontsize=10)
        ax.legend(fontsize=7, loc="upper right")
    axes[0].set_ylabel("motor torque |τ_m| [N·mm]")
    which = size.drive.name if size.drive is not None else "screw shaft, no drive given"
    fig.suptitle(f"Torque–speed demand of the cycle: {duty.side.run.trajectory.name} ({which})")
    return fig


def plot_axial_load_histogram(size: Sizing, bins: int = 40):
    """Per module, the share of screw revolutions [%] at each axial screw load |F| [N], its cubic mean marked."""
    fig, axes = _figure(3, height=2.2)
    side = size.duty.side
    revolutions = np.abs(side.speed) * side.weights[:, None]
    load = np.abs(side.axial_load)
    edges = np.linspace(0.0, max(float(load.max()), 1.0) * 1.02, bins + 1)
    for i, ax in enumerate(axes):
        total = revolutions[:, i].sum()
        share = np.histogram(load[:, i], edges, weights=revolutions[:, i])[0] / (total if total > 0 else 1.0) * 100.0
        ax.stairs(share, edges, fill=True, color=_MODULE_COLOURS[i], alpha=0.7, label=f"screw {i + 1}")
        cubic = size.modules[i].axial_force_cubic_mean_N
        ax.axvline(cubic, color="black", ls="--", lw=1.2, label=f"cubic mean {cubic:.0f} N")
        ax.set_ylabel("revolutions [%]")
        ax.legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("axial screw load |F| = |2π(τ − τ_L − τ_screw friction)/p| [N]")
    fig.suptitle(f"Axial load spectrum of the lead screws: {side.run.trajectory.name}")
    return fig
