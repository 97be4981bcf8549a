"""Tests of hipsim.motion.opensim: OpenSim .mot/.sto files of a hip's coordinates in, platform angles out.

The files are written here, from platform angles through rotation matrices
written out in the test (never through hipsim's conversions); when the
``opensim`` package is importable, OpenSim itself reads them and turns a hip
joint built as its gait models build it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from support import Rx, Ry, Rz, machine_R, zxy_angles, zyx_angles

from hipsim import TrajectoryError
from hipsim.motion.build import TrajectoryWarning
from hipsim.motion.hip_angles import PELVIS_AXES
from hipsim.motion.opensim import load_opensim
from hipsim.motion.readers import read_trajectory

HIP = ("hip_flexion", "hip_adduction", "hip_rotation")


def gait(t):
    """Platform angles [rad] of a smooth gait-like motion, (N, 3): well away from any gimbal lock."""
    s = 2 * np.pi * np.asarray(t)
    return np.radians(
        np.stack(
            [3.5 + 21.5 * np.cos(s), 1.5 + 5.5 * np.cos(s - 0.7) + 2 * np.sin(2 * s), -4 + 6 * np.cos(s - np.pi)],
            axis=1,
        )
    )


def hip_coordinates(q):
    """The right hip's ISB chain angles of platform angles q: R = Rz·Ry·Rx, R_h = Cᵀ·R·C, then Z–X–Y, all written out."""
    C = PELVIS_AXES
    return np.array([zxy_angles(C.T @ machine_R(*row) @ C) for row in q])


def mot_text(t, columns: dict, in_degrees: bool | None = True, header_extra: str = "", separator="\t") -> str:
    """An OpenSim 4 .mot file (as its inverse kinematics writes one) of the columns, full precision."""
    lines = ["Coordinates", "version=1", f"nRows={len(t)}", f"nColumns={len(columns) + 1}"]
    if in_degrees is not None:
        lines.append(f"inDegrees={'yes' if in_degrees else 'no'}")
    lines += ["", "Units are S.I. units (second, meters, Newtons, ...)", header_extra, "endheader"]
    lines.append(separator.join(["time", *columns]))
    for k in range(len(t)):
        lines.append(separator.join(repr(float(v)) for v in [t[k], *(values[k] for values in columns.values())]))
    return "\n".join(lines) + "\n"


def write_mot(path, t, q, side="r", in_degrees=True, extra=None, **kwargs):
    hip = hip_coordinates(q)
    if in_degrees:
        hip = np.degrees(hip)
    columns = {"pelvis_tilt": np.zeros(len(t))}
    columns |= {f"{name}_{side}": hip[:, k] for k, name in enumerate(HIP)}
    columns |= {"knee_angle_r": np.full(len(t), 12.0)}
    columns |= extra or {}
    path.write_text(mot_text(t, columns, in_degrees, **kwargs))
    return path


# --------------------------------------------------------------------------- the required check


