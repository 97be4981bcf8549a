"""The machine's parameter set: one TOML file, loaded into an immutable object in SI units.

The file (``models/hip_simulator.toml`` is the default) is written in the
design data's units (mm, kg, kg·mm², N·mm, degrees), with the unit in every
key. :func:`load_parameters` checks every key against :data:`SCHEMA`, converts
to SI and returns a frozen :class:`Parameters`. Both the analytic and the
Pinocchio model read this one object, so a change in the file changes both.

Example:
    >>> import hipsim
    >>> params = hipsim.load_parameters(overrides={"lever.length_mm": 330})
    >>> params.lever_length
    0.33
"""

from __future__ import annotations

import codecs
import dataclasses
import difflib
import math
import tomllib
from dataclasses import dataclass
from functools import cached_property
from importlib import resources
from pathlib import Path
from types import MappingProxyType
from typing import Any, Mapping

import numpy as np

from ..arrays import readonly
from ..exceptions import ParameterError

__all__ = [
    "ControlSettings",
    "Friction",
    "Parameters",
    "OPTIONAL_SECTIONS",
    "SCHEMA",
    "check_entry",
    "default_parameters_path",
    "file_values",
    "check_key",
    "load_parameters",
    "override_parameters",
    "parse_override",
    "read_toml",
    "slender_levers",
]

_MM = 1e-3
_KGMM2 = 1e-6
_NMM = 1e-3
_DEG = math.pi / 180.0


@dataclass(frozen=True)
class _Key:
    """One entry of the parameter file: its shape, SI scale, bound and meaning."""

    kind: str  # "float", "vector", "inertia", "signs", "bool"
    scale: float = 1.0
    bound: str = "none"  # "positive", "nonnegative", "none"
    length: int = 0  # for vectors
    unit: str = ""
    meaning: str = ""
    finite: bool = True  # False to allow inf (e.g. "no limit")
    # Largest magnitude, in the file's unit: far beyond any machine of this kind, so
    # only a typo or a unit slip reaches it, and the physics never meets overflow.
    limit: float = 1e9
    # The value of a key that files may leave out (keys added after files were
    # written, so that those files still load); None: the key is required.
    default: Any = None


