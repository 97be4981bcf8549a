"""Laws of the validation on held-out logs, on tiny logs made by hand: the envelope of a log's usable samples (window by
window), its margin, the warnings' words and order, the RMS error per tenth of the gait cycle and the note's text."""

from types import SimpleNamespace

import numpy as np
import pytest
from support import given

from hipsim.motion.trajectories import Trajectory
from hipsim.rig.identification.validation import (
    BINS,
    MARGIN,
    Envelope,
    ValidationNote,
    _core,
    _phase_rms,
    envelope,
    training_envelope,
    validation_note,
)
from hipsim.rig.logs.log import Log, MeasuredLog


def _envelope(load, angles, speeds) -> Envelope:
    return Envelope((float(load[0]), float(load[1])), np.array(angles, dtype=float), np.array(speeds, dtype=float))


def _log(t, q_deg, qd_deg, Fe, edge=0, name="held.csv") -> MeasuredLog:
    t = np.asarray(t, dtype=float)
    n = t.size
    trajectory = Trajectory(
        t,
        np.radians(np.asarray(q_deg, float)),
        np.radians(np.asarray(qd_deg, float)),
        np.zeros((n, 3)),
        np.asarray(Fe, float),
        name=name,
    )
    return MeasuredLog(trajectory, np.zeros((n, 3)), name=name, edge=edge)


class Pieces(Log):
    """A log handed out in windows of ``piece`` samples with ``halo`` samples of the log on either side (as a long log's reader does)."""

    cutoff = None
    motion_from = "exact"
    notes = ()

    def __init__(self, whole: MeasuredLog, piece: int, halo: int):
        self.whole, self.piece, self.halo = whole, piece, halo
        self.name, self.edge = whole.name, whole.edge

    def __len__(self) -> int:
        return len(self.whole)

    @property
    def rate(self) -> float:
        return self.whole.rate

    @property
    def t(self) -> np.ndarray:
        return self.whole.t

    def windows(self):
        n = len(self.whole)
        for start in range(0, n, self.piece):
            stop = min(start + self.piece, n)
            lo, hi = max(0, start - self.halo), min(n, stop + self.halo)
            window = MeasuredLog(self.whole.trajectory.slice(slice(lo, hi)), self.whole.tau[lo:hi], name=self.name)
            yield window, slice(start - lo, stop - lo), start

    def filtered_angles(self, most=None):
        raise NotImplementedError


# 17 samples, the first two and last two the filter's edges: far out, so that any of them read shows.
LOAD = np.array([9e9, -9e9, 1500, 1200, 1300, 1800, 1400, 1700, 1250, 1600, 1350, 1650, 1450, 1550, 1900, -9e9, 9e9])
N = LOAD.size


def _motion():
    k = np.arange(N, dtype=float)
    q = np.column_stack([10 + 0.5 * k, -20 + 0.25 * k, 3 - 0.5 * k])  # [deg], extremes at the usable ends
    qd = np.column_stack([100 - 10 * k, 40 + 2 * k, -7 + 0 * k])  # [deg/s]
    q[[0, 1, -2, -1]] = [[90, -90, 90], [-90, 90, -90], [90, -90, 90], [-90, 90, -90]]
    qd[[0, 1, -2, -1]] = [[900, -900, 900], [-900, 900, -900], [900, -900, 900], [-900, 900, -900]]
    return q, qd


# By hand: samples 2 … 14.
EXPECTED = _envelope(
    (1200, 1900),
    [[10 + 0.5 * 2, 10 + 0.5 * 14], [-20 + 0.25 * 2, -20 + 0.25 * 14], [3 - 0.5 * 14, 3 - 0.5 * 2]],
    [[100 - 10 * 14, 100 - 10 * 2], [40 + 2 * 2, 40 + 2 * 14], [-7, -7]],
)


