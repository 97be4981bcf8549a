"""The machine's laws, each written once: the rotation maps (spec §2, §3) and the friction laws (spec §4.3, §7.3).

Every model calls these functions: the vectorised analytic model
(:mod:`hipsim.analytic.inverse_kinematics`, :mod:`hipsim.analytic.virtual_work`),
the compiled single-state kernel (:mod:`hipsim.analytic.kernel`) and the
Pinocchio model and plant (:mod:`hipsim.closed_chain`). So a change of a law —
a new friction term, say — is an edit of one function here, and every model
follows it.

How one source serves both. Each law is plain arithmetic on its arguments
(``+ − × /``, ``np.abs``, ``np.sqrt``) on vectors given by their components
(:mod:`hipsim.physics.vectors`), and returns vectors as triples. Called from
NumPy with arrays, it evaluates the law for all samples at once; called from
compiled code, numba compiles it on floats and 3-tuples into its caller
(``register_jitable``, via :func:`hipsim.physics.vectors.jitable`). Why
NumPy runs the laws itself, measured on 10⁴ samples: R(q) takes 80 µs in
NumPy, 100 µs numba-compiled on the same arrays, 16 µs as a compiled loop over
the samples; the central-chain friction 75, 63 and 51 µs; ŝ 22 µs in NumPy
and 39 µs as a ``@vectorize`` ufunc. The laws are under 1 ms of the analytic
model's ~13 ms at 10 kHz, so no variant moves ``scripts/bench.py``, and
NumPy needs no numba import (0.2 s) and no compilation on the way.

Friction coefficients come as a record ``F`` with the fields of
:class:`hipsim.machine.parameters.Friction`: the dataclass itself in NumPy
code, a :data:`FrictionRecord` in compiled code.

Compiled callers are built with :func:`jit`, which keys their on-disk cache on
these files too (numba's own key is only the caller's file).
"""

from __future__ import annotations

import functools
import hashlib
import warnings
from collections import namedtuple
from pathlib import Path

import numpy as np

from . import vectors
from .vectors import add, cross, dot, jitable, scale, sub

__all__ = [
    "FrictionRecord",
    "central_friction_moment",
    "friction_record",
    "guide_friction",
    "inverse_transpose",
    "jit",
    "lever_angular_acceleration",
    "lever_angular_velocity",
    "lever_axes",
    "lever_joint_friction",
    "lever_joint_friction_on",
    "rotation",
    "screw_friction",
    "smooth_sign",
    "smooth_sign_vector",
    "spin_transpose",
    "t_dot_times",
    "t_times",
    "t_transpose_times",
]


# --- Rotation maps (spec §2) ------------------------------------------------------------
# They take the cosines c and sines s of q = [α, β, γ] (after the angle signs), each a
# vector: callers evaluate them once, and they cost more than the products that follow.
# (Pinocchio's rpy module has R and T too, but the analytic layer does not import Pinocchio.)


@jitable
def rotation(c, s):
    """R = Rz(γ)·Ry(β)·Rx(α), by its rows; its columns are the platform's x, y, z axes.

    Written out rather than SciPy's ``Rotation.from_euler("ZYX", ...)``: the
    compiled kernels cannot call SciPy, and on 10⁴ samples SciPy took seven
    times as long (10 ms against 1.4 ms, cosines and sines included).
    """
    ca, cb, cg = c[0], c[1], c[2]
    sa, sb, sg = s[0], s[1], s[2]
    return (
        (cb * cg, cg * sb * sa - sg * ca, cg * sb * ca + sg * sa),
        (cb * sg, sg * sb * sa + cg * ca, sg * sb * ca - cg * sa),
        (-sb, cb * sa, cb * ca),
    )


