"""Per-chain geometry: the [geometry] table, each platform's inverse and forward kinematics, their derivatives."""

import numpy as np
import pytest
from support import given

import hipsim
from hipsim.analytic.inverse_kinematics import slider_heights, slider_jacobian
from hipsim.analytic.stations import (
    attitude_sensitivities,
    carriage_sensitivities,
    carriages_for_platform,
    follower_motion,
    platform_attitude,
    platform_jacobian,
    platform_motion,
)
from hipsim.exceptions import ParameterError
from hipsim.machine.chains import ChainGeometry, geometry_table
from hipsim.machine.toml_writer import parameter_toml

PARAMS = hipsim.load_parameters()
RNG = np.random.default_rng(34)
#: A machine built to ~0.3 mm: every deviation drawn at 0.3 mm standard deviation.
DEVIATED = PARAMS.replace(geometry=ChainGeometry.from_vector(RNG.normal(0.0, 0.3e-3, 48)))


def walking(n=501):
    """A smooth periodic motion like the built-in cycle (gait angles, rates, accelerations), by hand."""
    t = np.linspace(0.0, 1.0, n)
    w = 2 * np.pi
    amp, mean, lag = np.radians([21.5, 5.5, 6.0]), np.radians([3.5, 1.5, -4.0]), np.array([0.0, 0.7, np.pi])
    phase = w * t[:, None] - lag
    return t, mean + amp * np.cos(phase), -w * amp * np.sin(phase), -(w**2) * amp * np.cos(phase)


def random_poses(n=200):
    return np.radians(RNG.uniform(-1, 1, (n, 3)) * [20.0, 7.0, 10.0])


# --- The drawing, kept -------------------------------------------------------------------


def test_drawing_carriages_are_todays_slider_heights_bit_for_bit():
    q = random_poses()
    today = slider_heights(PARAMS, q)[:, 0, :]
    for platform in (1, 2):
        assert np.array_equal(carriages_for_platform(PARAMS, q, platform), today)
        assert np.array_equal(platform_jacobian(PARAMS, q, platform), slider_jacobian(PARAMS, q))


def test_zero_deviations_through_the_per_chain_path_give_the_drawing():
    zero = PARAMS.replace(geometry=ChainGeometry.zeros())
    q = random_poses()
    today = slider_heights(PARAMS, q)[:, 0, :]
    for platform in (1, 2):
        np.testing.assert_allclose(carriages_for_platform(zero, q, platform), today, rtol=0, atol=1e-15)
        np.testing.assert_allclose(platform_jacobian(zero, q, platform), slider_jacobian(PARAMS, q), rtol=0, atol=1e-14)


def test_a_zero_table_is_the_drawing(tmp_path):
    path = tmp_path / "zero.toml"
    path.write_text(parameter_toml(PARAMS) + "[geometry]\nlever_offset_mm = [0, 0, 0, 0, 0, 0]\n", encoding="utf-8")
    assert hipsim.load_parameters(path).geometry is None


def test_the_drawings_functions_refuse_a_per_chain_machine():
    with pytest.raises(ParameterError, match="per-chain geometry is not supported"):
        slider_heights(DEVIATED, np.zeros((1, 3)))


# --- Hand-computed deviations at home ----------------------------------------------------


def home_carriage(i=0, lever_mm=328.0, gap_extra=(0.0, 0.0)):
    """Carriage reading of module i (0, 1, 2) for platform 1 at home in mm, from spec §1 and §7.1 by hand.

    θ = (−60°, 60°, 180°), φ = θ + 30°, E = 265 mm, e = 144 mm, h_1 = 899 mm; ``gap_extra`` is taken off the
    horizontal gap a − c.
    """
    theta = np.radians([-60.0, 60.0, 180.0][i])
    c = 265.0 * np.array([np.cos(theta), np.sin(theta)])
    a = 144.0 * np.array([np.cos(theta + np.radians(30)), np.sin(theta + np.radians(30))])
    gap = a - c - np.array(gap_extra)
    return 899.0 - np.sqrt(lever_mm**2 - gap @ gap)


