"""Tests of hipsim.machine.parameters: the TOML parameter file, SI conversion, overrides, validation.

Expected values come from the spec (the model specification, §1, §7.1, §7.4), written out
here by hand, never from the code's output.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from hipsim import ParameterError, Parameters, load_parameters, slender_levers
from hipsim.machine.parameters import OPTIONAL_SECTIONS, SCHEMA, default_parameters_path, file_values, parse_override

DEG = math.pi / 180.0

# The published figures of spec §1 / §7.1, in the design data's units.
E_MM = 265.0
SMALL_E_MM = 144.0
THETA_DEG = (-60.0, 60.0, 180.0)
DELTA_DEG = 30.0
I_M_KGMM2 = (248030.50, 249940.25, 386502.35)
I_L_LEVER_KGMM2 = (26395.81, 26339.29, 480.07)


# --------------------------------------------------------------------------- helpers


def default_raw() -> dict:
    """The shipped file as TOML reads it (a fresh deep copy, for mutating)."""
    with open(default_parameters_path(), "rb") as stream:
        return copy.deepcopy(tomllib.load(stream))


def toml_value(value) -> str:
    """A Python value as TOML text (numbers, bools, strings, lists, nested lists)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)  # repr of a float (incl. 1e-05, inf, nan) is valid TOML
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    raise TypeError(value)


def toml_text(raw: dict) -> str:
    """Sections of key = value as TOML text (top-level scalars first, as TOML requires)."""
    lines = [f"{key} = {toml_value(value)}" for key, value in raw.items() if not isinstance(value, dict)]
    for section, table in raw.items():
        if isinstance(table, dict):
            lines.append(f"[{section}]")
            lines.extend(f"{key} = {toml_value(value)}" for key, value in table.items())
    return "\n".join(lines) + "\n"


def write_params(tmp_path: Path, raw: dict, name: str = "params.toml") -> Path:
    path = tmp_path / name
    path.write_text(toml_text(raw), encoding="utf-8")
    return path


def mutated(tmp_path: Path, section: str, key: str, value) -> Path:
    raw = default_raw()
    raw[section][key] = value
    return write_params(tmp_path, raw)


def assert_error(info, key: str | None, source: str | Path | None):
    """The ParameterError names the key and the file (or ``--set``)."""
    message = str(info.value)
    if key is not None:
        assert f"'{key}'" in message, message
        assert info.value.key == key
    if source is not None:
        assert str(source) in message, message


def scalar_fields(params: Parameters) -> dict[str, np.ndarray]:
    """Every number of a Parameters object by attribute name (friction and control flattened)."""
    out = {}
    for field in dataclasses.fields(Parameters):
        value = getattr(params, field.name)
        if field.name in ("source", "motor"):  # motor: optional ratings, compared as a dict where needed
            continue
        if dataclasses.is_dataclass(value):  # friction, control
            for f in dataclasses.fields(value):
                out[f"{field.name}.{f.name}"] = np.asarray(getattr(value, f.name), dtype=float)
        else:
            out[field.name] = np.asarray(value, dtype=float)
    return out


# --------------------------------------------------------------------------- the default file


@pytest.fixture(scope="module")
def params() -> Parameters:
    return load_parameters()


def test_default_file_is_shipped_and_loads(params):
    path = default_parameters_path()
    assert path.is_file()
    assert path.name == "hip_simulator.toml"
    assert str(path) in params.source
    # The explicit path gives the same set.
    explicit = load_parameters(str(path))
    for name, value in scalar_fields(params).items():
        np.testing.assert_array_equal(scalar_fields(explicit)[name], value, err_msg=name)