@pytest.mark.parametrize("in_degrees", [False, True])
def test_mot_from_a_known_R_sequence_reproduces_alpha_beta_gamma(tmp_path, in_degrees):
    t = np.arange(200) / 200  # one cycle without its closing row
    rng = np.random.default_rng(3)
    q = gait(t) + np.radians(rng.uniform(-1, 1, (200, 3)))  # not smooth: only the values are compared
    path = write_mot(tmp_path / "ik.mot", t, q, in_degrees=in_degrees)
    traj = load_opensim(path, periodic=False)
    assert traj.name == str(path) and len(traj) == 200
    np.testing.assert_array_equal(traj.t, t)
    np.testing.assert_allclose(traj.q, q, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(traj.Fe, 0.0)


def test_a_left_hip_drives_the_machine_as_its_mirror_image(tmp_path):
    """OpenSim's left hip turns about +z, −x, −y; mirrored through the sagittal plane it is a right hip."""
    t = np.arange(120) / 120
    coordinates = np.radians(
        np.stack([20 * np.cos(2 * np.pi * t), 6 * np.sin(2 * np.pi * t), -8 + 5 * np.cos(2 * np.pi * t)], axis=1)
    )
    path = tmp_path / "left.mot"
    path.write_text(mot_text(t, {f"{name}_l": np.degrees(coordinates[:, k]) for k, name in enumerate(HIP)}))
    traj = load_opensim(path, side="left", periodic=False)
    M, C = np.diag([1.0, 1.0, -1.0]), PELVIS_AXES
    for k, (f, a, r) in enumerate(coordinates):
        left_femur = Rz(f) @ Rx(-a) @ Ry(-r)  # pelvis axes, OpenSim's left-side axes
        np.testing.assert_allclose(machine_R(*traj.q[k]), C @ M @ left_femur @ M @ C.T, rtol=0, atol=1e-13)
    with pytest.raises(
        TrajectoryError, match=r"no column 'hip_flexion_r' \(the right hip's coordinate\).*the other hip's are there"
    ):
        load_opensim(path)


def test_derivatives_of_a_smooth_mot_match_the_motion(tmp_path):
    t = np.arange(501) / 500  # one whole cycle with its closing row: periodic
    q = gait(t)
    traj = load_opensim(write_mot(tmp_path / "cycle.mot", t, q))
    assert traj.periodic and len(traj) == 500
    h = 1e-5  # central differences of the exact motion
    qd = (gait(traj.t + h) - gait(traj.t - h)) / (2 * h)
    assert np.abs(traj.qd - qd).max() <= 1e-6 * np.abs(qd).max()


# --------------------------------------------------------------------------- the format, as labs write it


def test_old_simm_header_space_separated_and_state_paths(tmp_path):
    t = np.arange(50) / 100
    q = gait(t)
    hip = np.degrees(hip_coordinates(q))
    lines = ["walk.mot", "datacolumns 4", "datarows 50", "range 0 0.49", "inDegrees yes", "endheader"]
    lines.append(
        "time   /jointset/hip_r/hip_flexion_r/value   /jointset/hip_r/hip_adduction_r/value   /jointset/hip_r/hip_rotation_r/value"
    )
    lines += ["  " + "   ".join(repr(float(v)) for v in (t[k], *hip[k])) for k in range(50)]
    path = tmp_path / "walk.mot"
    path.write_text("\n".join(lines) + "\n")
    np.testing.assert_allclose(load_opensim(path).q, q, rtol=0, atol=1e-12)


def test_inDegrees_absent_means_radians_as_OpenSim_reads_it(tmp_path):
    t = np.arange(40) / 100
    q = gait(t)
    np.testing.assert_allclose(
        load_opensim(write_mot(tmp_path / "rad.mot", t, q, in_degrees=None)).q, q, rtol=0, atol=1e-12
    )
    # Degrees in a file that does not say so: refused where they are, not read as radians.
    path = tmp_path / "deg.mot"
    flexion = np.degrees(hip_coordinates(q))
    path.write_text(mot_text(t, {f"{n}_r": flexion[:, k] for k, n in enumerate(HIP)}, in_degrees=None))
    line = 10 + int(np.argmax(np.abs(flexion[:, 0])))  # the labels are on line 9
    with pytest.raises(
        TrajectoryError,
        match=rf"deg.mot, line {line}, column 'hip_flexion_r': .* rad is more than half a turn: these look like degrees",
    ):
        load_opensim(path)


def test_load_column_in_newtons_or_percent_body_weight(tmp_path):
    t = np.arange(30) / 100
    force = 250 + 100 * np.sin(2 * np.pi * t)  # % body weight
    path = write_mot(tmp_path / "jr.sto", t, gait(t), extra={"hip_r_on_pelvis_fy": -force})
    traj = read_trajectory(path, load_column="-hip_r_on_pelvis_fy", body_weight=75 * 9.80665)
    np.testing.assert_allclose(traj.Fe, force / 100 * 75 * 9.80665, rtol=1e-15)
    traj = read_trajectory(path, load_column="-hip_r_on_pelvis_fy:N")
    np.testing.assert_allclose(traj.Fe, force, rtol=1e-15)
    with pytest.raises(
        TrajectoryError, match=r"jr.sto, line 11, column 'hip_r_on_pelvis_fy': load -\d.* N is negative"
    ):
        read_trajectory(path, load_column="hip_r_on_pelvis_fy")


def set_cell(text: str, line: int, column: int, value: str) -> str:
    """The file with the value at 1-based ``line`` and 0-based ``column`` (tab separated) replaced."""
    lines = text.split("\n")
    cells = lines[line - 1].split("\t")
    cells[column] = value
    lines[line - 1] = "\t".join(cells)
    return "\n".join(lines)


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda text: text.replace("endheader\n", ""), "no 'endheader' line: not an OpenSim .mot/.sto file"),
        (
            lambda text: text.replace("inDegrees=yes", "inDegrees=maybe"),
            "line 5: inDegrees must be yes or no, got 'maybe'",
        ),
        (
            lambda text: text.replace("hip_adduction_r", "hip_abduction_r"),
            "line 10: no column 'hip_adduction_r' (the right hip's coordinate)",
        ),
        (lambda text: set_cell(text, 15, 3, "abc"), "line 15, column 'hip_adduction_r': 'abc' is not a number"),
        (lambda text: set_cell(text, 16, 0, "0.04"), "line 16, column 'time': time 0.04 s does not increase"),
        (lambda text: set_cell(text, 17, 2, "nan"), "line 17, column 'hip_flexion_r': 'nan' is not finite"),
        (
            lambda text: "\n".join(x if k != 12 else x.rsplit("\t", 1)[0] for k, x in enumerate(text.split("\n"))),
            "line 13: 5 values, the labels are 6",
        ),
    ],
)
def test_bad_files_are_one_line_naming_file_line_and_column(tmp_path, edit, message):
    t = np.arange(20) / 100
    path = write_mot(tmp_path / "bad.mot", t, gait(t))
    path.write_text(edit(path.read_text()))
    with pytest.raises(TrajectoryError) as info:
        load_opensim(path)
    text = str(info.value)
    assert text.startswith(str(path)) and "\n" not in text
    assert message in text, text