DRAWING_HOME = [home_carriage(i) for i in range(3)]
CENTRE_HOME = [home_carriage(i, gap_extra=(-0.1, -0.2)) - 0.3 for i in range(3)]  # o_1 moved (0.1, 0.2, −0.3) mm


@pytest.mark.parametrize(
    ("key", "row", "expected_mm"),
    [
        (
            "slider_offset_mm",
            [0.3, 0, 0, 0, 0, 0],
            [DRAWING_HOME[0] - 0.3, *DRAWING_HOME[1:]],
        ),  # slider higher: carriage lower
        ("lever_offset_mm", [0, 0.3, 0, 0, 0, 0], [DRAWING_HOME[0], home_carriage(1, 328.3), DRAWING_HOME[2]]),
        (
            "ujoint_offset_mm",
            [[0.2, -0.1]] + [[0, 0]] * 5,
            [home_carriage(0, gap_extra=(0.2, -0.1)), *DRAWING_HOME[1:]],
        ),
        (
            "joint_offset_mm",
            [[0, 0, 0]] * 2 + [[0, 0, 0.4]] + [[0, 0, 0]] * 3,
            [*DRAWING_HOME[:2], DRAWING_HOME[2] + 0.4],
        ),
        ("centre_offset_mm", [[0.1, 0.2, -0.3], [0, 0, 0]], CENTRE_HOME),
    ],
)
def test_one_deviation_at_home_by_hand(tmp_path, key, row, expected_mm):
    path = tmp_path / "one.toml"
    path.write_text(parameter_toml(PARAMS) + f"[geometry]\n{key} = {row}\n", encoding="utf-8")
    params = hipsim.load_parameters(path)
    home = np.zeros((1, 3))
    np.testing.assert_allclose(carriages_for_platform(params, home, 1)[0] * 1e3, expected_mm, rtol=0, atol=1e-9)
    # Platform 2's chains are untouched: its readings stay the drawing's.
    np.testing.assert_allclose(carriages_for_platform(params, home, 2)[0] * 1e3, DRAWING_HOME, rtol=0, atol=1e-9)


def test_platform_2s_slider_offset_moves_its_carriage_reading_one_for_one():
    geometry = ChainGeometry.zeros().replace(slider=np.array([[0, 0, 0], [0, 0.5e-3, 0]]))
    q = random_poses(20)
    shift = carriages_for_platform(PARAMS.replace(geometry=geometry), q, 2) - carriages_for_platform(PARAMS, q, 2)
    np.testing.assert_allclose(shift, np.array([0.0, -0.5e-3, 0.0]) + 0 * shift, rtol=0, atol=1e-15)


# --- Forward ∘ inverse kinematics --------------------------------------------------------


@pytest.mark.parametrize("platform", [1, 2])
def test_forward_of_inverse_is_the_identity_along_a_motion(platform):
    t, q, _, _ = walking()
    L = carriages_for_platform(DEVIATED, q, platform)
    assert np.abs(platform_attitude(DEVIATED, L, platform, t=t, q0=q[0]) - q).max() < 1e-12


@pytest.mark.parametrize("platform", [1, 2])
def test_forward_of_inverse_is_the_identity_at_random_poses(platform):
    q = random_poses(40)
    L = carriages_for_platform(DEVIATED, q, platform)
    back = np.array([platform_attitude(DEVIATED, L[k : k + 1], platform, q0=q[k])[0] for k in range(len(q))])
    assert np.abs(back - q).max() < 1e-12


