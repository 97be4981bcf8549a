"""Excitation design: the limits hold (checked by the models, on a finer grid), the motion repeats, the fit is better posed than on ISO."""

import math

import numpy as np
import pytest

import hipsim
from hipsim.cli.main import main
from hipsim.exceptions import ExcitationError, HipsimError
from hipsim.motion.trajectories import Trajectory
from hipsim.rig import excitation
from hipsim.rig.identification.excitation import Limits, condition_number

PARAMS = hipsim.load_parameters()


@pytest.fixture(scope="module")
def design():
    # Small, to keep the suite fast: two harmonics, a few iterations.
    return excitation(PARAMS, frequency=0.5, harmonics=2, samples=100, max_iter=6, seeds=1)


def test_the_limits_hold_along_the_written_trajectory(design, tmp_path):
    path = design.write_csv(tmp_path / "excite.csv", rate=500.0, duration=3.0)
    trajectory = hipsim.load_trajectory_csv(path)
    assert trajectory.periodic and len(trajectory) == 2000  # two whole periods of 2 s
    run = hipsim.analyse(PARAMS, trajectory, lever_spin=True)  # raises on a pose out of reach or singular
    limits = design.limits
    assert np.degrees(np.abs(trajectory.q).max()) <= math.degrees(limits.max_angle) + 1e-6
    assert run.cond_inv.min() >= limits.min_cond_inv * (1 - 1e-6)
    assert np.abs(run.Ld).max() <= limits.max_speed * (1 + 1e-4)  # the spline's derivative, not the series'
    assert np.abs(run.Ldd).max() <= limits.max_acceleration * (1 + 1e-3)
    assert np.abs(run.torques.total).max() <= limits.torque_limit * (1 + 1e-3)
    assert limits.min_load - 1e-6 <= trajectory.Fe.min() and trajectory.Fe.max() <= limits.max_load + 1e-6


def test_the_series_is_periodic_with_exact_derivatives(design):
    period = 1.0 / design.frequency
    a, b = design.at(np.array([0.3])), design.at(np.array([0.3 + period]))
    for name in ("q", "qd", "qdd", "Fe"):
        np.testing.assert_allclose(getattr(a, name), getattr(b, name), atol=1e-12)
    h = 1e-5
    t = np.array([0.7])
    numeric = (design.at(t + h).q - design.at(t - h).q) / (2 * h)
    np.testing.assert_allclose(design.at(t).qd, numeric, rtol=1e-7, atol=1e-9)


def test_better_posed_than_the_iso_cycle(design):
    assert design.condition_number < design.iso_condition_number
    again = condition_number(PARAMS, design.trajectory(rate=1000.0))
    assert again == pytest.approx(design.condition_number, rel=1e-2)
    assert condition_number(PARAMS, hipsim.iso14242(rate=1000)) == pytest.approx(design.iso_condition_number, rel=1e-2)


def test_inseparable_parameters_make_the_condition_infinite_or_huge():
    iso = hipsim.iso14242(rate=200)
    steady = Trajectory(iso.t, iso.q, iso.qd, iso.qdd, np.full(iso.t.size, 1500.0))
    # Under a constant load the hip joint and the thrust bearing have proportional columns.
    assert condition_number(PARAMS, steady, quantities=("I_m,xx", "μ_h", "μ_t")) > 1e8


def test_impossible_limits_are_refused():
    with pytest.raises(ExcitationError, match="no excitation within the limits"):
        excitation(PARAMS, harmonics=1, limits=Limits(torque_limit=1e-4), max_iter=1, samples=100)
    with pytest.raises(HipsimError, match="harmonics: expected a whole number"):
        excitation(PARAMS, harmonics=0)


def test_excite_command(tmp_path, capsys):
    out = tmp_path / "excite.csv"
    assert (
        main(["excite", "--harmonics", "1", "--iterations", "2", "--duration", "4", "--rate", "200", "--out", str(out)])
        == 0
    )
    printed = capsys.readouterr().out
    assert "ISO 14242-1 cycle" in printed and "designed in" in printed
    assert hipsim.load_trajectory_csv(out).periodic
    assert main(["excite", "--harmonics", "1", "--torque-limit", "-5", "--out", str(tmp_path / "x.csv")]) == 2
    assert "--torque-limit -5 N·mm: motor torque limit must be above 0" in capsys.readouterr().err
    assert not (tmp_path / "x.csv").exists()


def test_sets_evaluated_together_give_what_each_gives_alone(design):
    """The gradient's one model run over many coefficient sets: each set's objective and margins as if it ran alone."""
    from hipsim.rig.identification.excitation import DESIGN_QUANTITIES, _design_columns, _evaluate_many, _series

    grid = np.arange(100) / (100 * design.frequency)
    columns = _design_columns(DESIGN_QUANTITIES)
    sets = [design.coefficients, design.coefficients * np.r_[1.0, 0.8, 0.9, 1.0][:, None], design.coefficients.copy()]
    sets[2][:3, 1:] *= 0.5
    together = _evaluate_many(PARAMS, sets, design.frequency, grid, columns, True, design.limits)
    for coefficients, (value, margins) in zip(sets, together):
        alone = _evaluate_many(PARAMS, [coefficients], design.frequency, grid, columns, True, design.limits)[0]
        assert value == pytest.approx(alone[0], rel=1e-12) and np.allclose(margins, alone[1], rtol=1e-12, atol=1e-14)
        # ... and the objective is the condition number computed by the public route.
        values, rates, accelerations = _series(coefficients, design.frequency, grid)
        trajectory = Trajectory(grid, values[:3].T, rates[:3].T, accelerations[:3].T, values[3])
        assert math.exp(value) == pytest.approx(condition_number(PARAMS, trajectory), rel=1e-9)
