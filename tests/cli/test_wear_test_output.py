"""The wear test's output helpers (hipsim.cli.wear_test_output): which platform a station is, a confidence interval
in words. The outputs through the command line: cli/test_wear_test.py."""

from __future__ import annotations

import math
from types import SimpleNamespace

from hipsim.cli.wear_test_output import _ci, _station_number


def test_a_stations_platform_from_its_motion_or_its_name():
    args = SimpleNamespace(station=["A=run/stations.csv:2", "B=snapshots", "C=x.csv:3"])
    assert _station_number(args, "A") == 2  # the platform its motion file names
    assert _station_number(args, "B") is None  # snapshots name no platform
    assert _station_number(args, "C") is None  # 3 is no platform
    assert _station_number(SimpleNamespace(station=None), "1") == 1  # a station named 1 or 2 is that platform
    assert _station_number(SimpleNamespace(station=["1=a.csv:2"]), "1") == 2  # its motion wins over its name


def test_a_confidence_interval_or_a_dash():
    assert _ci((1.23456, 2.5)) == "[1.235, 2.5]"
    assert _ci((math.nan, 2.0)) == "–" and _ci((0.0, math.inf)) == "–"