def _same(a: Envelope, b: Envelope):
    assert a.load == pytest.approx(b.load, abs=1e-9)
    np.testing.assert_allclose(a.angles, b.angles, atol=1e-9)
    np.testing.assert_allclose(a.speeds, b.speeds, atol=1e-9)
    assert a.angles.shape == (3, 2) and a.speeds.shape == (3, 2)


@pytest.mark.parametrize(("piece", "halo"), [(None, 0), (5, 3), (4, 0), (6, 2), (1, 1)])
def test_the_envelope_covers_the_usable_samples_window_by_window(piece, halo):
    q, qd = _motion()
    whole = _log(np.arange(N) * 0.01, q, qd, LOAD, edge=2)
    log = whole if piece is None else Pieces(whole, piece, halo)
    _same(envelope(log), EXPECTED)
    assert isinstance(envelope(log).load[0], float)


@pytest.mark.parametrize(("piece", "halo"), [(5, 3), (4, 0), (6, 2), (1, 1), (16, 16)])
def test_the_windows_give_each_usable_sample_once(piece, halo):
    q, qd = _motion()
    whole = _log(np.arange(N) * 0.01, q, qd, LOAD, edge=2)
    parts = list(_core(Pieces(whole, piece, halo)))
    np.testing.assert_array_equal(np.concatenate([p[0] for p in parts]), whole.t[2:-2])
    np.testing.assert_array_equal(np.concatenate([p[1] for p in parts]), LOAD[2:-2])
    np.testing.assert_allclose(np.degrees(np.concatenate([p[2] for p in parts])), q[2:-2], rtol=1e-14)
    np.testing.assert_allclose(np.degrees(np.concatenate([p[3] for p in parts])), qd[2:-2], rtol=1e-14)


def test_union_takes_the_outer_ends_of_each_range():
    a = _envelope((100, 900), [[-1, 2], [-3, 4], [-5, 6]], [[-10, 20], [-30, 40], [-50, 60]])
    b = _envelope((50, 500), [[0, 3], [-4, 1], [-2, 7]], [[-20, 10], [-10, 50], [-70, 0]])
    want = _envelope((50, 900), [[-1, 3], [-4, 4], [-5, 7]], [[-20, 20], [-30, 50], [-70, 60]])
    _same(a.union(b), want)
    _same(b.union(a), want)


def test_the_training_envelope_is_the_union_of_its_logs():
    q, qd = _motion()
    first = _log(np.arange(N) * 0.01, q, qd, LOAD, edge=2)
    second = _log(np.arange(4) * 0.01, np.full((4, 3), 50.0), np.full((4, 3), -500.0), [100.0, 200.0, 300.0, 400.0])
    _same(training_envelope([first]), EXPECTED)
    _same(training_envelope([first, second]), EXPECTED.union(envelope(second)))
    _same(envelope(second), _envelope((100, 400), [[50, 50]] * 3, [[-500, -500]] * 3))


TRAINING = _envelope((1000, 2000), [[-10, 10], [-20, 0], [0, 40]], [[-100, 100], [0, 50], [-10, 10]])


def test_within_the_margin_no_warning_beyond_it_one():
    assert MARGIN == 0.05
    # Exactly 5 % of each width beyond either end: still inside.
    edge = _envelope((950, 2050), [[-11, 11], [-21, 1], [-2, 42]], [[-110, 110], [-2.5, 52.5], [-11, 11]])
    assert edge.beyond(TRAINING) == []
    assert TRAINING.beyond(TRAINING) == []
    inside = _envelope((1200, 1300), [[0, 1], [-5, -4], [10, 11]], [[0, 0], [10, 10], [0, 1]])
    assert inside.beyond(TRAINING) == []
    low = _envelope((949.9, 1500), TRAINING.angles, TRAINING.speeds)
    assert low.beyond(TRAINING) == ["load 949.9 to 1500 N (training 1000 to 2000)"]
    high = _envelope((1500, 2050.1), TRAINING.angles, TRAINING.speeds)
    assert high.beyond(TRAINING) == ["load 1500 to 2050 N (training 1000 to 2000)"]


