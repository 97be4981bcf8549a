"""hipsim.motion.filtering: one low-pass for trajectory files and rig logs; a whole record filtered without losing samples or edges that go wrong."""

import numpy as np
import pytest

from hipsim.exceptions import TrajectoryError
from hipsim.motion.filtering import edge_samples, lowpass, lowpass_record
from hipsim.motion.gait_events import gait_cycles
from hipsim.motion.trajectories import iso14242
from hipsim.rig.logs import log as rig_log


def test_the_rig_logs_filter_is_this_one_and_halves_the_cutoff():
    # Not a copy: the rig's log path calls this very function (each law lives once).
    assert rig_log.lowpass is lowpass
    # Forwards and backwards, the gain at the cut-off is (1/√2)² = 1/2: a 20 Hz sine at 1 kHz comes
    # out at half its amplitude away from the edges (tests/motion/test_filtering_laws.py pins the whole curve).
    t = np.arange(4000) / 1000.0
    y = lowpass(np.sin(2 * np.pi * 20.0 * t), 1000.0, 20.0)[400:-400]
    assert np.abs(y).max() == pytest.approx(0.5, rel=2e-3)


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
    # The ISO load sits at its swing level until each cycle's start, so the heel strikes are the
    # first samples of the cycles: 0, 0.8, 1.6, 2.4 and 3.2 s inside 4.5 cycles, 4 whole cycles.
    assert events.cycles == 4
    assert events.period == pytest.approx(0.8, abs=1e-12)


def test_reading_motion_loads_scipy_signal_only_to_filter():
    """scipy.signal is most of a command's start-up (0.3 s of CPU): the motion readers import it where they filter."""
    import subprocess
    import sys

    code = "import sys, hipsim.motion.build, hipsim.motion.trajectories; print('scipy.signal' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False", done.stderr
