"""The machine's parameter set (hipsim.machine.parameter_set): the points and axes derived from the published
figures (spec §1, §7.1, written out by hand), shapes checked by key, ``replace`` routing friction and control fields,
the drawing-only refusal, slender levers. Reading the file: test_parameters.py."""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest
from stations_synthetic import deviated

from hipsim import ParameterError, Parameters, load_parameters, slender_levers
from hipsim.machine.parameter_set import FRICTION_COEFFICIENTS, ControlSettings

DEG = math.pi / 180.0
E_MM = 265.0
SMALL_E_MM = 144.0
THETA_DEG = (-60.0, 60.0, 180.0)
DELTA_DEG = 30.0


@pytest.fixture(scope="module")
def params() -> Parameters:
    return load_parameters()


def test_platform_angles_are_minus30_90_210(params):
    np.testing.assert_allclose(np.degrees(params.platform_angles), [-30.0, 90.0, 210.0], rtol=0, atol=1e-12)


def test_screw_points_from_spec_definition(params):
    # c_i = E·[cos θ_i, sin θ_i, 0], computed here from the published figures.
    expected = np.array([[E_MM * math.cos(th * DEG), E_MM * math.sin(th * DEG), 0.0] for th in THETA_DEG]) * 1e-3
    np.testing.assert_allclose(params.screw_points, expected, rtol=0, atol=1e-15)
    # Written out: c_1 = (132.5, -229.5, 0) mm, c_2 = (132.5, 229.5, 0) mm, c_3 = (-265, 0, 0) mm:
    # X is perpendicular to A1A2 and points away from A3.
    half_sqrt3 = math.sqrt(3.0) / 2.0
    np.testing.assert_allclose(
        params.screw_points,
        [[0.1325, -0.265 * half_sqrt3, 0.0], [0.1325, 0.265 * half_sqrt3, 0.0], [-0.265, 0.0, 0.0]],
        rtol=0,
        atol=1e-15,
    )


def test_platform_points_from_spec_definition(params):
    # r0_i = e·[cos φ_i, sin φ_i, 0] with φ_i = θ_i + δ.
    expected = (
        np.array(
            [
                [SMALL_E_MM * math.cos((th + DELTA_DEG) * DEG), SMALL_E_MM * math.sin((th + DELTA_DEG) * DEG), 0.0]
                for th in THETA_DEG
            ]
        )
        * 1e-3
    )
    np.testing.assert_allclose(params.platform_points, expected, rtol=0, atol=1e-15)
    # The platform's y axis passes through a_j2.
    np.testing.assert_allclose(params.platform_points[1], [0.0, 0.144, 0.0], rtol=0, atol=1e-15)
    half_sqrt3 = math.sqrt(3.0) / 2.0
    np.testing.assert_allclose(params.platform_points[0], [0.144 * half_sqrt3, -0.072, 0.0], rtol=0, atol=1e-15)
    np.testing.assert_allclose(params.platform_points[2], [-0.144 * half_sqrt3, -0.072, 0.0], rtol=0, atol=1e-15)


def test_ujoint_axes_are_z_cross_radial(params):
    for i, c in enumerate(params.screw_points):
        u1 = np.cross([0.0, 0.0, 1.0], c / np.linalg.norm(c))
        np.testing.assert_allclose(params.ujoint_axes[i], u1, rtol=0, atol=1e-15)
        assert np.linalg.norm(params.ujoint_axes[i]) == pytest.approx(1.0, abs=1e-15)


def test_parameters_are_immutable(params):
    with pytest.raises(dataclasses.FrozenInstanceError):
        params.lever_length = 1.0
    with pytest.raises(ValueError, match="read-only"):
        params.heights[0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        params.lever_inertia[0, 0] = 1.0


def test_slender_levers_of_a_custom_lever():
    custom = load_parameters(overrides={"lever.inertia_kgmm2": [1900.0, 2100.0, 600.0]})
    np.testing.assert_allclose(slender_levers(custom).lever_inertia, np.diag([2e-3, 2e-3, 0.0]), rtol=1e-14, atol=0)


def test_replace_routes_friction_and_control_fields_to_their_records(params):
    changed = params.replace(hip_mu=0.5, kp=np.array([1.0, 2.0, 3.0]), lever_mass=0.0)
    assert changed.friction.hip_mu == 0.5 and changed.friction.thrust_mu == params.friction.thrust_mu
    assert changed.control.kp.tolist() == [1.0, 2.0, 3.0] and changed.control.kd.tolist() == params.control.kd.tolist()
    assert changed.lever_mass == 0.0
    assert params.friction.hip_mu != 0.5 and params.lever_mass != 0.0  # the original untouched
    # a whole record given wins over its fields (they are then Parameters' own, unknown: refused by dataclasses)
    with pytest.raises(TypeError):
        params.replace(friction=params.friction, hip_mu=0.5)


@pytest.mark.parametrize(
    ("name", "value", "shape"),
    [("screw_angles", np.zeros(2), "(3,)"), ("heights", np.zeros(3), "(2,)"), ("lever_inertia", np.eye(2), "(3, 3)")],
)
def test_a_field_of_the_wrong_shape_is_refused_by_its_key(params, name, value, shape):
    with pytest.raises(ParameterError, match=re.escape(f"expected shape {shape}")) as info:
        params.replace(**{name: value})
    assert info.value.key == name


def test_control_gains_of_the_wrong_shape_name_their_key():
    with pytest.raises(ParameterError) as info:
        ControlSettings(1000.0, 1e-3, np.ones(3), np.ones(2), math.inf)
    assert info.value.key == "control.kd"


def test_a_geometry_that_is_not_a_chain_geometry_is_refused(params):
    with pytest.raises(ParameterError, match="expected a ChainGeometry or None, got dict") as info:
        params.replace(geometry={})
    assert info.value.key == "geometry"


def test_the_drawing_only_refusal_names_what_and_the_geometry_table(params):
    params.require_drawing("the reduced plant")  # the drawing: nothing said
    assert not params.per_chain
    machine = params.replace(geometry=deviated(seed=1, size_mm=0.1))
    assert machine.per_chain
    with pytest.raises(ParameterError, match="not supported by the reduced plant yet") as info:
        machine.require_drawing("the reduced plant")
    assert info.value.key == "geometry"


def test_the_friction_coefficients_are_the_scaled_ones_in_order():
    assert FRICTION_COEFFICIENTS == (
        "hip_mu",
        "thrust_mu",
        "screw_coulomb",
        "screw_viscous",
        "guide_coulomb",
        "guide_viscous",
        "ujoint_coulomb",
        "ujoint_viscous",
        "sjoint_coulomb",
        "sjoint_viscous",
    )


def test_slender_levers_keep_the_mean_transverse_inertia(params):
    lever = params.replace(lever_inertia=np.array([[1.0, 0.3, 0.0], [0.3, 3.0, 0.0], [0.0, 0.0, 9.0]]))
    assert slender_levers(lever).lever_inertia.tolist() == [[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 0.0]]
    assert dataclasses.replace(lever).lever_inertia[2, 2] == 9.0
