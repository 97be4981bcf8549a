"""Is a sampled motion too noisy to differentiate? A check of its acceleration's spectrum.

Measured kinematics (a motion-capture inverse-kinematics walk, a rig's
encoder log) carry noise that differentiation amplifies: white noise of σ on
an angle becomes noise of about √6·σ·f_s² on its second difference, so at
60 Hz a hundredth of a degree of noise is already 90 °/s² of spurious
acceleration, and the torques that follow from it are wrong. Gait lab practice
is a zero-phase low-pass at about 6 Hz before differentiating.

The check: the second differences of the angles (the acceleration the
readers would compute, up to their spline's smoothing) are split by
frequency, and the share of their power above :data:`MOTION_BAND` (12 Hz,
twice the gait cutoff; human gait, running included, has almost no
acceleration content there) is measured. Above :data:`NOISE_SHARE` (10 %)
the motion is called noisy, with the suggested cutoff
:data:`SUGGESTED_CUTOFF`. Motions sampled at 2·12 Hz or less cannot be
checked and pass.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["MOTION_BAND", "NOISE_SHARE", "SUGGESTED_CUTOFF", "NoiseCheck", "check_noise"]

#: Frequency in [Hz] above which a gait's acceleration has (almost) no content of its own.
MOTION_BAND = 12.0

#: Share of the acceleration's power above :data:`MOTION_BAND` from which a motion counts as noisy.
NOISE_SHARE = 0.10

#: The low-pass cutoff in [Hz] gait labs use, suggested for a noisy motion.
SUGGESTED_CUTOFF = 6.0


@dataclass(frozen=True)
class NoiseCheck:
    """The acceleration spectrum's verdict.

    Attributes:
        share: per angle α, β, γ, the share of the acceleration's power above :data:`MOTION_BAND`, shape (3,).
        rate: the sampling rate in [Hz].
        noisy: True when an angle's share is at least :data:`NOISE_SHARE`.
    """

    share: np.ndarray
    rate: float
    noisy: bool

    def warning(self, source: str) -> str | None:
        """The one-line warning for a noisy motion, or None."""
        if not self.noisy:
            return None
        worst = int(np.argmax(self.share))
        return (
            f"{source}: {100 * self.share[worst]:.0f} % of the {('alpha', 'beta', 'gamma')[worst]} acceleration lies above "
            f"{MOTION_BAND:g} Hz, where gait has none: measurement noise, amplified by differentiation at {self.rate:g} Hz; "
            f"filter it with --cutoff {SUGGESTED_CUTOFF:g}"
        )


def check_noise(t: np.ndarray, q: np.ndarray) -> NoiseCheck:
    """Measure how much of a sampled motion's acceleration lies above the gait band.

    Args:
        t: sample times in [s], shape (N,), evenly spaced (the readers resample otherwise).
        q: angles in [rad] (any unit: the share is a ratio), shape (N, 3).

    Returns:
        The shares and the verdict (never noisy below 2·12 Hz sampling or with fewer than 16 samples).
    """
    t, q = np.asarray(t, dtype=float), np.asarray(q, dtype=float)
    rate = 1.0 / float(np.median(np.diff(t))) if t.size > 1 else 0.0
    if t.size < 16 or rate <= 2.0 * MOTION_BAND:
        return NoiseCheck(np.zeros(3), rate, False)
    acceleration = np.diff(q, n=2, axis=0) * rate**2
    acceleration -= acceleration.mean(axis=0)
    # A Hann window keeps the leakage of a motion that is not a whole number of periods out of the high band.
    window = np.hanning(acceleration.shape[0])[:, None]
    power = np.abs(np.fft.rfft(acceleration * window, axis=0)) ** 2
    frequency = np.fft.rfftfreq(acceleration.shape[0], 1.0 / rate)
    total = power.sum(axis=0)
    share = np.where(total > 0, power[frequency > MOTION_BAND].sum(axis=0) / np.where(total > 0, total, 1.0), 0.0)
    return NoiseCheck(share, rate, bool((share >= NOISE_SHARE).any()))
