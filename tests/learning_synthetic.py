"""A machine as built that runs carriage commands, by a route other than hipsim.learning: the learning tests' rig.

The drive: a discrete first-order lag stepped through three repetitions of
the period (the last one kept), or a pure delay of whole samples. The
platforms: the true per-chain machine's forward kinematics of
tests/stations_synthetic.py (SciPy rotations, Newton on central differences).
The sensors: the true attitudes plus white noise.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from stations_synthetic import reference_attitude

from hipsim.learning.step import CycleLog


def drive(commands: np.ndarray, dt: float, lag_s: float = 0.0, delay_samples: int = 0) -> np.ndarray:
    """Encoder readings (N, 3) of a drive that lags its commands (N, 3), one period repeated until it settles."""
    y = np.roll(commands, delay_samples, axis=0) if delay_samples else np.array(commands, dtype=float)
    if lag_s <= 0:
        return y
    a = np.exp(-dt / lag_s)
    state = y[0].copy()
    out = np.empty_like(y)
    for _ in range(4):  # four periods: what is left of the start is e^(−4T/τ), round-off for τ ≤ T/10
        for n in range(len(y)):
            state = a * state + (1.0 - a) * y[n]
            out[n] = state
    return out


class Rig:
    """The machine as built: ``run(commands)`` gives the log of one period and the true attitudes."""

    def __init__(self, drawing, geometry, desired, lag_s=0.0, delay_samples=0, noise_deg=0.0, seed=0):
        self.drawing, self.geometry, self.desired = drawing, geometry, desired
        self.lag_s, self.delay_samples, self.noise = lag_s, delay_samples, np.radians(noise_deg)
        self.rng = np.random.default_rng(seed)

    def run(self, commands: np.ndarray) -> tuple[CycleLog, np.ndarray]:
        t = self.desired.t
        encoders = drive(commands, t[1] - t[0], self.lag_s, self.delay_samples)
        true = np.stack(
            [reference_attitude(self.drawing, self.geometry, j, encoders, self.desired.q) for j in (1, 2)], axis=1
        )
        sensors = true + self.rng.normal(0.0, self.noise, true.shape) if self.noise else true
        return CycleLog(t, encoders, commands, sensors, True, "rig"), true


def write_run_log(path: Path, log: CycleLog, commands: bool = True, platforms=(1, 2), periods: int = 1) -> Path:
    """The log as the acquisition writes it: t_s, L_1i_mm, L_1i_cmd_mm (if ``commands``), the sensors of ``platforms``."""
    n = len(log.t)
    period = (log.t[-1] - log.t[0]) * n / (n - 1)
    t = np.concatenate([log.t + k * period for k in range(periods)])
    names, columns = ["t_s"], [t]
    names += [f"L_1{i}_mm" for i in (1, 2, 3)]
    columns += [np.tile(log.encoders[:, i] * 1e3, periods) for i in range(3)]
    if commands:
        names += [f"L_1{i}_cmd_mm" for i in (1, 2, 3)]
        columns += [np.tile(log.commands[:, i] * 1e3, periods) for i in range(3)]
    for j in platforms:
        for k, a in enumerate(("alpha", "beta", "gamma")):
            names.append(f"{a}_{j}_deg")
            columns.append(np.tile(np.degrees(log.sensors[:, j - 1, k]), periods))
    np.savetxt(path, np.column_stack(columns), delimiter=",", header=",".join(names), comments="", fmt="%.15g")
    return path
