"""hipsim.rig.logs.log pinned on tiny logs written here (100 Hz, a few hundred samples): a log in memory's checks,
rate, usable samples and thinned angles; a log read in pieces: its notes, edge, halo and piece size worked out by
hand, windows whose cores tile the log and give the whole log's values, the encoders' angles (the heights written from
the inverse kinematics, another route) against the attitude sensor, and errors naming the file, line and column.
"""

from __future__ import annotations

import gc
import hashlib
import math
import warnings

import numpy as np
import pytest
from support import given

import hipsim
from hipsim.analytic.inverse_kinematics import slider_heights
from hipsim.exceptions import ArgumentError, TrajectoryError
from hipsim.motion.trajectories import Trajectory
from hipsim.rig.logs.log import (
    DEFAULT_CUTOFF,
    DEFAULT_TOLERANCE_DEG,
    PIECE,
    SPLINE_HALO,
    LogInfo,
    LogPieces,
    MeasuredLog,
    load_log,
)
from hipsim.rig.logs.reader import RigLogFile
from hipsim.rig.logs.smoothing import filter_halo

RATE = 100.0


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


def motion(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Times in [s] and gait angles in [deg] of a slow swing: α 12 sin(πt), β −4 + 3 cos(πt), γ 5 sin(2πt)."""
    t = np.arange(n) / RATE
    q = np.column_stack([12 * np.sin(np.pi * t), -4 + 3 * np.cos(np.pi * t), 5 * np.sin(2 * np.pi * t)])
    return t, q


def write_log(path, n: int, params=None, angles=True, heights=False, extra=(), offsets=(), ripple=False, late=False):
    """A log of the swing: load 1000 + k N, torques 100 + k, −50, 25.5 N·mm; the angles (each ``offsets`` entry
    (sample, angle, degrees) added to the sensor's) and/or platform 1's slider heights from the inverse kinematics.
    ``ripple``: ±1 N·mm on τ₂ and ±0.01° on α alternating each sample (50 Hz, which a 20 Hz low-pass removes), and
    100 N at 20 Hz on the load (halved by it). ``late``: the last time stamp 9 µs late (within the 10 µs allowed)."""
    t, q = motion(n)
    sign = (-1.0) ** np.arange(n) if ripple else np.zeros(n)
    load = 1000 + np.arange(n) + (100 * np.sin(40 * np.pi * t) if ripple else 0)
    columns = {"t_s": [f"{x:.2f}" for x in t], "Fe_N": [f"{x:.15g}" for x in load]}
    if late:
        columns["t_s"][-1] = f"{t[-1] + 9e-6:.6f}"
    columns |= {"tau_1_Nmm": [f"{100 + k}" for k in range(n)], "tau_2_Nmm": [f"{-50 + x:g}" for x in sign]}
    columns["tau_3_Nmm"] = ["25.5"] * n
    if angles:
        sensor = q.copy()
        sensor[:, 0] += 0.01 * sign
        for k, j, degrees in offsets:
            sensor[k, j] += degrees
        for j, name in enumerate(("alpha", "beta", "gamma")):
            columns[f"{name}_deg"] = [f"{x:.15g}" for x in sensor[:, j]]
    if heights:
        L = slider_heights(params, np.radians(q) * params.angle_signs)[:, 0] * 1e3
        for j in range(3):
            columns[f"L_1{j + 1}_mm"] = [f"{x:.15g}" for x in L[:, j]]
    for name in extra:
        columns[name] = ["21"] * n
    names = list(columns)
    text = ",".join(names) + "\n" + "".join(",".join(columns[c][k] for c in names) + "\n" for k in range(n))
    path.write_text(text)
    return path


def test_the_constants():
    assert (DEFAULT_CUTOFF, DEFAULT_TOLERANCE_DEG, PIECE) == (20.0, 0.5, 20_000)
    # The quintic spline's reach: its response shrinks by 0.43058 a sample, below 2⁻¹⁰⁶ after 88 samples; 4 more.
    assert 0.4305753470999737**87 > 2.0**-106 > 0.4305753470999737**88 and SPLINE_HALO == 92


# --- A log in memory ---------------------------------------------------------------------------------------------


def measured(n=20, edge=0, cutoff=None, **options) -> MeasuredLog:
    t = np.arange(n) * 0.125  # 8 Hz, exact in binary
    q = np.column_stack([t, -t, 2 * t])
    still = np.zeros((n, 3))
    return MeasuredLog(
        Trajectory(t, q, still, still, np.full(n, 500.0)), np.ones((n, 3)), cutoff, "m.csv", edge=edge, **options
    )


@pytest.mark.parametrize("edge", [-1, 10, 11])
def test_an_edge_that_leaves_nothing(edge):
    with pytest.raises(TrajectoryError) as error:
        measured(20, edge)
    assert str(error.value) == f"m.csv: edge of {edge} samples leaves nothing of 20"


def test_a_log_in_memory_checks_its_arrays():
    assert measured(20, 9).usable == slice(9, 11) and measured(20, 0).usable == slice(0, 20)
    t = np.arange(10) * 0.125
    trajectory = Trajectory(t, np.zeros((10, 3)), np.zeros((10, 3)), np.zeros((10, 3)), np.ones(10))
    with pytest.raises(ArgumentError, match=r"MeasuredLog.tau: expected shape \(10, 3\), got shape \(10, 2\)"):
        MeasuredLog(trajectory, np.zeros((10, 2)))
    with pytest.raises(ArgumentError, match=r"MeasuredLog.lines: expected shape \(10,\), got shape \(9,\)"):
        MeasuredLog(trajectory, np.zeros((10, 3)), lines=np.arange(9))
    assert given(MeasuredLog(trajectory, np.zeros((10, 3)), lines=np.arange(10)).lines).size == 10
    tau = np.zeros((10, 3))
    tau[4, 2] = math.inf
    with pytest.raises(TrajectoryError) as error:
        MeasuredLog(trajectory, tau, name="x.csv")
    assert str(error.value) == "x.csv: torques are not finite"


@pytest.mark.parametrize("cutoff", [0.0, -5.0, math.nan, math.inf])
def test_a_cutoff_that_is_no_positive_frequency(cutoff):
    with pytest.raises(TrajectoryError) as error:
        measured(20, cutoff=cutoff)
    assert str(error.value) == f"m.csv: cutoff must be a positive frequency in Hz, got {cutoff!r}"


def test_a_log_in_memory_is_its_own_one_window():
    log = measured(20, 3, cutoff=2.0, notes=("a note",))
    assert log.rate == 8.0 and len(log) == 20 and log.t is log.trajectory.t
    assert measured(20, sample_rate=7.5).rate == 7.5
    assert list(log.windows()) == [(log, slice(0, 20), 0)] and next(log.windows())[0] is log
    assert log.info() == LogInfo("m.csv", 8.0, 2.0, "exact", ("a note",))
    assert measured(20, cutoff=0.5).cutoff == 0.5  # any positive frequency, below 1 Hz too
    with log as same:
        assert same is log


@pytest.mark.parametrize(
    ("most", "kept"),
    [
        (None, range(3, 17)),  # the 14 usable samples
        (14, range(3, 17)),
        (1000, range(3, 17)),
        (7, range(3, 17, 2)),  # 14/7: every 2nd
        (5, range(3, 17, 3)),  # ⌈14/5⌉ = 3
        (4, range(3, 17, 4)),  # ⌈14/4⌉ = 4
        (1, range(3, 4)),
    ],
)
def test_the_angles_of_a_log_in_memory_thinned(most, kept):
    log = measured(20, 3)
    t, q = log.filtered_angles(most)
    k = np.array(kept)
    np.testing.assert_array_equal(t, k * 0.125)
    np.testing.assert_array_equal(q, np.column_stack([k * 0.125, -k * 0.125, k * 0.25]))


# --- A log read in pieces: arguments, notes, sizes -----------------------------------------------------------------


@pytest.mark.parametrize("piece", [0, -3, True, 2.5, "10", None])
def test_a_piece_that_is_no_positive_whole_number(tmp_path, piece):
    with pytest.raises(ArgumentError) as error:
        LogPieces(tmp_path / "not read.csv", piece=piece)
    assert str(error.value) == f"piece: expected a positive number of samples, got {piece!r}"


def test_an_unfiltered_log_of_angles_in_pieces(tmp_path, params):
    path = write_log(tmp_path / "a.csv", 200, extra=("temp_C", "note"))
    with LogPieces(path, params, cutoff=None, piece=40) as pieces:
        assert (pieces.edge, pieces.halo, pieces.piece, len(pieces)) == (0, SPLINE_HALO, 40, 200)
        assert (pieces.name, pieces.source, pieces.motion_from, pieces.cutoff) == ("a.csv", str(path), "angles", None)
        assert pieces.notes == ("columns not used: temp_C, note",) and pieces.params is params
        assert pieces.rate == pytest.approx(RATE, rel=1e-12) and pieces.t is pieces.raw.t
        data = path.read_bytes()
        assert (pieces.sha256, pieces.size) == (hashlib.sha256(data).hexdigest(), len(data))
        whole = pieces.whole()
        t, q = motion(200)
        np.testing.assert_allclose(whole.trajectory.q, np.radians(q), rtol=0, atol=1e-15)  # the spline passes its knots
        np.testing.assert_allclose(whole.tau[:, 0], (100 + np.arange(200)) * 1e-3, rtol=1e-15)
        np.testing.assert_array_equal(whole.trajectory.Fe, 1000.0 + np.arange(200))
        assert (whole.edge, whole.cutoff, whole.sample_rate, whole.name) == (0, None, pieces.rate, "a.csv")
        assert_windows_give_the_whole(pieces, [0, 40, 80, 120, 160], 40)
        assert pieces.info() == LogInfo("a.csv", pieces.rate, None, "angles", ("columns not used: temp_C, note",))
    assert pieces.raw._store.closed


@pytest.mark.parametrize("piece", [1, 2])
def test_the_smallest_piece_without_a_filter_is_six_samples(tmp_path, params, piece):
    path = write_log(tmp_path / "a.csv", 30)
    with LogPieces(path, params, cutoff=None, piece=piece) as pieces:
        assert pieces.piece == 6 and [start for _, _, start in pieces.windows()] == [0, 6, 12, 18, 24]


def assert_windows_give_the_whole(pieces, starts, piece):
    """The windows' cores tile the log, each window the log around its core (the halo, cut at the ends), and give
    the whole log's values there to round-off."""
    whole, n = pieces.whole(), len(pieces)
    found = []
    for window, core, start in pieces.windows():
        lo, hi = max(0, start - pieces.halo), min(n, start + piece + pieces.halo)
        assert core == slice(start - lo, min(start + piece, n) - lo) and len(window) == hi - lo
        assert (window.edge, window.sample_rate, window.cutoff) == (0, pieces.rate, pieces.cutoff)
        assert (window.name, window.motion_from, window.notes) == (pieces.name, pieces.motion_from, pieces.notes)
        assert window.trajectory.name == pieces.name
        np.testing.assert_array_equal(window.lines, pieces.raw.lines[lo:hi])
        np.testing.assert_array_equal(window.t, pieces.t[lo:hi])
        part = slice(start, start + core.stop - core.start)
        for name in ("q", "qd", "qdd", "Fe"):
            mine, theirs = getattr(window.trajectory, name)[core], getattr(whole.trajectory, name)[part]
            scale = np.max(np.abs(getattr(whole.trajectory, name)))
            np.testing.assert_allclose(mine, theirs, rtol=0, atol=1e-10 * scale, err_msg=name)
        np.testing.assert_allclose(window.tau[core], whole.tau[part], rtol=0, atol=1e-12)
        found.append(start)
    assert found == starts


def test_a_filtered_log_in_pieces(tmp_path, params):
    # The last stamp late: a window's own times give another rate than the log's, and the 20 Hz load would show it.
    path = write_log(tmp_path / "f.csv", 400, ripple=True, late=True)
    with LogPieces(path, params, cutoff=20.0, piece=10) as pieces:
        # 1.5 periods of the cutoff at 100 Hz: 7.5, so 8 samples; the filter's edges 20 (four periods); 80 at least.
        assert pieces.halo == 2 * filter_halo(RATE, 20.0) + SPLINE_HALO + 8 + 2 == 298
        assert (pieces.edge, pieces.piece) == (20, 80)
        assert pieces.notes == (
            "low-passed at 20 Hz (zero-phase Butterworth); the first and last 0.2 s are the filter's edges",
        )
        whole = pieces.whole()
        assert (whole.edge, whole.cutoff, whole.usable) == (20, 20.0, slice(20, 380))
        # The ripple is gone from the angles and the torques (the swing's 0.5 and 1 Hz pass unchanged).
        usable = whole.usable
        np.testing.assert_allclose(whole.trajectory.q[usable], np.radians(motion(400)[1])[usable], rtol=0, atol=1e-6)
        np.testing.assert_allclose(whole.tau[usable, 1], -0.05, rtol=0, atol=1e-6)
        np.testing.assert_allclose(whole.tau[usable, 0], (100 + np.arange(20, 380)) * 1e-3, rtol=0, atol=1e-6)
        assert_windows_give_the_whole(pieces, [0, 80, 160, 240, 320], 80)
        # The angles the figures take, every k-th of the usable samples, through the pieces as through the whole.
        for most in (None, 52, 1000, 7):
            t, q = pieces.filtered_angles(most)
            t0, q0 = whole.filtered_angles(most)
            np.testing.assert_array_equal(t, t0)
            np.testing.assert_allclose(q, q0, rtol=0, atol=1e-12)
        assert pieces.filtered_angles(52)[0].size == 52  # ⌈360/52⌉ = 7: samples 20, 27, … 377
        assert pieces.filtered_angles(52)[0][-1] == 3.77


def test_a_log_too_short_to_filter_is_refused_before_any_work(tmp_path, params):
    path = write_log(tmp_path / "short.csv", 60, heights=True, params=params)
    with pytest.raises(TrajectoryError) as error:
        LogPieces(path, params)
    assert str(error.value).startswith(f"{path}: 60 samples (0.6 s) are too short to filter at 20 Hz")


def test_a_scan_handed_to_a_refused_log_in_pieces_stays_its_callers(tmp_path, params):
    """A scan passed in (``raw=``) is the caller's to close: a refusal leaves it readable."""
    path = write_log(tmp_path / "short.csv", 60, heights=True, params=params)
    scanned = RigLogFile(path)
    try:
        with pytest.raises(TrajectoryError):
            LogPieces(path, params, raw=scanned)
        assert len(scanned.read().t) == 60
    finally:
        scanned.close()


def test_a_refused_log_in_pieces_leaves_no_temporary_store_open(tmp_path, params):
    """The scan's store, opened before the refusal, is closed at once (not left to the garbage collector)."""
    path = write_log(tmp_path / "short.csv", 60, heights=True, params=params)
    gc.collect()  # earlier tests' garbage is not this test's
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        for _ in range(3):
            with pytest.raises(TrajectoryError):
                LogPieces(path, params)
        gc.collect()
    assert not [r for r in record if issubclass(r.category, ResourceWarning)]


def test_load_log_is_the_whole_log_of_its_pieces(tmp_path, params):
    path = write_log(tmp_path / "w.csv", 120)
    log = load_log(path, params, cutoff=None)
    assert isinstance(log, MeasuredLog) and (log.edge, log.cutoff, log.motion_from, len(log)) == (
        0,
        None,
        "angles",
        120,
    )
    np.testing.assert_allclose(log.trajectory.q, np.radians(motion(120)[1]), rtol=0, atol=1e-15)
    filtered = load_log(path)  # the published machine, 20 Hz
    assert (filtered.edge, filtered.cutoff) == (20, 20.0) and given(filtered.lines)[0] == 2


# --- Torques from currents, notes ----------------------------------------------------------------------------------


def test_notes_on_the_torques(tmp_path, params):
    path = write_log(tmp_path / "t.csv", 30)
    with LogPieces(path, params, torque_constant=0.25, cutoff=None) as pieces:
        assert pieces.notes == ("the log gives torques: the torque constant was not needed",)
    currents = tmp_path / "c.csv"
    currents.write_text(path.read_text().replace("tau_", "current_").replace("_Nmm", "_A"))
    with LogPieces(currents, params, torque_constant=0.25, cutoff=None) as pieces:
        assert pieces.notes == ("torques from the motor currents × 0.25 N·m/A",)
        np.testing.assert_allclose(pieces.whole().tau[3], [25.75, -12.5, 6.375], rtol=1e-15)  # 103, −50, 25.5 A
    with pytest.raises(TrajectoryError, match="no torque constant"):
        load_log(currents, params, cutoff=None)
    np.testing.assert_allclose(load_log(currents, params, 0.5, None).tau[3], [51.5, -25.0, 12.75], rtol=1e-15)


# --- Angles from the encoders ---------------------------------------------------------------------------------------


def test_angles_from_the_encoders_piece_by_piece(tmp_path, params):
    path = write_log(tmp_path / "e.csv", 250, params, angles=False, heights=True)
    with LogPieces(path, params, cutoff=None, piece=25) as pieces:
        assert pieces.motion_from == "encoders" and pieces.notes == ()
        whole = pieces.whole()
        np.testing.assert_allclose(whole.trajectory.q, np.radians(motion(250)[1]), rtol=0, atol=1e-12)
        # Windows inside the log (samples 33 … 241 around 125 … 149, say) read their angles alone from the store.
        assert_windows_give_the_whole(pieces, list(range(0, 250, 25)), 25)
        t, q = pieces.filtered_angles(84)  # every 3rd
        np.testing.assert_array_equal(t, np.arange(0, 250, 3) / RATE)
        np.testing.assert_allclose(q, np.radians(motion(250)[1][::3]), rtol=0, atol=1e-12)
        stored = pieces._q
    assert stored.closed and pieces.raw._store.closed


def test_the_attitude_sensor_within_its_tolerance(tmp_path, params):
    offsets = [(40, 1, 0.3), (90, 2, -0.25)]
    path = write_log(tmp_path / "b.csv", 120, params, heights=True, offsets=offsets)
    with LogPieces(path, params, cutoff=None, piece=25) as pieces:
        assert pieces.notes == ("encoders used; the attitude sensor agrees within 0.3° (tolerance 0.5°)",)
        np.testing.assert_allclose(pieces.whole().trajectory.q, np.radians(motion(120)[1]), rtol=0, atol=1e-12)


def test_the_attitude_sensor_beyond_its_tolerance(tmp_path, params):
    """The first sample beyond the tolerance is named, and the worst of all (pieces of 25 samples: 10, 30 and 31, 70
    are in the first, second and third)."""
    offsets = [(10, 0, 0.45), (30, 2, -0.55), (31, 2, 0.6), (70, 0, 0.7)]
    path = write_log(tmp_path / "b.csv", 120, params, heights=True, offsets=offsets)
    with pytest.raises(TrajectoryError) as error:
        LogPieces(path, params, cutoff=None, piece=25)
    assert str(error.value) == (
        f"{path}, line 32, column 'gamma_deg': the attitude sensor and the encoders disagree by 0.55° in gamma "
        "(tolerance 0.5°; 0.7° at worst, line 72): check the sensor's mounting, zero and sign conventions, or the "
        "machine's parameters"
    )
    assert (error.value.line, error.value.column) == (32, "gamma_deg")
    with LogPieces(path, params, cutoff=None, piece=25, tolerance_deg=0.75) as pieces:
        assert pieces.notes == ("encoders used; the attitude sensor agrees within 0.7° (tolerance 0.75°)",)
    assert load_log(path, params, cutoff=None, tolerance_deg=0.75).motion_from == "encoders"


def test_the_machine_turns_heights_into_angles(tmp_path, params):
    """The encoders' angles are the given machine's: heights written for a machine whose α turns the other way
    agree with the attitude sensor through that machine, not through the published one."""
    mirrored = params.replace(angle_signs=np.array([-1.0, 1.0, 1.0]))
    path = write_log(tmp_path / "m.csv", 60, mirrored, heights=True)
    assert load_log(path, mirrored, cutoff=None).motion_from == "encoders"
    with pytest.raises(
        TrajectoryError, match=r"in alpha \(tolerance 0.5°; 24° at worst, line 52\)"
    ):  # 2 × 12° at 0.5 s
        load_log(path, cutoff=None)


def test_heights_no_pose_reaches_are_named_by_line(tmp_path, params):
    path = write_log(tmp_path / "p.csv", 80, params, angles=False, heights=True)
    lines = path.read_text().split("\n")
    cells = lines[61].split(",")  # sample 60, in the third piece of 25
    cells[-3:] = ["100", "100", "100"]
    lines[61] = ",".join(cells)
    path.write_text("\n".join(lines))
    with pytest.raises(TrajectoryError) as error:
        LogPieces(path, params, cutoff=None, piece=25)
    assert str(error.value).startswith(
        f"{path}, line 62: encoder heights L_11_mm … at t = 0.6 s: no platform orientation gives the slider heights "
        "(100.000, 100.000, 100.000) mm"
    )
    assert error.value.line == 62


def test_a_file_scanned_already_is_taken_as_it_is(tmp_path, params):
    path = write_log(tmp_path / "r.csv", 100)
    raw = RigLogFile(path, lines=(12, 62))  # samples 10 … 59
    with LogPieces(tmp_path / "never opened.csv", params, cutoff=None, piece=20, raw=raw) as pieces:
        assert pieces.raw is raw and len(pieces) == 50 and pieces.name == "r.csv"
        np.testing.assert_array_equal(pieces.t, np.arange(10, 60) / RATE)
        assert [window.lines[core][0] for window, core, _ in pieces.windows()] == [12, 32, 52]
    assert LogPieces(path, None, cutoff=None).params.lever_mass == params.lever_mass  # the published machine
