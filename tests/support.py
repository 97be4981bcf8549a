"""Trajectories at arbitrary times, for finite differences and cross-checks."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np

from hipsim.motion.trajectories import Trajectory, iso14242_angles, iso14242_load

_T = TypeVar("_T")


def given(value: _T | None) -> _T:
    """``value``, which the test expects to be there (a regex match, an optional field): fails on None, narrows the type."""
    assert value is not None
    return value


#: Every friction coefficient on, U/S-joint friction (zero by default) included, for Parameters.replace.
ALL_FRICTION = dict(
    screw_coulomb=0.05,
    screw_viscous=2e-4,
    guide_coulomb=15.0,
    guide_viscous=40.0,
    ujoint_coulomb=0.3,
    ujoint_viscous=0.02,
    sjoint_coulomb=0.4,
    sjoint_viscous=0.03,
)


def iso_at(t, frequency: float = 1.0) -> Trajectory:
    """The built-in ISO cycle evaluated at any times t in [s]."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    q, qd, qdd = iso14242_angles(t, frequency)
    return Trajectory(t, q, qd, qdd, iso14242_load(t, frequency), name="ISO at t")


class SmoothMotion:
    """A random smooth orientation trajectory: a few sinusoids per angle, kept well inside the workspace.

    Args:
        seed: random seed.
        amplitude_deg: largest amplitude of each angle in [deg].
    """

    def __init__(self, seed: int = 0, amplitude_deg: float = 12.0, harmonics: int = 3):
        rng = np.random.default_rng(seed)
        self.offset = np.radians(rng.uniform(-3.0, 3.0, 3))
        self.amp = np.radians(rng.uniform(0.2, 1.0, (harmonics, 3)) * amplitude_deg / harmonics)
        self.freq = rng.uniform(0.3, 2.0, (harmonics, 3))
        self.phase = rng.uniform(0.0, 2 * np.pi, (harmonics, 3))
        self.load = rng.uniform(300.0, 3000.0)

    def __call__(self, t) -> Trajectory:
        t = np.atleast_1d(np.asarray(t, dtype=float))[:, None, None]
        w = 2 * np.pi * self.freq
        arg = w * t + self.phase
        q = self.offset + np.sum(self.amp * np.sin(arg), axis=1)
        qd = np.sum(self.amp * w * np.cos(arg), axis=1)
        qdd = -np.sum(self.amp * w**2 * np.sin(arg), axis=1)
        load = self.load * (1.0 + 0.3 * np.sin(2 * np.pi * t[:, 0, 0]))
        return Trajectory(t[:, 0, 0], q, qd, qdd, load, name="smooth random")


def central_difference(f, t, h):
    """(f(t + h) − f(t − h)) / 2h for a function of an array of times."""
    return (f(t + h) - f(t - h)) / (2 * h)


def relative_error(actual, expected) -> float:
    """Largest |actual − expected| over the peak |expected|."""
    return float(np.max(np.abs(actual - expected)) / np.max(np.abs(expected)))


# Rotations written out, for checks that must not go through hipsim's (or SciPy's) conversions.


def Rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def Ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def Rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def machine_R(alpha, beta, gamma):
    return Rz(gamma) @ Ry(beta) @ Rx(alpha)


def zxy_angles(Rh):
    """Rh = Rz(z)·Rx(x)·Ry(y) → (z, x, y), closed form for |x| < 90°."""
    return np.arctan2(-Rh[0, 1], Rh[1, 1]), np.arcsin(Rh[2, 1]), np.arctan2(-Rh[2, 0], Rh[2, 2])


def zyx_angles(R):
    """R = Rz(γ)·Ry(β)·Rx(α) → (α, β, γ), closed form for |β| < 90°."""
    return np.arctan2(R[2, 1], R[2, 2]), -np.arcsin(R[2, 0]), np.arctan2(R[1, 0], R[0, 0])


def smooth_cycle(t):
    """A smooth orientation cycle with exact derivatives (duck-typed trajectory)."""
    from types import SimpleNamespace

    t = np.atleast_1d(np.asarray(t, dtype=float))
    w = 2 * np.pi
    amplitude, phase = np.array([20.0, 6.0, 7.0]) * (np.pi / 180.0), np.array([0.3, -0.7, 2.0])
    arg = w * t[:, None] + phase
    return SimpleNamespace(
        t=t,
        q=amplitude * np.cos(arg),
        qd=-w * amplitude * np.sin(arg),
        qdd=-w * w * amplitude * np.cos(arg),
        name="test",
    )


def closed_hip():
    """The hip's closed-chain model closed along 41 samples of :func:`smooth_cycle`, with a workspace and its layout."""
    from types import SimpleNamespace

    from hipsim import load_parameters
    from hipsim.closed_chain.build import load_model
    from hipsim.closed_chain.closure import kinematics
    from hipsim.closed_chain.workspace import Workspace

    chain = load_model(load_parameters())
    kin = kinematics(chain, smooth_cycle(np.linspace(0.0, 1.0, 41)))
    return SimpleNamespace(chain=chain, kin=kin, ws=Workspace(chain), layout=chain.layout)


def recorded_calls(monkeypatch, module, name: str) -> list[tuple[tuple, tuple]]:
    """Wrap ``module.name`` (a compiled kernel, as its caller looks it up) to keep each call's arguments, by reference,
    with their numba types as the call saw them (:func:`argument_types`: a log frozen afterwards is typed writable).

    The arguments a production caller passes carry the exact types numba compiled the kernel for: a test that calls
    the kernel again with arguments of those types reuses that compiled specialisation instead of compiling a new one
    (seconds of CPU each).
    """
    calls: list[tuple[tuple, tuple]] = []
    kernel = getattr(module, name)

    def recorded(*args):
        calls.append((args, argument_types(args)))
        return kernel(*args)

    monkeypatch.setattr(module, name, recorded)
    return calls


def argument_types(args: tuple) -> tuple:
    """The numba types a compiled kernel's dispatcher sees for ``args``: one specialisation per distinct tuple."""
    from numba import typeof
    from numba.core.typing.typeof import Purpose

    return tuple(typeof(arg, Purpose.argument) for arg in args)


@dataclass(frozen=True)
class Recorded:
    """One recorded call of a compiled kernel: its arguments by parameter name, and their numba types at the call."""

    args: dict[str, Any]
    types: tuple


#: A still pose of the ramp and the start of the turn below [rad], and the ramp's constant rates [rad/s].
RAMP_Q0 = np.radians([4.0, 1.0, -2.0])
RAMP_QD0 = np.array([0.1, -0.05, 0.02])


def ramp(t: Any) -> Trajectory:
    """A still pose at RAMP_Q0 (its rates RAMP_QD0 given, not integrated) whose load rises: F_e = 1000 + 500·t N."""
    t = np.asarray(t, dtype=float)
    n = t.size
    q = np.tile(RAMP_Q0, (n, 1))
    return Trajectory(t, q, np.tile(RAMP_QD0, (n, 1)), np.zeros((n, 3)), 1000.0 + 500.0 * t, name="ramp")


def turn(t: Any) -> Trajectory:
    """A slow turn from RAMP_Q0 at (0.2, −0.1, 0.05) rad/s under a load that rises: 1000 + 500·t N."""
    t = np.asarray(t, dtype=float)
    rate = np.array([0.2, -0.1, 0.05])
    q = RAMP_Q0 + t[:, None] * rate
    return Trajectory(t, q, np.tile(rate, (t.size, 1)), np.zeros((t.size, 3)), 1000.0 + 500.0 * t, name="turn")