def test_si_conversion_matches_published_figures(params):
    assert params.gravity == pytest.approx(9.8, rel=1e-15)
    assert params.screw_radius == pytest.approx(0.265, rel=1e-14)
    assert params.joint_radius == pytest.approx(0.144, rel=1e-14)
    np.testing.assert_allclose(params.heights, [0.899, 0.490], rtol=1e-14)
    assert params.lever_length == pytest.approx(0.328, rel=1e-14)
    assert params.lead == pytest.approx(0.010, rel=1e-14)
    assert params.screw_inertia == pytest.approx(54.91e-6, rel=1e-12)  # I_L in kg·m²
    assert params.lever_mass == pytest.approx(1.43, rel=1e-15)
    assert params.slider_mass == pytest.approx(3.0, rel=1e-15)
    assert params.platform_mass == pytest.approx(20.0, rel=1e-15)  # the documented estimate
    np.testing.assert_allclose(
        params.platform_inertia, np.diag([0.24803050, 0.24994025, 0.38650235]), rtol=1e-12, atol=0
    )
    np.testing.assert_allclose(params.lever_inertia, np.diag([0.02639581, 0.02633929, 0.00048007]), rtol=1e-12, atol=0)
    np.testing.assert_allclose(params.screw_angles, np.radians(THETA_DEG), rtol=1e-14)
    assert params.home_offset == pytest.approx(math.pi / 6, rel=1e-14)
    np.testing.assert_array_equal(params.angle_signs, [1.0, 1.0, 1.0])


def test_friction_defaults_in_si(params):
    f = params.friction
    assert f.epsilon == pytest.approx(1e-3, rel=1e-15)
    assert f.hip_radius == pytest.approx(0.015, rel=1e-14)
    assert f.hip_mu == pytest.approx(0.095, rel=1e-15)
    assert f.thrust_radius == pytest.approx(0.064, rel=1e-14)
    assert f.thrust_mu == pytest.approx(0.025, rel=1e-15)
    for name in (
        "screw_coulomb",
        "screw_viscous",
        "guide_coulomb",
        "guide_viscous",
        "ujoint_coulomb",
        "ujoint_viscous",
        "sjoint_coulomb",
        "sjoint_viscous",
    ):
        assert getattr(f, name) == 0.0, name
    assert f.thrust_bearing_axial_only is False  # the publication's central-chain friction


def test_axial_thrust_bearing_switch(tmp_path):
    """A boolean key: set in the file or by override, and left out by files written before it existed."""
    assert (
        load_parameters(
            mutated(tmp_path, "friction", "thrust_bearing_axial_only", True)
        ).friction.thrust_bearing_axial_only
        is True
    )
    assert (
        load_parameters(
            overrides=dict([parse_override("friction.thrust_bearing_axial_only=true")])
        ).friction.thrust_bearing_axial_only
        is True
    )
    raw = default_raw()
    del raw["friction"]["thrust_bearing_axial_only"]
    older = load_parameters(write_params(tmp_path, raw, "older.toml"))
    assert older.friction.thrust_bearing_axial_only is False
    assert file_values(older)["friction.thrust_bearing_axial_only"] is False
    with pytest.raises(ParameterError, match="expected true or false, got 'yes'") as info:
        load_parameters(overrides={"friction.thrust_bearing_axial_only": "yes"})
    assert info.value.key == "friction.thrust_bearing_axial_only"


# --------------------------------------------------------------------------- overrides


def test_override_lever_length(params):
    changed = load_parameters(overrides={"lever.length_mm": 330})
    assert changed.lever_length == pytest.approx(0.330, rel=1e-14)
    assert "lever.length_mm=330" in changed.source
    assert str(default_parameters_path()) in changed.source
    # Nothing else moved.
    a, b = scalar_fields(params), scalar_fields(changed)
    for name in a:
        if name != "lever_length":
            np.testing.assert_array_equal(a[name], b[name], err_msg=name)


def test_parse_override_number():
    assert parse_override("lever.length_mm=330") == ("lever.length_mm", 330)
    key, value = parse_override(" friction.hip_mu = 0.1 ")
    assert key == "friction.hip_mu"
    assert value == 0.1 and isinstance(value, float)


