"""The xacro → URDF expansion and the closure file: structure, numbers, loaders, staleness.

The geometric checks use yourdfpy's forward kinematics (not Pinocchio's) and
the spec's own formulas (§2, §7.1), so they test the URDF, not the code that
wrote it.
"""

from __future__ import annotations

import re

import numpy as np
import pinocchio as pin
import pytest
import yaml
import yourdfpy

import hipsim.machine.model_files as model_files
from hipsim import ModelError, load_parameters
from hipsim.machine.model_files import (
    closure_file_path,
    default_urdf_path,
    urdf_text,
    write_urdf,
    xacro_arguments,
    xacro_path,
)

JOINTS = (
    [f"slider_{i}" for i in (1, 2, 3)]
    + [f"u{k}_{j}{i}" for j in (1, 2) for i in (1, 2, 3) for k in (1, 2)]
    + [f"platform_{j}_r{axis}" for j in (1, 2) for axis in "zyx"]
)


@pytest.fixture(scope="module")
def params():
    return load_parameters()


@pytest.fixture(scope="module")
def urdf(params, tmp_path_factory):
    path = tmp_path_factory.mktemp("urdf") / "hip.urdf"
    write_urdf(params, path)
    return yourdfpy.URDF.load(str(path), load_meshes=False)


def _rot(axis: str, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return {
        "x": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
        "y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
        "z": np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]),
    }[axis]


def test_committed_urdf_is_not_stale(params):
    assert default_urdf_path().read_text(encoding="utf-8") == urdf_text(params), (
        "models/hip_simulator.urdf is stale: regenerate it with `hipsim urdf --out models/hip_simulator.urdf`"
    )


def test_expansion_is_deterministic(params):
    assert urdf_text(params) == urdf_text(load_parameters())


def test_every_xacro_arg_is_filled_and_used(params):
    declared = set(re.findall(r'<xacro:arg\s+name="([^"]+)"', xacro_path().read_text(encoding="utf-8")))
    assert declared == set(xacro_arguments(params))


def test_a_missing_arg_is_a_model_error(params, monkeypatch):
    def incomplete(p):
        args = xacro_arguments(p)
        del args["lever_length"]
        return args

    monkeypatch.setattr(model_files, "xacro_arguments", incomplete)
    with pytest.raises(ModelError, match="xacro"):
        urdf_text(params)


def test_write_is_atomic_and_leaves_no_temporary(params, tmp_path):
    path = tmp_path / "out.urdf"
    path.write_text("old")
    assert write_urdf(params, path) == path
    assert path.read_text(encoding="utf-8") == urdf_text(params)
    assert [p.name for p in tmp_path.iterdir()] == ["out.urdf"]


def test_yourdfpy_validates_links_and_joints(urdf):
    assert urdf.validate(), urdf._errors
    assert set(JOINTS) <= set(urdf.joint_map)
    assert urdf.base_link == "base_link"
    for name in JOINTS:
        assert urdf.joint_map[name].type == ("prismatic" if name.startswith("slider") else "revolute")
    for j in (1, 2):
        for i in (1, 2, 3):
            assert f"lever_{j}{i}_tip" in urdf.link_map
            assert f"platform_{j}_joint_{i}" in urdf.link_map


def test_limits_are_generous(urdf, params):
    h1, l = params.heights[0], params.lever_length
    for name in JOINTS:
        limit = urdf.joint_map[name].limit
        assert limit.effort > 0 and limit.velocity > 0
        if name.startswith("slider"):
            assert limit.lower == 0.0 and limit.upper > h1 + l
        else:
            assert limit.lower == pytest.approx(-np.pi) and limit.upper == pytest.approx(np.pi)


