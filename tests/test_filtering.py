"""hipsim.motion.filtering: the rig's low-pass, copied; a whole record filtered without losing samples or edges that go wrong."""

import numpy as np
import pytest

from hipsim.exceptions import TrajectoryError
from hipsim.motion.filtering import edge_samples, lowpass, lowpass_record
from hipsim.motion.gait_events import gait_cycles
from hipsim.motion.trajectories import iso14242
from hipsim.rig.logs.log import lowpass as rig_lowpass


def test_the_copy_is_the_rig_logs_filter():
    x = np.random.default_rng(0).normal(size=(2000, 3))
    assert np.array_equal(lowpass(x, 1000.0, 20.0), rig_lowpass(x, 1000.0, 20.0))


def test_a_periodic_record_wraps_around_and_a_slow_motion_passes_unchanged():
    t = np.arange(61) / 60.0
    x = np.cos(2 * np.pi * t) + np.sin(4 * np.pi * t)
    y = lowpass_record(x, 60.0, 6.0, periodic=True)
    assert y.shape == x.shape and y[-1] == y[0]
    assert np.abs(y - x).max() < 3e-4  # the gain at 2 Hz is 1 − (2/6)⁸ ≈ 1 − 1.5e-4, and there are no edges


def test_the_ends_of_a_record_keep_its_curvature():
    t = np.arange(300) / 60.0
    x = np.cos(2 * np.pi * t)
    y = lowpass_record(x, 60.0, 6.0)
    n = edge_samples(60.0, 6.0)
    assert (
        np.abs(y - x)[n:-n].max() < 1e-4 and np.abs(y - x).max() < 2e-3
    )  # a plain odd extension is 5x worse at the ends


@pytest.mark.parametrize("cutoff", [-1.0, 0.0, 30.0, 40.0])
def test_bad_cutoffs(cutoff):
    with pytest.raises(TrajectoryError, match="cutoff"):
        lowpass_record(np.zeros(100), 60.0, cutoff, source="walk.csv")


def test_the_cycle_count_and_period_of_a_trajectory():
    events = gait_cycles(iso14242(rate=200.0, cycles=4.5, frequency=1.25))
    assert events.cycles == 4 - 1 or events.cycles == 4  # heel strikes inside 4.5 cycles
    assert events.period == pytest.approx(0.8, abs=1 / 200.0)