#: Every section and key the parameter file must contain, with its SI scale and bound.
SCHEMA: dict[str, dict[str, _Key]] = {
    "environment": {
        "gravity_m_s2": _Key("float", 1.0, "nonnegative", unit="m/s²", meaning="gravity g along -Z"),
    },
    "base": {
        "screw_radius_mm": _Key("float", _MM, "positive", unit="mm", meaning="E, screw axes radius"),
        "screw_angles_deg": _Key("vector", _DEG, "none", 3, "deg", "θ_i, screw base angles", limit=360.0),
    },
    "platform": {
        "joint_radius_mm": _Key("float", _MM, "positive", unit="mm", meaning="e, platform joint radius"),
        "home_offset_deg": _Key("float", _DEG, "none", unit="deg", meaning="δ, platform joint offset", limit=360.0),
        "heights_mm": _Key("vector", _MM, "positive", 2, "mm", "h_1, h_2, platform centre heights"),
        "mass_kg": _Key("float", 1.0, "nonnegative", unit="kg", meaning="m_m, platform mass (estimate)"),
        "inertia_kgmm2": _Key("inertia", _KGMM2, unit="kg·mm²", meaning="I_m, platform inertia"),
    },
    "lever": {
        "length_mm": _Key("float", _MM, "positive", unit="mm", meaning="l, lever length"),
        "mass_kg": _Key("float", 1.0, "nonnegative", unit="kg", meaning="m_l, lever mass"),
        "inertia_kgmm2": _Key("inertia", _KGMM2, unit="kg·mm²", meaning="I_l, lever inertia"),
    },
    "slider": {
        "mass_kg": _Key("float", 1.0, "nonnegative", unit="kg", meaning="m_L, slider mass"),
    },
    "screw": {
        "lead_mm": _Key("float", _MM, "positive", unit="mm", meaning="p, screw lead"),
        "inertia_kgmm2": _Key("float", _KGMM2, "nonnegative", unit="kg·mm²", meaning="I_L, screw inertia"),
    },
    "friction": {
        "epsilon_rad_s": _Key("float", 1.0, "positive", unit="rad/s", meaning="ε of the smooth sign"),
        "hip_radius_mm": _Key("float", _MM, "nonnegative", unit="mm", meaning="r_h"),
        "hip_mu": _Key("float", 1.0, "nonnegative", meaning="μ_h"),
        "thrust_radius_mm": _Key("float", _MM, "nonnegative", unit="mm", meaning="r_t"),
        "thrust_mu": _Key("float", 1.0, "nonnegative", meaning="μ_t"),
        "screw_coulomb_Nmm": _Key("float", _NMM, "nonnegative", unit="N·mm", meaning="screw Coulomb torque"),
        "screw_viscous_Nmm_s_rad": _Key("float", _NMM, "nonnegative", unit="N·mm·s/rad", meaning="screw viscous"),
        "guide_coulomb_N": _Key("float", 1.0, "nonnegative", unit="N", meaning="slider guide Coulomb force"),
        "guide_viscous_N_s_mm": _Key("float", 1.0 / _MM, "nonnegative", unit="N·s/mm", meaning="guide viscous"),
        "ujoint_coulomb_Nmm": _Key("float", _NMM, "nonnegative", unit="N·mm", meaning="U-joint Coulomb moment"),
        "ujoint_viscous_Nmm_s_rad": _Key("float", _NMM, "nonnegative", unit="N·mm·s/rad", meaning="U-joint viscous"),
        "sjoint_coulomb_Nmm": _Key("float", _NMM, "nonnegative", unit="N·mm", meaning="S-joint Coulomb moment"),
        "sjoint_viscous_Nmm_s_rad": _Key("float", _NMM, "nonnegative", unit="N·mm·s/rad", meaning="S-joint viscous"),
        "thrust_bearing_axial_only": _Key(
            "bool", meaning="thrust bearing resists only rotation about the platform's z axis (false: along ω)", default=False
        ),
    },
    "convention": {
        "angle_signs": _Key("signs", 1.0, "none", 3, meaning="sign flips of α, β, γ"),
    },
    "control": {
        "servo_rate_Hz": _Key("float", 1.0, "positive", unit="Hz", meaning="servo (controller) rate"),
        "integration_step_ms": _Key("float", 1e-3, "positive", unit="ms", meaning="plant integration step (RK4)"),
        "kp_Nm_rad": _Key("vector", 1.0, "nonnegative", 3, "N·m/rad", "K_p, platform moment per orientation error"),
        "kd_Nm_s_rad": _Key("vector", 1.0, "nonnegative", 3, "N·m·s/rad", "K_d, platform moment per rate error"),
        "torque_limit_Nmm": _Key("float", _NMM, "positive", unit="N·mm", meaning="motor torque limit (inf: none)", finite=False),
    },
    # Optional: the motor and linear module to check a design against (hipsim report).
    "motor": {
        "rated_torque_Nmm": _Key("float", 1.0, "positive", unit="N·mm", meaning="rated (continuous) motor torque, vs RMS"),
        "peak_torque_Nmm": _Key("float", 1.0, "positive", unit="N·mm", meaning="peak motor torque"),
        "max_speed_rpm": _Key("float", 1.0, "positive", unit="rpm", meaning="maximum motor speed"),
        "stroke_mm": _Key("float", 1.0, "positive", unit="mm", meaning="usable stroke of the linear module"),
        "axial_force_N": _Key("float", 1.0, "positive", unit="N", meaning="permissible axial screw load"),
    },
}

