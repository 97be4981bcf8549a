"""The human model beside the machine: example-robot-data's ``human`` URDF, its right hip turning as the platforms do.

The human model (``Viewer(human=True)`` in :mod:`hipsim.present.viewer`,
example-robot-data's ``human`` URDF, life size) stands beside the machine;
its right hip turns exactly as the platforms do. Machine axes map onto the
body as X → the subject's right, Y → anterior, Z → superior, so α (about X)
is flexion, β (about Y) adduction and γ (about Z) internal rotation, each
positive (ISB convention for a right hip). The femur's orientation relative
to the pelvis is then R = Rz(γ)·Ry(β)·Rx(α) expressed in the pelvis axes,
decomposed into the model's hip joints, which follow the ISB joint
coordinate system (right_hip_Z flexion, right_hip_X about −X so positive is
abduction, right_hip_Y internal rotation): see :func:`human_hip_angles`. The
angles used are the platform's (the parameter set's angle_signs applied), so
the thigh always turns exactly as the platforms do.

Where the body stands is :data:`HUMAN_PELVIS_ROTATION` and
:data:`HUMAN_PELVIS_POSITION`; :func:`load_human` finds and loads the model.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pinocchio as pin

from ..exceptions import ModelError
from ..motion.hip_angles import PELVIS_AXES, hip_angles_of

__all__ = [
    "HIP_JOINTS",
    "HUMAN_PELVIS_POSITION",
    "HUMAN_PELVIS_ROTATION",
    "human_hip_angles",
    "load_human",
]

#: Human model placement: pelvis axes (ISB: x anterior, y superior, z right) in world axes, as columns
#: (x_p -> +Y, y_p -> +Z, z_p -> +X): the machine's own mapping onto the body, hipsim.motion.hip_angles.PELVIS_AXES.
HUMAN_PELVIS_ROTATION = PELVIS_AXES
#: Where the human's pelvis frame stands, in [m]: beside the machine (on its +Y side, facing +Y), feet on the floor.
HUMAN_PELVIS_POSITION = np.array([0.0, 0.9, 1.056])
_HUMAN_URDF = "example-robot-data/robots/human_description/robots/human.urdf"
#: The model's right-hip joints, in the order :func:`human_hip_angles` gives their values.
HIP_JOINTS = ("right_hip_Z", "right_hip_X", "right_hip_Y")


def human_hip_angles(R: np.ndarray) -> np.ndarray:
    """The human model's right-hip joint values that turn its femur exactly as the platforms turn.

    With the pelvis placed by :data:`HUMAN_PELVIS_ROTATION` (machine X = the
    subject's right, Y = anterior, Z = superior), the femur's world rotation
    equals the platform's R when its rotation relative to the pelvis is
    R_h = Cᵀ·R·C, C = HUMAN_PELVIS_ROTATION. The model's hip is
    R_h = Rz(z)·R₋ₓ(x)·Ry(y) (joints right_hip_Z about +z, right_hip_X about
    −x, right_hip_Y about +y), so with b = −x: R_h = Rz(z)·Rx(b)·Ry(y), the
    ISB hip chain of :mod:`hipsim.motion.hip_angles` with b its adduction:
    (z, b, y) = :func:`~hipsim.motion.hip_angles.hip_angles_of` (R).

    One angle at a time, z = α (flexion), x = −β (β > 0 is adduction, the
    model's right_hip_X > 0 abduction), y = γ (internal rotation). Combined,
    they differ: the machine's R turns about the fixed vertical first (γ) and
    flexes last, the ISB hip flexes first and rotates about the femur last.
    Along the built-in ISO cycle the model's adduction differs from β by up to
    4.8° (it spans +5.0°/−4.1° where β spans +7°/−4°), its rotation from γ by
    up to 1.9° and its flexion from α by up to 0.9°: the human shows the
    motion the rig actually produces.

    Args:
        R: platform rotations, shape (3, 3) or (N, 3, 3).

    Returns:
        [right_hip_Z, right_hip_X, right_hip_Y] in [rad], shape (3,) or (N, 3).
    """
    flexion, adduction, rotation = np.moveaxis(hip_angles_of(R), -1, 0)
    return np.stack([flexion, -adduction, rotation], axis=-1)


def _human_urdf() -> tuple[Path, Path]:
    """(human.urdf, the share folder that resolves its package:// meshes)."""
    candidates = []
    try:
        from importlib import metadata

        candidates.append(Path(str(metadata.distribution("example-robot-data").locate_file("cmeel.prefix/share"))))
    except Exception:  # any failure: try the paths below
        pass
    candidates += [Path(p) / "cmeel.prefix" / "share" for p in sys.path if p]
    candidates += [Path(sys.prefix) / "share", Path("/opt/openrobots/share"), Path("/usr/share")]
    for share in candidates:
        if (share / _HUMAN_URDF).is_file():
            return share / _HUMAN_URDF, share
    raise ModelError("cannot find example-robot-data's human model (pip install example-robot-data)")


def load_human() -> tuple[pin.Model, pin.GeometryModel]:
    """example-robot-data's human model (life size) and its visual geometry.

    Raises:
        ModelError: example-robot-data is not installed.
    """
    urdf, share = _human_urdf()
    model = pin.buildModelFromUrdf(str(urdf))
    visual = pin.buildGeomFromUrdf(model, str(urdf), pin.GeometryType.VISUAL, package_dirs=[str(share)])
    return model, visual