def test_parse_override_list_and_load():
    key, value = parse_override("platform.heights_mm=[900, 490]")
    assert key == "platform.heights_mm"
    assert value == [900, 490]
    changed = load_parameters(overrides={key: value})
    np.testing.assert_allclose(changed.heights, [0.900, 0.490], rtol=1e-14)


def test_parse_override_then_load_lever_length():
    key, value = parse_override("lever.length_mm=330")
    assert load_parameters(overrides={key: value}).lever_length == pytest.approx(0.33, rel=1e-14)


def test_override_units_are_the_files():
    changed = load_parameters(
        overrides={
            "friction.guide_viscous_N_s_mm": 0.5,  # 0.5 N·s/mm = 500 N·s/m
            "friction.screw_coulomb_Nmm": 120.0,  # 0.12 N·m
            "friction.sjoint_viscous_Nmm_s_rad": 7.0,  # 0.007 N·m·s/rad
            "platform.home_offset_deg": 0.0,
            "base.screw_angles_deg": [0.0, 120.0, 240.0],
            "convention.angle_signs": [-1, 1, -1],
            "environment.gravity_m_s2": 0.0,
            "lever.mass_kg": 0.0,
            "screw.inertia_kgmm2": 100.0,
        }
    )
    assert changed.friction.guide_viscous == pytest.approx(500.0, rel=1e-14)
    assert changed.friction.screw_coulomb == pytest.approx(0.12, rel=1e-14)
    assert changed.friction.sjoint_viscous == pytest.approx(0.007, rel=1e-14)
    assert changed.home_offset == 0.0
    np.testing.assert_allclose(changed.platform_angles, np.radians([0.0, 120.0, 240.0]), rtol=1e-14)
    np.testing.assert_array_equal(changed.angle_signs, [-1.0, 1.0, -1.0])
    assert changed.gravity == 0.0
    assert changed.lever_mass == 0.0
    assert changed.screw_inertia == pytest.approx(1e-4, rel=1e-14)


def test_override_full_inertia_matrix():
    matrix = [[2000.0, 300.0, 0.0], [300.0, 2000.0, -100.0], [0.0, -100.0, 1000.0]]
    changed = load_parameters(overrides={"platform.inertia_kgmm2": matrix})
    np.testing.assert_allclose(changed.platform_inertia, np.array(matrix) * 1e-6, rtol=1e-14)


def test_override_into_a_file_that_lacks_the_section(tmp_path):
    raw = default_raw()
    del raw["slider"]
    path = write_params(tmp_path, raw)
    assert load_parameters(path, overrides={"slider.mass_kg": 2.5}).slider_mass == 2.5


def test_lever_reach_boundary_from_geometry():
    # At home the horizontal gap from c_i to a_ji is |E·e^{iθ} − e·e^{i(θ+δ)}| =
    # sqrt(E² + e² − 2·E·e·cos δ) = 157.69 mm; a lever just longer reaches, one just shorter does not.
    gap = math.sqrt(E_MM**2 + SMALL_E_MM**2 - 2 * E_MM * SMALL_E_MM * math.cos(DELTA_DEG * DEG))
    assert 157.6 < gap < 157.8
    assert load_parameters(overrides={"lever.length_mm": gap + 0.5}).lever_length == pytest.approx((gap + 0.5) * 1e-3)
    with pytest.raises(ParameterError) as info:
        load_parameters(overrides={"lever.length_mm": gap - 0.5})
    assert_error(info, "lever.length_mm", default_parameters_path())


# --------------------------------------------------------------------------- file_values round trip


def sections_from_file_values(values: dict) -> dict:
    raw: dict = {}
    for dotted, value in values.items():
        section, _, key = dotted.partition(".")
        raw.setdefault(section, {})[key] = value
    return raw