@jitable
def t_times(c, s, v):
    """T(q)·v with T = [[cβ·cγ, −sγ, 0], [cβ·sγ, cγ, 0], [−sβ, 0, 1]]: ω = T·q̇ (world frame)."""
    cb, cg = c[1], c[2]
    sb, sg = s[1], s[2]
    return (cb * cg * v[0] - sg * v[1], cb * sg * v[0] + cg * v[1], -sb * v[0] + v[2])


@jitable
def t_transpose_times(c, s, m):
    """T(q)ᵀ·m: a moment m on the platform as generalised forces on the angles q."""
    cb, cg = c[1], c[2]
    sb, sg = s[1], s[2]
    return (cb * cg * m[0] + cb * sg * m[1] - sb * m[2], -sg * m[0] + cg * m[1], m[2])


@jitable
def t_dot_times(c, s, qd, v):
    """Ṫ(q, q̇)·v, so that ω̇ = T·q̈ + Ṫ·q̇; q̇ in [rad/s]."""
    cb, cg = c[1], c[2]
    sb, sg = s[1], s[2]
    bd, gd = qd[1], qd[2]
    return (
        (-sb * cg * bd - cb * sg * gd) * v[0] - cg * gd * v[1],
        (-sb * sg * bd + cb * cg * gd) * v[0] - sg * gd * v[1],
        -cb * bd * v[0],
    )


@jitable
def inverse_transpose(J):
    """J⁻ᵀ by its rows (j₁ × j₂, j₂ × j₀, j₀ × j₁)/det J, from J by its rows j_i.

    In closed form: ten times faster than LAPACK's batched solve on 3x3 matrices.
    """
    r0, r1, r2 = cross(J[1], J[2]), cross(J[2], J[0]), cross(J[0], J[1])
    inverse_det = 1.0 / dot(J[0], r0)
    return scale(r0, inverse_det), scale(r1, inverse_det), scale(r2, inverse_det)


# --- The lever's frame and spin (spec §3, §7.1) ------------------------------------------
# u1 is the universal joint's slider-fixed axis, e the lever's unit vector, ω_⊥ the lever's
# angular velocity without spin about e (spec §3) and ω̇_⊥ its rate.


@jitable
def lever_axes(u1, e):
    """The lever's body axes x, y, z of spec §7.1: z = e, x = u2 = e × u1/|e × u1|, y = z × x."""
    x = cross(e, u1)
    x = scale(x, 1.0 / np.sqrt(dot(x, x)))
    return x, cross(e, x), e


@jitable
def lever_angular_velocity(u1, e, w_perp):
    """ω_l = ω_⊥ + s·e: a universal joint keeps ω_l in span{u1, u2}, so s = c·(ω_⊥·u1)/(1 − c²), c = u1·e."""
    c = dot(u1, e)
    s = c * dot(w_perp, u1) / (1.0 - c**2)
    return add(w_perp, scale(e, s))


@jitable
def lever_angular_acceleration(u1, e, w_perp, w_perp_dot):
    """ω̇_l = ω̇_⊥ + ṡ·e + s·ė, the rate of :func:`lever_angular_velocity` (ė = ω_⊥ × e)."""
    c = dot(u1, e)
    d = 1.0 - c**2
    w = dot(w_perp, u1)
    s = c * w / d
    e_dot = cross(w_perp, e)
    c_dot = dot(u1, e_dot)
    s_dot = (c_dot * w + c * dot(w_perp_dot, u1)) / d + 2.0 * c**2 * c_dot * w / d**2
    return add(add(w_perp_dot, scale(e, s_dot)), scale(e_dot, s))


@jitable
def spin_transpose(u1, e, m):
    """The transpose of the spin map ω_⊥ ↦ ω_l on a moment m: m + c/(1 − c²)·(e·m)·u1.

    A moment m on the spinning lever does the virtual work of this moment on ω_⊥.
    """
    c = dot(u1, e)
    return add(m, scale(u1, c / (1.0 - c**2) * dot(e, m)))


# --- Friction (spec §4.3, §7.3) -----------------------------------------------------------


