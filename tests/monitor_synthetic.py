"""Synthetic snapshots of a wear test, made by the analytic model (hipsim.analysis.analyse), not by the monitor's regressor.

The hip friction coefficient follows a known curve over the test's cycles
(running-in decay, a slow rise, and optionally a step); each snapshot is a few
ISO 14242-1 cycles of that machine's motor torques, with noise as on a rig
(3 N·mm on the torques, 0.003° on the angles) and the cycle counter.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

import hipsim
from hipsim.motion.trajectories import Trajectory

__all__ = ["EXACT_MACHINE", "MU0", "hip_mu", "write_exact", "write_identified", "write_snapshot", "write_test"]

#: The published machine's hip friction coefficient, the curve's level after running-in.
MU0 = 0.095


def hip_mu(cycle: float, step_at: float | None = None, step: float = 0.0) -> float:
    """μ_h at a cycle: running-in (+0.02 decaying over 150,000 cycles), a slow rise (+0.002 per million), a step."""
    value = MU0 + 0.02 * np.exp(-cycle / 150_000.0) + 0.002 * cycle / 1e6
    if step_at is not None and cycle >= step_at:
        value += step
    return float(value)


def write_snapshot(
    path: Path,
    params,
    mu: float,
    first_cycle: int,
    rng,
    cycles: int = 3,
    rate: float = 250.0,
    torque_noise_Nmm: float = 3.0,
    angle_noise_deg: float = 0.003,
    station_loads: tuple[float, float] | None = None,
    station_mu: tuple[float, float] | None = None,
    cycle_column: bool = True,
    load_gain: float = 1.0,
    commanded: bool = False,
    wobble: tuple[float, float] = (0.3, 1.0),
) -> Path:
    """One snapshot: ``cycles`` ISO cycles of the machine with μ_h = ``mu``, torques and angles noisy, the counter from ``first_cycle``.

    With ``station_loads`` = (s1, s2) the stations carry Fe·s1 and Fe·(s2 + A·sin(2π·f·t)) (their loads differ in
    shape; ``wobble`` = (A, f in [Hz])),
    logged as Fe_1_N and Fe_2_N, each station with its own μ_h (``station_mu``, default ``mu`` for both); the
    machine's torque is then the sum of each station's half (the model counts both platforms alike). With
    ``station_mu`` alone the two stations share the one load (nothing tells them apart), each with its own μ_h.
    ``load_gain``: the load cell reads this times the true load (the torques are the true load's); ``commanded``:
    log the true load as the commanded one, ``Fe_cmd_N``.
    """
    trajectory = hipsim.iso14242(rate=rate, cycles=cycles)
    machine = params.replace(hip_mu=mu)
    true_load = trajectory.Fe
    if station_loads is None and station_mu is not None:
        tau = sum(
            0.5 * hipsim.analyse(params.replace(hip_mu=each), trajectory, lever_spin=True).torques.total
            for each in station_mu
        )
        extra: dict[str, np.ndarray] = {}
    elif station_loads is None:
        tau = hipsim.analyse(machine, trajectory, lever_spin=True).torques.total
        extra = {}
    else:
        phase = 2 * np.pi * wobble[1] * trajectory.t
        loads = (trajectory.Fe * station_loads[0], trajectory.Fe * (station_loads[1] + wobble[0] * np.sin(phase)))
        tau = np.zeros((len(trajectory), 3))
        for load, each_mu in zip(loads, station_mu or (mu, mu)):
            each = Trajectory(trajectory.t, trajectory.q, trajectory.qd, trajectory.qdd, load, name="station")
            tau += 0.5 * hipsim.analyse(params.replace(hip_mu=each_mu), each, lever_spin=True).torques.total
        extra = {"Fe_1_N": loads[0], "Fe_2_N": loads[1]}
        trajectory = Trajectory(
            trajectory.t, trajectory.q, trajectory.qd, trajectory.qdd, 0.5 * (loads[0] + loads[1])
        )  # Fe_N: the mean
    columns = {"t_s": trajectory.t}
    if cycle_column:
        columns["cycle"] = first_cycle + np.floor(trajectory.t * 1.0).astype(int)
    columns["Fe_N"] = trajectory.Fe * load_gain
    if commanded:
        columns["Fe_cmd_N"] = true_load
    noisy = tau * 1e3 + rng.normal(0.0, torque_noise_Nmm, tau.shape)
    for i in range(3):
        columns[f"tau_{i + 1}_Nmm"] = noisy[:, i]
    angles = np.degrees(trajectory.q) + rng.normal(0.0, angle_noise_deg, trajectory.q.shape)
    for k, name in enumerate(("alpha", "beta", "gamma")):
        columns[f"{name}_deg"] = angles[:, k]
    columns |= extra
    names = list(columns)
    data = np.column_stack([columns[name] for name in names])
    with open(path, "w", encoding="utf-8") as stream:
        stream.write(",".join(names) + "\n")
        for row in data:
            stream.write(",".join(f"{v:.0f}" if name == "cycle" else f"{v:.10g}" for name, v in zip(names, row)) + "\n")
    return path


def write_test(
    folder: Path,
    params,
    every: int = 250_000,
    last: int = 3_000_000,
    step_at: float | None = None,
    step: float = 0.0,
    seed: int = 7,
    vary=None,
    **options,
) -> dict[int, float]:
    """A test's snapshots every ``every`` cycles up to ``last``: {first cycle: true μ_h}.

    ``vary(cycle, mu)``: more options of :func:`write_snapshot` for the snapshot at that cycle (a station's own μ_h,
    a load-cell drift), or None.
    """
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    truth = {}
    for cycle in range(0, last + 1, every):
        mu = hip_mu(cycle, step_at, step)
        more = vary(cycle, mu) if vary is not None else {}
        write_snapshot(folder / f"snap_{cycle:08d}.csv", params, mu, cycle, rng, **(options | more))
        truth[cycle] = mu
    return truth


def write_identified(path: Path) -> Path:
    """An identified parameter file: the published machine with the header hipsim identify writes."""
    published = Path(hipsim.load_parameters().source).read_text(encoding="utf-8")
    path.write_text(
        "# Identified by hipsim identify: a parameter file every hipsim command accepts (--params).\n"
        "# Model: analytic, lever spin on; regressor condition number 10.\n\n" + published,
        encoding="utf-8",
    )
    return path


#: The machine the exact logs are made with: every term the monitor fits non-zero (N·m, N·m·s/rad).
EXACT_MACHINE = hipsim.load_parameters().replace(hip_mu=0.1, screw_coulomb=0.05, screw_viscous=0.002)


def write_exact(
    path: Path,
    machine=None,
    rate: float = 50.0,
    cycles: int = 1,
    first_cycle: int = 0,
    lever_spin: bool = True,
    newline: bool = True,
    torque_constant: float | None = None,
    encoders: bool = False,
    angle_offset_deg: float = 0.0,
    stamp_step: float | None = None,
) -> Path:
    """The ISO cycle on ``machine`` logged without noise (17 digits): the analytic model's torques, the counter.

    ``torque_constant``: log motor currents τ/k (``current_i_A``) instead of torques; ``encoders``: log platform 1's
    slider heights (``L_1i_mm``, from the machine's inverse kinematics) beside the angles, these ``angle_offset_deg``
    off; ``stamp_step``: time stamps rounded down to this step in [s] (too coarse: the rate must be given).
    """
    from hipsim.analytic.inverse_kinematics import slider_heights

    machine = EXACT_MACHINE if machine is None else machine
    trajectory = hipsim.iso14242(rate=rate, cycles=cycles)
    tau = hipsim.analyse(machine, trajectory, lever_spin=lever_spin).torques.total
    angles = np.degrees(trajectory.q) + angle_offset_deg
    torques = ["tau_1_Nmm", "tau_2_Nmm", "tau_3_Nmm"]
    if torque_constant is None:
        tau = tau * 1e3
    else:
        tau, torques = tau / torque_constant, ["current_1_A", "current_2_A", "current_3_A"]
    names = ["t_s", "cycle", "Fe_N", "alpha_deg", "beta_deg", "gamma_deg", *torques]
    heights = None
    if encoders:
        names += ["L_11_mm", "L_12_mm", "L_13_mm"]
        heights = slider_heights(machine, trajectory.q * machine.angle_signs)[:, 0, :] * 1e3
    lines = [",".join(names)]
    for k, t in enumerate(trajectory.t):
        stamp = t if stamp_step is None else math.floor(t / stamp_step) * stamp_step
        values = [stamp, first_cycle + math.floor(t), trajectory.Fe[k], *angles[k], *tau[k]]
        values += [] if heights is None else list(heights[k])
        lines.append(",".join(f"{v:.17g}" for v in values))
    path.write_text("\n".join(lines) + ("\n" if newline else ""), encoding="utf-8")
    return path
