"""What the plant-and-model run decides itself (hipsim.cli.simulate_machine): whether it was asked for, the sensor's
options only with the sensors, the output's kind, the sensor's noise, the servo instants, each station's verdict
line. The run through the command line: cli/test_simulate_plant.py."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from hipsim.cli.simulate_machine import (
    MACHINE_OPTIONS,
    _instants,
    check_options,
    machine_loop_asked,
    sensor_noise,
    station_verdicts,
)
from hipsim.exceptions import HipsimError
from hipsim.motion.iso_compliance import DEFAULT_TOLERANCES
from hipsim.motion.iso_verdict import station_iso
from hipsim.motion.trajectories import iso14242


def args(**given):
    return SimpleNamespace(**({name: None for name in MACHINE_OPTIONS} | {"out": "-"} | given))


def test_the_loop_is_asked_for_by_any_of_its_options():
    assert not machine_loop_asked(args())
    for name in MACHINE_OPTIONS:
        assert machine_loop_asked(args(**{name: 0}))  # even a zero is given


def test_the_sensors_options_need_the_sensors(tmp_path):
    check_options(args(feedback="sensors", sensor_noise=0.1, out=str(tmp_path / "r.parquet")))
    with pytest.raises(HipsimError, match="--sensor-drift describes the attitude sensor: it needs --feedback sensors "
                       r"\(the loop closes on the encoders\)"):  # fmt: skip
        check_options(args(sensor_drift=0.1))
    with pytest.raises(HipsimError, match=r"--out r.txt: expected a .csv or .parquet file"):
        check_options(args(out="r.txt"))


def test_the_sensors_noise_in_radians_only_with_the_sensors():
    assert sensor_noise(args(feedback="encoders", sensor_noise=1.0)) == 0.0
    assert sensor_noise(args(feedback="sensors", sensor_noise=2.0)) == pytest.approx(math.radians(2.0))
    assert sensor_noise(args(feedback="sensors")) == pytest.approx(math.radians(0.05))  # the default 0.05°


def test_the_servo_instants_cover_the_duration_without_its_end():
    assert _instants(0.01, 1000.0).tolist() == pytest.approx([k / 1000.0 for k in range(10)])
    assert len(_instants(1.0, 999.9)) == 1000  # rounded, not floored


def test_a_verdict_line_per_station_with_its_role():
    iso = iso14242(rate=50.0)
    attitudes = (iso.q, iso.q + np.radians([0.0, 5.0, 0.0]))  # m_2 5° off on β

    def run(n: int, control: int) -> SimpleNamespace:
        stations = tuple(
            station_iso(f"m_{j}", iso.t[:n], q[:n], iso.q[:n], iso.Fe[:n], DEFAULT_TOLERANCES, periodic=n == len(iso.t))
            for j, q in enumerate(attitudes, start=1)
        )
        return SimpleNamespace(stations=stations, controller="pd", control=control)

    one, two = station_verdicts([run(len(iso.t), 1)])
    assert one.startswith("ISO 14242-1 check of station 1's motion under pd (m_1, controlled) (1 cycle(s)): PASS: ")
    assert two.startswith("ISO 14242-1 check of station 2's motion under pd (m_2, following) (1 cycle(s)): FAIL (beta)")
    lines = station_verdicts([run(5, 2)])
    assert len(lines) == 2 and all(": not made (" in line for line in lines)
    assert "(m_2, controlled)" in lines[1] and "(m_1, following)" in lines[0]
