"""The learning law: u_{k+1} = Q(u_k + L·e_k), from one cycle of the machine to the next (spec: issue 45).

A wear test repeats one cycle millions of times, so the error of a cycle
repeats too, and the next cycle's command can be corrected by it (iterative
learning control; Bristow, Tharayil & Alleyne, IEEE Control Systems Magazine
26(3), 2006). Here the learned signal u_k is the correction of the carriage
commands over the model's own command L⁰ (what ``hipsim stations`` gives),
one period long; cycle k runs L⁰ + u_k and its attitude sensors give the
error e_k = q_d − q_k per platform. Then

    u_{k+1} = Q( u_k + γ·G_m⁻¹[ K·e_k ] )

- K, per sample, inverts the model's carriage-to-attitude map at the desired
  motion: for ``control`` j, K = ∂L_j/∂q (the inverse of A_j = ∂q_j/∂L); for
  ``both``, the weighted least squares K e = (Σ_j w_j A_jᵀA_j)⁻¹ Σ_j w_j A_jᵀ e_j;
- G_m(f) = 1/(1 + i2πfτ), the drive's position loop as the model knows it (τ
  ``drive_lag``; 0: G_m = 1), so that L = γ·G_m⁻¹·K is the model's inverse;
- γ, the learning gain (1: the whole correction at once);
- Q, the zero-phase periodic low-pass of :mod:`~hipsim.learning.filters`
  (Norrlöf & Gunnarsson, Int. J. Control 75(14), 2002): it stops learning what
  the model cannot tell (sensor noise, high-frequency mismatch).

The update converges monotonically (in the lifted, cycle-to-cycle sense) when
‖Q(I − L·P)‖ < 1, P the machine's cycle map from carriage commands to
attitudes. On the model, L·P = γ·G_m⁻¹·G_m·I = γ·I, so the model's figure is
|1 − γ|·max Q: the gain must lie in (0, 2). What the model cannot know is the
real drive's response: where a log has the commands beside the encoders, each
harmonic h of the cycle gives G_d(f_h) = encoder/command, and the data's
figure is max_h Q(f_h)·|1 − γ·G_d(f_h)/G_m(f_h)| (the Jacobian's mismatch,
~1e-3 relative at 0.3 mm deviations, is left out). A figure ≥ 1 refuses the step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..exceptions import ArgumentError
from ..machine.parameters import Parameters
from ..stations.commands import CONTROLS
from ..stations.sensitivity import inverse3, reading_rate
from .filters import apply_response, frequencies, lag_response, q_response

__all__ = [
    "DEFAULT_Q_CUTOFF",
    "LearningLaw",
    "data_spectral_radius",
    "gain_matrices",
    "model_spectral_radius",
    "update",
]

#: Q's default cutoff in [Hz]: ten harmonics of a 1 Hz gait, well below the noise of attitude sensors.
DEFAULT_Q_CUTOFF = 10.0
#: A harmonic of the command weaker than this share of its strongest is too weak to measure the drive's response on.
HARMONIC_FLOOR = 1e-3


@dataclass(frozen=True)
class LearningLaw:
    """What the update learns and how fast.

    Attributes:
        control: "1", "2" (that platform's error) or "both" (the weighted sum of both platforms' squared errors).
        weights: (w_1, w_2) of ``both``, dimensionless.
        gain: the learning gain γ, dimensionless, > 0 (1: the model's whole correction at once).
        q_cutoff: Q's cutoff in [Hz], or None for no filter (Q = 1).
        drive_lag: the model's drive position loop as a first-order lag, time constant in [s] (0: none).
    """

    control: str = "2"
    weights: tuple[float, float] = (1.0, 1.0)
    gain: float = 1.0
    q_cutoff: float | None = DEFAULT_Q_CUTOFF
    drive_lag: float = 0.0

    def __post_init__(self):
        if self.control not in CONTROLS:
            raise ArgumentError("control", self.control, "one of 1, 2, both")
        w = tuple(float(x) for x in self.weights)
        if len(w) != 2 or not all(math.isfinite(x) and x >= 0 for x in w) or sum(w) == 0:
            raise ArgumentError("weights", self.weights, "two finite weights >= 0, not both zero")
        object.__setattr__(self, "weights", w)
        if not (math.isfinite(self.gain) and self.gain > 0):
            raise ArgumentError("gain", self.gain, "a finite learning gain > 0")
        if self.q_cutoff is not None and not (math.isfinite(self.q_cutoff) and self.q_cutoff > 0):
            raise ArgumentError("q_cutoff", self.q_cutoff, "a positive frequency in Hz, or None")
        if not (math.isfinite(self.drive_lag) and self.drive_lag >= 0):
            raise ArgumentError("drive_lag", self.drive_lag, "a time constant >= 0 in s")

    @property
    def platforms(self) -> tuple[int, ...]:
        """The platforms whose errors the law learns from (whose sensors a log must have)."""
        return (1, 2) if self.control == "both" else (int(self.control),)


def gain_matrices(model: Parameters, q_d: np.ndarray, law: LearningLaw) -> np.ndarray:
    """K_j per sample: the carriage correction [m] per radian of platform j's error, (N, 2, 3, 3).

    ΔL = Σ_j K_j·e_j; zero for a platform the law does not learn from.

    Args:
        model: the controller's machine (the drawing, a calibrated or identified file).
        q_d: the desired attitude in [rad], (N, 3).
        law: the law.
    """
    q_d = np.asarray(q_d, dtype=float)
    K = np.zeros((len(q_d), 2, 3, 3))
    if law.control != "both":
        j = int(law.control)
        K[:, j - 1] = reading_rate(model, q_d, j)
        return K
    A = {j: inverse3(reading_rate(model, q_d, j)) for j in (1, 2)}
    w = law.weights
    H = sum(w[j - 1] * np.matmul(np.swapaxes(A[j], 1, 2), A[j]) for j in (1, 2))
    Hinv = inverse3(H)
    for j in (1, 2):
        K[:, j - 1] = w[j - 1] * np.matmul(Hinv, np.swapaxes(A[j], 1, 2))
    return K


def update(learned: np.ndarray, errors: np.ndarray, K: np.ndarray, law: LearningLaw, period: float) -> np.ndarray:
    """u_{k+1} = Q(u_k + γ·G_m⁻¹[Σ_j K_j·e_j]) in [m], (N, 3).

    Args:
        learned: u_k, the correction cycle k ran over the model's command, in [m], (N, 3).
        errors: e_k = q_d − q_k per platform in [rad], (N, 2, 3) (a platform not learned from may be NaN).
        K: :func:`gain_matrices`, (N, 2, 3, 3).
        law: the law.
        period: the cycle's period in [s] (the N samples cover it evenly).
    """
    e = np.where(np.isfinite(errors), errors, 0.0)
    correction = np.einsum("njab,njb->na", K, e)
    f = frequencies(len(learned), period)
    correction = apply_response(correction, 1.0 / lag_response(f, law.drive_lag))
    return apply_response(learned + law.gain * correction, q_response(f, law.q_cutoff))


def model_spectral_radius(law: LearningLaw) -> float:
    """‖Q(I − L·P)‖ on the model: |1 − γ|·max Q = |1 − γ| (L inverts the model's P; Q(0) = 1)."""
    return abs(1.0 - law.gain)


def data_spectral_radius(
    commands: np.ndarray, encoders: np.ndarray, law: LearningLaw, period: float
) -> tuple[float, float]:
    """‖Q(I − L·P)‖ with the drive's response measured in a log: (figure, the frequency in [Hz] where it is worst).

    Per carriage and harmonic f_h of the cycle with a command strong enough to measure (at least
    :data:`HARMONIC_FLOOR` of the carriage's strongest), G_d = encoder/command, and the figure
    Q(f_h)·|1 − γ·G_d/G_m|; the largest over carriages and harmonics. (nan, nan) when no harmonic is measurable.

    Args:
        commands, encoders: one period of the carriage commands and readings in [m], (N, 3).
        law: the law.
        period: the cycle's period in [s].
    """
    C = np.fft.rfft(np.asarray(commands, dtype=float), axis=0)[1:]
    E = np.fft.rfft(np.asarray(encoders, dtype=float), axis=0)[1:]
    f = frequencies(len(commands), period)[1:]
    if len(commands) % 2 == 0:  # the Nyquist bin holds no phase
        C, E, f = C[:-1], E[:-1], f[:-1]
    if not len(f):
        return math.nan, math.nan
    strong = np.abs(C) >= HARMONIC_FLOOR * np.abs(C).max(axis=0)
    strong &= np.abs(C) > 0
    if not strong.any():
        return math.nan, math.nan
    ratio = np.divide(E, C, out=np.zeros_like(C), where=strong)
    G_m = lag_response(f, law.drive_lag)[:, None]
    figure = q_response(f, law.q_cutoff)[:, None] * np.abs(1.0 - law.gain * ratio / G_m)
    figure = np.where(strong, figure, -np.inf)
    k = np.unravel_index(int(np.argmax(figure)), figure.shape)
    return float(figure[k]), float(f[k[0]])