def assert_same_numbers(a: Parameters, b: Parameters, rtol=1e-12):
    fa, fb = scalar_fields(a), scalar_fields(b)
    assert fa.keys() == fb.keys()
    for name in fa:
        np.testing.assert_allclose(fb[name], fa[name], rtol=rtol, atol=0, err_msg=name)


def test_file_values_are_in_the_files_units(params):
    values = file_values(params)
    assert set(values) == {f"{s}.{k}" for s, keys in SCHEMA.items() for k in keys if s not in OPTIONAL_SECTIONS}
    assert values["base.screw_radius_mm"] == pytest.approx(265.0)
    assert values["lever.length_mm"] == pytest.approx(328.0)
    assert values["screw.inertia_kgmm2"] == pytest.approx(54.91)
    assert values["platform.inertia_kgmm2"] == pytest.approx(list(I_M_KGMM2))
    assert values["lever.inertia_kgmm2"] == pytest.approx(list(I_L_LEVER_KGMM2))
    assert values["base.screw_angles_deg"] == pytest.approx(list(THETA_DEG))
    assert values["friction.epsilon_rad_s"] == pytest.approx(1e-3)


@pytest.mark.parametrize(
    "overrides",
    [
        {},
        {
            "platform.inertia_kgmm2": [[2000.0, 300.0, 0.0], [300.0, 2000.0, -100.0], [0.0, -100.0, 1000.0]],
            "convention.angle_signs": [1, -1, -1],
            "friction.thrust_bearing_axial_only": True,
            "friction.guide_viscous_N_s_mm": 0.25,
            "friction.ujoint_coulomb_Nmm": 12.5,
            "platform.home_offset_deg": 17.5,
            "lever.length_mm": 333.3,
        },
    ],
    ids=["default", "changed"],
)
def test_file_values_round_trip_through_toml(tmp_path, overrides):
    original = load_parameters(overrides=overrides)
    values = file_values(original)
    path = write_params(tmp_path, sections_from_file_values(values))
    reloaded = load_parameters(path)
    assert_same_numbers(original, reloaded)
    assert file_values(reloaded) == values
    if "platform.inertia_kgmm2" in overrides:  # a full matrix stays a full matrix
        assert values["platform.inertia_kgmm2"] == overrides["platform.inertia_kgmm2"]


def test_file_values_round_trip_keeps_small_values(tmp_path):
    original = load_parameters(overrides={"friction.epsilon_rad_s": 1e-10, "friction.hip_mu": 1.234567890123e-3})
    path = write_params(tmp_path, sections_from_file_values(file_values(original)))
    assert_same_numbers(original, load_parameters(path))


# --------------------------------------------------------------------------- slender levers


def test_slender_levers(params):
    slender = slender_levers(params)
    transverse = 0.5 * (26395.81 + 26339.29) * 1e-6  # I_t = 26367.55 kg·mm²
    np.testing.assert_allclose(slender.lever_inertia, np.diag([transverse, transverse, 0.0]), rtol=1e-12, atol=0)
    # The original is untouched, and nothing else changed.
    np.testing.assert_allclose(params.lever_inertia, np.diag(I_L_LEVER_KGMM2) * 1e-6, rtol=1e-12)
    a, b = scalar_fields(params), scalar_fields(slender)
    for name in a:
        if name != "lever_inertia":
            np.testing.assert_array_equal(a[name], b[name], err_msg=name)


