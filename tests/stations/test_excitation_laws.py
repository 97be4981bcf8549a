"""hipsim/stations/excitation.py's design loop and record by hand: the defaults it draws with, the 40 shrinks a candidate
gets, a dropped candidate that does not end the search, the first of equal condition numbers kept, the summary, and
the peaks of a motion out of reach. The costly parts (the structure, the Jacobian's condition, the peaks) are stood in
where the loop itself is pinned; their laws are pinned in test_excitation.py."""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np
import pytest

from hipsim.analytic.stations import platform_jacobian, platform_motion
from hipsim.exceptions import ExcitationError
from hipsim.machine.parameters import Parameters, load_parameters
from hipsim.physics.orientation import inverse_condition_number
from hipsim.records import Level
from hipsim.rig.identification.excitation import Limits
from hipsim.rig.identification.excitation_summary import ExcitationPeaks
from hipsim.stations import deviations as dv
from hipsim.stations import excitation as excitation_module
from hipsim.stations.excitation import CalibrationExcitation, _peaks, _series, calibration_condition
from hipsim.stations.sensitivity import Structure, attitude_jacobian

LIMITS = Limits(max_angle=math.radians(20.0), max_speed=0.2, max_acceleration=1.5, min_cond_inv=0.3)
WITHIN = ExcitationPeaks(angle_deg=20.0, speed_mm_s=200.0, acceleration_mm_s2=1500.0, cond_inv_min=0.3)
BEYOND = ExcitationPeaks(angle_deg=90.0, speed_mm_s=200.0, acceleration_mm_s2=1500.0, cond_inv_min=0.3)
COEFFICIENTS = np.array([[0.1, 0.0, 0.0, 0.2], [0.0, 0.3, 0.0, 0.0], [0.0, 0.0, -0.1, 0.0]])


@pytest.fixture(scope="module")
def params() -> Parameters:
    return load_parameters()


def _pair() -> Structure:
    names = dv.names()
    return Structure(
        2,
        np.array([names.index("lever_11"), names.index("lever_12")]),
        np.array([], dtype=int),
        np.zeros((2, 0)),
        False,
    )


def test_the_record_of_a_design():
    design = CalibrationExcitation(0.5, COEFFICIENTS, 3.5, 12.0, WITHIN, LIMITS)
    summary = design.summary()
    assert (summary.for_, summary.frequency_Hz, summary.harmonics) == ("calibration", 0.5, 2)
    assert (summary.condition_number, summary.iso_condition_number, summary.peaks) == (3.5, 12.0, WITHIN)
    assert summary.level == Level.PASS and summary.verdict.judged.endswith("each of 4 within")
    assert summary.verdict.numbers["speed_limit_mm_s"] == pytest.approx(200.0)
    document = summary.to_json()
    assert document["for"] == "calibration" and type(document["harmonics"]) is int  # the schema's integer: 2, not 2.0
    past = CalibrationExcitation(0.5, COEFFICIENTS, 3.5, 12.0, BEYOND, LIMITS).summary()
    assert past.level == Level.FAIL and past.verdict.judged.endswith("angle 90 beyond its limit 20 deg")


