"""The cup's motion relative to the head: its body angular velocity Ω and the contact centre n, per sample.

The cup is fixed to the platform and the head to the base (``moving="cup"``):
the cup's orientation in the head frame is R_rel = R·M, with R the platform's
orientation (the machine's R = Rz(γ)·Ry(β)·Rx(α), or another Euler sequence
for a file written in one) and M the cup's mount in the platform. With the
head on the platform instead (``moving="head"``) the cup sits in the base and
R_rel = Rᵀ·M. The load presses along the base's +Z, so the contact centre in
the cup frame is n = R_cupᵀ·ẑ with R_cup the cup's orientation in the base:
R·M when the cup moves, M (a fixed point of the cup) when the head moves.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..exceptions import ArgumentError
from ..motion.trajectories import Trajectory

__all__ = ["CupSetup", "RelativeMotion", "elementary", "relative_motion", "sequence_rotation"]

#: The machine's Euler sequence: R = Rz(γ)·Ry(β)·Rx(α), read left to right as the matrix product.
MACHINE_SEQUENCE = "ZYX"
#: Largest head diameter in [mm] taken as meant (hip heads are 22 to 60 mm).
MAX_HEAD_DIAMETER_MM = 100.0
_AXIS = {"X": 0, "Y": 1, "Z": 2}


@dataclass(frozen=True)
class CupSetup:
    """How the cup and head sit in the machine.

    Attributes:
        head_diameter_mm: the head's diameter in [mm], in (0, 100].
        sequence: the Euler sequence of the angles, the letters of the matrix product left to right
            ("ZYX": R = Rz(γ)·Ry(β)·Rx(α), the machine's; "XYZ": R = Rx(α)·Ry(β)·Rz(γ)); α is always about X,
            β about Y, γ about Z.
        cup_mount_rad: the cup's mount in the platform [α, β, γ] in [rad], composed in the machine's sequence.
        moving: "cup" (the cup on the platform, the head on the base) or "head" (swapped).
    """

    head_diameter_mm: float = 28.0
    sequence: str = MACHINE_SEQUENCE
    cup_mount_rad: tuple[float, float, float] = (0.0, 0.0, 0.0)
    moving: str = "cup"

    def __post_init__(self):
        d = self.head_diameter_mm
        if isinstance(d, bool) or not isinstance(d, (int, float)) or not math.isfinite(d) or d <= 0:
            raise ArgumentError("head diameter", d, "a positive diameter in mm")
        if d > MAX_HEAD_DIAMETER_MM:
            raise ArgumentError("head diameter", d, f"at most {MAX_HEAD_DIAMETER_MM:g} mm (hip heads are 22 to 60 mm)")
        sequence = str(self.sequence).upper()
        if sorted(sequence) != ["X", "Y", "Z"]:
            raise ArgumentError("sequence", self.sequence, "a permutation of X, Y and Z, e.g. ZYX or XYZ")
        object.__setattr__(self, "sequence", sequence)
        mount = tuple(float(a) for a in self.cup_mount_rad)
        if len(mount) != 3 or not all(math.isfinite(a) for a in mount):
            raise ArgumentError("cup mount", self.cup_mount_rad, "three finite angles in rad")
        object.__setattr__(self, "cup_mount_rad", mount)
        if self.moving not in ("cup", "head"):
            raise ArgumentError("moving", self.moving, "'cup' or 'head'")

    @property
    def radius_mm(self) -> float:
        """The head's radius r in [mm]."""
        return self.head_diameter_mm / 2.0

    @property
    def mount(self) -> np.ndarray:
        """M, the cup's orientation in the platform, (3, 3)."""
        return sequence_rotation(np.array([self.cup_mount_rad]), MACHINE_SEQUENCE)[0]


@dataclass(frozen=True, eq=False)
class RelativeMotion:
    """The cup against the head over some samples (module docstring).

    Attributes:
        t: times in [s], (N,).
        omega: Ω, the cup's body angular velocity relative to the head, in the cup frame, in [rad/s], (N, 3).
        n: the contact centre, a unit vector in the cup frame, (N, 3).
        load: the load F in [N], (N,).
        n_dot: ṅ in [1/s], (N, 3): −Ω × n when the cup moves, 0 when the head does (n is then a fixed point of the cup).
        rotation: R_rel, the cup's orientation in the head frame, (N, 3, 3).
    """

    t: np.ndarray
    omega: np.ndarray
    n: np.ndarray
    load: np.ndarray
    n_dot: np.ndarray
    rotation: np.ndarray


def elementary(axis: int, angle: np.ndarray) -> np.ndarray:
    """The rotation by ``angle`` [rad], (N,), about coordinate axis ``axis`` (0, 1, 2 for X, Y, Z), (N, 3, 3)."""
    c, s = np.cos(angle), np.sin(angle)
    out = np.zeros((angle.size, 3, 3))
    i, j = (axis + 1) % 3, (axis + 2) % 3
    out[:, axis, axis] = 1.0
    out[:, i, i], out[:, i, j], out[:, j, i], out[:, j, j] = c, -s, s, c
    return out


def sequence_rotation(q: np.ndarray, sequence: str = MACHINE_SEQUENCE) -> np.ndarray:
    """R of angles q = [α, β, γ] in [rad], (N, 3), composed in ``sequence`` (:class:`CupSetup`), (N, 3, 3)."""
    parts = [elementary(_AXIS[letter], q[:, _AXIS[letter]]) for letter in sequence]
    return parts[0] @ parts[1] @ parts[2]


def body_velocity(q: np.ndarray, qd: np.ndarray, sequence: str = MACHINE_SEQUENCE) -> np.ndarray:
    """Ω = vee(Rᵀ·Ṙ) in [rad/s], (N, 3), of R = A(a)·B(b)·C(c): Ω = Cᵀ·Bᵀ·e_A·ȧ + Cᵀ·e_B·ḃ + e_C·ċ."""
    axes = [_AXIS[letter] for letter in sequence]
    rates = [qd[:, a] for a in axes]
    later = [elementary(a, q[:, a]) for a in axes]
    units = np.eye(3)
    omega = units[axes[2]] * rates[2][:, None]
    omega = omega + np.einsum("nji,j->ni", later[2], units[axes[1]]) * rates[1][:, None]
    first = np.einsum("nji,nj->ni", later[1], np.broadcast_to(units[axes[0]], qd.shape))
    omega = omega + np.einsum("nji,nj->ni", later[2], first) * rates[0][:, None]
    return omega


def relative_motion(trajectory: Trajectory, setup: CupSetup) -> RelativeMotion:
    """The cup against the head over a trajectory's samples (module docstring)."""
    R = sequence_rotation(trajectory.q, setup.sequence)
    omega_body = body_velocity(trajectory.q, trajectory.qd, setup.sequence)
    M = setup.mount
    z = np.array([0.0, 0.0, 1.0])
    if setup.moving == "cup":
        rotation = R @ M
        omega = omega_body @ M  # Mᵀ·Ω, row by row
        n = np.einsum("nji,j->ni", rotation, z)
        n_dot = -np.cross(omega, n)
    else:
        rotation = np.swapaxes(R, 1, 2) @ M
        omega = -np.einsum("nij,nj->ni", R, omega_body) @ M  # −Mᵀ·ω, ω = R·Ω the platform's in the base
        n = np.broadcast_to(M.T @ z, omega.shape).copy()
        n_dot = np.zeros_like(n)
    return RelativeMotion(trajectory.t, omega, n, trajectory.Fe, n_dot, rotation)
