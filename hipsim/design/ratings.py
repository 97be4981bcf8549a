"""What a drive's parts can take, in closed forms tested against hand calculations: winding temperature rise, ball screw life, critical speed and buckling load.

Each function's docstring gives its formula and the standard it follows (and
the README's table "Sizing the drive" the same, with the sources).
"""

from __future__ import annotations

import math

import numpy as np

from ..exceptions import ArgumentError
from ..machine.drive_parts import END_FIXINGS, LeadScrew

__all__ = [
    "STEEL_DENSITY",
    "STEEL_MODULUS",
    "buckling_load",
    "critical_speed",
    "screw_life",
    "weighted_mean",
    "winding_rise",
]

#: Young's modulus [Pa] and density [kg/m³] of screw steel, for critical speed and buckling.
STEEL_MODULUS = 2.06e11
STEEL_DENSITY = 7850.0


def weighted_mean(values: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Weighted mean over the sample axis; weights (N,) or like values."""
    weights = weights if weights.ndim == values.ndim else weights[:, None]
    return np.sum(values * weights, axis=0) / np.sum(weights, axis=0)


def winding_rise(
    heating: np.ndarray, weights: np.ndarray, time_constant: float | None
) -> tuple[np.ndarray, np.ndarray]:
    """Mean and peak winding temperature rise of a first-order thermal model under a repeated cycle.

    dΔT/dt = (H(t) − ΔT)/τ_th with H = R_th·P_cu(t) the rise each instant's loss
    would settle at. Its cycle-periodic solution is found exactly for H held
    over each sample's time share.

    Args:
        heating: H in [K], (N, k).
        weights: each sample's time share in [s], (N,).
        time_constant: τ_th in [s]; None for the mean only (peak = mean).

    Returns:
        (mean, peak) rise in [K], each (k,).
    """
    mean = weighted_mean(heating, weights)
    if time_constant is None:
        return mean, mean
    decay = np.exp(-weights / time_constant)
    total_decay = float(np.prod(decay))
    steps = decay.tolist()
    peak = np.array([_periodic_peak(steps, column.tolist(), total_decay, m) for column, m in zip(heating.T, mean)])
    return mean, peak


def _periodic_peak(decay: list[float], heating: list[float], total_decay: float, mean: float) -> float:
    """The largest ΔT along the cycle-periodic solution of ΔT_k = a_k·ΔT_{k−1} + (1 − a_k)·H_k.

    Once through from ΔT = 0 gives ΔT_end = A·0 + B; the periodic start solves
    x = A·x + B (A = Π a_k, ``total_decay``). Plain floats: a sample's step is
    nanoseconds where a NumPy call on one number is microseconds (sizing ran
    this loop for most of its time).

    Args:
        decay: a_k = exp(−Δt_k/τ_th) per sample.
        heating: H_k in [K] per sample.
        total_decay: Π a_k over the cycle.
        mean: the time-weighted mean of H in [K], the start when nothing decays.
    """
    x = 0.0
    for a, h in zip(decay, heating, strict=True):
        x = a * x + (1.0 - a) * h
    x = x / (1.0 - total_decay) if total_decay < 1.0 else mean
    peak = x
    for a, h in zip(decay, heating, strict=True):
        x = a * x + (1.0 - a) * h
        if not x <= peak:  # NaN propagates, as np.maximum's would
            peak = x
    return peak


def screw_life(
    axial_load: np.ndarray, speed: np.ndarray, weights: np.ndarray, rating: float, preload: float = 0.0
) -> tuple[float, float]:
    """L10 life of a ball screw in revolutions, and its equivalent load, per ISO 3408-5.

    Each nut half (or, without preload, each flank direction) carries
    F₁ = F_pr·(1 + F/(2^{3/2}·F_pr))^{3/2}, F₂ = F₁ − F for |F| ≤ 2^{3/2}·F_pr
    (beyond it one half carries everything). Each half's cubic mean over the
    revolutions F_m,k = (Σ F_k³·|n|·Δt / Σ |n|·Δt)^{1/3} gives
    L_k = (C_a/F_m,k)³·10⁶ revolutions, and the nut L = (L₁^{-10/9} + L₂^{-10/9})^{-9/10}.

    Args:
        axial_load: F in [N], (N,), signed.
        speed: screw speed in [rad/s], (N,).
        weights: time shares in [s], (N,).
        rating: dynamic load rating C_a in [N].
        preload: F_pr in [N].

    Returns:
        (L10 in revolutions, equivalent load F_m in [N]: the constant load giving the same life).
    """
    revolutions = np.abs(speed) * weights / (2.0 * math.pi)
    if revolutions.sum() <= 0:
        return math.inf, 0.0
    limit = 2.0**1.5 * preload
    if preload > 0:
        inside = np.abs(axial_load) <= limit
        ratio = np.clip(axial_load / limit, -1.0, 1.0)
        first = np.where(inside, preload * (1.0 + ratio) ** 1.5, np.maximum(axial_load, 0.0))
    else:
        first = np.maximum(axial_load, 0.0)
    second = first - axial_load
    inverse = 0.0
    for half in (first, second):
        cubic_mean = (np.sum(half**3 * revolutions) / revolutions.sum()) ** (1.0 / 3.0)
        if cubic_mean > 0:
            inverse += ((rating / cubic_mean) ** 3 * 1e6) ** (-10.0 / 9.0)
    if inverse == 0.0:
        return math.inf, 0.0
    life = inverse ** (-9.0 / 10.0)
    return float(life), float(rating / (life / 1e6) ** (1.0 / 3.0))


def _geometry(screw: LeadScrew) -> tuple[float, float, str]:
    """The screw's root diameter d₂ in [m], free length l in [m] and end fixing, which its ratings need.

    Raises:
        ArgumentError: the screw does not give all three.
    """
    if screw.root_diameter is None or screw.free_length is None or screw.end_fixing is None:
        raise ArgumentError("screw", screw, "a screw with root_diameter_mm, free_length_mm and end_fixing")
    return screw.root_diameter, screw.free_length, screw.end_fixing


def critical_speed(screw: LeadScrew) -> float:
    """The first bending (whirling) speed of the screw in [rad/s]: n = λ²/l² · √(E·I/(ρ·A)), √(I/A) = d₂/4."""
    d2, length, fixing = _geometry(screw)
    lam = END_FIXINGS[fixing][0]
    return lam**2 / length**2 * d2 / 4.0 * math.sqrt(STEEL_MODULUS / STEEL_DENSITY)


def buckling_load(screw: LeadScrew) -> float:
    """Euler buckling load of the screw in [N]: m·π²·E·I/l², I = π·d₂⁴/64, m from the end fixing."""
    d2, length, fixing = _geometry(screw)
    m = END_FIXINGS[fixing][1]
    return m * math.pi**2 * STEEL_MODULUS * math.pi * d2**4 / 64.0 / length**2
