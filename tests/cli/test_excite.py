"""The excite command's refusals before any design (hipsim.cli.excite.run): the rate for the harmonics asked (at its
edge), positive limits, the load range, at least one seed. The design itself: rig/identification/test_excitation*.py."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import pytest

from hipsim.cli.excite import run
from hipsim.exceptions import ArgumentError, OutputError


def options(tmp_path, **given):
    base: dict[str, Any] = dict(
        params=None, overrides=[], out=str(tmp_path / "e.csv"), duration=10.0, rate=200.0, harmonics=5,
        frequency=10.0, max_speed=None, max_acceleration=None, torque_limit=None, min_cond_inv=None, max_angle=None,
        load=None, target="dynamics", summary_format="text", seeds=0, iterations=1,
    )  # fmt: skip
    return SimpleNamespace(**(base | given))


def test_the_rate_must_be_four_samples_a_period_of_the_highest_harmonic(tmp_path, capsys):
    # 5 harmonics of 10 Hz: up to 50 Hz, 200 Hz at least; 200 Hz passes this check and stops at --seeds 0
    with pytest.raises(ArgumentError, match="--seeds, --iterations"):
        run(options(tmp_path))
    with pytest.raises(ArgumentError, match="--rate: expected at least 200 Hz for harmonics up to 50 Hz, got 199.9"):
        run(options(tmp_path, rate=199.9))
    assert not (tmp_path / "e.csv").exists()


@pytest.mark.parametrize(
    ("given", "option"),
    [
        ({"duration": 0.0}, "--duration"),
        ({"max_speed": 0.0}, "--max-speed"),
        ({"max_angle": -5.0}, "--max-angle"),
        ({"min_cond_inv": float("nan")}, "--min-cond-inv"),
        ({"load": "500:500"}, "--load-range"),
        ({"load": "-1:500"}, "--load-range"),
    ],
)
def test_limits_must_be_positive_and_a_load_range_rising(tmp_path, given, option):
    with pytest.raises(ArgumentError, match=option):
        run(options(tmp_path, **given))


def test_a_folder_is_no_output(tmp_path):
    with pytest.raises(OutputError, match="is a folder"):
        run(options(tmp_path, out=str(tmp_path)))
