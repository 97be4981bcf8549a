"""The MJCF (hipsim/mujoco_engine/mjcf.py): compiled, its keyframe closed, following the parameters, its tree
and visuals against the URDF as Pinocchio and meshcat read it.

Skipped when ``mujoco`` is not installed or too old (the ``test`` extra installs it).
"""

from __future__ import annotations

import io

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

mujoco = pytest.importorskip("mujoco")

import hipsim  # noqa: E402
from hipsim.exceptions import MissingDependencyError  # noqa: E402

try:
    import hipsim.mujoco_engine
except MissingDependencyError as error:  # installed, but a release the engine refuses
    pytest.skip(str(error), allow_module_level=True)

from hipsim.closed_chain.build import load_model as load_pinocchio  # noqa: E402
from hipsim.machine.model_files import urdf_text  # noqa: E402
from hipsim.motion.trajectories import iso14242_at  # noqa: E402
from hipsim.mujoco_engine.mjcf import KEYFRAME, MjcfSettings, keyframe_gap, mjcf_text, write_mjcf  # noqa: E402


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


@pytest.fixture(scope="module")
def model(params, tmp_path_factory):
    """The MJCF written to a file and compiled back from it, as a user gets it."""
    path = write_mjcf(params, tmp_path_factory.mktemp("mjcf") / "hip.xml")
    return mujoco.MjModel.from_xml_path(str(path))


def _rank(J: np.ndarray) -> int:
    sigma = np.linalg.svd(J, compute_uv=False)
    return int(np.sum(sigma > 1e-9 * sigma[0]))


def test_mjcf_compiles_with_three_degrees_of_freedom_after_the_closures(model):
    assert (model.nq, model.nv, model.neq, model.nu) == (21, 21, 6, 3)
    assert np.all(model.eq_type == mujoco.mjtEq.mjEQ_CONNECT)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, KEYFRAME))
    mujoco.mj_forward(model, data)
    assert data.nefc == 18  # the closures only: no contacts, no joint limits
    J = data.efc_J.reshape(data.nefc, model.nv)
    assert model.nv - _rank(J) == 3
    # and it is the closures that remove them: without them all 21 joints are free.
    assert _rank(J[:15]) == 15


def test_keyframe_is_the_iso_start_with_closures_closed(params, model):
    assert keyframe_gap(model) <= 1e-9  # measured 1.2e-16 m after writing and reading the file
    key = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, KEYFRAME)
    start = iso14242_at(np.array([0.0]))
    names = [[f"platform_{j}_r{axis}" for axis in "xyz"] for j in (1, 2)]
    for joints in names:
        angles = [model.key_qpos[key, model.joint(name).qposadr[0]] for name in joints]
        np.testing.assert_allclose(angles, params.angle_signs * start.q[0], atol=1e-15)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, key)
    mujoco.mj_forward(model, data)
    closure_rates = data.efc_J.reshape(18, model.nv) @ data.qvel
    assert np.abs(closure_rates).max() < 1e-12
    rates = [data.qvel[model.joint(name).dofadr[0]] for name in names[0]]
    np.testing.assert_allclose(rates, params.angle_signs * start.qd[0], atol=1e-14)
    # The controls are the motor torques of the cycle's first sample, as the analytic model gives them.
    expected = hipsim.analyse(params, start, lever_spin=True).torques.total[0]
    np.testing.assert_allclose(model.key_ctrl[key], expected, rtol=0, atol=1e-9 * np.abs(expected).max())


def test_the_mjcf_follows_the_parameters(params):
    changed = params.replace(lead=0.005, screw_inertia=80e-6, torque_limit=1.5, lever_length=0.33)
    model = mujoco.MjModel.from_xml_string(mjcf_text(changed))
    sliders = [model.joint(f"slider_{i}").dofadr[0] for i in (1, 2, 3)]
    np.testing.assert_allclose(model.dof_armature[sliders], 80e-6 * (2 * np.pi / 0.005) ** 2, rtol=1e-15)
    assert np.count_nonzero(model.dof_armature) == 3
    np.testing.assert_allclose(model.actuator_gear[:, 0], 2 * np.pi / 0.005, rtol=1e-15)
    np.testing.assert_allclose(model.actuator_ctrlrange, [[-1.5, 1.5]] * 3)
    assert np.all(model.actuator_ctrllimited)
    assert model.site("lever_11_tip").pos[2] == pytest.approx(0.33, abs=1e-15)
    assert keyframe_gap(model) <= 1e-9
    # A motor torque τ pushes its carriage with (2π/p)·τ.
    data = mujoco.MjData(model)
    data.ctrl[:] = [0.3, -0.2, 0.1]
    mujoco.mj_forward(model, data)
    np.testing.assert_allclose(data.qfrc_actuator[sliders], 2 * np.pi / 0.005 * np.array([0.3, -0.2, 0.1]), rtol=1e-14)
    # Settings are written as asked: integrator, step, the closures' softness.
    model = mujoco.MjModel.from_xml_string(
        mjcf_text(params, MjcfSettings(timestep=1e-3, integrator="Euler"), keyframe=False)
    )
    assert model.opt.timestep == 1e-3 and model.opt.integrator == mujoco.mjtIntegrator.mjINT_EULER and model.nkey == 0
    np.testing.assert_allclose(model.eq_solref, [[2e-3, 1.0]] * 6)  # two steps with Euler
    np.testing.assert_allclose(model.eq_solimp[:, :2], 0.9999)


