"""The human model beside the machine: its hip axes, and a femur that turns exactly as the platforms do, with the ISB signs."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from hipsim.analytic.inverse_kinematics import rotation_matrix
from hipsim.present.human import HUMAN_PELVIS_ROTATION, human_hip_angles, load_human


@pytest.fixture(scope="module")
def human():
    model, _ = load_human()
    return model, model.createData()


def _human_pose(human, alpha, beta, gamma):
    model, data = human
    R = rotation_matrix(np.radians([[alpha, beta, gamma]]))[0]
    angles = human_hip_angles(R)
    q = pin.neutral(model)
    for name, value in zip(("right_hip_Z", "right_hip_X", "right_hip_Y"), angles):
        q[model.joints[model.getJointId(name)].idx_q] = value
    pin.forwardKinematics(model, data, q)
    C = HUMAN_PELVIS_ROTATION
    joint = {
        name: data.oMi[model.getJointId(name)]
        for name in ("right_hip_Z", "right_hip_Y", "right_knee_Z", "right_ankle_X")
    }
    femur = C @ joint["right_hip_Y"].rotation @ C.T  # femur rotation, world axes, relative to standing
    knee = C @ (joint["right_knee_Z"].translation - joint["right_hip_Z"].translation)  # world axes
    toes = C @ joint["right_ankle_X"].rotation[:, 0]  # the foot's anterior axis, world axes
    return R, angles, femur, knee, toes


def test_human_model_hip_axes_are_as_documented(human):
    """The URDF's right hip: Z (mediolateral, +z to the right) flexion, X about −x, Y about +y; ISB pelvis axes."""
    model, _ = human
    axes = {}
    for name in ("right_hip_Z", "right_hip_X", "right_hip_Y", "left_hip_Z"):
        joint = model.joints[model.getJointId(name)]
        axes[name] = joint.shortname()
    assert axes["right_hip_Z"] == "JointModelRZ"
    assert axes["right_hip_X"] in ("JointModelRX", "JointModelRevoluteUnaligned")
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    right = data.oMi[model.getJointId("right_hip_Z")].translation
    left = data.oMi[model.getJointId("left_hip_Z")].translation
    assert right[2] > 0 > left[2]  # pelvis z points to the subject's right
    assert data.oMi[model.getJointId("right_knee_Z")].translation[1] < right[1]  # y up: the knee is below


def test_human_femur_turns_exactly_as_the_platform(human):
    rng = np.random.default_rng(5)
    for angles in rng.uniform(-30.0, 30.0, (20, 3)):
        R, _, femur, _, _ = _human_pose(human, *angles)
        assert np.abs(femur - R).max() <= 1e-12


def test_human_anatomical_signs(human):
    # Positive α is flexion: the knee moves forward (+Y, where the subject faces) and up.
    _, hip, _, knee, _ = _human_pose(human, 20.0, 0.0, 0.0)
    assert knee[1] > 0.1 and knee[2] > -0.439 + 0.02 and hip[0] == pytest.approx(math.radians(20.0))
    _, _, _, knee_ext, _ = _human_pose(human, -15.0, 0.0, 0.0)
    assert knee_ext[1] < -0.05  # extension: backward
    # Positive β is adduction: the right knee moves medially, towards −X (the subject's left).
    _, hip, _, knee, _ = _human_pose(human, 0.0, 10.0, 0.0)
    assert knee[0] < -0.07 and hip[1] == pytest.approx(math.radians(-10.0))  # the model's right_hip_X > 0 is abduction
    # Positive γ is internal rotation: the toes turn medially (towards −X).
    _, hip, _, knee, toes = _human_pose(human, 0.0, 0.0, 15.0)
    assert toes[0] == pytest.approx(-math.sin(math.radians(15.0))) and hip[2] == pytest.approx(math.radians(15.0))
    assert np.allclose(knee, [0.0, 0.0, -0.439])  # rotation leaves the knee where it is
