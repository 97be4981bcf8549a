"""Commands a drive takes (hipsim.learning.export, hipsim export): positions, velocities and torques against the
command and the model, every limit checked before anything is written."""

from __future__ import annotations

import hashlib
import json

import numpy as np
import pytest
from stations_synthetic import deviated

from hipsim.analysis.runs import analyse
from hipsim.analytic.stations import platform_motion
from hipsim.cli.main import main
from hipsim.design.feasibility import Limits
from hipsim.exceptions import TrajectoryError
from hipsim.learning.export import command_period, drive_tables
from hipsim.machine.parameters import load_parameters
from hipsim.motion.trajectories import iso14242
from hipsim.stations.commands import station_commands


@pytest.fixture(scope="module")
def params():
    return load_parameters()


@pytest.fixture(scope="module")
def iso():
    return iso14242(rate=1000.0)


@pytest.fixture(scope="module")
def exact(params, iso):
    """The ISO cycle's carriages, rates and accelerations from the exact angle derivatives."""
    return platform_motion(params, iso.q, iso.qd, iso.qdd, 2)


def test_positions_velocities_torques_agree_with_the_command_and_the_model(params, iso, exact):
    L, Ld, Ldd = exact
    tables = drive_tables(params, iso.t, L, iso.Fe, 1000.0, 4096.0, Limits())
    assert np.array_equal(tables.L, L)  # the command's own samples, untouched
    assert np.abs(tables.Ld - Ld).max() < 1e-9 * np.abs(Ld).max()
    assert np.abs(tables.Ldd - Ldd).max() < 1e-7 * np.abs(Ldd).max()
    torque = analyse(params, iso).torques.total  # the model's inverse dynamics along the desired motion itself
    assert np.abs(tables.torque - torque).max() < 1e-7 * np.abs(torque).max()
    cols = tables.motor_columns(2)
    assert cols["position_counts"] == pytest.approx(L[:, 1] / params.lead * 4096.0, rel=1e-15)
    assert cols["velocity_rev_s"] == pytest.approx(Ld[:, 1] / 0.010, rel=1e-9, abs=1e-9)


def test_a_command_at_half_the_servo_rate_is_interpolated(params, iso, exact):
    L, Ld, _ = exact
    tables = drive_tables(params, iso.t[::2], L[::2], iso.Fe[::2], 1000.0, 10000.0, Limits())
    assert len(tables.t) == 1000
    assert tables.L[::2] == pytest.approx(L[::2], abs=1e-15)  # the command's samples kept
    assert np.abs(tables.L[1::2] - L[1::2]).max() < 1e-9  # between them, the trig interpolant: 1e-6 mm
    assert np.abs(tables.Ld - Ld).max() < 1e-6 * np.abs(Ld).max()


def test_a_repeated_period_is_found_and_repeated(params, iso, exact):
    L = exact[0]
    assert command_period(np.tile(L, (3, 1))) == 1000
    assert command_period(L) == 1000
    t = np.arange(3000) / 1000.0
    tables = drive_tables(params, t, np.tile(L, (3, 1)), np.tile(iso.Fe, 3), 1000.0, 10000.0, Limits())
    assert np.array_equal(tables.torque[2000:], tables.torque[:1000])
    assert tables.t[-1] == pytest.approx(2.999, abs=1e-12)


def test_a_speed_over_the_limit_is_refused_with_its_time_and_value(params, iso, exact):
    limits = Limits(motor_speed=1000.0 * 2 * np.pi / 60)  # 1000 rpm; the ISO cycle needs ~1870 rpm of motor 2
    with pytest.raises(
        TrajectoryError, match=r"motor 2 needs a speed of 1,8\d\d rpm at t = 0\.0\d+ s; the limit is 1,000 rpm"
    ):
        drive_tables(params, iso.t, exact[0], iso.Fe, 1000.0, 10000.0, limits)