#: Sections whose keys may each be left out (their values are kept in the file's units).
OPTIONAL_SECTIONS = {"motor"}




@dataclass(frozen=True, eq=False)
class Friction:
    """Friction coefficients, SI. Coulomb terms use the smooth sign ŝ(w) = w/√(w² + ε²).

    Attributes:
        epsilon: ε of the smooth sign in [rad/s] (slider guides use it on the motor speed).
        hip_radius: r_h in [m]; hip_mu: μ_h.
        thrust_radius: r_t in [m]; thrust_mu: μ_t.
        screw_coulomb: [N·m]; screw_viscous: [N·m·s/rad], on the motor shaft.
        guide_coulomb: [N]; guide_viscous: [N·s/m], on each slider.
        ujoint_coulomb: [N·m]; ujoint_viscous: [N·m·s/rad], lever relative to slider.
        sjoint_coulomb: [N·m]; sjoint_viscous: [N·m·s/rad], lever relative to platform.
        thrust_bearing_axial_only: False for the publication's central-chain
            friction (the thrust bearing's moment along ŝ(ω), like the hip
            joint's); True for a bearing that resists only rotation about its
            own axis, the platform's z axis (:func:`hipsim.physics.laws.central_friction_moment`).
    """

    epsilon: float
    hip_radius: float
    hip_mu: float
    thrust_radius: float
    thrust_mu: float
    screw_coulomb: float
    screw_viscous: float
    guide_coulomb: float
    guide_viscous: float
    ujoint_coulomb: float
    ujoint_viscous: float
    sjoint_coulomb: float
    sjoint_viscous: float
    thrust_bearing_axial_only: bool = False


@dataclass(frozen=True, eq=False)
class ControlSettings:
    """Servo loop settings (spec §8), SI.

    Attributes:
        servo_rate: controller rate in [Hz].
        integration_step: plant integration step in [s], at most one servo period.
        kp: K_p per angle α, β, γ in [N·m/rad], shape (3,).
        kd: K_d per angle in [N·m·s/rad], shape (3,).
        torque_limit: motor torque limit in [N·m]; inf for none.
    """

    servo_rate: float
    integration_step: float
    kp: np.ndarray
    kd: np.ndarray
    torque_limit: float

    def __post_init__(self):
        for name in ("kp", "kd"):
            value = readonly(np.asarray(getattr(self, name), dtype=float))
            if value.shape != (3,):
                raise ParameterError(f"expected shape (3,), got {value.shape}", key=f"control.{name}", value=value)
            object.__setattr__(self, name, value)


