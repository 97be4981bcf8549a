"""The laws of hipsim.physics.laws against hand formulas, finite differences and SciPy, on both routes.

Each law is checked where it is defined, independently of the models that
use it: rotation maps against SciPy's rotations and finite differences of
the spec's T(q), the lever's spin against the universal joint's constraint
solved another way, friction against the spec's formulas written out here
with numbers. Then each law evaluated by NumPy on arrays must equal the same
law compiled by numba on one sample (the two routes of one source), and the
compiled callers' cache must follow an edit of a law.
"""

from __future__ import annotations

import dataclasses
import subprocess
import sys
import textwrap
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from support import ALL_FRICTION

import hipsim
from hipsim.physics import laws, vectors

RNG = np.random.default_rng(11)


def hand_T(q):
    """T(q) of spec §2, written out: ω = T·q̇."""
    _, b, g = q
    cb, sb, cg, sg = np.cos(b), np.sin(b), np.cos(g), np.sin(g)
    return np.array([[cb * cg, -sg, 0.0], [cb * sg, cg, 0.0], [-sb, 0.0, 1.0]])


def trig(q):
    """The cosines and sines the rotation laws take, components-first."""
    return np.cos(q), np.sin(q)


def skew_vector(S):
    """v from a skew-symmetric [v]×."""
    return np.array([S[2, 1] - S[1, 2], S[0, 2] - S[2, 0], S[1, 0] - S[0, 1]]) / 2.0


def random_unit(n=None):
    v = RNG.normal(size=(3,) if n is None else (3, n))
    return v / np.linalg.norm(v, axis=0)


# --- rotation maps --------------------------------------------------------------------------


def test_rotation_is_scipys_intrinsic_zyx():
    q = RNG.uniform(-1.5, 1.5, (3, 50))
    R = np.moveaxis(np.array(laws.rotation(*trig(q))), -1, 0)  # (N, 3, 3)
    expected = Rotation.from_euler("ZYX", q[::-1].T).as_matrix()  # Rz(γ)·Ry(β)·Rx(α)
    np.testing.assert_allclose(R, expected, rtol=0, atol=1e-15)


def test_t_times_is_the_angular_velocity_of_R():
    """[ω]× = Ṙ·Rᵀ, Ṙ by central differences of SciPy's R along q(t) = q₀ + t·q̇."""
    h = 1e-6
    for _ in range(20):
        q, qd = RNG.uniform(-1.2, 1.2, 3), RNG.normal(size=3)

        def R(t):
            return Rotation.from_euler("ZYX", (q + t * qd)[::-1]).as_matrix()

        omega = skew_vector((R(h) - R(-h)) / (2 * h) @ R(0).T)
        np.testing.assert_allclose(laws.t_times(*trig(q), qd), omega, rtol=0, atol=1e-9 * np.abs(qd).max())
        np.testing.assert_allclose(laws.t_times(*trig(q), qd), hand_T(q) @ qd, rtol=0, atol=1e-15)


def test_t_transpose_times_is_the_transpose():
    for _ in range(20):
        q, m = RNG.uniform(-1.2, 1.2, 3), RNG.normal(size=3)
        np.testing.assert_allclose(laws.t_transpose_times(*trig(q), m), hand_T(q).T @ m, rtol=0, atol=1e-15)


def test_t_dot_times_is_the_rate_of_T():
    h = 1e-6
    for _ in range(20):
        q, qd, v = RNG.uniform(-1.2, 1.2, 3), RNG.normal(size=3), RNG.normal(size=3)
        T_dot = (hand_T(q + h * qd) - hand_T(q - h * qd)) / (2 * h)
        np.testing.assert_allclose(laws.t_dot_times(*trig(q), qd, v), T_dot @ v, rtol=0, atol=1e-9)


def test_inverse_transpose():
    J = RNG.normal(size=(30, 3, 3))
    rows = laws.inverse_transpose(np.moveaxis(J, 0, -1))  # J's rows, components-first (xyz, N)
    inverse_T = np.moveaxis(np.array(rows), -1, 0)  # (N, row, xyz)
    np.testing.assert_allclose(inverse_T, np.linalg.inv(J).transpose(0, 2, 1), rtol=1e-11, atol=1e-12)