@jitable
def smooth_sign(w, epsilon):
    """ŝ(w) = w/√(w² + ε²) of a speed w (elementwise): below ε the Coulomb friction fades linearly to zero.

    Args:
        w: speed in [rad/s].
        epsilon: ε in [rad/s].
    """
    return w / np.sqrt(w * w + epsilon * epsilon)


@jitable
def smooth_sign_vector(w, epsilon):
    """ŝ(w) = w/√(|w|² + ε²) of an angular velocity w in [rad/s]; ε in [rad/s]."""
    return scale(w, 1.0 / np.sqrt(dot(w, w) + epsilon * epsilon))


@jitable
def screw_friction(F, motor_speed):
    """The lead screw's own friction torque on the motor shaft in [N·m]: Coulomb plus viscous.

    Args:
        F: the friction record.
        motor_speed: θ̇ in [rad/s].
    """
    return F.screw_coulomb * smooth_sign(motor_speed, F.epsilon) + F.screw_viscous * motor_speed


@jitable
def guide_friction(F, Ld, motor_speed):
    """The friction force of one slider guide in [N], against the slider's motion.

    The Coulomb part is regularised on the motor speed (ε is a rate in [rad/s]).

    Args:
        F: the friction record.
        Ld: slider speed L̇ in [m/s].
        motor_speed: θ̇ = 2π·L̇/p in [rad/s].
    """
    return F.guide_coulomb * smooth_sign(motor_speed, F.epsilon) + F.guide_viscous * Ld


@jitable
def central_friction_moment(F, omega, z, Fe, weight):
    """τ_mf: the friction moment of one platform's central chain (hip joint and thrust bearing), spec §4.3.

    The hip joint resists along ŝ(ω) with r_h·μ_h·|F_e|. The thrust bearing
    carries F_e and the platform's weight: by default (the publication's form)
    it too resists along ŝ(ω), with r_t·μ_t·|F_e + m_m·g|; with
    ``F.thrust_bearing_axial_only`` it resists only rotation about its own
    axis, the platform's z axis: the moment r_t·μ_t·|F_e + m_m·g|·ŝ(ω·z)·z.

    Args:
        F: the friction record.
        omega: platform angular velocity ω in [rad/s].
        z: the platform's z axis (unit vector; read only with the axial-only bearing).
        Fe: load magnitude in [N], pushing down like the platform's weight.
        weight: the platform's weight m_m·g in [N].

    Returns:
        τ_mf in [N·m]; its power τ_mf·ω ≥ 0 is what the friction dissipates.
    """
    hip = F.hip_radius * F.hip_mu * np.abs(Fe)
    thrust = F.thrust_radius * F.thrust_mu * np.abs(Fe + weight)
    direction = smooth_sign_vector(omega, F.epsilon)
    if F.thrust_bearing_axial_only:
        return add(scale(direction, hip), scale(z, thrust * smooth_sign(dot(omega, z), F.epsilon)))
    return scale(direction, hip + thrust)


@jitable
def _coulomb_viscous(w, coulomb, viscous, epsilon):
    """coulomb·ŝ(w) + viscous·w for an angular velocity w."""
    return add(scale(smooth_sign_vector(w, epsilon), coulomb), scale(w, viscous))


@jitable
def lever_joint_friction(F, omega_l, omega):
    """The friction moments of a lever's universal joint (τ_bf) and spherical joint (τ_af), in [N·m].

    U: the lever relative to its slider, which does not rotate; S: the lever
    relative to the platform (the moment acts on the lever and, oppositely, on
    the platform).

    Args:
        F: the friction record.
        omega_l: the lever's angular velocity in [rad/s].
        omega: the platform's angular velocity in [rad/s].

    Returns:
        τ_bf, τ_af, each resisting its joint's relative rotation.
    """
    relative = sub(omega_l, omega)
    return (
        _coulomb_viscous(omega_l, F.ujoint_coulomb, F.ujoint_viscous, F.epsilon),
        _coulomb_viscous(relative, F.sjoint_coulomb, F.sjoint_viscous, F.epsilon),
    )