@dataclass(frozen=True, eq=False)
class Parameters:
    """The machine, in SI units. Build it with :func:`load_parameters`.

    Attributes:
        gravity: g in [m/s²], along -Z.
        screw_radius: E in [m].
        screw_angles: θ_i in [rad], shape (3,).
        joint_radius: e in [m].
        home_offset: δ in [rad].
        heights: h_1, h_2 in [m], shape (2,).
        platform_mass: m_m in [kg] (not published; an estimate by default).
        platform_inertia: I_m about o_j in platform axes in [kg·m²], shape (3, 3).
        lever_length: l in [m].
        lever_mass: m_l in [kg].
        lever_inertia: I_l about its centre in lever axes in [kg·m²], shape (3, 3).
        slider_mass: m_L in [kg].
        lead: p in [m] per motor turn.
        screw_inertia: I_L in [kg·m²].
        friction: the :class:`Friction` coefficients.
        angle_signs: ±1 per angle α, β, γ, shape (3,).
        control: the :class:`ControlSettings` (servo rate, gains, limits).
        motor: the optional motor and module ratings, by key of the file's
            ``[motor]`` table, in its units (N·mm, rpm, mm, N); empty if none.
        source: where the values came from (file and overrides).
    """

    gravity: float
    screw_radius: float
    screw_angles: np.ndarray
    joint_radius: float
    home_offset: float
    heights: np.ndarray
    platform_mass: float
    platform_inertia: np.ndarray
    lever_length: float
    lever_mass: float
    lever_inertia: np.ndarray
    slider_mass: float
    lead: float
    screw_inertia: float
    friction: Friction
    angle_signs: np.ndarray
    control: "ControlSettings"
    motor: Mapping[str, float] = dataclasses.field(default_factory=lambda: MappingProxyType({}))
    source: str = "<built in>"

    def __post_init__(self):
        for name, shape in (
            ("screw_angles", (3,)),
            ("heights", (2,)),
            ("platform_inertia", (3, 3)),
            ("lever_inertia", (3, 3)),
            ("angle_signs", (3,)),
        ):
            value = readonly(np.asarray(getattr(self, name), dtype=float))
            if value.shape != shape:
                raise ParameterError(f"expected shape {shape}, got {value.shape}", key=name, value=value)
            object.__setattr__(self, name, value)

    @cached_property
    def platform_angles(self) -> np.ndarray:
        """φ_i = θ_i + δ in [rad], shape (3,)."""
        return readonly(self.screw_angles + self.home_offset)

    @cached_property
    def screw_points(self) -> np.ndarray:
        """c_i, the screw feet on the base plane in [m], shape (3, 3) (row i = c_i)."""
        th = self.screw_angles
        return readonly(self.screw_radius * np.stack([np.cos(th), np.sin(th), np.zeros(3)], axis=1))

    @cached_property
    def platform_points(self) -> np.ndarray:
        """r⁰_i, the platform joints in platform axes in [m], shape (3, 3) (row i = r⁰_i)."""
        ph = self.platform_angles
        return readonly(self.joint_radius * np.stack([np.cos(ph), np.sin(ph), np.zeros(3)], axis=1))

    @cached_property
    def ujoint_axes(self) -> np.ndarray:
        """u1_i = ẑ × c_i/|c_i|, the universal joints' first (slider-fixed) axes, shape (3, 3)."""
        th = self.screw_angles
        return readonly(np.stack([-np.sin(th), np.cos(th), np.zeros(3)], axis=1))

    def replace(self, **changes) -> "Parameters":
        """A copy with some attributes changed, e.g. ``params.replace(lever_mass=0.0)``."""
        if "friction" not in changes:
            friction_changes = {k: changes.pop(k) for k in list(changes) if k in _FRICTION_FIELDS}
            if friction_changes:
                changes["friction"] = dataclasses.replace(self.friction, **friction_changes)
        if "control" not in changes:
            control_changes = {k: changes.pop(k) for k in list(changes) if k in _CONTROL_FIELDS}
            if control_changes:
                changes["control"] = dataclasses.replace(self.control, **control_changes)
        return dataclasses.replace(self, **changes)


_FRICTION_FIELDS = {f.name for f in dataclasses.fields(Friction)}
_CONTROL_FIELDS = {f.name for f in dataclasses.fields(ControlSettings)}


def slender_levers(params: Parameters) -> Parameters:
    """The cross-check configuration of spec §7.4: each lever a slender rod.

    I_l becomes diag(I_t, I_t, 0), I_t the mean of the two transverse values, so
    that the lever's spin about its own axis carries no energy.
    """
    inertia = params.lever_inertia
    transverse = 0.5 * (inertia[0, 0] + inertia[1, 1])
    return params.replace(lever_inertia=np.diag([transverse, transverse, 0.0]))


def default_parameters_path() -> Path:
    """The parameter file shipped with hipsim (the published machine)."""
    return Path(str(resources.files("hipsim.models").joinpath("hip_simulator.toml")))