# --------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    ("section", "key", "value"),
    [
        ("lever", "length_mm", "328"),  # string for a number
        ("lever", "mass_kg", True),  # bool is not a number
        ("environment", "gravity_m_s2", [9.8]),  # list for a number
        ("platform", "heights_mm", [899.0]),  # list length wrong
        ("platform", "heights_mm", [899.0, 490.0, 100.0]),
        ("base", "screw_angles_deg", [-60.0, 60.0]),
        ("base", "screw_angles_deg", [-60.0, "60", 180.0]),
        ("base", "screw_angles_deg", 30.0),  # number for a list
        ("lever", "inertia_kgmm2", [1.0, 2.0]),  # inertia neither 3 nor 3x3
        ("lever", "inertia_kgmm2", [[1.0, 0.0], [0.0, 1.0]]),
        ("lever", "inertia_kgmm2", [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, "x"]]),
        ("screw", "inertia_kgmm2", [54.91, 0.0, 0.0]),  # a scalar inertia given as a list
        ("convention", "angle_signs", [1, 1]),
        ("convention", "angle_signs", [True, True, True]),
        ("friction", "thrust_bearing_axial_only", 1),  # a number for a switch
        ("friction", "thrust_bearing_axial_only", "true"),  # a string for a switch
        ("friction", "thrust_bearing_axial_only", [True]),
    ],
)
def test_wrong_type(tmp_path, section, key, value):
    path = mutated(tmp_path, section, key, value)
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert_error(info, f"{section}.{key}", path)


def test_a_section_that_is_not_a_table(tmp_path):
    raw = default_raw()
    raw["slider"] = 3.0
    path = write_params(tmp_path, raw)
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert_error(info, "slider", path)


def test_unknown_key(tmp_path):
    path = mutated(tmp_path, "lever", "colour_mm", 1.0)
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert_error(info, "lever.colour_mm", path)


def test_unknown_section(tmp_path):
    raw = default_raw()
    raw["gearbox"] = {"ratio": 3.0}
    path = write_params(tmp_path, raw)
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert_error(info, "gearbox", path)


@pytest.mark.parametrize(
    ("section", "key"), [("lever", "mass_kg"), ("friction", "hip_mu"), ("convention", "angle_signs")]
)
def test_missing_key(tmp_path, section, key):
    raw = default_raw()
    del raw[section][key]
    path = write_params(tmp_path, raw)
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert_error(info, f"{section}.{key}", path)


def test_missing_section(tmp_path):
    raw = default_raw()
    del raw["screw"]
    path = write_params(tmp_path, raw)
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert info.value.key in ("screw.lead_mm", "screw.inertia_kgmm2")
    assert_error(info, info.value.key, path)


@pytest.mark.parametrize(
    ("section", "key", "value"),
    [
        ("lever", "length_mm", 0.0),
        ("lever", "length_mm", -328.0),
        ("base", "screw_radius_mm", 0.0),
        ("platform", "joint_radius_mm", -144.0),
        ("platform", "heights_mm", [899.0, -490.0]),
        ("platform", "heights_mm", [0.0, 490.0]),
        ("screw", "lead_mm", 0.0),
        ("friction", "epsilon_rad_s", 0.0),
    ],
)
def test_non_positive_length(tmp_path, section, key, value):
    path = mutated(tmp_path, section, key, value)
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert_error(info, f"{section}.{key}", path)


@pytest.mark.parametrize(
    ("section", "key", "value"),
    [
        ("lever", "mass_kg", -1.43),
        ("slider", "mass_kg", -3.0),
        ("platform", "mass_kg", -0.001),
        ("screw", "inertia_kgmm2", -54.91),
        ("environment", "gravity_m_s2", -9.8),
        ("friction", "hip_mu", -0.095),
        ("friction", "guide_viscous_N_s_mm", -1.0),
    ],
)
def test_negative_mass_or_coefficient(tmp_path, section, key, value):
    path = mutated(tmp_path, section, key, value)
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert_error(info, f"{section}.{key}", path)


def test_zero_masses_are_allowed():
    changed = load_parameters(overrides={"lever.mass_kg": 0.0, "slider.mass_kg": 0, "platform.mass_kg": 0.0})
    assert (changed.lever_mass, changed.slider_mass, changed.platform_mass) == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_non_finite_number(tmp_path, value):
    path = mutated(tmp_path, "environment", "gravity_m_s2", value)
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert_error(info, "environment.gravity_m_s2", path)