def test_masses_and_inertias(urdf, params):
    links = urdf.link_map
    for j in (1, 2):
        for i in (1, 2, 3):
            inertial = links[f"lever_{j}{i}"].inertial
            assert inertial.mass == params.lever_mass
            np.testing.assert_array_equal(inertial.inertia, params.lever_inertia)
            np.testing.assert_allclose(inertial.origin[:3, 3], [0, 0, params.lever_length / 2], atol=1e-15)
            np.testing.assert_array_equal(inertial.origin[:3, :3], np.eye(3))
            assert links[f"ujoint_{j}{i}_cross"].inertial is None
        platform = links[f"platform_{j}"].inertial
        assert platform.mass == params.platform_mass
        np.testing.assert_array_equal(platform.inertia, params.platform_inertia)
        np.testing.assert_array_equal(platform.origin, np.eye(4))
        assert links[f"platform_{j}_gimbal_z"].inertial is None
    for i in (1, 2, 3):
        carriage = links[f"carriage_{i}"].inertial
        assert carriage.mass == 2 * params.slider_mass
        assert np.all(np.linalg.eigvalsh(carriage.inertia) > 0)
    total = sum(link.inertial.mass for link in urdf.robot.links if link.inertial is not None)
    assert total == pytest.approx(6 * params.lever_mass + 6 * params.slider_mass + 2 * params.platform_mass)


def test_every_link_has_a_visual(urdf):
    massive = [link for link in urdf.robot.links if link.inertial is not None]
    assert all(link.visuals for link in massive)
    assert len(urdf.link_map["base_link"].visuals) >= 6  # plate, column, two hip balls, three screws


def test_geometry_follows_the_spec(urdf, params):
    """At a random configuration: b_ji, the U-joint axes, the lever frame (§7.1), the platform (§2)."""
    rng = np.random.default_rng(1)
    cfg = {name: rng.uniform(-0.6, 0.6) for name in JOINTS}
    cfg.update({f"slider_{i}": rng.uniform(0.3, 0.6) for i in (1, 2, 3)})
    urdf.update_cfg(cfg)
    h = params.heights
    for i in (1, 2, 3):
        c, u1 = params.screw_points[i - 1], params.ujoint_axes[i - 1]
        for j in (1, 2):
            T = urdf.get_transform(f"lever_{j}{i}", "base_link")
            b = c + (cfg[f"slider_{i}"] - (h[0] - h[j - 1])) * np.array([0, 0, 1])
            np.testing.assert_allclose(T[:3, 3], b, atol=1e-14)
            x, y, e = T[:3, :3].T
            # u1 is fixed in the carriage, u2 = lever x = (e × u1)/|e × u1|, y = z × x.
            np.testing.assert_allclose(x, np.cross(e, u1) / np.linalg.norm(np.cross(e, u1)), atol=1e-14)
            np.testing.assert_allclose(y, np.cross(e, x), atol=1e-14)
            tip = urdf.get_transform(f"lever_{j}{i}_tip", "base_link")[:3, 3]
            np.testing.assert_allclose(tip, b + params.lever_length * e, atol=1e-14)
    for j in (1, 2):
        R = _rot("z", cfg[f"platform_{j}_rz"]) @ _rot("y", cfg[f"platform_{j}_ry"]) @ _rot("x", cfg[f"platform_{j}_rx"])
        T = urdf.get_transform(f"platform_{j}", "base_link")
        np.testing.assert_allclose(T[:3, :3], R, atol=1e-14)
        np.testing.assert_allclose(T[:3, 3], [0, 0, h[j - 1]], atol=1e-15)
        for i in (1, 2, 3):
            a = urdf.get_transform(f"platform_{j}_joint_{i}", "base_link")[:3, 3]
            np.testing.assert_allclose(a, T[:3, 3] + R @ params.platform_points[i - 1], atol=1e-14)