def parse_override(text: str, source: str = "override") -> tuple[str, Any]:
    """Split ``"section.key=value"`` into the key and a TOML-typed value.

    Args:
        text: one override, e.g. ``"lever.length_mm=330"`` or
            ``"platform.heights_mm=[900, 490]"``.
        source: where it came from, for errors (the command line says ``--set``).

    Returns:
        The dotted key and the value as TOML reads it.
    """
    if "=" not in text:
        raise ParameterError(f"expected KEY=VALUE, got '{text}'", source=source)
    key, _, value = text.partition("=")
    key = key.strip()
    if not key:
        raise ParameterError(f"no key before '=' in '{text}' (expected e.g. lever.length_mm=330)", source=source)
    try:
        parsed = tomllib.loads(f"v = {value.strip()}")["v"]
    except tomllib.TOMLDecodeError:
        raise ParameterError(f"'{value.strip()}' is not a number, list or TOML value", key=key, source=source) from None
    return key, parsed


def read_toml(path: str | Path, what: str = "parameter file") -> dict[str, Any]:
    """The tables of a TOML file.

    Args:
        path: the file.
        what: what the file is, for messages ("parameter file", "rating file").

    Raises:
        ParameterError: naming the file when it is missing, a folder, unreadable or not TOML.
    """
    source = str(path)
    try:
        with open(path, "rb") as stream:
            data = stream.read()
        # Some editors start UTF-8 files with a byte-order mark, which TOML does not allow.
        return tomllib.loads(data.removeprefix(codecs.BOM_UTF8).decode("utf-8"))
    except FileNotFoundError:
        raise ParameterError(f"no such {what}", source=source) from None
    except IsADirectoryError:
        raise ParameterError(f"is a folder, not a {what}", source=source) from None
    except OSError as error:
        raise ParameterError(f"cannot read ({error.strerror})", source=source) from None
    except UnicodeDecodeError:
        raise ParameterError("not a UTF-8 text file", source=source) from None
    except tomllib.TOMLDecodeError as error:
        raise ParameterError(f"not valid TOML ({error})", source=source) from None


def check_entry(section: str, key: str, value: Any, source: str) -> Any:
    """One entry of :data:`SCHEMA` checked and converted to SI.

    Raises:
        ParameterError: naming the file and key of an unknown or invalid entry.
    """
    if section not in SCHEMA or key not in SCHEMA[section]:
        known = ", ".join(SCHEMA.get(section, SCHEMA))
        raise ParameterError(f"unknown key (known: {known})", key=f"{section}.{key}", source=source)
    return _convert(value, SCHEMA[section][key], f"{section}.{key}", source)


def load_parameters(
    path: str | Path | None = None,
    overrides: Mapping[str, Any] | None = None,
    overrides_source: str = "overrides",
) -> Parameters:
    """Read, check and convert a parameter file.

    Args:
        path: a TOML file in the layout of ``models/hip_simulator.toml``;
            None for the published machine.
        overrides: values that replace single entries, by dotted key in the
            file's units, e.g. ``{"lever.length_mm": 330}``.
        overrides_source: what to call the overrides in errors.

    Returns:
        The parameter set in SI units.

    Raises:
        ParameterError: naming the file and key of an unknown, missing,
            mistyped or physically impossible entry.
    """
    path = Path(path) if path is not None else default_parameters_path()
    source = str(path)
    raw = read_toml(path, "parameter file")
    for dotted, value in (overrides or {}).items():
        section, key = check_key(dotted, overrides_source)
        if not isinstance(raw.setdefault(section, {}), dict):
            raise ParameterError("expected a [section] table", key=section, source=source)
        raw[section][key] = value
    if overrides:
        source += " with " + ", ".join(f"{k}={v}" for k, v in overrides.items())
    return _build(_check(raw, source), source)


def check_key(dotted: str, source: str = "overrides") -> tuple[str, str]:
    """The section and key of a dotted key of :data:`SCHEMA`, e.g. ``"lever.length_mm"`` → ``("lever", "length_mm")``.

    Raises:
        ParameterError: naming the key and ``source`` when it is unknown, with the nearest known key.
    """
    section, _, key = dotted.partition(".")
    if section not in SCHEMA or key not in SCHEMA[section]:
        raise ParameterError(f"unknown key{_did_you_mean(dotted)}; `hipsim params` lists them all", key=dotted, source=source)
    return section, key


