"""hipsim.wear.kinematics by hand: the elementary rotations, the sequence's order, Ω against finite differences of R,
the contact centre of a moving cup and of a moving head, the mount, and the set-up's refusals at their bounds."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from hipsim.exceptions import ArgumentError
from hipsim.motion.trajectories import Trajectory
from hipsim.wear.kinematics import CupSetup, body_velocity, elementary, relative_motion, sequence_rotation

C, S = math.cos(0.3), math.sin(0.3)


def test_elementary_rotations_by_hand():
    angle = np.array([0.3])
    assert_allclose(elementary(0, angle)[0], np.array([[1, 0, 0], [0, C, -S], [0, S, C]]), atol=1e-15)
    assert_allclose(elementary(1, angle)[0], np.array([[C, 0, S], [0, 1, 0], [-S, 0, C]]), atol=1e-15)
    assert_allclose(elementary(2, angle)[0], np.array([[C, -S, 0], [S, C, 0], [0, 0, 1]]), atol=1e-15)
    assert elementary(2, np.zeros(4)).shape == (4, 3, 3)


def test_the_sequence_is_the_matrix_product_left_to_right():
    """α = γ = 90°: ZYX sends x̂ to Rz·Rx·x̂ = ŷ; XYZ to Rx·Rz·x̂ = Rx·ŷ = ẑ; lower case is taken."""
    q = np.array([[math.pi / 2, 0.0, math.pi / 2]])
    x = np.array([1.0, 0.0, 0.0])
    assert_allclose(sequence_rotation(q, "ZYX")[0] @ x, [0, 1, 0], atol=1e-15)
    assert_allclose(sequence_rotation(q, "XYZ")[0] @ x, [0, 0, 1], atol=1e-15)
    assert_allclose(sequence_rotation(q)[0], sequence_rotation(q, "ZYX")[0])  # the machine's by default
    q = np.array([[0.1, 0.2, 0.3]])
    assert_allclose(
        sequence_rotation(q, "YZX")[0],
        elementary(1, q[:, 1])[0] @ elementary(2, q[:, 2])[0] @ elementary(0, q[:, 0])[0],
    )


@pytest.mark.parametrize("sequence", ["ZYX", "XYZ", "YXZ"])
def test_body_velocity_is_the_vee_of_r_transpose_r_dot(sequence):
    """Ω = vee(Rᵀ·Ṙ), Ṙ by central differences along q̇ (another route than the composed formula)."""
    rng = np.random.default_rng(7)
    q, qd = rng.uniform(-0.9, 0.9, (6, 3)), rng.uniform(-2.0, 2.0, (6, 3))
    h = 1e-6
    Rd = (sequence_rotation(q + h * qd, sequence) - sequence_rotation(q - h * qd, sequence)) / (2 * h)
    skew = np.swapaxes(sequence_rotation(q, sequence), 1, 2) @ Rd
    expected = np.stack([skew[:, 2, 1], skew[:, 0, 2], skew[:, 1, 0]], axis=1)
    assert_allclose(body_velocity(q, qd, sequence), expected, atol=1e-8)
    assert_allclose(body_velocity(q, qd), body_velocity(q, qd, "ZYX"))


def _one(q, qd, load=1000.0) -> Trajectory:
    q, qd = np.atleast_2d(q).astype(float), np.atleast_2d(qd).astype(float)
    return Trajectory(np.arange(len(q)) * 0.01, q, qd, np.zeros_like(q), np.full(len(q), load))


def test_a_moving_cup_sees_the_load_at_r_transpose_z():
    """Cup on the platform turned α = 90° about X: n = Rᵀ·ẑ = Rx(−90°)·ẑ = ŷ; Ω = (a, 0, 0) gives ṅ = −Ω × n = −a·ẑ."""
    motion = relative_motion(_one([math.pi / 2, 0, 0], [2.0, 0, 0], 700.0), CupSetup())
    assert_allclose(motion.n[0], [0, 1, 0], atol=1e-15)
    assert_allclose(motion.omega[0], [2, 0, 0], atol=1e-15)
    assert_allclose(motion.n_dot[0], [0, 0, -2], atol=1e-15)
    assert_allclose(motion.rotation[0], elementary(0, np.array([math.pi / 2]))[0], atol=1e-15)
    assert motion.load.tolist() == [700.0] and motion.t.tolist() == [0.0]


def test_a_moving_head_keeps_the_contact_at_the_mounts_z():
    """Head on the platform, cup mounted α = 90° about X in the base: n = Mᵀ·ẑ = ŷ, still; Ω = −Mᵀ·R·Ω_platform."""
    mount = (math.pi / 2, 0.0, 0.0)
    setup = CupSetup(moving="head", cup_mount_rad=mount)
    motion = relative_motion(_one([[0, 0, 0.4], [0, 0, 0.4]], [[0, 0, 3.0], [0, 0, 3.0]]), setup)
    assert_allclose(motion.n, [[0, 1, 0], [0, 1, 0]], atol=1e-15)
    assert_allclose(motion.n_dot, 0.0)
    # ω = R·Ω = 3·ẑ in the base (a turn about Z); in the cup frame −Mᵀ·ω = −3·Rx(−90°)·ẑ = −3·ŷ.
    assert_allclose(motion.omega[0], [0, -3, 0], atol=1e-14)
    M = elementary(0, np.array([math.pi / 2]))[0]
    assert_allclose(motion.rotation[0], elementary(2, np.array([0.4]))[0].T @ M, atol=1e-15)


def test_a_mounted_cup_turns_omega_and_n_into_its_frame():
    """Cup turned γ = 90° about Z in the platform, platform still at q = 0 turning about X: Ω_cup = Mᵀ·Ω = (0, −a, 0)."""
    setup = CupSetup(cup_mount_rad=(0.0, 0.0, math.pi / 2))
    motion = relative_motion(_one([0, 0, 0], [1.5, 0, 0]), setup)
    assert_allclose(motion.omega[0], [0, -1.5, 0], atol=1e-15)
    assert_allclose(motion.n[0], [0, 0, 1], atol=1e-15)
    assert_allclose(setup.mount, elementary(2, np.array([math.pi / 2]))[0], atol=1e-15)


def test_a_setup_by_hand_and_at_its_bounds():
    setup = CupSetup(32.0, "xyz", (0, 1, 2), "head")
    assert setup.radius_mm == 16.0 and setup.sequence == "XYZ" and setup.cup_mount_rad == (0.0, 1.0, 2.0)
    assert isinstance(setup.cup_mount_rad[0], float)
    assert CupSetup(100.0).head_diameter_mm == 100.0  # the largest taken
    with pytest.raises(ArgumentError, match=r"head diameter: .*at most 100 mm \(hip heads are 22 to 60 mm\)"):
        CupSetup(100.0001)
    for bad in (0.0, -1.0, math.nan, math.inf, True, "28"):
        with pytest.raises(ArgumentError, match="head diameter: .*a positive diameter in mm"):
            CupSetup(bad)  # type: ignore[arg-type]
    assert CupSetup(1e-3).radius_mm == 5e-4  # any positive diameter under the bound
    for sequence in ("ZYY", "ZY", "ZYXZ", "ABC"):
        with pytest.raises(ArgumentError, match="sequence: .*a permutation of X, Y and Z"):
            CupSetup(sequence=sequence)
    for mount in ((0.0, 0.0), (0.0, 0.0, math.inf), (math.nan, 0.0, 0.0)):
        with pytest.raises(ArgumentError, match="cup mount: .*three finite angles in rad"):
            CupSetup(cup_mount_rad=mount)  # type: ignore[arg-type]
    with pytest.raises(ArgumentError, match="moving: .*'cup' or 'head'"):
        CupSetup(moving="Cup")


def test_each_refusal_shows_the_value_given():
    with pytest.raises(ArgumentError, match=r"^head diameter: expected a positive diameter in mm, got -1\.0$"):
        CupSetup(-1.0)
    with pytest.raises(
        ArgumentError, match=r"^head diameter: expected at most 100 mm \(hip heads are 22 to 60 mm\), got 101\.0$"
    ):
        CupSetup(101.0)
    with pytest.raises(
        ArgumentError, match=r"^sequence: expected a permutation of X, Y and Z, e\.g\. ZYX or XYZ, got 'ZZX'$"
    ):
        CupSetup(sequence="ZZX")
    with pytest.raises(ArgumentError, match=r"^cup mount: expected three finite angles in rad, got \(0\.0, 0\.0\)$"):
        CupSetup(cup_mount_rad=(0.0, 0.0))  # type: ignore[arg-type]
    with pytest.raises(ArgumentError, match=r"^moving: expected 'cup' or 'head', got 'both'$"):
        CupSetup(moving="both")


def test_the_setups_sequence_is_the_one_used():
    """A file written in XYZ: R_rel and Ω are those of R = Rx·Ry·Rz, not the machine's ZYX."""
    q, qd = np.array([[0.3, -0.2, 0.5]]), np.array([[1.0, 2.0, -0.5]])
    motion = relative_motion(_one(q, qd), CupSetup(sequence="XYZ"))
    assert_allclose(motion.rotation, sequence_rotation(q, "XYZ"), atol=1e-15)
    assert_allclose(motion.omega, body_velocity(q, qd, "XYZ"), atol=1e-15)
    assert not np.allclose(motion.rotation, sequence_rotation(q, "ZYX"))
