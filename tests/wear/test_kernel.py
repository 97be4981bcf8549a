"""hipsim.wear.kernel by hand on two cup points and two samples, and the exact direction search against a brute-force
maximum of its work curve.

The two points: the pole w = ẑ (t1 = x̂, t2 = ŷ) and the rim point w = x̂ (t1 = ŷ, t2 = ẑ). The samples: Ω = (0, 2, 0)
about Y with the contact at the pole (n = ẑ, F·dt = 4), then Ω = (3, 0, 4) with the contact tilted to
n = (0.6, 0, 0.8) (F·dt = 2), dt = 0.5 each, c = coef·F·dt·(w·n), coef = 0.1. At the pole u = (0, 2) then (3, 0), both
loaded (c = 0.4, then 0.16); at the rim u = (2, 0) with w·n = 0 (on the edge of contact: not loaded), then (0, 4)
loaded (c = 0.12). The work along the angle θ at the pole is A·|cos θ| + B·|sin θ| with A = 0.16·3 = 0.48 and
B = 0.4·2 = 0.8: largest √(A² + B²) at θ = atan2(B, A), across it 2AB/√(A² + B²).

Every call takes the argument types hipsim.wear.maps passes (recorded from its runs), so the specialisations compiled
for the maps are the ones these tests run.
"""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest
from support import argument_types, recorded_calls

import hipsim.wear.maps as maps_module
from hipsim.motion.trajectories import Trajectory
from hipsim.wear import kernel
from hipsim.wear.kinematics import CupSetup
from hipsim.wear.maps import wear_maps
from hipsim.wear.points import cup_points

S2 = math.sqrt(0.5)
T1 = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
T2 = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
W = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
OMEGA = np.array([[0.0, 2.0, 0.0], [3.0, 0.0, 4.0]])
N = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8]])
LOAD_DT, DT, COEF = np.array([4.0, 2.0]), np.array([0.5, 0.5]), 0.1
A, B = 0.48, 0.8  # the pole's work along t1 and along t2


def _names(function) -> list[str]:
    return list(inspect.signature(getattr(function, "py_func", function)).parameters)


@pytest.fixture(scope="module")
def production() -> dict[str, tuple]:
    """The numba types of the arguments wear_maps passes each kernel: three cup points under eight samples, held (the
    exact search) and re-read (the L1 iteration)."""
    qd = np.zeros((8, 3))
    qd[:2, 1], qd[2:, 0] = 2.0, 2.0
    zeros = np.zeros((8, 3))
    motion = Trajectory(np.arange(8) / 8, zeros, qd, zeros, np.full(8, 1000.0), name="hand")
    points = cup_points(np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [S2, 0.0, S2]]))
    calls: dict[str, list[tuple[tuple, tuple]]] = {}
    with pytest.MonkeyPatch.context() as patch:
        for name in ("first_pass", "exact_direction", "direction_pass"):
            calls[name] = recorded_calls(patch, maps_module, name)
        wear_maps(motion, 1.0, CupSetup(28.0), points)
        patch.setattr(maps_module, "KEEP_SAMPLES", 0)
        wear_maps(motion, 1.0, CupSetup(28.0), points)
    return {name: made[0][1] for name, made in calls.items()}


#: The hand-worked case's arguments every kernel takes: two points, their tangents, the samples and the wear factor.
HAND = dict(t1=T1, t2=T2, w=W, omega=OMEGA, n=N, load_dt=LOAD_DT, coef=COEF)


def _call(production: dict[str, tuple], name: str, **arguments) -> None:
    """The kernel ``name`` on these arguments, checked to be of the types wear_maps gave it."""
    function = getattr(kernel, name)
    args = tuple(arguments[key] for key in _names(function))
    assert argument_types(args) == production[name]
    function(*args)


def _sums(P: int = 2, fill: float = 0.0) -> dict[str, np.ndarray]:
    return dict(
        s=np.full(P, fill),
        s_loaded=np.full(P, fill),
        work=np.full(P, fill),
        tensor=np.full((P, 3), fill),
        coarse=np.full((P, 4), fill),
    )