def override_parameters(params: Parameters, overrides: Mapping[str, Any], overrides_source: str = "overrides") -> Parameters:
    """``params`` with single entries replaced, checked as :func:`load_parameters` checks them, without reading a file.

    For many variants of one machine (``hipsim sweep``): only the replaced
    entries are converted again, then the whole set is rebuilt and its
    geometry checked, so a variant costs a fraction of a millisecond.

    Args:
        params: the machine the variants start from.
        overrides: values by dotted key in the file's units, e.g. ``{"lever.length_mm": 330}``.
        overrides_source: what to call the overrides in errors.

    Raises:
        ParameterError: as :func:`load_parameters`, naming the key.
    """
    values: dict[str, Any] = {}
    for dotted, attribute in _ATTRIBUTES.items():
        value = params
        for part in attribute.split("."):
            value = getattr(value, part)
        values[dotted] = value
    values |= {f"motor.{key}": value for key, value in params.motor.items()}
    for dotted, value in overrides.items():
        section, key = check_key(dotted, overrides_source)
        values[dotted] = _convert(value, SCHEMA[section][key], dotted, overrides_source)
    source = params.source + " with " + ", ".join(f"{k}={v}" for k, v in overrides.items()) if overrides else params.source
    return _build(values, source)


def _did_you_mean(dotted: str) -> str:
    """ " (did you mean 'lever.length_mm'?)" for the nearest known keys, or nothing."""
    known = [f"{s}.{k}" for s, keys in SCHEMA.items() for k in keys]
    close = difflib.get_close_matches(dotted, known, n=1, cutoff=0.6)
    return f" (did you mean {' or '.join(repr(k) for k in close)}?)" if close else ""


def _check(raw: Mapping[str, Any], source: str) -> dict[str, Any]:
    """Every key of SCHEMA present, typed and within bounds; returns SI values by dotted key."""
    for section, table in raw.items():
        if section not in SCHEMA:
            raise ParameterError(f"unknown section (known: {', '.join(SCHEMA)})", key=section, source=source)
        if not isinstance(table, dict):
            raise ParameterError("expected a [section] table", key=section, source=source)
        for key in table:
            if key not in SCHEMA[section]:
                known = ", ".join(SCHEMA[section])
                raise ParameterError(f"unknown key (known in [{section}]: {known})", key=f"{section}.{key}", source=source)
    values = {}
    for section, keys in SCHEMA.items():
        for key, spec in keys.items():
            dotted = f"{section}.{key}"
            if key not in raw.get(section, {}):
                if section in OPTIONAL_SECTIONS:
                    continue
                if spec.default is not None:
                    values[dotted] = spec.default
                    continue
                raise ParameterError(f"missing ({spec.meaning}, in {spec.unit or 'no unit'})", key=dotted, source=source)
            values[dotted] = _convert(raw[section][key], spec, dotted, source)
    return values


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _convert(value, spec: _Key, key: str, source: str):
    def fail(message):
        raise ParameterError(message, key=key, value=value, source=source)

    if spec.kind == "bool":
        if not isinstance(value, bool):
            fail(f"expected true or false, got {value!r}")
        return value
    if spec.kind == "float":
        if not _is_number(value):
            fail(f"expected a number in {spec.unit or 'no unit'}, got {value!r}")
        numbers = np.array([float(value)])
    elif spec.kind in ("vector", "signs"):
        if not isinstance(value, list) or len(value) != spec.length or not all(map(_is_number, value)):
            fail(f"expected a list of {spec.length} numbers, got {value!r}")
        numbers = np.array(value, dtype=float)
        if spec.kind == "signs" and not np.all(np.abs(numbers) == 1):
            fail(f"expected each sign to be 1 or -1, got {value!r}")
    elif spec.kind == "inertia":
        numbers = _inertia_matrix(value, fail)
    else:  # pragma: no cover - SCHEMA is ours
        raise AssertionError(spec.kind)
    if np.any(np.isnan(numbers)) or (spec.finite and not np.all(np.isfinite(numbers))):
        fail(f"expected finite numbers, got {value!r}")
    if np.any(np.abs(numbers[np.isfinite(numbers)]) > spec.limit):
        fail(f"out of range: at most {spec.limit:g} {spec.unit or ''} in magnitude, got {value!r}".replace("  ", " "))
    if spec.bound == "positive" and np.any(numbers <= 0):
        fail(f"must be positive, got {value!r}")
    if spec.bound == "nonnegative" and np.any(numbers < 0):
        fail(f"must not be negative, got {value!r}")
    numbers = numbers * spec.scale
    return float(numbers[0]) if spec.kind == "float" else numbers