def test_the_two_platforms_of_a_deviated_machine_turn_differently():
    t, q, _, _ = walking()
    L = carriages_for_platform(DEVIATED, q, 2)
    follower = platform_attitude(DEVIATED, L, 1, t=t, q0=q[0])
    error = np.degrees(np.abs(follower - q).max(axis=0))
    # 0.3 mm over lever arms of ~0.1–0.3 m: of order 0.1–1°, as the simulated machine shows.
    assert np.all(error > 0.01) and np.all(error < 3.0)


# --- Derivatives against finite differences ----------------------------------------------


@pytest.mark.parametrize("platform", [1, 2])
def test_jacobian_against_finite_differences(platform):
    q = random_poses(30)
    J = platform_jacobian(DEVIATED, q, platform)
    T = hipsim.analytic.inverse_kinematics.angular_velocity_map(q)
    h = 1e-6
    for k in range(3):
        dq = np.zeros(3)
        dq[k] = h
        fd = (
            carriages_for_platform(DEVIATED, q + dq, platform) - carriages_for_platform(DEVIATED, q - dq, platform)
        ) / (2 * h)
        np.testing.assert_allclose(np.einsum("nij,nj->ni", J, T[:, :, k]), fd, rtol=0, atol=1e-9)


@pytest.mark.parametrize("platform", [1, 2])
def test_carriage_rates_and_accelerations_against_finite_differences(platform):
    t, q, qd, qdd = walking(4001)
    L, Ld, Ldd = platform_motion(DEVIATED, q, qd, qdd, platform)
    dt = t[1] - t[0]
    np.testing.assert_allclose(Ld[1:-1], (L[2:] - L[:-2]) / (2 * dt), rtol=0, atol=2e-6 * np.abs(Ld).max())
    np.testing.assert_allclose(Ldd[1:-1], (Ld[2:] - Ld[:-2]) / (2 * dt), rtol=0, atol=2e-6 * np.abs(Ldd).max())
    assert np.array_equal(L, carriages_for_platform(DEVIATED, q, platform))