def _pinocchio_map(model, chain):
    """MuJoCo dof indices and the Pinocchio velocity indices of the same joints, by name."""
    names = [model.joint(k).name for k in range(model.njnt)]
    return (
        np.array([model.joint(n).dofadr[0] for n in names]),
        np.array([chain.model.joints[chain.model.getJointId(n)].idx_v for n in names]),
    )


def test_tree_is_the_urdf_tree_as_pinocchio_reads_it(params, model):
    """At random configurations (not closed): closure frames, mass matrix and gravity, joint by joint."""
    chain = load_pinocchio(params)
    mj, pn = _pinocchio_map(model, chain)
    data, pdata = mujoco.MjData(model), chain.model.createData()
    rng = np.random.default_rng(7)
    for _ in range(5):
        q_pin = rng.uniform(-0.6, 0.6, chain.model.nq)
        q_mj = np.empty(model.nq)
        q_mj[mj] = q_pin[pn]
        data.qpos[:] = q_mj
        mujoco.mj_forward(model, data)
        pin.framesForwardKinematics(chain.model, pdata, q_pin)
        for a, b in chain.closure_frames:
            for frame in (a, b):
                expected = pdata.oMf[chain.model.getFrameId(frame)].translation
                np.testing.assert_allclose(data.site(frame).xpos, expected, rtol=0, atol=1e-14)
        M = np.zeros((model.nv, model.nv))
        if hasattr(data, "qM"):  # MuJoCo 3.x
            mujoco.mj_fullM(model, M, data.qM)
        else:
            mujoco.mj_fullM(model, data, M)
        M_pin = pin.crba(chain.model, pdata, q_pin)  # the armature included, as in MuJoCo
        M_pin = np.triu(M_pin) + np.triu(M_pin, 1).T
        np.testing.assert_allclose(M[np.ix_(mj, mj)], M_pin[np.ix_(pn, pn)], rtol=0, atol=1e-13 * np.abs(M_pin).max())
        gravity = pin.computeGeneralizedGravity(chain.model, pdata, q_pin)
        np.testing.assert_allclose(data.qfrc_bias[mj], gravity[pn], rtol=0, atol=1e-12 * np.abs(gravity).max())


def test_visual_geometry_is_the_meshcat_scene(params, model):
    """Every URDF visual (what the meshcat viewer draws through Pinocchio) is a geom in the same place, size and colour."""
    chain = load_pinocchio(params)
    links = {
        link.name: link for link in yourdfpy.URDF.load(io.StringIO(urdf_text(params)), load_meshes=False).robot.links
    }
    mj, pn = _pinocchio_map(model, chain)
    q_pin = np.random.default_rng(3).uniform(-0.4, 0.4, chain.model.nq)
    q_mj = np.empty(model.nq)
    q_mj[mj] = q_pin[pn]
    data = mujoco.MjData(model)
    data.qpos[:] = q_mj
    mujoco.mj_forward(model, data)
    pdata, gdata = chain.model.createData(), chain.visual_model.createData()
    pin.forwardKinematics(chain.model, pdata, q_pin)
    pin.updateGeometryPlacements(chain.model, pdata, chain.visual_model, gdata)
    assert model.ngeom == len(chain.visual_model.geometryObjects) == 30
    for k, g in enumerate(chain.visual_model.geometryObjects):
        link, _, index = g.name.rpartition("_")
        geom = data.geom(links[link].visuals[int(index)].name)
        placement = gdata.oMg[k]
        np.testing.assert_allclose(geom.xpos, placement.translation, rtol=0, atol=1e-14)
        shape = g.geometry
        kind = model.geom_type[geom.id]
        if kind == mujoco.mjtGeom.mjGEOM_SPHERE:
            np.testing.assert_allclose(model.geom_size[geom.id][0], shape.radius, rtol=1e-15)
        else:  # a cylinder or box is turned as well
            np.testing.assert_allclose(geom.xmat.reshape(3, 3), placement.rotation, rtol=0, atol=1e-14)
            size = [shape.radius, shape.halfLength] if kind == mujoco.mjtGeom.mjGEOM_CYLINDER else shape.halfSide
            np.testing.assert_allclose(model.geom_size[geom.id][: len(size)], size, rtol=1e-15)
        material = model.geom_matid[geom.id]
        np.testing.assert_allclose(model.mat_rgba[material], g.meshColor, atol=1e-7)  # Pinocchio keeps float32
        assert model.geom_contype[geom.id] == 0 and model.geom_conaffinity[geom.id] == 0
    np.testing.assert_array_equal(model.body_mass[1:] > 0, True)  # the geoms add no mass: bodies have the URDF's