def _inertia_matrix(value, fail) -> np.ndarray:
    """A diagonal [Ixx, Iyy, Izz] or a full symmetric 3x3 list, positive semi-definite."""
    if isinstance(value, list) and len(value) == 3 and all(map(_is_number, value)):
        matrix = np.diag(np.array(value, dtype=float))
    elif (
        isinstance(value, list)
        and len(value) == 3
        and all(isinstance(row, list) and len(row) == 3 and all(map(_is_number, row)) for row in value)
    ):
        matrix = np.array(value, dtype=float)
        if not np.allclose(matrix, matrix.T, rtol=1e-12, atol=0.0):
            fail("inertia matrix is not symmetric")
    else:
        fail(f"expected [Ixx, Iyy, Izz] or a 3x3 list of numbers, got {value!r}")
    if not np.all(np.isfinite(matrix)):
        fail(f"expected finite numbers, got {value!r}")
    eigenvalues = np.linalg.eigvalsh(matrix)
    tolerance = 1e-12 * max(1.0, abs(eigenvalues[-1]))
    if eigenvalues[0] < -tolerance:
        fail(f"inertia is not positive semi-definite (eigenvalues {np.round(eigenvalues, 6).tolist()})")
    # Every rigid body's principal moments obey I_a ≤ I_b + I_c (a slender rod is the equality).
    if eigenvalues[2] > eigenvalues[0] + eigenvalues[1] + tolerance:
        fail(f"no rigid body has these principal moments: {eigenvalues[2]:g} exceeds the sum of the other two "
             f"({eigenvalues[0]:g} + {eigenvalues[1]:g})")  # fmt: skip
    return matrix


#: Where each file entry lands in :class:`Parameters` (dotted attribute path).
_ATTRIBUTES = {
    "environment.gravity_m_s2": "gravity",
    "base.screw_radius_mm": "screw_radius",
    "base.screw_angles_deg": "screw_angles",
    "platform.joint_radius_mm": "joint_radius",
    "platform.home_offset_deg": "home_offset",
    "platform.heights_mm": "heights",
    "platform.mass_kg": "platform_mass",
    "platform.inertia_kgmm2": "platform_inertia",
    "lever.length_mm": "lever_length",
    "lever.mass_kg": "lever_mass",
    "lever.inertia_kgmm2": "lever_inertia",
    "slider.mass_kg": "slider_mass",
    "screw.lead_mm": "lead",
    "screw.inertia_kgmm2": "screw_inertia",
    "convention.angle_signs": "angle_signs",
    **{f"friction.{key}": f"friction.{name}" for key, name in zip(SCHEMA["friction"], (f.name for f in dataclasses.fields(Friction)))},
    **{f"control.{key}": f"control.{name}" for key, name in zip(SCHEMA["control"], (f.name for f in dataclasses.fields(ControlSettings)))},
}


