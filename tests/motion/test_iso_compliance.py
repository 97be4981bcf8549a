"""ISO 14242-1 compliance: the built-in cycle passes, a scaled angle or another frequency fails and is named."""

import numpy as np
import pytest

from hipsim.exceptions import ArgumentError, TrajectoryError
from hipsim.motion.iso_compliance import DEFAULT_TOLERANCES, Tolerances, iso_check, parse_tolerances
from hipsim.motion.trajectories import iso14242, iso14242_angles, iso14242_load


def run(frequency=1.0, cycles=4.0, rate=500.0, offset=0.0, alpha_scale=1.0, load_scale=1.0):
    """The standard's waveforms at another frequency, offset, or with α / the load scaled, written out by hand."""
    t = offset + np.arange(int(cycles * rate / frequency)) / rate
    q, _, _ = iso14242_angles(t, frequency)
    q[:, 0] *= alpha_scale
    return t, q, load_scale * iso14242_load(t, frequency)


def test_the_built_in_cycle_passes_at_any_phase():
    trajectory = iso14242(rate=1000, cycles=3)
    check = iso_check(trajectory.t, trajectory.q, trajectory.Fe)
    assert check.passed and check.failing == ()
    assert len(check.cycles) >= 2
    for offset in np.random.default_rng(3).uniform(0, 1, 5):
        check = iso_check(*run(offset=offset))
        assert check.passed
        # Aligned to a fraction of a sample (a whole 2 ms sample would be 0.27° of α): the deviations
        # are those of the crossing's linear interpolation, far inside the tolerances.
        assert check.worst("alpha") < 0.03 and check.worst("load") < 5.0
        assert check.worst("frequency") < 1e-6


def test_alpha_scaled_by_1_2_fails_and_names_alpha():
    check = iso_check(*run(alpha_scale=1.2))
    assert check.failing == ("alpha",)
    # 0.2 × the largest |α| (25°) is 5°.
    assert check.worst("alpha") == pytest.approx(5.0, abs=0.05)
    assert not check.passes("alpha").any()


def test_a_cycle_at_1_2_hz_fails_and_names_the_frequency():
    check = iso_check(*run(frequency=1.2))
    assert check.failing == ("frequency",)
    assert check.worst("frequency") == pytest.approx(0.2, abs=1e-6)


def test_a_load_off_by_ten_percent_fails_on_the_load_only():
    check = iso_check(*run(load_scale=1.1))
    assert check.failing == ("load",)
    assert check.worst("load") == pytest.approx(300.0, rel=0.01)


def test_tolerances_parse_like_the_command_line():
    tol = parse_tolerances("alpha=2, load=5%,frequency=0.05")
    assert (tol.alpha, tol.beta, tol.load, tol.frequency) == (2.0, 3.0, 150.0, 0.05)
    assert parse_tolerances("load=120").load == 120.0
    assert parse_tolerances("") == DEFAULT_TOLERANCES
    for bad, match in (
        ("alpha", "NAME=VALUE"),
        ("delta=3", "NAME=VALUE"),
        ("alpha=3%", "percentage"),
        ("beta=x", "number"),
        ("gamma=-1", "positive"),
    ):
        with pytest.raises(ArgumentError, match=match):
            parse_tolerances(bad)
    with pytest.raises(ArgumentError):
        Tolerances(frequency=float("nan"))


def test_too_short_or_flat_runs_are_refused():
    with pytest.raises(TrajectoryError, match="no whole gait cycle"):
        iso_check(*run(cycles=0.9))
    t, q, load = run()
    with pytest.raises(TrajectoryError, match="no stance and swing"):
        iso_check(t, q, np.full(t.size, 1000.0))