def test_first_pass_sums_sliding_work_tensor_and_fixed_directions_by_hand(production):
    sums = _sums()
    _call(
        production,
        "first_pass",
        **HAND,
        dt=DT,
        rough=True,
        **sums,
    )
    np.testing.assert_allclose(sums["s"], [(2 + 3) * 0.5, (2 + 4) * 0.5], rtol=1e-15)
    np.testing.assert_allclose(sums["s_loaded"], [(2 + 3) * 0.5, 4 * 0.5], rtol=1e-15)  # the rim's first: w·n = 0
    np.testing.assert_allclose(sums["work"], [0.4 * 2 + 0.16 * 3, 0.12 * 4], rtol=1e-15)
    # Σ c·u·uᵀ/|u|: (0.4/2)·(0, 2)(0, 2)ᵀ + (0.16/3)·(3, 0)(3, 0)ᵀ at the pole; (0.12/4)·(0, 4)(0, 4)ᵀ at the rim.
    np.testing.assert_allclose(sums["tensor"], [[0.48, 0.0, 0.8], [0.0, 0.0, 0.48]], rtol=1e-15, atol=1e-17)
    # Σ c·|u·m| along 0°, 45°, 90°, 135° from t1.
    pole = [A, (A + B) * S2, B, (A + B) * S2]
    np.testing.assert_allclose(sums["coarse"], [pole, [0.0, 0.48 * S2, 0.48, 0.48 * S2]], rtol=1e-15, atol=1e-17)


def test_first_pass_adds_to_the_sums_and_skips_the_rough_ones_on_request(production):
    """A second piece adds (sums filled with 1 first); without ``rough`` the tensor and the directions are left."""
    sums = _sums(fill=1.0)
    _call(
        production,
        "first_pass",
        **HAND,
        dt=DT,
        rough=False,
        **sums,
    )
    np.testing.assert_allclose(sums["s"], [1.0 + 2.5, 1.0 + 3.0], rtol=1e-15)
    np.testing.assert_allclose(sums["work"], [1.0 + A + B, 1.0 + 0.48], rtol=1e-15)
    assert (sums["tensor"] == 1.0).all() and (sums["coarse"] == 1.0).all()


def test_direction_pass_sums_along_across_and_the_pull_by_hand(production):
    """At the pole along m = (−1, 1)/√2: u = (0, 2) has u·m > 0 and pulls +c·u, u = (3, 0) has u·m < 0 and pulls −c·u;
    the work along and across m are both (A + B)/√2. The rim inactive: left as it was."""
    m = np.array([[-S2, S2], [1.0, 0.0]])
    pull, along, across = np.full((2, 2), 7.0), np.full(2, 7.0), np.full(2, 7.0)
    pull[0], along[0], across[0] = 0.0, 0.0, 0.0
    _call(
        production,
        "direction_pass",
        **HAND,
        active=np.array([True, False]),
        m=m,
        pull=pull,
        along=along,
        across=across,
    )
    np.testing.assert_allclose(pull, [[-0.48, 0.8], [7.0, 7.0]], rtol=1e-15)
    np.testing.assert_allclose(along, [(A + B) * S2, 7.0], rtol=1e-15)
    np.testing.assert_allclose(across, [(A + B) * S2, 7.0], rtol=1e-15)
    # Along t1: u = (0, 2) neither pulls nor works along it, all its work is across.
    pull, along, across = np.zeros((2, 2)), np.zeros(2), np.zeros(2)
    _call(
        production,
        "direction_pass",
        **HAND,
        active=np.array([True, True]),
        m=np.array([[1.0, 0.0], [1.0, 0.0]]),
        pull=pull,
        along=along,
        across=across,
    )
    np.testing.assert_allclose(pull, [[A, 0.0], [0.0, 0.0]], rtol=1e-15, atol=1e-17)
    np.testing.assert_allclose(along, [A, 0.0], rtol=1e-15, atol=1e-17)
    np.testing.assert_allclose(across, [B, 0.48], rtol=1e-15)


