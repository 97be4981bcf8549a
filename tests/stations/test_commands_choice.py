"""hipsim/stations/commands.py's choice of command for ``both``: the least squares is a stationary point of the weighted
squared error (central differences on tests/stations_synthetic.py's hand-built machine), the best-of-three keeps a
single command where it is exactly optimal (a weight of zero: the least squares is then that command to round-off
only), and the arrays handed in: integers, blocks each solved once."""

from __future__ import annotations

import numpy as np
import pytest
from stations_synthetic import deviated, reference_attitude

from hipsim.exceptions import PoseError
from hipsim.machine.parameters import load_parameters
from hipsim.stations import commands as commands_module
from hipsim.stations.commands import squared_errors, station_commands

Q = np.radians(np.array([[5.0, -3.0, 8.0], [-6.0, 4.0, -2.0], [2.0, 7.0, 3.0], [-1.0, -8.0, 5.0]]))


@pytest.fixture(scope="module")
def drawing():
    return load_parameters()


@pytest.fixture(scope="module")
def machine(drawing):
    return drawing.replace(geometry=deviated(seed=5, size_mm=0.3))


@pytest.fixture(scope="module")
def seated(drawing):
    """0.3 mm deviations and a seat of (2, −1, 1.5) mm: m_1's centre rides m_2's tilt."""
    return drawing.replace(geometry=deviated(seed=11, size_mm=0.3).replace(spline=np.array([2e-3, -1e-3, 1.5e-3])))


def _cost(drawing, geometry, L, weights):
    """Σ_j w_j·|q_j(L) − q_d|² in [deg²] per sample, the attitudes by the hand route."""
    q = np.stack([reference_attitude(drawing, geometry, j, L, Q) for j in (1, 2)], axis=1)
    return squared_errors(q - Q[:, None], weights)


def test_the_least_squares_is_where_the_weighted_error_is_flat(drawing, machine):
    """The cost's slope along each carriage by central differences (±1 µm): at ``both``'s command under weights
    (1, 2) it is under 1e-2 of its slope at either single command (first-order optimal: a few δ/l ~ 1e-3 are left),
    while a single command is far from flat (the other platform's error pulls)."""
    weights = (1.0, 2.0)
    h = 1e-6

    def slope(L):
        out = np.empty((len(L), 3))
        for i in range(3):
            dL = np.zeros(3)
            dL[i] = h
            plus = _cost(drawing, machine.geometry, L + dL, weights)
            out[:, i] = (plus - _cost(drawing, machine.geometry, L - dL, weights)) / (2 * h)
        return np.linalg.norm(out, axis=1)

    t = np.arange(len(Q)) * 0.1
    both = station_commands(machine, t, Q, "both", weights)
    flat = slope(both.carriages)
    for control in ("1", "2"):
        steep = slope(station_commands(machine, t, Q, control).carriages)
        assert np.all(flat < 1e-2 * steep), flat / steep
        assert np.all(steep > 100.0)  # [deg²/m]
    cost = _cost(drawing, machine.geometry, both.carriages, weights)
    np.testing.assert_allclose(squared_errors(both.errors, weights), cost, rtol=1e-9)


@pytest.mark.parametrize("block", [8192, 1])
def test_a_zero_weight_makes_both_the_single_command(machine, seated, monkeypatch, block):
    """Weights (w, 0): only m_1 counts, so control 1 (m_1 exact) is the true optimum and the least squares reaches it
    to round-off only: the best-of-three must keep control 1's command and attitudes bit for bit; (0, w) the same for
    m_2; each sample on its own as well (blocks of one sample)."""
    monkeypatch.setattr(commands_module, "BLOCK", block)
    t = np.arange(len(Q)) * 0.1
    cases = [(machine, (1.0, 0.0), "1")]
    if block > 1:
        cases += [(machine, (0.0, 1.0), "2"), (seated, (3.0, 0.0), "1"), (seated, (0.0, 1.0), "2")]
    for params, weights, control in cases:
        both = station_commands(params, t, Q, "both", weights)
        single = station_commands(params, t, Q, control)
        np.testing.assert_array_equal(both.carriages, single.carriages)
        np.testing.assert_array_equal(both.attitudes, single.attitudes)
        assert np.all(both.errors[:, int(control) - 1] == 0.0)


def test_integer_angles_and_times_are_read_as_numbers(machine):
    """The home pose and times given as integers: the same commands as from floats (not carriages cut to whole
    metres), and a refused sample's time a float."""
    run = station_commands(machine, np.arange(3), np.zeros((3, 3), dtype=int), "both")
    home = station_commands(machine, np.arange(3.0), np.zeros((3, 3)), "both")
    np.testing.assert_array_equal(run.carriages, home.carriages)
    assert np.abs(run.carriages).max() > 1e-3
    far = np.zeros((3, 3), dtype=int)
    far[2, 1] = 3  # β of 3 rad: out of chain 13's reach
    with pytest.raises(PoseError) as error:
        station_commands(machine, np.arange(3), far, "2")
    assert str(error.value) == "t = 2 s: chain 13's lever cannot reach platform 1's desired attitude"
    assert isinstance(error.value.time, float) and error.value.index == 2


def test_each_sample_is_solved_once_in_blocks(machine, monkeypatch):
    """Eight samples in blocks of three: three blocks of 3, 3 and 2 samples, the last starting at the seventh."""
    monkeypatch.setattr(commands_module, "BLOCK", 3)
    blocks = []
    original = commands_module._block_commands

    def spy(params, t, q_d, control, w):
        blocks.append(t.tolist())
        return original(params, t, q_d, control, w)

    monkeypatch.setattr(commands_module, "_block_commands", spy)
    q = np.concatenate([Q, Q[::-1]])
    run = station_commands(machine, np.arange(8.0), q, "2")
    assert blocks == [[0.0, 1.0, 2.0], [3.0, 4.0, 5.0], [6.0, 7.0]]
    assert np.all(np.abs(run.errors[:, 1]) < 1e-12)