def test_follower_motion_against_finite_differences_and_round_trip():
    t, q, qd, qdd = walking(4001)
    L, Ld, Ldd = platform_motion(DEVIATED, q, qd, qdd, 2)
    # The controlled platform back from its own carriages: its rates and accelerations exactly.
    q2, qd2, qdd2 = follower_motion(DEVIATED, L, Ld, Ldd, 2, t=t, q0=q[0])
    np.testing.assert_allclose(q2, q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(qd2, qd, rtol=0, atol=1e-10)
    np.testing.assert_allclose(qdd2, qdd, rtol=0, atol=1e-8)
    # The follower: its rates are the time derivatives of its attitude.
    q1, qd1, qdd1 = follower_motion(DEVIATED, L, Ld, Ldd, 1, t=t, q0=q[0])
    dt = t[1] - t[0]
    np.testing.assert_allclose(qd1[1:-1], (q1[2:] - q1[:-2]) / (2 * dt), rtol=0, atol=2e-6 * np.abs(qd1).max())
    np.testing.assert_allclose(qdd1[1:-1], (qd1[2:] - qd1[:-2]) / (2 * dt), rtol=0, atol=2e-6 * np.abs(qdd1).max())


# --- The parameter file ------------------------------------------------------------------


def test_file_round_trip(tmp_path):
    path = tmp_path / "built.toml"
    path.write_text(parameter_toml(DEVIATED.replace(geometry=DEVIATED.geometry.replace(control=1))), encoding="utf-8")
    back = hipsim.load_parameters(path)
    assert back.geometry.control == 1
    np.testing.assert_allclose(back.geometry.as_vector(), DEVIATED.geometry.as_vector(), rtol=1e-14, atol=1e-19)
    assert "[geometry]" in parameter_toml(DEVIATED) and "[geometry]" not in parameter_toml(PARAMS)


def test_overrides_set_one_key():
    params = hipsim.load_parameters(overrides={"geometry.lever_offset_mm": [0, 0, 0, 0, 0.25, 0]})
    assert params.geometry.lever[1, 1] == pytest.approx(0.25e-3, abs=1e-18)
    again = hipsim.machine.parameters.override_parameters(params, {"geometry.slider_offset_mm": [0.1, 0, 0, 0, 0, 0]})
    assert given(again.geometry).lever[1, 1] == given(params.geometry).lever[1, 1] and given(again.geometry).slider[
        0, 0
    ] == pytest.approx(1e-4)


def test_vector_names_and_round_trip():
    names = ChainGeometry.names()
    assert len(names) == 51 == len(set(names))
    assert names[0] == "ujoint_x_11" and names[47] == "centre_z_2" and "lever_22" in names
    assert names[48:] == ("spline_x_1", "spline_y_1", "spline_z_1")
    x = RNG.normal(size=51)
    assert np.array_equal(ChainGeometry.from_vector(x).as_vector(), x)
    g = ChainGeometry.from_vector(x)
    assert g.lever[1, 1] == x[names.index("lever_22")] and g.joint[0, 2, 1] == x[names.index("joint_y_13")]
    assert geometry_table(g)["centre_offset_mm"][1][2] == pytest.approx(x[names.index("centre_z_2")] * 1e3)
    assert geometry_table(g)["spline_seat_mm"][1] == pytest.approx(x[names.index("spline_y_1")] * 1e3)
    # The chains' 48 alone (as before the stack-up): the seat zero.
    assert np.array_equal(ChainGeometry.from_vector(x[:48]).as_vector(), np.concatenate([x[:48], np.zeros(3)]))


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ("lever_offset_mm = [0, 0, 0]", "geometry.lever_offset_mm.*6 numbers"),
        ("joint_offset_mm = [[0, 0]] ", "geometry.joint_offset_mm.*6 rows"),
        ("slider_offset_mm = [0, 0, 0, 0, 0, 80]", "at most 50 mm"),
        ("lever_offset = [0, 0, 0, 0, 0, 0]", "geometry.lever_offset.*unknown key"),
        ('centre_offset_mm = [[0, 0, "x"], [0, 0, 0]]', "centre_offset_mm"),
        ("control = 3\nlever_offset_mm = [0.1, 0, 0, 0, 0, 0]", "geometry.control.*1 or 2"),
    ],
)
def test_bad_tables_are_refused_by_name(tmp_path, table, message):
    path = tmp_path / "bad.toml"
    path.write_text(parameter_toml(PARAMS) + "[geometry]\n" + table + "\n", encoding="utf-8")
    with pytest.raises(ParameterError, match=message) as caught:
        hipsim.load_parameters(path)
    assert "bad.toml" in str(caught.value) and "\n" not in str(caught.value)


# --- Sensitivities to the geometry (for calibration and tolerances) --------------------------


def with_values(x):
    return PARAMS.replace(geometry=ChainGeometry.from_vector(x))


@pytest.mark.parametrize("platform", [1, 2])
def test_carriage_sensitivities_against_finite_differences(platform):
    x = DEVIATED.geometry.as_vector()
    q = random_poses(5)
    S = carriage_sensitivities(DEVIATED, q, platform)
    h = 1e-7
    for k in range(48):
        step = np.zeros(x.size)
        step[k] = h
        fd = (
            carriages_for_platform(with_values(x + step), q, platform)
            - carriages_for_platform(with_values(x - step), q, platform)
        ) / (2 * h)
        np.testing.assert_allclose(S[:, :, k], fd, rtol=0, atol=1e-8, err_msg=ChainGeometry.names()[k])
    # Only the platform's own chains and centre move its carriages; its slider offset one for one.
    own = [
        k
        for k, name in enumerate(ChainGeometry.names())
        if name[-2:-1] == str(platform) or name.endswith(f"_{platform}")
    ]
    assert np.all(np.delete(S, own, axis=2) == 0.0)
    assert np.all(S[:, :, 12 + 3 * (platform - 1) : 15 + 3 * (platform - 1)] == -np.eye(3))


