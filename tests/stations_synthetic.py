"""A per-chain machine computed by hand: a route other than hipsim.analytic.stations, for the stations' tests.

Chain ji (platform j, module i) from the parameter file's drawing and the
deviations' raw fields, as the [geometry] table defines them:

    b_ji = c_i + (u_ji, 0) + (L_i + h_j − h_1 + s_ji)·ẑ,   a_ji = (0, 0, h_j) + δo_j + R·(r⁰_i + δr_ji),
    |a_ji − b_ji| = l + δl_ji,

R from SciPy's Rotation ("ZYX", [γ, β, α]); the forward kinematics by Newton
on a central-difference Jacobian. The intermediate chain's stack-up raises o_1 by
[R_2·e − e]_z (R_2 m_2's rotation, e the seat): platform 1 then needs m_2's attitude
``q_other``, and its attitude at given carriages solves m_2's first. Synthetic calibration logs: carriages along a
smooth motion, each sensor the reference attitude plus Gaussian noise.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from hipsim.machine.chains import ChainGeometry
from hipsim.machine.parameters import load_parameters
from hipsim.stations import deviations as dv
from hipsim.stations.calibration import Calibration, Confounding
from hipsim.stations.sensitivity import Structure


def _pieces(params, geometry: ChainGeometry | None):
    g = ChainGeometry.zeros() if geometry is None else geometry
    theta = np.asarray(params.screw_angles)
    phi = theta + params.home_offset
    c = params.screw_radius * np.stack([np.cos(theta), np.sin(theta), np.zeros(3)], axis=1)
    r0 = params.joint_radius * np.stack([np.cos(phi), np.sin(phi), np.zeros(3)], axis=1)
    return g, c, r0


def _rotation(q: np.ndarray) -> np.ndarray:
    return Rotation.from_euler("ZYX", np.asarray(q)[:, ::-1]).as_matrix()  # Rz(γ)·Ry(β)·Rx(α)


def reference_carriages(params, geometry, j: int, q: np.ndarray, q_other: np.ndarray | None = None) -> np.ndarray:
    """Carriage readings (N, 3) in [m] putting platform j (1, 2) at gait angles q (N, 3) in [rad] (angle signs +1).

    ``q_other``: m_2's gait angles (N, 3) for platform 1 on a machine with a stack-up (its centre's lift).
    """
    g, c, r0 = _pieces(params, geometry)
    h = np.asarray(params.heights)
    R = _rotation(q)
    centre = np.array([0.0, 0.0, h[j - 1]]) + g.centre[j - 1] + np.zeros((len(q), 3))
    if j == 1 and np.any(g.spline):
        assert q_other is not None, "platform 1 on a machine with a stack-up needs m_2's attitude"
        centre[:, 2] += (_rotation(q_other) @ g.spline - g.spline)[:, 2]
    out = np.empty((len(q), 3))
    for i in range(3):
        a = centre + R @ (r0[i] + g.joint[j - 1, i])
        gap = a[:, :2] - c[i, :2] - g.ujoint[j - 1, i]
        lever = params.lever_length + g.lever[j - 1, i]
        out[:, i] = a[:, 2] - (h[j - 1] - h[0] + g.slider[j - 1, i]) - np.sqrt(lever**2 - (gap**2).sum(axis=1))
    return out


def reference_attitude(params, geometry, j: int, L: np.ndarray, guess: np.ndarray) -> np.ndarray:
    """Platform j's gait angles (N, 3) at carriage readings L (N, 3), by Newton from ``guess`` (N, 3)."""
    q_other = reference_attitude(params, geometry, 2, L, guess) if j == 1 and geometry is not None else None
    q = np.array(guess, dtype=float)
    step = 1e-6
    for _ in range(30):
        r = reference_carriages(params, geometry, j, q, q_other) - L
        D = np.empty((len(q), 3, 3))
        for k in range(3):
            dq = np.zeros(3)
            dq[k] = step
            D[:, :, k] = (
                reference_carriages(params, geometry, j, q + dq, q_other)
                - reference_carriages(params, geometry, j, q - dq, q_other)
            ) / (2 * step)
        delta = np.linalg.solve(D, r[..., None])[..., 0]
        q -= delta
        if np.abs(delta).max() < 1e-14:
            break
    return q


