"""The monitor command's option checks (hipsim.cli.monitor._check): each refused at its edge in one line naming the
option, the edges themselves accepted. The monitor's runs: rig/monitoring/test_monitor_run*.py."""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any

import pytest

from hipsim.cli.monitor import LEAST_BASELINE_MIN, _check
from hipsim.exceptions import HipsimError


def options(**given):
    base: dict[str, Any] = dict(
        workers=None, alarm_rise=0.01, window=None, rate=None, settle=5.0, baseline_min=5, acknowledge=[],
        poll=30.0, on_alarm=None, watch=False, pdf=False, report=None,
    )  # fmt: skip
    return SimpleNamespace(**(base | given))


def test_the_edges_are_accepted():
    _check(options(workers=1, window=1, rate=1e-9, settle=0.0, baseline_min=LEAST_BASELINE_MIN, acknowledge=[0]))
    _check(options(on_alarm="notify-send 'alarm'", watch=True, pdf=True, report="page"))
    assert LEAST_BASELINE_MIN == 2


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ({"workers": 0}, "--workers: expected a positive number of processes, got 0"),
        ({"alarm_rise": 0.0}, "--alarm-rise: expected a positive change"),
        ({"alarm_rise": math.nan}, "--alarm-rise"),
        ({"window": 0}, "--window: expected a positive number of cycles, got 0"),
        ({"rate": 0.0}, "--rate: expected a positive sample rate in Hz, got 0"),
        ({"rate": math.inf}, "--rate"),
        ({"settle": -1e-9}, "--settle: expected seconds ≥ 0"),
        ({"baseline_min": 1}, "--baseline-min: expected a count of snapshots ≥ 2, got 1"),
        ({"acknowledge": [3, -1]}, "--acknowledge: expected a cycle ≥ 0, got -1"),
        ({"poll": 0.0}, "--poll: expected seconds > 0"),
        ({"on_alarm": "beep"}, "--on-alarm: runs with --watch only"),
        ({"pdf": True}, "--pdf: prints the page, so it needs --report DIR"),
        ({"on_alarm": "  ", "watch": True}, "--on-alarm: expected a command, got '  ' \\(empty\\)"),
        ({"on_alarm": "say 'open", "watch": True}, "--on-alarm: expected a command, got"),
    ],
)
def test_each_option_refused_in_one_line(given, message):
    with pytest.raises(HipsimError, match=message) as caught:
        _check(options(**given))
    assert "\n" not in str(caught.value)
