"""The lead screw's transmission: a slider travels one lead p per motor turn, θ = 2π·L/p (spec §4.1).

Every conversion between the slider's side (travel L, speed L̇, force F) and
the motor's side (angle θ, speed θ̇, torque τ) goes through these functions,
NumPy arrays and compiled kernels alike (each is :func:`~hipsim.physics.vectors.jitable`).
They keep the order of the arithmetic each caller had, so that runs stay bit
for bit what they were: ``angle_from_travel(x, p)`` is ``2π·x/p`` and
``radians_per_travel(p) * x`` is ``(2π/p)·x``, which may differ in the last bit.
"""

from __future__ import annotations

import math

from .vectors import jitable

__all__ = ["TWO_PI", "angle_from_travel", "lead_from_ratio", "radians_per_travel", "travel_per_radian"]

#: One motor turn in [rad].
TWO_PI = 2.0 * math.pi


@jitable
def angle_from_travel(x, lead):
    """2π·x/p: a slider travel in [m] (speed [m/s], acceleration [m/s²]) as the motor's angle in [rad] ([rad/s], [rad/s²]).

    Args:
        x: travel, speed or acceleration of the slider (or a quantity per metre
            of travel, such as a rotor inertia to be reflected), any shape.
        lead: p, the screw's lead in [m] per turn.
    """
    return 2.0 * math.pi * x / lead


@jitable
def radians_per_travel(lead):
    """2π/p in [rad/m]: the screw's ratio, motor angle per slider travel; lead p in [m]."""
    return 2.0 * math.pi / lead


@jitable
def travel_per_radian(lead):
    """p/2π in [m/rad]: slider travel per motor angle, the factor from a slider force in [N] to a motor torque in [N·m]; lead p in [m]."""
    return lead / (2.0 * math.pi)


def lead_from_ratio(ratio: float) -> float:
    """The lead p = 2π/k in [m] of a screw whose ratio k is in [rad/m] (a MuJoCo actuator's gear)."""
    return 2.0 * math.pi / ratio