# --- the lever's frame and spin ------------------------------------------------------------


def test_lever_axes_are_the_spec_frame():
    u1, e = np.array([-np.sin(0.3), np.cos(0.3), 0.0]), random_unit()
    x, y, z = (np.array(axis) for axis in laws.lever_axes(u1, e))
    frame = np.column_stack([x, y, z])
    np.testing.assert_allclose(frame.T @ frame, np.eye(3), atol=1e-15)
    assert np.linalg.det(frame) == pytest.approx(1.0, abs=1e-15)
    np.testing.assert_array_equal(z, e)
    np.testing.assert_allclose(x, np.cross(e, u1) / np.linalg.norm(np.cross(e, u1)), atol=1e-15)


def spin_case():
    """A universal joint axis u1 (horizontal), a lever direction e and a spin-free ω_⊥ ⊥ e."""
    u1 = np.array([-np.sin(1.1), np.cos(1.1), 0.0])
    e = np.array([0.3, -0.4, 0.8]) / np.linalg.norm([0.3, -0.4, 0.8])
    w = RNG.normal(size=3)
    return u1, e, w - (w @ e) * e


def test_lever_spin_obeys_the_universal_joint():
    """ω_l = ω_⊥ + s·e with no component along u1 × u2, solved here as that one linear equation."""
    for _ in range(10):
        u1, e, w_perp = spin_case()
        u2 = np.cross(e, u1) / np.linalg.norm(np.cross(e, u1))
        normal = np.cross(u1, u2)
        s = -(w_perp @ normal) / (e @ normal)
        np.testing.assert_allclose(laws.lever_angular_velocity(u1, e, w_perp), w_perp + s * e, rtol=0, atol=1e-14)


def test_lever_spin_rate_is_the_derivative_of_the_spin():
    """Along a lever direction e(t): ω_⊥ = e × ė, and ω̇_l is the central difference of ω_l."""
    u1 = np.array([-np.sin(1.1), np.cos(1.1), 0.0])
    e0 = np.array([0.3, -0.4, 0.8]) / np.linalg.norm([0.3, -0.4, 0.8])
    a, b = RNG.normal(size=3), RNG.normal(size=3)
    h = 1e-4

    def e_at(t):
        return Rotation.from_rotvec(a * t + b * t**2).apply(e0)

    def state(t):
        """e and the lever's angular velocity without spin, ω_⊥ = e × ė."""
        e = e_at(t)
        return e, np.cross(e, (e_at(t + h) - e_at(t - h)) / (2 * h))

    for t in (0.1, 0.4, 0.7):
        e, w_perp = state(t)
        w_perp_dot = (state(t + h)[1] - state(t - h)[1]) / (2 * h)
        spin = [np.array(laws.lever_angular_velocity(u1, *state(t + k * h))) for k in (-1, 1)]
        expected = (spin[1] - spin[0]) / (2 * h)
        actual = laws.lever_angular_acceleration(u1, e, w_perp, w_perp_dot)
        np.testing.assert_allclose(actual, expected, rtol=0, atol=1e-6 * np.abs(expected).max())


def test_spin_transpose_is_the_adjoint_of_the_spin():
    for _ in range(10):
        u1, e, w_perp = spin_case()
        m = RNG.normal(size=3)
        assert m @ np.array(laws.lever_angular_velocity(u1, e, w_perp)) == pytest.approx(
            np.array(laws.spin_transpose(u1, e, m)) @ w_perp, rel=1e-13
        )


# --- friction ------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def published():
    return hipsim.load_parameters()