@pytest.mark.parametrize("platform", [1, 2])
def test_attitude_sensitivities_against_finite_differences_of_the_forward_kinematics(platform):
    x = DEVIATED.geometry.as_vector()
    q = random_poses(4)
    L = carriages_for_platform(DEVIATED, q, platform)
    A = attitude_sensitivities(DEVIATED, q, platform)
    h = 1e-6
    names = ChainGeometry.names()
    for name in (
        f"ujoint_x_{platform}1",
        f"slider_{platform}2",
        f"joint_z_{platform}3",
        f"lever_{platform}1",
        f"centre_y_{platform}",
    ):
        k = names.index(name)
        step = np.zeros(x.size)
        step[k] = h
        moved = [
            np.array([platform_attitude(with_values(x + s), L[n : n + 1], platform, q0=q[n])[0] for n in range(len(q))])
            for s in (step, -step)
        ]
        np.testing.assert_allclose(
            A[:, :, k],
            (moved[0] - moved[1]) / (2 * h),
            rtol=0,
            atol=1e-6 * np.abs(A[:, :, k]).max() + 1e-9,
            err_msg=name,
        )


def test_the_urdf_stands_m1_on_the_spline_and_the_shaft_end_on_the_seat():
    """With a stack-up the tree carries the intermediate chain: its joints, and where its frames sit at home, read from the XML."""
    import xml.etree.ElementTree as ET

    from hipsim.machine.chains import STACKUP_CLOSURE, STACKUP_JOINTS
    from hipsim.machine.model_files import closure_declaration, urdf_text

    seat = np.array([1e-3, 2e-3, -1e-3])
    stacked = PARAMS.replace(geometry=given(DEVIATED.geometry).replace(spline=seat))
    joints = {j.get("name"): j for j in ET.fromstring(urdf_text(stacked)).iter("joint")}

    def read(joint, tag: str, key: str) -> str:  # an attribute of a joint's sub-element
        return str(given(given(joint.find(tag)).get(key)))

    slide, tip_x, tip_y = (joints[name] for name in STACKUP_JOINTS)
    assert [j.get("type") for j in (slide, tip_x, tip_y)] == ["prismatic"] * 3
    assert [read(j, "axis", "xyz") for j in (slide, tip_x, tip_y)] == ["0 0 1", "1 0 0", "0 1 0"]
    spline = read(slide, "child", "link")
    assert read(joints["platform_1_rz"], "parent", "link") == spline == read(tip_x, "parent", "link")
    parent_of = {read(j, "child", "link"): j for j in joints.values()}

    def home(link):  # a link's origin at zero joint values: the joints' offsets summed up to the base (no rotations)
        out = np.zeros(3)
        while link in parent_of:
            assert read(parent_of[link], "origin", "rpy") == "0 0 0"
            out += np.array(read(parent_of[link], "origin", "xyz").split(), dtype=float)
            link = read(parent_of[link], "parent", "link")
        return out

    chains = stacked.chains
    np.testing.assert_allclose(home("platform_1"), chains.centres[0], rtol=0, atol=1e-15)
    for frame in STACKUP_CLOSURE:  # the shaft's end on the seat o_2 + e
        np.testing.assert_allclose(home(frame), chains.centres[1] + seat, rtol=0, atol=1e-15)
    declared = closure_declaration(stacked)
    assert declared["closed_loop"][-1] == list(STACKUP_CLOSURE) and declared["type"] == ["3d"] * 7
    # A zero seat is today's tree and closures, to the byte.
    zero = PARAMS.replace(geometry=given(DEVIATED.geometry).replace(spline=np.zeros(3)))
    assert urdf_text(zero) == urdf_text(DEVIATED) and "spline" not in urdf_text(zero)
    assert len(closure_declaration(zero)["closed_loop"]) == 6
