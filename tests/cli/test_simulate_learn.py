"""What ``simulate --learn`` decides itself (hipsim.cli.simulate_learn): one period to learn on, and the words of
its table. The learning run through the command line: cli/test_learn.py."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from hipsim.cli.simulate_learn import _apart, _change_mm, _one_period
from hipsim.exceptions import HipsimError
from hipsim.motion.trajectories import Trajectory, iso14242


def test_the_built_in_cycle_is_one_period_at_a_kilohertz():
    args = SimpleNamespace(cycles=None, frequency=None, period=None, trajectory=None)
    motion = _one_period(args, None)
    assert motion.periodic and len(motion) == 1000
    assert len(_one_period(SimpleNamespace(cycles=1, frequency=None, period=None), None)) == 1000
    with pytest.raises(HipsimError, match="--cycles 2: --learn runs one period per cycle"):
        _one_period(SimpleNamespace(cycles=2.0, frequency=None, period=None), None)


def test_a_file_must_be_one_whole_period():
    iso = iso14242(rate=50.0)
    assert _one_period(SimpleNamespace(trajectory="a.csv"), iso) is iso
    open_ = Trajectory(iso.t, iso.q, iso.qd, iso.qdd, iso.Fe, "a.csv", False)
    with pytest.raises(HipsimError, match="--trajectory a.csv: --learn repeats one period"):
        _one_period(SimpleNamespace(trajectory="a.csv"), open_)


def test_the_tables_words():
    assert _change_mm(SimpleNamespace(update=SimpleNamespace(change_rms_mm=(0.1, 0.3, 0.2)))) == 0.3
    assert _apart(SimpleNamespace(plant_params=None, feedback=None), None) == ""
    assert _apart(SimpleNamespace(plant_params="built.toml", feedback="sensors"), object()) == (
        " (built.toml under the model, sensors feedback)"
    )
    assert _apart(SimpleNamespace(plant_params=None, feedback=None), object()) == (
        " (the --params machine under the model, encoders feedback)"
    )