def test_smooth_sign_by_hand():
    # 3-4-5: ŝ(3 mrad/s) with ε = 4 mrad/s is 3/5.
    assert laws.smooth_sign(3e-3, 4e-3) == pytest.approx(0.6, rel=1e-15)
    np.testing.assert_allclose(laws.smooth_sign(np.array([-5.0, 0.0, 5.0]), 1e-3), [-1, 0, 1], atol=1e-7)
    np.testing.assert_allclose(laws.smooth_sign_vector((3e-3, 0.0, 0.0), 4e-3), (0.6, 0.0, 0.0), rtol=1e-15)
    assert np.linalg.norm(laws.smooth_sign_vector((3.0, 4.0, 0.0), 1e-3)) == pytest.approx(1.0, abs=1e-7)


def test_screw_and_guide_friction_by_hand(published):
    F = published.replace(screw_coulomb=0.05, screw_viscous=2e-4, guide_coulomb=15.0, guide_viscous=40.0).friction
    speed = 3e-3  # [rad/s]: with ε = 1e-3, ŝ = 3/√10
    sign = 3.0 / np.sqrt(10.0)
    assert laws.screw_friction(F, speed) == pytest.approx(0.05 * sign + 2e-4 * 3e-3, rel=1e-14)
    Ld = speed * 0.010 / (2 * np.pi)  # the slider speed at that motor speed, p = 10 mm
    assert laws.guide_friction(F, Ld, speed) == pytest.approx(15.0 * sign + 40.0 * Ld, rel=1e-14)


def test_central_friction_by_hand(published):
    """Spec §4.3 with the published figures: r_h μ_h F_e + r_t μ_t (F_e + m_m g) along ω."""
    omega = np.array([0.0, 0.6, 0.8])  # |ω| = 1 rad/s ≫ ε
    Fe, weight = 1500.0, 20.0 * 9.8
    magnitude = 0.015 * 0.095 * 1500.0 + 0.064 * 0.025 * 1696.0  # 2.1375 + 2.7136 N·m
    moment = laws.central_friction_moment(published.friction, omega, (0.0, 0.0, 1.0), Fe, weight)
    np.testing.assert_allclose(moment, magnitude * omega, rtol=1e-6)  # ŝ(ω) = ω/√(1 + 1e-6)
    # The load's sign does not matter (|F_e|), nor does the thrust bearing's if the load lifts the platform.
    np.testing.assert_allclose(
        laws.central_friction_moment(published.friction, omega, (0, 0, 1), -Fe, weight),
        (0.015 * 0.095 * 1500.0 + 0.064 * 0.025 * 1304.0) * omega,
        rtol=1e-6,
    )


def test_axial_only_thrust_bearing_by_hand(published):
    """friction.thrust_bearing_axial_only: the bearing resists only rotation about the platform's z axis."""
    F = published.replace(thrust_bearing_axial_only=True).friction
    Fe, weight = 1500.0, 20.0 * 9.8
    hip, thrust = 0.015 * 0.095 * 1500.0, 0.064 * 0.025 * 1696.0  # 2.1375 and 2.7136 N·m
    z = np.array([0.0, 0.6, 0.8])  # a tilted platform
    across = np.array([1.0, 0.0, 0.0])  # ω ⊥ z: the bearing does not turn, only the hip joint rubs
    np.testing.assert_allclose(laws.central_friction_moment(F, across, z, Fe, weight), hip * across, rtol=1e-6)
    along = 2.0 * z  # ω ∥ z: the publication's moment
    np.testing.assert_allclose(laws.central_friction_moment(F, along, z, Fe, weight), (hip + thrust) * z, rtol=1e-6)
    np.testing.assert_allclose(
        laws.central_friction_moment(published.friction, along, z, Fe, weight), (hip + thrust) * z, rtol=1e-6
    )
    omega = np.array([1.0, 2.0, 0.5])  # ω·z = 1.6 rad/s
    expected = hip * omega / np.linalg.norm(omega) + thrust * z
    np.testing.assert_allclose(laws.central_friction_moment(F, omega, z, Fe, weight), expected, rtol=1e-6)


