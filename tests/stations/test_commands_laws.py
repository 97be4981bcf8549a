"""hipsim/stations/commands.py's laws on a few samples: the records' checks and messages, the weighted squared error by
hand, the blocks a long motion is cut into, a desired attitude out of reach named by chain, sample and file, and a
machine with the intermediate chain's seat (m_1 rides on m_2) against tests/stations_synthetic.py's hand-built one."""

from __future__ import annotations

import numpy as np
import pytest
from stations_synthetic import deviated, reference_attitude

from hipsim.analytic.stations import carriages_for_platform
from hipsim.exceptions import ArgumentError, PoseError
from hipsim.machine.parameters import load_parameters
from hipsim.motion.trajectories import iso14242
from hipsim.stations import commands as commands_module
from hipsim.stations.commands import StationMotion, attitudes, squared_errors, station_commands


@pytest.fixture(scope="module")
def drawing():
    return load_parameters()


@pytest.fixture(scope="module")
def seated(drawing):
    """0.3 mm deviations and a seat of (2, −1, 1.5) mm: m_1's centre rides m_2's tilt."""
    geometry = deviated(seed=11, size_mm=0.3).replace(spline=np.array([2e-3, -1e-3, 1.5e-3]))
    return drawing.replace(geometry=geometry), geometry


@pytest.fixture(scope="module")
def cycle():
    iso = iso14242(rate=100)
    return iso.t[::10], iso.q[::10]


def test_a_motions_arrays_are_checked_by_name():
    with pytest.raises(ArgumentError) as error:
        StationMotion(np.zeros(2), np.zeros((2, 3)), np.zeros((2, 2)), np.zeros((2, 2, 3)), "2")
    assert str(error.value) == "carriages: expected shape (2, 3), got shape (2, 2)"
    motion = StationMotion(np.array([0, 1]), np.array([[0, 0, 1]] * 2), np.zeros((2, 3)), np.ones((2, 2, 3)), "1")
    assert motion.desired.dtype == float and not motion.t.flags.writeable
    assert motion.errors[0, 1] == pytest.approx([1.0, 1.0, 0.0]) and motion.weights == (1.0, 1.0)


def test_the_weighted_squared_error_by_hand():
    """m_1 off by (1°, 2°, 0), m_2 by (0, 0, 3°): w = (2, 3) gives 2·5 + 3·9 = 37 deg²."""
    e = np.radians(np.array([[[1.0, 2.0, 0.0], [0.0, 0.0, 3.0]], [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]]))
    assert squared_errors(e, (2.0, 3.0)) == pytest.approx([37.0, 3.0])
    assert squared_errors(e) == pytest.approx([14.0, 1.0])


@pytest.mark.parametrize("weights", [(1.0,), (0.0, 0.0), (-1.0, 1.0), (np.inf, 1.0), (1.0, np.nan), (1.0, 1.0, 1.0)])
def test_bad_weights_are_refused_whole(drawing, cycle, weights):
    t, q = cycle
    with pytest.raises(ArgumentError) as error:
        station_commands(drawing, t, q, "both", weights)
    assert str(error.value) == f"weights: expected two finite weights >= 0, not both zero, got {weights!r}"


def test_weights_of_zero_or_under_one_and_the_default_control(drawing, cycle):
    t, q = cycle
    for weights in ((0.0, 1.0), (1.0, 0.0), (0.5, 0.25)):
        assert station_commands(drawing, t, q, "both", weights).weights == weights
    run = station_commands(drawing, t, q)
    assert run.control == "2" and run.weights == (1.0, 1.0)
    with pytest.raises(ArgumentError) as error:
        station_commands(drawing, t, q, "3")
    assert str(error.value) == "control: expected one of 1, 2, both, got '3'"


@pytest.mark.parametrize("control", ["1", "2", "both"])
def test_blocks_give_the_same_commands(seated, cycle, monkeypatch, control):
    params, _ = seated
    t, q = cycle
    whole = station_commands(params, t, q, control, (1.0, 2.0))
    monkeypatch.setattr(commands_module, "BLOCK", 3)
    blocks = station_commands(params, t, q, control, (1.0, 2.0))
    np.testing.assert_allclose(blocks.carriages, whole.carriages, rtol=1e-13, atol=0)
    np.testing.assert_allclose(blocks.attitudes, whole.attitudes, rtol=0, atol=1e-13)
    assert blocks.control == control and blocks.weights == (1.0, 2.0)


def test_a_desired_attitude_out_of_reach_names_its_chain_sample_and_file(drawing, monkeypatch):
    """β = 120° on sample 3: chain 13's lever cannot reach (the other two can: hand-checked on the drawing's
    inverse kinematics), platform 1's command computed first."""
    q = np.zeros((5, 3))
    q[3] = np.radians([0.0, 120.0, 0.0])
    L = carriages_for_platform(drawing, q[3:4], 1)
    assert np.isfinite(L[0, :2]).all() and not np.isfinite(L[0, 2])
    t = np.arange(5) * 0.25
    monkeypatch.setattr(commands_module, "BLOCK", 2)  # the sample in the second block: its index counts from 0
    with pytest.raises(PoseError) as error:
        station_commands(drawing.replace(geometry=deviated(seed=1, size_mm=0.1)), t, q, "1", source="gait.csv")
    assert error.value.index == 3 and error.value.time == 0.75
    assert str(error.value) == "gait.csv, t = 0.75 s: chain 13's lever cannot reach platform 1's desired attitude"


@pytest.mark.parametrize("control", ["1", "2", "both"])
def test_with_a_seat_each_platform_is_where_its_chains_put_it(drawing, seated, cycle, control):
    """The attitudes reported are those the commanded carriages give m_2, and m_1 riding on it (hand route)."""
    params, geometry = seated
    t, q = cycle
    run = station_commands(params, t, q, control, (1.0, 2.0))
    for j in (1, 2):
        reference = reference_attitude(drawing, geometry, j, run.carriages, q)
        np.testing.assert_allclose(run.attitudes[:, j - 1], reference, atol=1e-11)
    if control != "both":
        assert np.abs(run.errors[:, int(control) - 1]).max() < 1e-12
        assert np.degrees(np.abs(run.errors[:, 2 - int(control)])).max() > 0.05


def test_attitudes_from_carriages_with_or_without_a_guess(drawing, seated, cycle):
    params, geometry = seated
    t, q = cycle
    L = station_commands(params, t, q, "2").carriages
    expected = np.stack([reference_attitude(drawing, geometry, j, L, q) for j in (1, 2)], axis=1)
    for guess in (None, q, np.stack([q, q], axis=1)):
        np.testing.assert_allclose(attitudes(params, L, guess, t), expected, atol=1e-11)
    far = np.array(L)
    far[2] += 0.4
    for guess in (None, q):
        with pytest.raises(PoseError) as error:
            attitudes(drawing, far, guess, t, "log.csv")
        assert str(error.value).startswith(f"log.csv, t = {t[2]:.6g} s: ")
        assert error.value.index == 2