def test_zero_configuration_has_upright_levers(urdf, params):
    urdf.update_cfg({name: 0.0 for name in JOINTS})
    for i in (1, 2, 3):
        c = params.screw_points[i - 1]
        R = urdf.get_transform(f"lever_1{i}", "base_link")[:3, :3]
        np.testing.assert_allclose(R[:, 2], [0, 0, 1], atol=1e-15)
        np.testing.assert_allclose(R[:, 0], -c / np.linalg.norm(c), atol=1e-15)
        np.testing.assert_allclose(R[:, 1], -params.ujoint_axes[i - 1], atol=1e-15)


def test_pinocchio_loads_it_and_agrees_with_yourdfpy(urdf):
    text = default_urdf_path().read_text(encoding="utf-8")
    model = pin.buildModelFromXML(text)
    visual = pin.buildGeomFromUrdfString(model, text, pin.GeometryType.VISUAL)
    assert (model.nq, model.nv) == (21, 21)
    assert visual.ngeoms == len([v for link in urdf.robot.links for v in link.visuals])
    data = model.createData()
    rng = np.random.default_rng(2)
    q = rng.uniform(-0.5, 0.5, model.nq)
    pin.framesForwardKinematics(model, data, q)
    urdf.update_cfg({name: q[model.joints[model.getJointId(name)].idx_q] for name in JOINTS})
    for link in ("lever_23_tip", "platform_1_joint_2", "carriage_3", "lever_12"):
        expected = urdf.get_transform(link, "base_link")
        np.testing.assert_allclose(data.oMf[model.getFrameId(link)].homogeneous, expected, atol=1e-14)
    # Massless intermediate links must not break the mass matrix.
    M = pin.crba(model, data, q)
    M = np.triu(M) + np.triu(M, 1).T
    assert np.linalg.eigvalsh(M).min() > 0


def test_changing_the_parameter_file_changes_the_urdf(params):
    longer = load_parameters(overrides={"lever.length_mm": 340})
    text = urdf_text(longer)
    assert text != urdf_text(params)
    model = pin.buildModelFromXML(text)
    tip = model.frames[model.getFrameId("lever_11_tip")].placement.translation
    np.testing.assert_allclose(tip, [0, 0, 0.34], atol=1e-15)
    assert model.inertias[model.getJointId("u2_11")].lever[2] == pytest.approx(0.17)


def test_closure_file(params):
    content = yaml.safe_load(closure_file_path().read_text(encoding="utf-8"))
    pairs = [tuple(pair) for pair in content["closed_loop"]]
    assert sorted(pairs) == sorted((f"lever_{j}{i}_tip", f"platform_{j}_joint_{i}") for j in (1, 2) for i in (1, 2, 3))
    assert content["type"] == ["3d"] * 6
    assert content["name_mot"] == ["slider_1", "slider_2", "slider_3"]
    # The file's own transmission is the published machine's (hipsim overrides it from the parameters).
    for joint in content["name_mot"]:
        assert content["transmission"][joint]["lead_m"] == pytest.approx(params.lead, rel=1e-12)
        assert content["transmission"][joint]["rotor_inertia_kgm2"] == pytest.approx(params.screw_inertia, rel=1e-12)


def test_write_urdf_refuses_what_a_second_parser_cannot_read(tmp_path, monkeypatch):
    """yourdfpy reads every URDF before it is written: a joint whose parent link is missing is refused, no file left."""
    good = urdf_text()
    broken = good.replace('<parent link="carriage_1"/>', '<parent link="no_such_link"/>', 1)
    assert broken != good
    monkeypatch.setattr(model_files, "urdf_text", lambda params=None: broken)
    with pytest.raises(ModelError, match="no_such_link.*does not exist"):
        write_urdf(None, tmp_path / "broken.urdf")
    assert list(tmp_path.iterdir()) == []
    monkeypatch.setattr(
        model_files, "urdf_text", lambda params=None: "<robot name='x'><link name='a'/>"
    )  # not even XML
    with pytest.raises(ModelError, match="cannot read"):
        write_urdf(None, tmp_path / "cut.urdf")
    assert list(tmp_path.iterdir()) == []
