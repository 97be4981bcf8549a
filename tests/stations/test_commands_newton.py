"""hipsim/stations/commands.py's forward kinematics from close guesses, by hand-built cases: Newton on chains that
differ by sample (each sample its own machine, the blocks cut small), which sample converges by its last step, which by
its readings and which not at all; the attitudes solved from their linear predictions with no full solve (the full
solve only inside the stack-up's fixed point); a reading no platform can take named by platform, time and file."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from stations_synthetic import deviated, reference_carriages

from hipsim.analytic import stations as analytic_stations
from hipsim.analytic.chain_kinematics import chain_positions_per_sample
from hipsim.exceptions import PoseError
from hipsim.machine.parameters import load_parameters
from hipsim.stations import commands as commands_module
from hipsim.stations.commands import attitudes, newton_from_close, station_commands

SIGNS = np.array([1.0, -1.0, 1.0])
#: Each sample's truth and how far its guess is from it [rad]: 1e-7 converges by its last step (~1e-14), 3e-4 by its
#: readings (the last step ~1e-7, the error left ~1e-15 rad), 0.2 not at all in two steps.
OFF = np.array([1e-7, 3e-4, 0.2, 3e-4, 1e-7, 3e-4])
CONVERGED = np.array([True, True, False, True, True, True])


@pytest.fixture(scope="module")
def drawing():
    return load_parameters()


@pytest.fixture(scope="module")
def seated(drawing):
    """0.3 mm deviations and a seat of (2, −1, 1.5) mm: m_1's centre rides m_2's tilt."""
    return drawing.replace(geometry=deviated(seed=11, size_mm=0.3).replace(spline=np.array([2e-3, -1e-3, 1.5e-3])))


def _six_machines(drawing):
    """Six samples, each of platform m_2 of its own machine (the drawing, then 2 mm deviations of five seeds): the truth,
    the carriages the hand route gives each (at platform angles truth·signs) and the chains' arrays per sample."""
    geometries = [None] + [deviated(seed=s, size_mm=2.0) for s in range(5)]
    truth = np.radians(np.array([[5.0, -3.0, 8.0], [-6.0, 4.0, -2.0], [2.0, 7.0, 3.0], [0.0, -5.0, 9.0]] * 2)[:6])
    L = np.concatenate([reference_carriages(drawing, g, 2, (truth[k] * SIGNS)[None]) for k, g in enumerate(geometries)])
    chains = [drawing.replace(geometry=g).chains for g in geometries]
    points = np.stack([c.platform_points[1] for c in chains])
    offsets = np.stack([c.centres[1] - c.screw_points[1] for c in chains])
    levers = np.stack([c.lever_lengths[1] for c in chains])
    return truth, L, (points, offsets, levers)


def test_newton_on_chains_that_differ_by_sample(drawing, monkeypatch):
    """Blocks of two samples: each block's rows must reach its own chains, in the first Newton steps and in the check
    of the readings of the samples whose last step was not small."""
    truth, L, (points, offsets, levers) = _six_machines(drawing)
    monkeypatch.setattr(commands_module, "BLOCK", 2)
    seen = []

    def positions(p, rows):
        seen.append(np.arange(6)[rows].tolist())
        return chain_positions_per_sample(points[rows], offsets[rows], levers[rows], p)

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        q, converged = newton_from_close(positions, SIGNS, L, truth + OFF[:, None])
    np.testing.assert_array_equal(converged, CONVERGED)
    np.testing.assert_allclose(q[CONVERGED], truth[CONVERGED], rtol=0, atol=1e-13)
    assert np.abs(q[2] - truth[2]).max() > 1e-6
    # Two steps a block, then the readings of the samples not settled by their step: 1, then 2 and 3, then 5.
    assert seen == [[0, 1], [0, 1], [1], [2, 3], [2, 3], [2, 3], [4, 5], [4, 5], [5]]


def test_a_reading_no_lever_reaches_is_not_converged_and_silent(drawing):
    """Carriages 0.4 m apart: no platform angle gives them, NaN through Newton, without a warning."""
    truth, L, (points, offsets, levers) = _six_machines(drawing)
    far = np.array(L[:2])
    far[1, 0] += 0.4
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        q, converged = newton_from_close(
            lambda p, rows: chain_positions_per_sample(points[:2][rows], offsets[:2][rows], levers[:2][rows], p),
            SIGNS,
            far,
            truth[:2],
        )
    assert converged.tolist() == [True, False]
    np.testing.assert_allclose(q[0], truth[0], rtol=0, atol=1e-13)


