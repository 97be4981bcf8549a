"""What the controller sees of the machine: the controlled platform's attitude from the carriage encoders or from its sensor.

The paper closes the loop on m_2 (its Fig. 5 and 7). Which signal closes it
decides where the model's geometric error goes:

- :class:`EncoderFeedback` (the default of ``hipsim simulate``): each motor's
  encoder reads its carriage, quantised to ``step``; the controller's *model*
  turns the three readings into the controlled platform's attitude by its
  forward kinematics (:mod:`hipsim.control.chain_kernel`, the stations' law,
  the stack-up included: with m_1 controlled, m_2's attitude first and m_1's on the seen carriages),
  and the carriage rates into its rate (q̇ = T⁻¹·J⁻¹·L̇, the rates
  unquantised: a drive's velocity estimate is far finer than one count per
  period). A model that is not the machine puts its error on the controlled
  platform.
- :class:`SensorFeedback`: the controlled platform's attitude sensor (an
  AHRS): the true attitude plus seeded white noise of standard deviation
  ``noise`` on each angle and a zero drift growing at ``drift`` per second
  (the same on the three angles); its rate is the true rate (the gyros an
  AHRS fuses are far less noisy than its attitude). The controlled platform
  then carries no model error; the follower carries all of it.

A feedback is told the run's servo instants once (:meth:`Feedback.start`, so
that the sensor draws its noise for the whole run from its seed) and then,
each servo period, the plant's true carriages and attitudes.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod

import numpy as np

from ..exceptions import ArgumentError
from ..machine.parameters import Parameters
from . import chain_kernel

__all__ = [
    "EncoderFeedback",
    "Feedback",
    "SensorFeedback",
    "DEFAULT_ENCODER_STEP",
    "DEFAULT_SENSOR_NOISE",
    "encoder_reading",
]

#: The encoders' step, [m] (0.001 mm).
DEFAULT_ENCODER_STEP = 1e-6
#: The attitude sensor's white noise, standard deviation in [rad] (0.05°).
DEFAULT_SENSOR_NOISE = math.radians(0.05)


def encoder_reading(L: np.ndarray, step: float) -> np.ndarray:
    """What the encoders read for true carriage readings L [m], (3,): rounded to the step [m] (0: exact)."""
    return np.rint(L / step) * step if step > 0 else np.array(L, dtype=float)


class Feedback(ABC):
    """The controlled platform's measured state, from the plant's true one.

    Attributes:
        control: the controlled platform, 1 (m_1) or 2 (m_2).
        name: what closes the loop, for tables ("encoders", "sensors").
    """

    name = ""

    def __init__(self, control: int):
        if control not in (1, 2) or isinstance(control, bool):
            raise ArgumentError("control", control, "1 (m_1) or 2 (m_2)")
        self.control = int(control)

    @abstractmethod
    def start(self, t: np.ndarray, q0: np.ndarray) -> None:
        """Prepare a run whose servo instants are t [s], (n,), starting near gait angles q0 [rad], (3,)."""

    @abstractmethod
    def measure(
        self, k: int, t: float, L: np.ndarray, Ld: np.ndarray, q: np.ndarray, qd: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(carriage readings [m] (3,), measured gait angles [rad] (3,), their rates [rad/s] (3,)) at servo instant k.

        Args:
            k: the servo instant's index; t: its time [s].
            L, Ld: the carriages' true readings [m] and rates [m/s], (3,).
            q, qd: both platforms' true gait angles [rad] and rates [rad/s], (2, 3).
        """

    def sensing(self) -> tuple[bool, float, np.ndarray, np.ndarray]:
        """For the compiled loop (:mod:`hipsim.control.machine_kernel`), after :meth:`start`: (read the encoders?,
        encoder step [m], the sensor's offsets [rad] (n, 3), the last attitude read [rad] (3,))."""
        raise NotImplementedError


class EncoderFeedback(Feedback):
    """The controlled platform's attitude from the carriage encoders through the model's forward kinematics.

    Args:
        model: the controller's model (the drawing, a calibrated or an identified machine).
        control: the controlled platform, 1 or 2.
        step: the encoders' resolution in carriage travel [m] (> 0; 0 for exact readings).
    """

    name = "encoders"

    def __init__(self, model: Parameters, control: int, step: float = DEFAULT_ENCODER_STEP):
        super().__init__(control)
        if not (math.isfinite(step) and step >= 0):
            raise ArgumentError("step", step, "an encoder step >= 0 in m")
        self.step = float(step)
        self._model = chain_kernel.model_arrays(model, self.control)
        self._last = np.zeros(3)

    def start(self, t: np.ndarray, q0: np.ndarray) -> None:
        self._last = np.array(q0, dtype=float)

    def sensing(self):
        return True, self.step, np.zeros((1, 3)), self._last

    def measure(self, k, t, L, Ld, q, qd):
        reading = encoder_reading(L, self.step)
        angles = chain_kernel.model_attitude(*self._model, reading, self._last)
        if np.all(np.isfinite(angles)):
            self._last = angles
        return reading, angles, chain_kernel.model_rates(*self._model, angles, Ld)


class SensorFeedback(Feedback):
    """The controlled platform's attitude sensor: true attitude, white noise and a zero drift.

    Args:
        control: the controlled platform, 1 or 2.
        noise: standard deviation of the white noise on each angle in [rad] (>= 0).
        drift: the zero's drift in [rad/s], the same on the three angles.
        seed: the noise's seed.
        encoder_step: the encoders' resolution [m] for the carriages the run logs (the loop does not use them).
    """

    name = "sensors"

    def __init__(
        self,
        control: int,
        noise: float = DEFAULT_SENSOR_NOISE,
        drift: float = 0.0,
        seed: int = 0,
        encoder_step: float = DEFAULT_ENCODER_STEP,
    ):
        super().__init__(control)
        if not (math.isfinite(noise) and noise >= 0):
            raise ArgumentError("noise", noise, "a standard deviation >= 0 in rad")
        if not math.isfinite(drift):
            raise ArgumentError("drift", drift, "a finite drift in rad/s")
        if not (math.isfinite(encoder_step) and encoder_step >= 0):
            raise ArgumentError("encoder_step", encoder_step, "an encoder step >= 0 in m")
        self.noise, self.drift, self.seed = float(noise), float(drift), int(seed)
        self.step = float(encoder_step)
        self._offsets = np.zeros((0, 3))

    def start(self, t: np.ndarray, q0: np.ndarray) -> None:
        t = np.asarray(t, dtype=float)
        # (n, 3) either way, as sensing() promises the compiled loop (a noiseless sensor's were (n, 1)).
        rng = np.random.default_rng(self.seed)
        white = rng.standard_normal((t.size, 3)) if self.noise > 0 else np.zeros((t.size, 3))
        self._offsets = self.noise * white + self.drift * t[:, None]

    def sensing(self):
        return False, self.step, self._offsets, np.zeros(3)

    def measure(self, k, t, L, Ld, q, qd):
        c = self.control - 1
        return encoder_reading(L, self.step), q[c] + self._offsets[k], np.array(qd[c], dtype=float)