def motion(n: int, rate: float = 500.0, seed: int = 0, scale_deg: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """A smooth motion of n samples at ``rate`` [Hz]: four sines per angle, some 10-20° peak, times [s] and angles [rad]."""
    t = np.arange(n) / rate
    r = np.random.default_rng(seed)
    q = np.zeros((n, 3))
    for f in (0.31, 0.73, 1.17, 1.91):
        q += np.radians(scale_deg * r.uniform(2.0, 5.0, 3)) * np.sin(
            2 * np.pi * f * t[:, None] + r.uniform(0, 2 * np.pi, 3)
        )
    return t, q


def synthetic_log(params, geometry, n: int, seed: int, noise_deg: float = 0.05, offsets_deg=None):
    """(t [s], carriages [m] (N, 3), true attitudes [rad] (N, 2, 3), sensors [rad] (N, 2, 3)) of a log of the true machine."""
    t, q = motion(n, seed=seed)
    L = reference_carriages(params, geometry, 2, q)
    true = np.stack([reference_attitude(params, geometry, j, L, q) for j in (1, 2)], axis=1)
    sensors = true + np.random.default_rng(seed + 1000).normal(0.0, np.radians(noise_deg), true.shape)
    if offsets_deg is not None:
        sensors = sensors + np.radians(np.asarray(offsets_deg, dtype=float)).reshape(2, 3)
    return t, L, true, sensors


def write_log(path: Path, t, L, sensors) -> Path:
    """A calibration log CSV with the columns ``hipsim calibrate`` reads."""
    names = ["t_s", "L_11_mm", "L_12_mm", "L_13_mm"] + [
        f"{a}_{j}_deg" for j in (1, 2) for a in ("alpha", "beta", "gamma")
    ]
    values = np.column_stack([t, L * 1e3, np.degrees(sensors).reshape(len(t), 6)])
    np.savetxt(path, values, delimiter=",", header=",".join(names), comments="", fmt="%.12g")
    return path


def deviated(seed: int = 3, size_mm: float = 0.3) -> ChainGeometry:
    """A machine whose 48 values deviate uniformly within ±size_mm from the drawing."""
    return ChainGeometry.from_vector(np.random.default_rng(seed).uniform(-size_mm, size_mm, 48) * 1e-3)


NAMES = dv.names()
LEVER_11, LEVER_21, CENTRE_X_1 = NAMES.index("lever_11"), NAMES.index("lever_21"), NAMES.index("centre_x_1")


def hand_calibration(offsets: bool = True, confounded: tuple[Confounding, ...] = ()) -> Calibration:
    """Two values estimated (lever_11 +0.2 mm ± 0.1, lever_21 −0.05 mm ± 0.4), centre_x_1 kept at its prior (0.5 mm),
    the others neither; two logs."""
    start = load_parameters()
    theta = np.zeros(dv.COUNT)
    theta[[LEVER_11, LEVER_21]] = [2e-4, -5e-5]
    std = np.full(dv.COUNT, 5e-4)
    std[[LEVER_11, LEVER_21]] = [1e-4, 4e-4]
    determined = np.zeros(dv.COUNT, dtype=bool)
    determined[LEVER_11] = True
    structure = Structure(2, np.array([LEVER_11, LEVER_21]), np.array([CENTRE_X_1]), np.array([[0.5], [0.0]]), offsets)
    covariance = np.array([[1e-8, -2e-9], [-2e-9, 1.6e-7]])
    offsets_rad = np.zeros((2, 2, 3))
    if offsets:
        offsets_rad[1, 0, 2] = math.radians(0.25)
    noise = np.radians(np.array([[0.01, 0.02, 0.03], [0.04, 0.05, 0.06]]))
    return Calibration(
        machine=dv.machine(start, theta),
        start=start,
        theta=theta,
        theta_std=std,
        covariance=covariance,
        structure=structure,
        determined=determined,
        prior=5e-4,
        offsets=offsets_rad,
        noise=noise,
        residual_rms=np.stack([noise, 2 * noise]),
        start_rms=np.stack([10 * noise, 20 * noise]),
        logs=("a.csv", "b.csv"),
        samples=300,
        iterations=4,
        confounded=confounded,
    )