def test_lever_joint_friction_by_hand(published):
    F = published.replace(**ALL_FRICTION).friction
    omega_l, omega = np.array([0.0, 2.0, 0.0]), np.array([0.0, 0.0, 1.0])
    tau_bf, tau_af = laws.lever_joint_friction(F, omega_l, omega)
    c, v = ALL_FRICTION["ujoint_coulomb"], ALL_FRICTION["ujoint_viscous"]
    np.testing.assert_allclose(tau_bf, (c / np.sqrt(4 + 1e-6) + v) * omega_l, rtol=1e-15)
    relative = omega_l - omega  # |.| = √5
    c, v = ALL_FRICTION["sjoint_coulomb"], ALL_FRICTION["sjoint_viscous"]
    np.testing.assert_allclose(tau_af, (c / np.sqrt(5 + 1e-6) + v) * relative, rtol=1e-15)


def test_lever_joint_friction_on(published):
    assert not laws.lever_joint_friction_on(published.friction)
    for name in ("ujoint_coulomb", "ujoint_viscous", "sjoint_coulomb", "sjoint_viscous"):
        assert laws.lever_joint_friction_on(published.replace(**{name: 1e-6}).friction), name
    assert not laws.lever_joint_friction_on(published.replace(guide_coulomb=1.0, screw_viscous=1.0).friction)


def test_friction_only_dissipates(published):
    F = published.replace(**ALL_FRICTION).friction
    omega, omega_l = RNG.normal(size=(3, 500)), RNG.normal(size=(3, 500))
    z, Fe = random_unit(500), RNG.uniform(-3000, 3000, 500)
    assert np.all(vectors.dot(laws.central_friction_moment(F, omega, z, Fe, 196.0), omega) >= 0)
    axial = published.replace(thrust_bearing_axial_only=True).friction
    assert np.all(vectors.dot(laws.central_friction_moment(axial, omega, z, Fe, 196.0), omega) >= 0)
    tau_bf, tau_af = laws.lever_joint_friction(F, omega_l, omega)
    assert np.all(vectors.dot(tau_bf, omega_l) >= 0) and np.all(vectors.dot(tau_af, omega_l - omega) >= 0)
    speed = RNG.normal(size=500)
    assert np.all(laws.screw_friction(F, speed) * speed >= 0)
    assert np.all(laws.guide_friction(F, speed * 1e-3, speed) * speed >= 0)


def test_friction_record_has_every_coefficient(published):
    F = published.replace(**ALL_FRICTION).friction
    record = laws.friction_record(F)
    assert record._fields == tuple(field.name for field in dataclasses.fields(F))
    for name in record._fields:
        assert getattr(record, name) == getattr(F, name), name
        assert type(getattr(record, name)) in (float, bool), name


# --- one source, two routes ----------------------------------------------------------------


@pytest.fixture(scope="module")
def compiled_laws():
    """Every law compiled by numba for one sample of floats and 3-tuples."""
    from numba import njit

    vectors.register_jitables()

    @njit(cache=False, error_model="numpy")
    def evaluate(F, c, s, qd, v, J, u1, e, w_perp, w_perp_dot, m, omega_l, z, Fe, weight, Ld, speed):
        return (
            laws.rotation(c, s),
            laws.t_times(c, s, v),
            laws.t_transpose_times(c, s, m),
            laws.t_dot_times(c, s, qd, v),
            laws.inverse_transpose(J),
            laws.lever_axes(u1, e),
            laws.lever_angular_velocity(u1, e, w_perp),
            laws.lever_angular_acceleration(u1, e, w_perp, w_perp_dot),
            laws.spin_transpose(u1, e, m),
            laws.smooth_sign(speed, F.epsilon),
            laws.smooth_sign_vector(v, F.epsilon),
            laws.screw_friction(F, speed),
            laws.guide_friction(F, Ld, speed),
            laws.central_friction_moment(F, v, z, Fe, weight),
            laws.lever_joint_friction(F, omega_l, v),
            laws.lever_joint_friction_on(F),
        )

    return evaluate