def test_every_range_beyond_is_named_in_order_with_its_unit():
    out = _envelope((900, 1900), [[-12, 5], [-20, 2], [0, 50]], [[-100, 120], [-5, 50], [-10, 11.5]])
    assert out.beyond(TRAINING) == [
        "load 900 to 1900 N (training 1000 to 2000)",
        "alpha -12 to 5 ° (training -10 to 10)",
        "alpha speed -100 to 120 °/s (training -100 to 100)",
        "beta -20 to 2 ° (training -20 to 0)",
        "beta speed -5 to 50 °/s (training 0 to 50)",
        "gamma 0 to 50 ° (training 0 to 40)",
        "gamma speed -10 to 11.5 °/s (training -10 to 10)",
    ]


def test_a_training_range_of_no_width_has_a_floor_of_a_billionth():
    flat = _envelope((1000, 1000), [[5, 5]] * 3, [[0, 0]] * 3)
    # The margin is 5 % of 1e-9: 5e-11.
    assert _envelope((1000, 1000), [[5, 5 + 4e-11]] * 3, [[-4e-11, 0]] * 3).beyond(flat) == []
    words = _envelope((1000, 1000), [[5, 5 + 6e-11], [5, 5], [5, 5]], [[0, 0], [0, 0], [-6e-11, 0]]).beyond(flat)
    assert words == ["alpha 5 to 5 ° (training 5 to 5)", "gamma speed -6e-11 to 0 °/s (training 0 to 0)"]


EDGES = np.linspace(0.0, 100.0, 11)


def test_phase_rms_bins_tenths_in_newton_millimetres():
    phase = np.array([5.0, 5.0, 15.0, 100.0, -3.0, 95.0, 10.0, 99.9])
    error = (
        np.array(
            [
                [1.0, 2.0, 3.0],
                [-1.0, -2.0, 3.0],
                [4.0, 0.0, -1.0],
                [3.0, 3.0, 3.0],
                [2.0, -4.0, 0.0],
                [4.0, 4.0, 0.0],
                [2.0, 1.0, 1.0],
                [0.0, 0.0, 0.0],
            ]
        )
        * 1e-3
    )
    out = _phase_rms(SimpleNamespace(error=error), phase, EDGES)  # type: ignore[arg-type]  # only the error is read
    assert out.shape == (10, 3)
    # Bin 0: phases 5, 5 and -3 (below 0: clipped to the first); bin 1: 15 and 10 (an edge opens its bin);
    # bin 9: 100 (clipped to the last), 95, 99.9.
    np.testing.assert_allclose(out[0], [np.sqrt(6 / 3), np.sqrt(24 / 3), np.sqrt(18 / 3)], rtol=1e-12)
    np.testing.assert_allclose(out[1], [np.sqrt((16 + 4) / 2), np.sqrt(1 / 2), np.sqrt(2 / 2)], rtol=1e-12)
    np.testing.assert_allclose(out[9], [np.sqrt(25 / 3), np.sqrt(25 / 3), np.sqrt(9 / 3)], rtol=1e-12)
    assert np.isnan(out[2:9]).all()


def _gait_log(load_kind="steps", edge=2, piece=None):
    """Three seconds at 100 Hz: the load rises at samples 30, 130 and 230 (heel strikes at 0.29, 1.29 and 2.29 s, 1 s apart)."""
    t = np.arange(300) * 0.01
    load = np.full(300, 200.0)
    if load_kind == "steps":
        for k in (30, 130, 230):
            load[k : k + 60] = 2000.0
    q = np.zeros((300, 3))
    q[:, 1] = 30.0  # beyond the training's beta
    whole = _log(t, q, np.zeros((300, 3)), load, edge=edge, name="walk.csv")
    return whole if piece is None else Pieces(whole, piece, 7)