def _build(values: Mapping[str, Any], source: str) -> Parameters:
    def group(section):
        return {_ATTRIBUTES[k].split(".")[1]: v for k, v in values.items() if k.startswith(section + ".")}

    friction = Friction(**group("friction"))
    control = ControlSettings(**group("control"))
    if control.integration_step > 1.0 / control.servo_rate * (1 + 1e-12):
        raise ParameterError(
            f"integration step {control.integration_step * 1e3:g} ms is longer than the servo period "
            f"{1e3 / control.servo_rate:g} ms; the plant must be integrated at least as finely as the servo runs",
            key="control.integration_step_ms", value=control.integration_step, source=source,
        )
    fields = {_ATTRIBUTES[k]: v for k, v in values.items() if k in _ATTRIBUTES and "." not in _ATTRIBUTES[k]}
    motor = MappingProxyType({k.split(".", 1)[1]: v for k, v in values.items() if k.startswith("motor.")})
    params = Parameters(**fields, friction=friction, control=control, motor=motor, source=source)
    _check_geometry(params, source)
    return params


def _check_geometry(params: Parameters, source: str) -> None:
    """The machine must assemble at home: three distinct screws, levers long enough, platform 1 above 2, sliders above the base."""
    c = params.screw_points
    for i, k in ((0, 1), (1, 2), (0, 2)):
        if np.linalg.norm(c[i] - c[k]) < 1e-6:
            raise ParameterError(
                f"screws {i + 1} and {k + 1} stand at the same place (angles {np.degrees(params.screw_angles[i]):g}° "
                f"and {np.degrees(params.screw_angles[k]):g}°): the three legs must be distinct",
                key="base.screw_angles_deg", value=np.degrees(params.screw_angles), source=source,
            )
    gaps = np.linalg.norm(params.platform_points[:, :2] - params.screw_points[:, :2], axis=1)
    if gaps.max() >= params.lever_length:
        raise ParameterError(
            f"lever of {params.lever_length * 1e3:g} mm cannot reach from its screw to its platform joint "
            f"({gaps.max() * 1e3:.1f} mm apart horizontally at home)",
            key="lever.length_mm",
            value=params.lever_length,
            source=source,
        )
    h1, h2 = params.heights
    if not h1 > h2:
        raise ParameterError(
            f"platform 1 must be the upper one: h_1 = {h1 * 1e3:g} mm is not above h_2 = {h2 * 1e3:g} mm",
            key="platform.heights_mm", value=params.heights, source=source,
        )
    # At home the platform joints lie at height h_j, and each lever drops √(l² − gap²) below its joint.
    lowest = h2 - np.sqrt(params.lever_length**2 - gaps.max() ** 2)
    if lowest <= 0:
        raise ParameterError(
            f"at home the lower platform's sliders would sit {-lowest * 1e3:.1f} mm below the base: "
            f"raise h_2 ({h2 * 1e3:g} mm) or shorten the levers",
            key="platform.heights_mm", value=params.heights, source=source,
        )


def file_values(params: Parameters) -> dict[str, Any]:
    """The parameter set back in the file's units, by dotted key (what ``hipsim params`` prints)."""
    out = {}
    for section, keys in SCHEMA.items():
        for key, spec in keys.items():
            dotted = f"{section}.{key}"
            if section in OPTIONAL_SECTIONS:
                if key in params.motor:
                    out[dotted] = params.motor[key]
                continue
            value = params
            for part in _ATTRIBUTES[dotted].split("."):
                value = getattr(value, part)
            if spec.kind == "bool":
                out[dotted] = bool(value)
                continue
            value = np.asarray(value) / spec.scale
            if spec.kind == "inertia" and np.count_nonzero(value - np.diag(np.diag(value))) == 0:
                value = np.diag(value)
            # 15 significant figures hide the round-off of the unit conversion.
            value = np.vectorize(lambda x: float(f"{x:.15g}"))(value)
            out[dotted] = float(value) if value.ndim == 0 else value.tolist()
    return out