@pytest.mark.parametrize(
    ("section", "value"),
    [
        ("lever", [26395.81, 26339.29, -480.07]),  # diagonal with a negative entry
        ("platform", [[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),  # eigenvalues -1, 1, 3
        ("platform", [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1e-3]]),
        ("lever", [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, math.nan]]),
        ("lever", [math.inf, 1.0, 1.0]),
    ],
)
def test_inertia_not_positive_semidefinite(tmp_path, section, value):
    path = mutated(tmp_path, section, "inertia_kgmm2", value)
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert_error(info, f"{section}.inertia_kgmm2", path)


def test_inertia_positive_semidefinite_with_a_zero_is_allowed():
    # A slender rod along (1, 1, 0)/√2: I_t·(1 − u·uᵀ), eigenvalues 0, I_t, I_t.
    rod = [[1.0, -1.0, 0.0], [-1.0, 1.0, 0.0], [0.0, 0.0, 2.0]]
    changed = load_parameters(overrides={"lever.inertia_kgmm2": rod})
    np.testing.assert_allclose(changed.lever_inertia, np.array(rod) * 1e-6, rtol=1e-14, atol=0)


def test_inertia_not_symmetric(tmp_path):
    path = mutated(tmp_path, "platform", "inertia_kgmm2", [[1000.0, 10.0, 0.0], [0.0, 1000.0, 0.0], [0.0, 0.0, 1000.0]])
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert_error(info, "platform.inertia_kgmm2", path)
    assert "symmetric" in str(info.value)


@pytest.mark.parametrize("length_mm", [100, 150.0])
def test_lever_too_short_to_reach(length_mm):
    with pytest.raises(ParameterError) as info:
        load_parameters(overrides={"lever.length_mm": length_mm})
    assert_error(info, "lever.length_mm", default_parameters_path())


def test_lever_too_short_in_a_file(tmp_path):
    path = mutated(tmp_path, "lever", "length_mm", 100.0)
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert_error(info, "lever.length_mm", path)


@pytest.mark.parametrize("signs", [[1, 0, 1], [1, 2, 1], [1, 1, -0.5], [-1, -1, 1.5]])
def test_angle_signs_not_plus_minus_one(tmp_path, signs):
    path = mutated(tmp_path, "convention", "angle_signs", signs)
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert_error(info, "convention.angle_signs", path)


def test_bad_value_through_override_names_key_and_file():
    with pytest.raises(ParameterError) as info:
        load_parameters(overrides={"lever.mass_kg": -1.0})
    assert_error(info, "lever.mass_kg", default_parameters_path())
    with pytest.raises(ParameterError) as info:
        load_parameters(overrides={"platform.heights_mm": [900]})
    assert_error(info, "platform.heights_mm", default_parameters_path())


@pytest.mark.parametrize("text", ["lever.length_mm", "lever.length_mm 330", ""])
def test_override_without_equals(text):
    with pytest.raises(ParameterError) as info:
        parse_override(text, source="--set")
    assert "--set" in str(info.value)
    assert f"'{text}'" in str(info.value)


@pytest.mark.parametrize("text", ["lever.length_mm=abc", "lever.length_mm=", "platform.heights_mm=[900, 490"])
def test_override_value_not_toml(text):
    key = text.partition("=")[0]
    with pytest.raises(ParameterError) as info:
        parse_override(text)
    assert_error(info, key, "override")  # the library does not know the command line's option names


@pytest.mark.parametrize("key", ["lever.colour_mm", "gearbox.ratio", "lever", "length_mm", ""])
def test_unknown_override_key(key):
    with pytest.raises(ParameterError) as info:
        load_parameters(overrides={key: 1.0})
    message = str(info.value)
    assert "--set" not in message
    if key:
        assert_error(info, key, "overrides")
    assert "hipsim params` lists them" in message  # where to find the known keys, not all 38 inline