@pytest.mark.parametrize("axial", [False, True], ids=["publication", "axial bearing"])
def test_numpy_and_compiled_evaluations_agree(published, compiled_laws, axial):
    """The same source on arrays (NumPy, all samples at once) and compiled on one sample's floats."""
    params = published.replace(**ALL_FRICTION, thrust_bearing_axial_only=axial)
    n = 25
    q = RNG.uniform(-1.0, 1.0, (3, n))
    c, s = trig(q)
    qd, v, m, w_perp_dot, omega_l = (RNG.normal(size=(3, n)) for _ in range(5))
    J = RNG.normal(size=(3, 3, n))
    u1 = np.array([-np.sin(0.4), np.cos(0.4), 0.0])[:, None]
    e, z = random_unit(n), random_unit(n)
    w_perp = np.cross(e, RNG.normal(size=(3, n)), axis=0)
    Fe, Ld, speed = RNG.uniform(-3000, 3000, n), RNG.normal(size=n), RNG.normal(size=n)
    args = (c, s, qd, v, J, u1, e, w_perp, w_perp_dot, m, omega_l, z, Fe, 196.0, Ld, speed)

    on_arrays = flatten(compiled_laws.py_func(params.friction, *args))
    record = laws.friction_record(params.friction)
    for k in range(n):
        one = flatten(compiled_laws(record, *(sample(a, k) for a in args)))
        assert len(one) == len(on_arrays)
        for leaf, (a, b) in enumerate(zip(on_arrays, one)):
            expected = a[k] if np.ndim(a) else a
            assert b == pytest.approx(expected, rel=1e-13, abs=1e-13), (leaf, k)


def sample(x, k):
    """Sample k of a components-first argument, as floats and tuples (constants per leg are kept)."""
    if not isinstance(x, np.ndarray):
        return x
    return as_tuples(x[..., k if x.shape[-1] > 1 else 0])


def as_tuples(x):
    return float(x) if np.ndim(x) == 0 else tuple(as_tuples(y) for y in x)


def flatten(value):
    """The numbers of nested tuples (and of components-first arrays), in order."""
    if isinstance(value, tuple) or (isinstance(value, np.ndarray) and value.ndim > 1):
        return [leaf for item in value for leaf in flatten(item)]
    return [value]


# --- compiling the callers ------------------------------------------------------------------


def test_editing_a_law_recompiles_its_cached_callers(tmp_path):
    """numba keys a cache on the caller's file only; laws.jit adds the laws' files."""
    law = tmp_path / "law.py"
    law.write_text("from hipsim.physics.vectors import jitable\n\n\n@jitable\ndef law(x):\n    return 2.0 * x\n")
    (tmp_path / "caller.py").write_text(
        textwrap.dedent("""
        from pathlib import Path

        import law
        from hipsim.physics.laws import jit


        @jit(depends_on=(Path(law.__file__),))
        def caller(x):
            return law.law(x) + 1.0


        print(caller(1.0))
    """)
    )

    def run():
        done = subprocess.run([sys.executable, "caller.py"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
        assert done.returncode == 0, done.stderr
        return done.stdout.strip()

    assert run() == "3.0"
    assert list((tmp_path / "__pycache__").glob("caller.caller-*.nbi")), "numba wrote no cache: nothing was tested"
    law.write_text(law.read_text().replace("2.0 * x", "3.0 * x"))
    assert run() == "4.0"


def test_without_a_writable_cache_the_callers_compile_uncached_with_a_warning(monkeypatch):
    """numba refuses cache=True when it finds no writable folder; the compiled models must still work."""
    import numba

    real_njit = numba.njit

    def njit_without_cache_folder(cache=False, **options):
        if cache:
            raise RuntimeError("cannot cache function 'f': no locator available for file 'x.py'")
        return real_njit(cache=False, **options)

    monkeypatch.setattr(numba, "njit", njit_without_cache_folder)
    monkeypatch.setattr(laws, "_warned", set())

    def twice(x):
        return 2.0 * x

    with pytest.warns(UserWarning, match="no writable numba cache folder"):
        compiled = laws.jit(twice)
    assert compiled(1.5) == 3.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # once per process
        laws.jit(twice)
