"""Periodic signals of one cycle: the zero-phase robustness filter Q, a drive's lag, derivatives, all by the DFT.

A learned command is one period of a periodic signal: its last sample is
followed by its first. Filtering it as such (the discrete Fourier transform
of the period, multiplied by a real response, transformed back) has no edge
transients and no phase: what a forward-backward filter gives on an endless
repetition of the cycle.

- :func:`q_response`: Q(f) = 1 / (1 + (f/f_c)^8), the magnitude of a 4th-order
  Butterworth low-pass applied forwards and backwards (the project's
  ``--cutoff`` filter, made periodic); real, between 0 and 1, so ‖Q‖ ≤ 1;
- :func:`lag_response`: G(f) = 1 / (1 + i·2πf·τ), a position loop as a
  first-order lag of time constant τ;
- :func:`apply_response` and :func:`periodic_derivatives`.
"""

from __future__ import annotations

import numpy as np

from ..exceptions import ArgumentError

__all__ = ["ORDER", "apply_response", "frequencies", "lag_response", "periodic_derivatives", "q_response"]

#: Order of the Butterworth whose forward-backward magnitude Q is: |H|² = 1/(1 + (f/f_c)^(2·ORDER)).
ORDER = 4


def frequencies(n: int, period: float) -> np.ndarray:
    """The frequencies in [Hz] of the real DFT's bins of n samples over one period in [s], (n // 2 + 1,)."""
    return np.arange(n // 2 + 1) / period


def q_response(f: np.ndarray, cutoff: float | None) -> np.ndarray:
    """Q(f), real in [0, 1]: 1 / (1 + (f/cutoff)^8); all ones for cutoff None (no filter).

    Above the cutoff it is computed as r / (1 + r) with r = (cutoff/f)^8, so that a ratio never exceeds 1: a tiny
    cutoff gives Q = 0 (r underflows) instead of overflowing (f/cutoff)^8.

    Args:
        f: frequencies in [Hz].
        cutoff: the cutoff f_c in [Hz] (Q = 1/2 there), or None.
    """
    f = np.asarray(f, dtype=float)
    if cutoff is None:
        return np.ones_like(f)
    if not cutoff > 0:
        raise ArgumentError("cutoff", cutoff, "a positive frequency in Hz")
    a = np.abs(f)
    below = a <= cutoff
    r = (np.where(below, a, cutoff) / np.where(below, cutoff, a)) ** (2 * ORDER)  # f/f_c below, f_c/f above: ≤ 1
    return np.where(below, 1.0 / (1.0 + r), r / (1.0 + r))


def lag_response(f: np.ndarray, lag: float) -> np.ndarray:
    """G(f) = 1 / (1 + i·2πf·τ), complex: a first-order lag of time constant ``lag`` τ in [s] (0: G = 1)."""
    if not lag >= 0:
        raise ArgumentError("lag", lag, "a time constant >= 0 in s")
    return 1.0 / (1.0 + 2j * np.pi * np.asarray(f, dtype=float) * lag)


def apply_response(x: np.ndarray, response: np.ndarray) -> np.ndarray:
    """One period x (n, ...) through a frequency response (n // 2 + 1,) by the real DFT along axis 0; real, (n, ...).

    At the Nyquist bin of an even n only the real part of the response can act on a real signal; its real part is used.
    """
    x = np.asarray(x, dtype=float)
    n = len(x)
    H = np.array(response, dtype=complex)
    if n % 2 == 0:
        H[-1] = H[-1].real
    shape = (len(H),) + (1,) * (x.ndim - 1)
    return np.fft.irfft(np.fft.rfft(x, axis=0) * H.reshape(shape), n=n, axis=0)


def periodic_derivatives(x: np.ndarray, period: float) -> tuple[np.ndarray, np.ndarray]:
    """The first and second time derivatives of one period x (n, ...) sampled evenly over ``period`` in [s].

    The derivatives of the trigonometric interpolant through the samples (exact for a signal band-limited below
    the Nyquist frequency); the Nyquist bin of an even n is dropped from both (its derivative is not real).
    """
    n = len(x)
    w = 2j * np.pi * frequencies(n, period)
    if n % 2 == 0:
        w[-1] = 0.0
    return apply_response(x, w), apply_response(x, w * w)