def _no_full_solve(monkeypatch):
    """The full solve (assembly mode, singularities) refused outside the stack-up's fixed point, which starts m_2 from
    m_1's own attitude (~0.1° away) and needs it."""
    inside = []

    def fixed_point(*args, **kwargs):
        inside.append(True)
        try:
            return analytic_stations.stacked_carriages(*args, **kwargs)
        finally:
            inside.pop()

    def solve(params, L, guess, platform=None):
        raise AssertionError(f"a full solve of {len(L)} samples of platform {platform}")

    def solve_inside(params, L, guess, platform=None):
        if not inside:
            solve(params, L, guess, platform)
        return analytic_stations.solve_pose(params, L, guess, platform=platform)

    monkeypatch.setattr(commands_module, "stacked_carriages", fixed_point)
    monkeypatch.setattr(commands_module, "solve_pose", solve_inside)


@pytest.mark.parametrize("seat", [False, True])
def test_every_attitude_comes_from_its_linear_prediction(drawing, seated, monkeypatch, seat):
    """0.3 mm deviations: the follower's linear prediction is within ~1e-6 rad, so two Newton steps give every attitude
    (and m_1 on a seat is solved at m_2's attitude, not from its own prediction again), for every control, the
    best-of-three's single commands included (a weight of zero makes it choose one)."""
    params = seated if seat else drawing.replace(geometry=deviated(seed=5, size_mm=0.3))
    t = np.arange(6) * 0.1
    q = np.radians(np.array([[5.0, -3.0, 8.0], [-6.0, 4.0, -2.0], [2.0, 7.0, 3.0]] * 2))
    _no_full_solve(monkeypatch)
    for control, weights in (("1", (1.0, 1.0)), ("2", (1.0, 1.0)), ("both", (1.0, 2.0))):
        station_commands(params, t, q, control, weights)
    for weights in ((1.0, 0.0), (0.0, 1.0)):
        run = station_commands(params, t, q, "both", weights)
        assert np.all(run.errors[:, weights.index(1.0)] == 0.0)  # the single command chosen: exact
    both = station_commands(params, t, q, "both")
    np.testing.assert_allclose(attitudes(params, both.carriages, both.attitudes), both.attitudes, rtol=0, atol=1e-14)


def test_the_other_platforms_guess_is_not_its_own(monkeypatch):
    """Guesses one a platform: each is handed to its own platform (the other's, ~0.1° away, needs the full solve)."""
    params = load_parameters().replace(geometry=deviated(seed=5, size_mm=0.3))
    q = np.radians(np.array([[5.0, -3.0, 8.0], [-6.0, 4.0, -2.0]]))
    both = station_commands(params, np.arange(2.0), q, "1")
    _no_full_solve(monkeypatch)
    np.testing.assert_allclose(attitudes(params, both.carriages, both.attitudes), both.attitudes, rtol=0, atol=1e-14)
    with pytest.raises(AssertionError, match="full solve"):
        attitudes(params, both.carriages, both.attitudes[:, ::-1])


@pytest.mark.parametrize("seat", [False, True])
def test_a_reading_no_platform_takes_is_named(drawing, seated, seat):
    """Carriage 1 of sample 2 raised by 0.4 m: platform 2 (solved first: m_1 may ride on it) cannot take it; the
    message names the platform, the time (the sample's index when no times are given) and the file."""
    params = seated if seat else drawing.replace(geometry=deviated(seed=5, size_mm=0.3))
    q = np.radians(np.array([[5.0, -3.0, 8.0], [-6.0, 4.0, -2.0], [2.0, 7.0, 3.0]]))
    L = np.array(station_commands(params, np.arange(3.0), q, "2").carriages)
    L[2, 0] += 0.4
    for t, time in ((np.array([0.5, 1.5, 2.25]), 2.25), (None, 2.0)):
        with pytest.raises(PoseError) as error:
            attitudes(params, L, q, t, "log.csv")
        assert error.value.index == 2 and error.value.time == time and error.value.source == "log.csv"
        assert str(error.value).startswith(f"log.csv, t = {time:.6g} s: platform 2: ")
        assert error.value.reason.startswith("platform 2: ")
