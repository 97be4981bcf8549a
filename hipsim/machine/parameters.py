"""The machine's parameter file read: one TOML file, checked and loaded into an immutable object in SI units.

The file (``models/hip_simulator.toml`` is the default) is written in the
design data's units (mm, kg, kg·mm², N·mm, degrees), with the unit in every
key. :func:`load_parameters` checks every key against :data:`SCHEMA`, converts
to SI and returns a frozen :class:`Parameters`. Both the analytic and the
Pinocchio model read this one object, so a change in the file changes both.
The objects are :mod:`hipsim.machine.parameter_set`'s, the layout
:mod:`hipsim.machine.schema`'s; :mod:`hipsim.machine.toml_writer` writes a file back.

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
import tomllib
import warnings
from collections.abc import Mapping
from importlib import resources
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from ..exceptions import ParameterError
from .parameter_set import ControlSettings, Friction, Parameters, slender_levers
from .schema import OPTIONAL_SECTIONS, SCHEMA, Key, plausible_ranges

__all__ = [
    "ATTRIBUTES",
    "ControlSettings",
    "Friction",
    "Parameters",
    "OPTIONAL_SECTIONS",
    "ParameterWarning",
    "SCHEMA",
    "check_entry",
    "default_parameters_path",
    "file_values",
    "check_key",
    "implausible",
    "implausible_message",
    "load_parameters",
    "override_parameters",
    "parse_override",
    "read_toml",
    "slender_levers",
]


class ParameterWarning(UserWarning):
    """A parameter outside its plausible range for this class of machine (:func:`implausible`): loaded, but likely a slip.

    The command line prints it as ``hipsim: warning: …``; in Python, turn it
    into an error with ``warnings.simplefilter("error", ParameterWarning)``.
    """


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
        data = data.removeprefix(codecs.BOM_UTF8)
        return tomllib.loads(data.decode("utf-8"))
    except FileNotFoundError:
        raise ParameterError(f"no such {what}", source=source) from None
    except IsADirectoryError:
        raise ParameterError(f"is a folder, not a {what}", source=source) from None
    except OSError as error:
        raise ParameterError(f"cannot read ({error.strerror})", source=source) from None
    except UnicodeDecodeError as error:  # a Latin-1 "é" in a comment, say: the line to look at
        line = data.count(b"\n", 0, error.start) + 1
        raise ParameterError(
            f"line {line}: not UTF-8 text (byte 0x{data[error.start]:02x}); save the file as UTF-8", source=source
        ) from None
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
    params = _build(_check(raw, source), source)
    for key, value, (low, high) in implausible(params):
        warnings.warn(implausible_message(key, value, (low, high), source), ParameterWarning, stacklevel=2)
    return params


def implausible(params: Parameters) -> list[tuple[str, Any, tuple[float, float]]]:
    """The parameters outside their plausible range for this class of machine (:attr:`hipsim.machine.schema.Key.plausible`).

    A vector is outside when one of its elements is; an inertia when one of its diagonal elements is.
    Zero is plausible for a mass, an inertia and any key that may be zero
    (:attr:`~hipsim.machine.schema.Key.bound` "nonnegative"): a part left out of the model.

    Args:
        params: the machine.

    Returns:
        (dotted key, value in the file's unit, (low, high) in the file's unit), in the file's order; empty when all are plausible.
    """
    values = file_values(params)
    out = []
    for key, (low, high, _) in plausible_ranges().items():
        if key not in values:
            continue  # an optional [motor] key the machine does not have
        numbers = np.asarray(values[key], dtype=float)
        if numbers.ndim == 2:
            numbers = np.diag(numbers)
        section, _, name = key.partition(".")
        spec = SCHEMA[section][name]
        off = (numbers == 0) & (spec.bound == "nonnegative" or spec.kind == "inertia")  # a part left out of the model
        if np.any(((numbers < low) | (numbers > high)) & ~off):
            out.append((key, values[key], (low, high)))
    return out


def implausible_message(key: str, value: Any, plausible: tuple[float, float], source: str | None = None) -> str:
    """One line naming an implausible parameter, its value and its range (for :class:`ParameterWarning` and callers that refuse)."""
    section, _, name = key.partition(".")
    unit = SCHEMA[section][name].unit
    shown = f"{value:g}" if isinstance(value, float) else str(value)
    low, high = plausible
    where = f"{source}: " if source else ""
    return (
        f"{where}key '{key}' = {shown}{' ' + unit if unit else ''} is outside the plausible range {low:g} to {high:g}"
        f"{' ' + unit if unit else ''} for this class of machine (a unit slip?)"
    )


def check_key(dotted: str, source: str = "overrides") -> tuple[str, str]:
    """The section and key of a dotted key of :data:`SCHEMA`, e.g. ``"lever.length_mm"`` → ``("lever", "length_mm")``.

    Raises:
        ParameterError: naming the key and ``source`` when it is unknown, with the nearest known key.
    """
    section, _, key = dotted.partition(".")
    if section not in SCHEMA or key not in SCHEMA[section]:
        raise ParameterError(
            f"unknown key{_did_you_mean(dotted)}; `hipsim params` lists them all", key=dotted, source=source
        )
    return section, key


def override_parameters(
    params: Parameters, overrides: Mapping[str, Any], overrides_source: str = "overrides"
) -> Parameters:
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
    for dotted, attribute in ATTRIBUTES.items():
        value = params
        for part in attribute.split("."):
            value = getattr(value, part)
        values[dotted] = value
    values |= {f"motor.{key}": value for key, value in params.motor.items()}
    for dotted, value in overrides.items():
        section, key = check_key(dotted, overrides_source)
        values[dotted] = _convert(value, SCHEMA[section][key], dotted, overrides_source)
    source = (
        params.source + " with " + ", ".join(f"{k}={v}" for k, v in overrides.items()) if overrides else params.source
    )
    return _build(values, source)


def _did_you_mean(dotted: str) -> str:
    """ " (did you mean 'lever.length_mm'?)" for the nearest known keys, or nothing."""
    known = [f"{s}.{k}" for s, keys in SCHEMA.items() for k in keys]
    close = difflib.get_close_matches(dotted, known, n=1, cutoff=0.6)
    return f" (did you mean {' or '.join(repr(k) for k in close)}?)" if close else ""


def _check(raw: Mapping[str, Any], source: str) -> dict[str, Any]:
    """Every key of SCHEMA present, typed and within bounds; returns SI values by dotted key."""
    for section, table in raw.items():
        if section == "identification":  # what hipsim identify read or wrote: hipsim.rig.identification.uncertainty reads it
            continue
        if section not in SCHEMA:
            raise ParameterError(f"unknown section (known: {', '.join(SCHEMA)})", key=section, source=source)
        if not isinstance(table, dict):
            raise ParameterError("expected a [section] table", key=section, source=source)
        for key in table:
            if key not in SCHEMA[section]:
                known = ", ".join(SCHEMA[section])
                raise ParameterError(
                    f"unknown key (known in [{section}]: {known})", key=f"{section}.{key}", source=source
                )
    values = {}
    missing = []
    for section, keys in SCHEMA.items():
        for key, spec in keys.items():
            dotted = f"{section}.{key}"
            if key not in raw.get(section, {}):
                if section in OPTIONAL_SECTIONS:
                    continue
                if spec.default is not None:
                    values[dotted] = spec.default
                    continue
                missing.append((dotted, spec))
                continue
            values[dotted] = _convert(raw[section][key], spec, dotted, source)
    # A wrong value first (a negative lever length is the file's problem, not the keys it leaves out), then the first missing key.
    if missing:
        dotted, spec = missing[0]
        more = (
            f" (and {len(missing) - 1} more keys: start from the file `hipsim params` prints)"
            if len(missing) > 1
            else ""
        )
        raise ParameterError(f"missing ({spec.meaning}, in {spec.unit or 'no unit'}){more}", key=dotted, source=source)
    return values


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _convert(value, spec: Key, key: str, source: str):
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
        fail(
            f"no rigid body has these principal moments: {eigenvalues[2]:g} exceeds the sum of the other two "
            f"({eigenvalues[0]:g} + {eigenvalues[1]:g})"
        )
    return matrix


#: Where each file entry lands in :class:`Parameters`: dotted file key → dotted attribute path (``friction.hip_mu``).
ATTRIBUTES = {
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
    **{
        f"friction.{key}": f"friction.{name}"
        for key, name in zip(SCHEMA["friction"], (f.name for f in dataclasses.fields(Friction)))
    },
    **{
        f"control.{key}": f"control.{name}"
        for key, name in zip(SCHEMA["control"], (f.name for f in dataclasses.fields(ControlSettings)))
    },
}


def _build(values: Mapping[str, Any], source: str) -> Parameters:
    def group(section):
        return {ATTRIBUTES[k].split(".")[1]: v for k, v in values.items() if k.startswith(section + ".")}

    friction = Friction(**group("friction"))
    control = ControlSettings(**group("control"))
    if control.integration_step > 1.0 / control.servo_rate * (1 + 1e-12):
        raise ParameterError(
            f"integration step {control.integration_step * 1e3:g} ms is longer than the servo period "
            f"{1e3 / control.servo_rate:g} ms; the plant must be integrated at least as finely as the servo runs",
            key="control.integration_step_ms",
            value=control.integration_step,
            source=source,
        )
    fields = {ATTRIBUTES[k]: v for k, v in values.items() if k in ATTRIBUTES and "." not in ATTRIBUTES[k]}
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
                key="base.screw_angles_deg",
                value=np.degrees(params.screw_angles),
                source=source,
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
            key="platform.heights_mm",
            value=params.heights,
            source=source,
        )
    # At home the platform joints lie at height h_j, and each lever drops √(l² − gap²) below its joint.
    lowest = h2 - np.sqrt(params.lever_length**2 - gaps.max() ** 2)
    if lowest <= 0:
        raise ParameterError(
            f"at home the lower platform's sliders would sit {-lowest * 1e3:.1f} mm below the base: "
            f"raise h_2 ({h2 * 1e3:g} mm) or shorten the levers",
            key="platform.heights_mm",
            value=params.heights,
            source=source,
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
            for part in ATTRIBUTES[dotted].split("."):
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