def _comparison(t, error):
    return SimpleNamespace(t=np.asarray(t, float), error=np.asarray(error, float))


GAIT_TRAINING = _envelope((100, 2100), [[-1, 1], [-1, 1], [-1, 1]], [[-1, 1]] * 3)


@pytest.mark.parametrize("piece", [None, 64])
def test_the_note_bins_each_comparison_by_its_own_times_from_the_heel_strikes(piece):
    log = _gait_log(piece=piece)
    bins = np.arange(BINS)
    scale = np.outer(bins + 1, [1.0, 2.0, 3.0]) * 1e-3  # [N·m]: bin b, motor i
    # Identified: two samples a bin, at 2.5 % and 7.5 % into it, errors ±: RMS (b + 1)(i + 1) N·mm.
    t_id = 0.29 + np.concatenate([(10 * bins + 2.5) / 100, (10 * bins + 7.5) / 100])
    error_id = np.vstack([scale, -scale])
    # Starting: one sample a bin, at its middle, error 2 (b + 1)(i + 1) mN·m; times another route.
    t_start = 0.29 + (10 * bins + 5.0) / 100
    note = validation_note(_comparison(t_id, error_id), _comparison(t_start, 2 * scale), log, GAIT_TRAINING)
    assert note.log == "walk.csv"
    np.testing.assert_array_equal(note.phase_edges, np.linspace(0, 100, 11))
    np.testing.assert_allclose(given(note.identified_phase_rms), scale * 1e3, rtol=1e-9)
    np.testing.assert_allclose(given(note.starting_phase_rms), 2 * scale * 1e3, rtol=1e-9)
    assert note.warnings == ("beta 30 to 30 ° (training -1 to 1)",)


def test_without_two_heel_strikes_there_are_no_phases_but_still_the_warnings():
    log = _gait_log(load_kind="flat")
    note = validation_note(_comparison([0.5], [[1e-3, 0, 0]]), _comparison([0.5], [[0, 0, 0]]), log, GAIT_TRAINING)
    assert note.phase_edges is None and note.identified_phase_rms is None and note.starting_phase_rms is None
    assert note.text() == (
        "walk.csv: no two heel strikes in the load, so no error per gait phase\n"
        "WARNING: walk.csv leaves the training envelope, the prediction extrapolates: beta 30 to 30 ° (training -1 to 1)"
    )
    assert note.summary().to_json() == {"envelope_warnings": ["beta 30 to 30 ° (training -1 to 1)"]}


def test_the_note_in_words_and_as_its_record():
    identified = np.array([[1.0, 20.0, 0.123456], [2.0, 30.0, 4.5]])
    starting = np.array([[10.0, 200.0, 0.5], [3.0, 1234.0, 6.0]])
    note = ValidationNote("h.csv", np.array([0.0, 50.0, 100.0]), identified, starting, ("load 1 to 2 N", "x"))
    assert note.text() == "\n".join(
        [
            "RMS error per tenth of the gait cycle from heel strike [N·mm], identified (starting) on h.csv:",
            "  M1: 1 (10) 2 (3)",
            "  M2: 20 (200) 30 (1.23e+03)",
            "  M3: 0.123 (0.5) 4.5 (6)",
            "WARNING: h.csv leaves the training envelope, the prediction extrapolates: load 1 to 2 N",
            "WARNING: h.csv leaves the training envelope, the prediction extrapolates: x",
        ]
    )
    assert note.summary().to_json() == {
        "envelope_warnings": ["load 1 to 2 N", "x"],
        "gait_phase_edges_percent": [0.0, 50.0, 100.0],
        "identified_phase_rms_error_Nmm": identified.tolist(),
        "starting_phase_rms_error_Nmm": starting.tolist(),
    }
    quiet = ValidationNote("q.csv", None, None, None, ())
    assert quiet.text() == "q.csv: no two heel strikes in the load, so no error per gait phase"
    assert quiet.summary().to_json() == {"envelope_warnings": []}