@jitable
def lever_joint_friction_on(F):
    """True when the levers' U or S joints have friction (zero by default, and then not computed)."""
    return F.ujoint_coulomb != 0.0 or F.ujoint_viscous != 0.0 or F.sjoint_coulomb != 0.0 or F.sjoint_viscous != 0.0


#: The friction coefficients as compiled code reads them: the fields of
#: :class:`hipsim.machine.parameters.Friction`, in order, SI (a test holds the two lists equal;
#: the laws sit below the machine, so they name the fields rather than import the class).
FrictionRecord = namedtuple(
    "FrictionRecord",
    [
        "epsilon",
        "hip_radius",
        "hip_mu",
        "thrust_radius",
        "thrust_mu",
        "screw_coulomb",
        "screw_viscous",
        "guide_coulomb",
        "guide_viscous",
        "ujoint_coulomb",
        "ujoint_viscous",
        "sjoint_coulomb",
        "sjoint_viscous",
        "thrust_bearing_axial_only",
    ],
)


def friction_record(friction) -> FrictionRecord:
    """The coefficients as plain floats (switches as bools): numba compiles once per combination of types."""
    values = (getattr(friction, name) for name in FrictionRecord._fields)
    return FrictionRecord(*(value if isinstance(value, bool) else float(value) for value in values))


# --- Compiling the callers -------------------------------------------------------------------

#: The files whose functions compiled callers absorb.
LAW_FILES = (Path(__file__), Path(vectors.__file__), Path(__file__).with_name("transmission.py"))

_warned: set[str] = set()


def _warn_once(message: str) -> None:
    if message not in _warned:
        _warned.add(message)
        warnings.warn(f"hipsim: {message}", stacklevel=3)


@functools.cache
def _content_hash(paths: tuple[Path, ...]) -> str:
    digest = hashlib.sha256()
    for path in paths:
        digest.update(path.read_bytes())
    return digest.hexdigest()


def jit(function=None, *, depends_on: tuple[Path, ...] = LAW_FILES):
    """Compile a function that calls the laws with numba, caching its machine code where numba can write it.

    numba keys a cached function on its own source file only, so machine code
    that absorbed a law would outlive an edit of the law (numba issue #1833,
    documented under "Cache invalidation"): here the key also holds the
    content of ``depends_on`` (these files by default). ``error_model="numpy"``:
    x/0 gives inf or NaN as in NumPy instead of raising.

    numba caches next to the caller's file or, when that folder is read-only,
    in the user's cache folder; where neither can be written (or a numba
    release no longer offers the key this extends), the function is compiled
    afresh in every process, with a warning.

    Args:
        function: the function (or use ``@jit`` / ``@jit(depends_on=...)`` as a decorator).
        depends_on: source files whose content is part of the cache key.
    """
    if function is None:
        return functools.partial(jit, depends_on=depends_on)
    from numba import njit

    vectors.register_jitables()
    try:
        compiled = njit(cache=True, error_model="numpy")(function)
    except RuntimeError:  # "cannot cache function ...: no locator available"
        _warn_once("no writable numba cache folder; compiled models are compiled in every run (~10 s)")
        return njit(cache=False, error_model="numpy")(function)
    stamp = _content_hash(tuple(Path(path) for path in depends_on))
    try:
        index = compiled._cache._cache_file  # type: ignore[attr-defined]  # numba.core.caching.IndexDataCacheFile
        index._source_stamp = (index._source_stamp, stamp)
    except AttributeError:
        _warn_once(
            "this numba cannot key its cache on hipsim's laws; compiled models are compiled in every run (~10 s)"
        )
        return njit(cache=False, error_model="numpy")(function)
    return compiled