def test_a_command_that_does_not_close_is_refused(params, iso, exact):
    L = exact[0][:600]  # 60 % of a cycle: its end does not lead into its start
    with pytest.raises(TrajectoryError, match="not periodic: carriage"):
        drive_tables(params, iso.t[:600], L, iso.Fe[:600], 1000.0, 10000.0, Limits())


def _command(tmp_path, iso, L, nan_at=None):
    path = tmp_path / "next.csv"
    values = L * 1e3
    if nan_at is not None:
        values = values.copy()
        values[nan_at, 1] = np.nan
    rows = np.column_stack([iso.t, values, iso.Fe])
    np.savetxt(path, rows, delimiter=",", header="t_s,L_11_mm,L_12_mm,L_13_mm,Fe_N", comments="", fmt="%.15g")
    return path


def test_export_writes_tables_and_a_sidecar(tmp_path, iso, exact, capsys):
    path = _command(tmp_path, iso, exact[0])
    out = tmp_path / "drive"
    assert main(["export", "--commands", str(path), "--out", str(out), "--counts-per-rev", "8192"]) == 0
    text = (out / "motor_3.csv").read_text().splitlines()
    assert text[0] == "t_s,position_counts,velocity_counts_s,position_rev,velocity_rev_s,torque_ff_3_Nmm"
    first = [float(x) for x in text[1].split(",")]
    assert first[1] == pytest.approx(exact[0][0, 2] / 0.010 * 8192, abs=0.5e-6)  # written to a millionth of a count
    assert first[3] == pytest.approx(exact[0][0, 2] / 0.010, abs=0.5e-10)
    sidecar = json.loads((out / "export.json").read_text())
    assert sidecar["rate_Hz"] == 1000.0 and sidecar["counts_per_rev"] == 8192.0
    assert set(sidecar["limits"]["not_checked"]) == {"stroke", "motor speed", "motor torque"}
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    assert digest in json.dumps(sidecar["provenance"])
    assert "not checked" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("extra", "nan_at", "words"),
    [
        (["--set", "motor.max_speed_rpm=1000"], None, "needs a speed of"),
        ([], 17, "not a finite number at t = 0.017 s"),
        (
            ["--counts-per-rev", "0"],
            None,
            "--counts-per-rev 0 counts: encoder counts per motor revolution must be at least 1",
        ),
        (["--rate", "-5"], None, "--rate -5 Hz: sample rate must be above 0"),
    ],
)
def test_bad_input_one_line_nothing_written(tmp_path, iso, exact, capsys, extra, nan_at, words):
    path = _command(tmp_path, iso, exact[0], nan_at)
    out = tmp_path / "drive"
    assert main(["export", "--commands", str(path), "--out", str(out), *extra]) == 2
    err = [line for line in capsys.readouterr().err.splitlines() if line.startswith("hipsim: error")]
    assert len(err) == 1 and words in err[0], err  # warnings of an unusual value may come before it
    assert not out.exists()


def test_a_per_chain_model_follows_its_controlled_platform(params, iso):
    machine = params.replace(geometry=deviated(seed=3, size_mm=0.3))
    command = station_commands(machine, iso.t, iso.q, "2")
    tables = drive_tables(machine, iso.t, command.carriages, iso.Fe, 1000.0, 1e4, Limits(), command.attitudes[:, 1])
    torque = analyse(machine, iso).torques.total  # m_2 along the desired motion: the command puts it there exactly
    assert tables.platform == 2
    assert np.abs(tables.torque - torque).max() < 1e-7 * np.abs(torque).max()


def test_with_a_drive_every_limit_is_checked(tmp_path, iso, exact, capsys):
    from pathlib import Path

    drive = Path(__file__).resolve().parents[2] / "models" / "drive_example.toml"
    path = _command(tmp_path, iso, exact[0])
    out = tmp_path / "drive"
    assert main(["export", "--commands", str(path), "--drive", str(drive), "--out", str(out)]) == 0
    limits = json.loads((out / "export.json").read_text())["limits"]
    assert limits["not_checked"] == [] and "motor torque" in limits["checked"] and "stroke" in limits["checked"]