@pytest.mark.parametrize(
    "text",
    [
        "[lever\nlength_mm = 328.0\n",
        "[lever]\nlength_mm = \n",
        "[lever]\nlength_mm = 328.0\nlength_mm = 329.0\n",
        "this is not toml\n",
    ],
)
def test_invalid_toml(tmp_path, text):
    path = tmp_path / "broken.toml"
    path.write_text(text)
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert_error(info, None, path)
    assert "TOML" in str(info.value)


def test_missing_file(tmp_path):
    path = tmp_path / "nowhere" / "params.toml"
    with pytest.raises(ParameterError) as info:
        load_parameters(path)
    assert_error(info, None, path)


def test_directory_instead_of_file(tmp_path):
    with pytest.raises(ParameterError) as info:
        load_parameters(tmp_path)
    assert_error(info, None, tmp_path)


def test_override_into_a_section_that_is_not_a_table(tmp_path):
    raw = default_raw()
    raw["slider"] = 3.0
    path = write_params(tmp_path, raw)
    with pytest.raises(ParameterError) as info:
        load_parameters(path, overrides={"slider.mass_kg": 3.0})
    assert_error(info, "slider", path)


def test_optional_motor_ratings(tmp_path):
    """The [motor] table may be absent or partial; what is given is checked like any key."""
    assert dict(load_parameters().motor) == {}
    params = load_parameters(overrides={"motor.peak_torque_Nmm": 1910, "motor.stroke_mm": 200})
    assert dict(params.motor) == {"peak_torque_Nmm": 1910.0, "stroke_mm": 200.0}
    assert file_values(params)["motor.stroke_mm"] == 200.0
    with pytest.raises(ParameterError, match="motor.max_speed_rpm.*must be positive"):
        load_parameters(overrides={"motor.max_speed_rpm": -5})


# --------------------------------------------------------------------------- typos and unit slips


@pytest.mark.parametrize(
    ("section", "key", "value", "message"),
    [
        ("friction", "epsilon_rad_s", 1e300, r"out of range: at most 1e\+09 rad/s"),
        ("platform", "home_offset_deg", 1e30, "out of range: at most 360 deg"),
        ("base", "screw_angles_deg", [-60.0, 60.0, 540.0], "out of range: at most 360 deg"),
        ("base", "screw_angles_deg", [0.0, 0.0, 180.0], "screws 1 and 2 stand at the same place"),
        ("lever", "inertia_kgmm2", [1.0, 1.0, 100.0], "no rigid body has these principal moments"),
        ("platform", "inertia_kgmm2", [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.5]], "no rigid body"),
    ],
)
def test_values_no_machine_has_are_refused_by_key(tmp_path, section, key, value, message):
    path = mutated(tmp_path, section, key, value)
    with pytest.raises(ParameterError, match=message) as info:
        load_parameters(path)
    assert_error(info, f"{section}.{key}", path)


def test_a_slender_rod_is_a_rigid_body():
    """The triangle inequality's equality case (I_z = 0, I_x = I_y) is allowed: spec §7.4's levers."""
    params = load_parameters(overrides={"lever.inertia_kgmm2": [1000.0, 1000.0, 0.0]})
    assert params.lever_inertia[2, 2] == 0.0


def test_a_byte_order_mark_is_accepted(tmp_path, params):
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + default_parameters_path().read_bytes())
    assert load_parameters(path).lever_length == params.lever_length


def test_an_unknown_override_suggests_the_nearest_key():
    with pytest.raises(ParameterError, match=r"did you mean 'lever.length_mm'\?") as info:
        load_parameters(overrides={"lever.lenght_mm": 330})
    assert len(str(info.value)) < 200  # not the list of every key


def test_an_override_without_a_key_says_so():
    with pytest.raises(ParameterError, match="no key before '='"):
        parse_override("=5")


def test_the_command_line_names_its_option(capsys):
    from hipsim.cli import main

    assert main(["params", "--set", "lever.colour_mm=1"]) == 2
    assert "--set, key 'lever.colour_mm'" in capsys.readouterr().err
