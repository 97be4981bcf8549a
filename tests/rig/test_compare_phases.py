"""compare's errors per phase of the gait cycle, from heel strike: the same table wherever the log starts."""

import numpy as np
import pytest
from support import given

from hipsim import load_parameters
from hipsim.analysis import analyse
from hipsim.motion.trajectories import iso14242_at
from hipsim.rig import compare_torques
from hipsim.rig.logs.log import MeasuredLog

PARAMS = load_parameters()
RATE = 500.0


def iso_log(start: float, cycles: float = 3.0) -> MeasuredLog:
    """The built-in cycle from ``start`` [s], logged exactly; the 'measured' torque is the model's plus an error that
    lives in stance only (proportional to the load above its swing level), so the per-phase table has a known shape."""
    trajectory = iso14242_at(start + np.arange(int(cycles * RATE)) / RATE)
    tau = analyse(PARAMS, trajectory, lever_spin=True).torques.total
    error = 0.01 * (trajectory.Fe - 300.0) / 2700.0  # up to 10 N·mm, zero in swing
    return MeasuredLog(trajectory, tau + error[:, None], name=f"iso from {start:.3f} s")


def test_the_per_phase_table_does_not_depend_on_the_first_sample():
    tables: list[np.ndarray] = []
    for start in np.random.default_rng(7).uniform(0.0, 1.0, 20):
        comparison = compare_torques(PARAMS, iso_log(start), period=1.0)
        # Heel strike is the load's rise at whole seconds: found within one sample.
        heel_strike = given(comparison.heel_strike)
        assert abs(heel_strike - np.round(heel_strike)) <= 1.0 / RATE + 1e-9
        tables.append(given(comparison.phase_rms) * 1e3)
        assert given(comparison.stance).tolist() == [True] * 6 + [False] * 4  # stance ends at 62 % of the cycle
    table = np.array(tables)  # (starts, bins, motors)
    # Heel strike is known to a sample (2 ms, 0.2 % of the cycle): where the error rises steeply (10 N·mm over
    # 12 % of the cycle) that moves a bin's RMS by a few per cent. A table anchored at the log's first sample
    # instead would move whole bins (50 % and more).
    spread = np.ptp(table, axis=0)
    assert (spread <= 0.05 * table.mean(axis=0) + 0.06).all(), spread  # 0.06 N·mm: 0.6 % of the 10 N·mm error
    # The error is in stance only: swing bins show none, stance bins up to 10 N·mm.
    mean = table.mean(axis=0)
    assert mean[7:].max() < 0.05 and mean[:6].max() > 5.0


def test_phases_are_labelled_in_the_summary():
    summary = compare_torques(PARAMS, iso_log(0.37), period=1.0).summary()
    phases = summary.phases
    assert phases is not None and phases.from_ == "heel strike"
    assert phases.labels == ["stance"] * 6 + ["swing"] * 4
    assert phases.heel_strike_s == pytest.approx(1.0, abs=1.0 / RATE + 1e-9)