def test_side_and_mapping_mistakes_are_named(tmp_path):
    t = np.arange(20) / 100
    path = write_mot(tmp_path / "ik.mot", t, gait(t))
    with pytest.raises(TrajectoryError, match="side must be 'right' or 'left'"):
        load_opensim(path, side="both")
    with pytest.raises(TrajectoryError, match=r"line 10: no column 'a' \(mapped to alpha\)"):
        read_trajectory(path, columns="time=time,alpha=a,beta=b,gamma=c")


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (
            lambda text: text.replace("nRows=20", "nRows=25"),
            "line 3: the header says 25 rows, the file has 20: the rows are read",
        ),
        (
            lambda text: text.replace("nColumns=6", "nColumns=7"),
            "line 4: the header says 7 columns, the labels are 6: the labels are read",
        ),
    ],
)
def test_header_counts_that_disagree_with_the_data_are_a_warning_and_the_data_win(tmp_path, edit, message):
    t = np.arange(20) / 100
    path = write_mot(tmp_path / "ik.mot", t, gait(t))
    clean = load_opensim(path)
    path.write_text(edit(path.read_text()))
    with pytest.warns(TrajectoryWarning, match=message):
        read = load_opensim(path)
    assert np.array_equal(read.q, clean.q) and np.array_equal(read.qdd, clean.qdd)