def test_exact_direction_at_two_points_by_hand(production):
    """The pole: θ = atan2(B, A), W∥ = √(A² + B²), W⊥ = 2AB/√(A² + B²), so CS = 2AB/(A + B)². The rim: one loaded
    sample along t2, θ = π/2, all its work along it, none across."""
    theta, along, across = np.zeros(2), np.zeros(2), np.zeros(2)
    _call(
        production,
        "exact_direction",
        **HAND,
        active=np.array([True, True]),
        theta=theta,
        along=along,
        across=across,
    )
    np.testing.assert_allclose(theta, [math.atan2(B, A), math.pi / 2], rtol=1e-15)
    np.testing.assert_allclose(along, [math.hypot(A, B), 0.48], rtol=1e-15)
    np.testing.assert_allclose(across, [2 * A * B / math.hypot(A, B), 0.0], rtol=1e-15, atol=1e-17)
    assert across[0] / (along[0] + across[0]) == pytest.approx(2 * A * B / (A + B) ** 2, rel=1e-15)


def test_exact_direction_is_the_maximum_of_the_work_curve(production):
    """Seven loaded samples at the pole whose directions φ come in runs up and down (the kinks' sort merges them),
    against f(θ) = Σ c·|u·(cos θ, sin θ)| on a grid of 2·10⁵ angles refined by a parabola; a point inactive and a
    point never loaded alongside."""
    phi = np.radians([10.0, 100.0, 50.0, 160.0, 120.0, 30.0, 75.0])
    speed = np.array([1.0, 2.0, 0.5, 1.5, 1.2, 0.8, 0.3])
    omega = np.zeros((phi.size, 3))
    omega[:, 0], omega[:, 1] = speed * np.cos(phi), speed * np.sin(phi)  # u = (Ω·x̂, Ω·ŷ) at the pole
    normal = np.tile([0.0, 0.0, 1.0], (phi.size, 1))
    load_dt = np.linspace(1.0, 2.0, phi.size)
    points = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]])  # the pole twice, then its opposite
    t1, t2 = np.tile([1.0, 0.0, 0.0], (3, 1)), np.array([[0.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0]])
    theta, along, across = np.full(3, 5.0), np.full(3, 5.0), np.full(3, 5.0)
    _call(
        production,
        "exact_direction",
        t1=t1,
        t2=t2,
        w=points,
        omega=omega,
        n=normal,
        load_dt=load_dt,
        coef=COEF,
        active=np.array([True, False, True]),
        theta=theta,
        along=along,
        across=across,
    )
    c = COEF * load_dt
    u = np.stack([omega[:, 0], omega[:, 1]], axis=1)

    def work(angles):
        return np.abs(u @ np.stack([np.cos(angles), np.sin(angles)])).T @ c

    grid = np.linspace(0.0, math.pi, 200_001)
    values = work(grid)
    i = int(np.argmax(values))
    f0, f1, f2 = values[i - 1], values[i], values[i + 1]
    best = grid[i] + (grid[1] - grid[0]) * 0.5 * (f0 - f2) / (f0 - 2 * f1 + f2)
    assert 0 < i < grid.size - 1
    assert theta[0] == pytest.approx(best, abs=1e-6)
    assert along[0] == pytest.approx(float(work(np.array([best]))[0]), rel=1e-10)
    assert along[0] >= values.max() * (1 - 1e-15)  # no grid angle does better
    assert across[0] == pytest.approx(float(work(np.array([theta[0] + math.pi / 2]))[0]), rel=1e-12)
    assert (theta[1], along[1], across[1]) == (5.0, 5.0, 5.0)  # inactive: left as it was
    assert (theta[2], along[2], across[2]) == (0.0, 0.0, 0.0)  # the pole's opposite never touches the head