class _Loop:
    """The design loop with its costly parts stood in: the peaks fail the limits on the first ``failures`` calls and
    keep them after; the candidates' condition numbers are ``conditions`` in turn, the ISO cycle's 99."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch, failures: int, conditions: list[float]) -> None:
        self.failures, self.peaks_calls = failures, 0
        self.offsets_asked: list[bool] = []
        self.conditions: Iterator[float] = iter([*conditions, 99.0])
        monkeypatch.setattr(excitation_module, "structure", self._structure)
        monkeypatch.setattr(excitation_module, "_peaks", self._peaks)
        monkeypatch.setattr(excitation_module, "calibration_condition", lambda *args: next(self.conditions))

    def _structure(self, params: Parameters, offsets: bool) -> Structure:
        self.offsets_asked.append(offsets)
        return _pair()

    def _peaks(self, *args: object) -> ExcitationPeaks:
        self.peaks_calls += 1
        return BEYOND if self.peaks_calls <= self.failures else WITHIN


def _drawn(seed: int, k: int, harmonics: int, frequency: float, angle_deg: float) -> np.ndarray:
    """Candidate k: normal coefficients over 1, 1, 2, 2, …, H, H, scaled so that |q| peaks at the angle limit."""
    t = np.arange(240) / (240 * frequency)
    c = np.random.default_rng([seed, k]).normal(size=(3, 2 * harmonics)) / np.repeat(np.arange(1, harmonics + 1), 2)
    return c * math.radians(angle_deg) / np.abs(_series(c, frequency, t)[0]).max()


def test_the_defaults_eight_candidates_of_five_harmonics_at_0_2_hz_within_20_degrees(monkeypatch, params):
    loop = _Loop(monkeypatch, 0, [5.0, 4.0, 6.0, 3.5, 7.0, 8.0, 9.0, 3.6])
    design = excitation_module.calibration_excitation(params)
    assert loop.offsets_asked == [False] and loop.peaks_calls == 8
    assert next(loop.conditions, None) is None  # eight candidates and the ISO cycle, no more
    assert design.frequency == 0.2 and design.coefficients.shape == (3, 10)
    np.testing.assert_allclose(design.coefficients, _drawn(0, 3, 5, 0.2, 20.0), rtol=1e-12)
    assert (design.condition_number, design.iso_condition_number, design.peaks) == (3.5, 99.0, WITHIN)
    assert design.limits == Limits.for_machine(params, max_angle=math.radians(20.0))
    assert math.degrees(np.abs(design.angles(np.arange(240) / 48.0)[0]).max()) == pytest.approx(20.0)


def test_a_candidate_gets_40_shrinks_by_0_9(monkeypatch, params):
    _Loop(monkeypatch, 39, [2.0])
    design = excitation_module.calibration_excitation(params, 0.5, 2, LIMITS, seeds=1, seed=4)
    np.testing.assert_allclose(design.coefficients, _drawn(4, 0, 2, 0.5, 20.0) * 0.9**39, rtol=1e-12)
    assert design.limits == LIMITS
    _Loop(monkeypatch, 40, [2.0])
    with pytest.raises(ExcitationError) as error:
        excitation_module.calibration_excitation(params, 0.5, 2, LIMITS, seeds=1, seed=4)
    assert str(error.value) == (
        "no calibration motion within the limits: relax --max-angle, --max-speed or --min-cond-inv"
    )


def test_a_dropped_candidate_does_not_end_the_search(monkeypatch, params):
    loop = _Loop(monkeypatch, 40, [2.0])  # candidate 0 fails its 40 tries, candidate 1 keeps the limits at once
    design = excitation_module.calibration_excitation(params, 0.5, 2, LIMITS, seeds=2, seed=4)
    assert loop.peaks_calls == 41
    np.testing.assert_allclose(design.coefficients, _drawn(4, 1, 2, 0.5, 20.0), rtol=1e-12)


def test_of_equal_condition_numbers_the_first_candidate_is_kept(monkeypatch, params):
    _Loop(monkeypatch, 0, [4.0, 4.0, 4.0])
    design = excitation_module.calibration_excitation(params, 0.5, 2, LIMITS, seeds=3, offsets=True, seed=4)
    np.testing.assert_allclose(design.coefficients, _drawn(4, 0, 2, 0.5, 20.0), rtol=1e-12)


def test_the_condition_without_offsets_by_default_and_the_structure_asked_for(monkeypatch, params):
    """Two unit columns: the condition of [[1, c], [c, 1]]'s square root, c their cosine; without offsets the columns
    are not centred. Without a structure given, the machine's own is asked for with the offsets' choice."""
    pair = _pair()
    asked: list[tuple[object, bool]] = []

    def structure(p: Parameters, offsets: bool) -> Structure:
        asked.append((p, offsets))
        return pair

    monkeypatch.setattr(excitation_module, "structure", structure)
    q = _series(COEFFICIENTS, 1.0, np.arange(30) / 30.0)[0]
    Y = attitude_jacobian(params, np.stack([q, q], axis=1), pair.independent).reshape(-1, 2)
    unit = Y / np.linalg.norm(Y, axis=0)
    c = abs(float(unit[:, 0] @ unit[:, 1]))
    assert calibration_condition(params, q, seen=pair) == pytest.approx(math.sqrt((1 + c) / (1 - c)), rel=1e-9)
    assert calibration_condition(params, q) == pytest.approx(math.sqrt((1 + c) / (1 - c)), rel=1e-9)
    assert asked == [(params, False)]
    calibration_condition(params, q, True)
    assert asked[1][0] is params and asked[1][1] is True


def test_the_peaks_of_a_motion_out_of_reach(params):
    """γ of 1.5 rad (86°) leaves the platforms' reach: no speed or acceleration keeps a limit, the measure is 0."""
    coefficients = np.array([[0.0, 0.0], [0.0, 0.0], [1.5, 0.0]])
    t = np.arange(8) / 8.0
    q, qd, qdd = _series(coefficients, 1.0, t)
    assert all(np.isnan(platform_motion(params, q, qd, qdd, j)[1]).any() for j in (1, 2))  # out of reach, both
    peaks = _peaks(params, coefficients, 1.0, t)
    assert (peaks.speed_mm_s, peaks.acceleration_mm_s2, peaks.cond_inv_min) == (math.inf, math.inf, 0.0)
    assert peaks.angle_deg == pytest.approx(math.degrees(1.5))


def test_platform_1_can_set_the_singularity_measure(params):
    """Platform 1's lever 20 mm long: its Jacobian comes nearer a singularity than platform 2's, whose measure the
    peaks then do not report."""
    delta = np.zeros(dv.COUNT)
    delta[dv.names().index("lever_11")] = 20e-3
    machine = dv.machine(params, delta)
    t = np.arange(40) / 20.0
    q = _series(COEFFICIENTS * 0.5, 0.5, t)[0]
    own = [float(inverse_condition_number(platform_jacobian(machine, q, j)).min()) for j in (1, 2)]
    assert own[0] < own[1]
    assert _peaks(machine, COEFFICIENTS * 0.5, 0.5, t).cond_inv_min == pytest.approx(own[0], rel=1e-12)