def test_a_gait_in_radians_under_inDegrees_yes_is_refused(tmp_path):
    t = np.arange(40) / 100
    path = write_mot(tmp_path / "rad_labelled_deg.mot", t, gait(t), in_degrees=False)
    path.write_text(path.read_text().replace("inDegrees=no", "inDegrees=yes"))  # radians under inDegrees=yes
    with pytest.raises(TrajectoryError, match="the angles look like radians"):
        load_opensim(path)


# --------------------------------------------------------------------------- OpenSim itself, when installed


@pytest.fixture
def osim(tmp_path, monkeypatch):
    opensim = pytest.importorskip("opensim")
    monkeypatch.chdir(tmp_path)  # OpenSim writes its opensim.log into the working folder
    opensim.Logger.setLevelString("off")
    return opensim


def _hip_model(osim, side):
    """A pelvis welded to ground and a femur on a CustomJoint with OpenSim's gait-model hip axes."""
    model = osim.Model()
    pelvis = osim.Body("pelvis", 10.0, osim.Vec3(0, 0, 0), osim.Inertia(1, 1, 1))
    femur = osim.Body(f"femur_{side}", 5.0, osim.Vec3(0, 0, 0), osim.Inertia(1, 1, 1))
    model.addBody(pelvis)
    model.addBody(femur)
    model.addJoint(osim.WeldJoint("ground_pelvis", model.getGround(), pelvis))
    transform = osim.SpatialTransform()
    mirror = 1 if side == "r" else -1
    axes = [(0, 0, 1), (mirror, 0, 0), (0, mirror, 0)]
    for k, (name, axis) in enumerate(zip(HIP, axes)):
        rotation = transform.updTransformAxis(k)
        rotation.setCoordinateNames(osim.ArrayStr(f"{name}_{side}", 1))
        rotation.setAxis(osim.Vec3(*axis))
        rotation.set_function(osim.LinearFunction(1.0, 0.0))
    for k in range(3, 6):
        transform.updTransformAxis(k).set_function(osim.Constant(0.0))
    model.addJoint(osim.CustomJoint(f"hip_{side}", pelvis, femur, transform))
    return model, femur


@pytest.mark.parametrize("side", ["r", "l"])
def test_opensim_reads_the_file_and_turns_the_femur_as_hipsim_says(osim, tmp_path, side):
    t = np.arange(60) / 100
    rng = np.random.default_rng(7)
    coordinates = np.degrees(gait(t)) + rng.uniform(-5, 5, (60, 3))
    path = tmp_path / f"ik_{side}.mot"
    path.write_text(
        mot_text(t, {f"{n}_{side}": coordinates[:, k] for k, n in enumerate(HIP)} | {"knee_angle_r": np.ones(60)})
    )
    traj = load_opensim(path, side="right" if side == "r" else "left", periodic=False)

    storage = osim.Storage(str(path))
    assert storage.isInDegrees() and storage.getSize() == 60
    table = osim.TimeSeriesTable(str(path))
    np.testing.assert_array_equal(np.array(table.getIndependentColumn()), traj.t)
    model, femur = _hip_model(osim, side)
    state = model.initSystem()
    M, C = np.diag([1.0, 1.0, -1.0]), PELVIS_AXES
    for k in range(60):
        for j, name in enumerate(HIP):
            value = table.getDependentColumn(f"{name}_{side}")[k]
            assert value == coordinates[k, j]  # OpenSim reads the numbers hipsim reads
            model.getCoordinateSet().get(f"{name}_{side}").setValue(state, math.radians(value), False)
        model.realizePosition(state)
        rotation = femur.getTransformInGround(state).R()
        Rh = np.array([[rotation.get(i, j) for j in range(3)] for i in range(3)])  # femur in pelvis (= ground) axes
        if side == "l":
            Rh = M @ Rh @ M  # the left femur's mirror image: a right femur
        np.testing.assert_allclose(traj.q[k], zyx_angles(C @ Rh @ C.T), rtol=0, atol=1e-12)
