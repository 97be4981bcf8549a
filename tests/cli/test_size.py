"""The size command's own logic (hipsim.cli.size): the cycles it checks, the sizing rules it is given, its tables'
rows (a check's verdict and bound, a band's confidence). The ranking through the command line: design/test_ranking.py."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from hipsim.cli.size import _rules, _trajectories, format_bands, format_checks
from hipsim.design.checks import Check
from hipsim.exceptions import HipsimError
from hipsim.machine.drive_parts import SizingRules


def cycle_options(**given):
    return SimpleNamespace(**(dict(without_iso=False, trajectory=[], rate=None, cycles=None, frequency=None) | given))


def test_the_built_in_cycle_by_default_with_its_options():
    ((trajectory, cycles),) = _trajectories(cycle_options(rate=50.0, cycles=2.0))
    assert cycles == 2.0 and len(trajectory) == 100 and trajectory.t[1] == pytest.approx(0.02)


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ({"without_iso": True}, "--without-iso leaves no cycle to check: give --trajectory FILE"),
        (
            {"without_iso": True, "trajectory": ["a.csv"], "rate": 100.0, "frequency": 2.0},
            "--rate, --frequency apply to the built-in cycle, which --without-iso leaves out",
        ),
    ],
)
def test_without_the_iso_cycle(given, message):
    with pytest.raises(HipsimError, match=message):
        _trajectories(cycle_options(**given))


def test_the_rules_given_replace_the_drives_and_must_be_positive():
    base = SizingRules()
    rules = _rules(SimpleNamespace(life_cycles=1e7, inertia_ratio=None), base)
    assert rules.life_target_cycles == 1e7 and rules.inertia_ratio_max == base.inertia_ratio_max
    assert _rules(SimpleNamespace(life_cycles=None, inertia_ratio=None), base) == base
    for bad in (0.0, -1.0, math.inf):
        with pytest.raises(HipsimError, match="--inertia-ratio: expected a positive number"):
            _rules(SimpleNamespace(life_cycles=None, inertia_ratio=bad), base)


def test_a_check_row_says_pass_fail_or_not_checked():
    checks = [
        Check(1, "s1_rms", 216.6, 300.0, 0.278, True),
        Check(2, "s1_rms", 330.0, 300.0, -0.1, False, detail="at 0.4 s"),
        Check(3, "max_speed", 3000.0, None, None, None, detail="no top speed"),
    ]
    lines = format_checks(checks, "Checks").splitlines()
    rows = [line for line in lines if line.lstrip().startswith("LN")]
    assert rows[0].rstrip().endswith("pass") and "+27.8 %" in rows[0]
    assert "FAIL" in rows[1] and "at 0.4 s" in rows[1] and "≤ 300" in rows[1]
    assert "not checked" in rows[2] and "no top speed" in rows[2]


def test_a_band_without_a_deviation_is_left_out_and_one_below_confidence_says_no():
    check = Check(1, "s1_rms", 216.6, 300.0, 0.278, True)
    bands = [
        SimpleNamespace(std=None, check=check, interval=(0.0, 0.0), confident=None),
        SimpleNamespace(std=0.2, check=check, interval=(-0.05, 0.6), confident=False),
        SimpleNamespace(std=0.01, check=check, interval=(0.26, 0.3), confident=True),
    ]
    rows = [line for line in format_bands(bands).splitlines() if line.lstrip().startswith("LN")]
    assert len(rows) == 2
    assert "±20 %" in rows[0] and rows[0].rstrip().endswith("NO")
    assert "±1 %" in rows[1] and rows[1].rstrip().endswith("yes")
