"""hipsim monitor end to end: parallel = serial, resumed = fresh, the command's outputs and exit codes, bad input."""

from __future__ import annotations

import math
import shutil
from functools import partial
from pathlib import Path

import numpy as np
import pytest
from monitor_synthetic import write_snapshot, write_test

import hipsim
from hipsim.cli import monitor as monitor_cli
from hipsim.cli.main import main
from hipsim.rig.monitoring import control_chart, monitor_run
from hipsim.rig.monitoring.monitor_fit import MonitorSetup
from hipsim.rig.monitoring.monitor_table import read_table
from hipsim.rig.monitoring.snapshots import find_snapshots as _find

run_monitor = partial(
    monitor_run.run_monitor, baseline_min=3
)  # three baseline snapshots (every 250,000 cycles in 500,000-1,000,000): the chart's minimum set to them


def find_snapshots(logs, **options):
    """The snapshots alone (none is left out in these tests)."""
    snapshots, skipped = _find(logs, **options)
    assert not skipped
    return snapshots


MODELS = Path(hipsim.__file__).resolve().parent.parent / "models"


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


@pytest.fixture(scope="module")
def identified(tmp_path_factory):
    """An identified parameter file: the published machine with the header hipsim identify writes."""
    path = tmp_path_factory.mktemp("params") / "identified.toml"
    published = Path(hipsim.load_parameters().source).read_text(encoding="utf-8")
    path.write_text(
        "# Identified by hipsim identify: a parameter file every hipsim command accepts (--params).\n"
        "# Model: analytic, lever spin on; regressor condition number 10.\n\n" + published,
        encoding="utf-8",
    )
    return path


@pytest.fixture(scope="module")
def test_logs(tmp_path_factory, params):
    folder = tmp_path_factory.mktemp("snapshots")
    write_test(folder, params, every=250_000, last=2_000_000, step_at=1_600_000, step=0.035)
    return folder


def _same(a: dict, b: dict) -> None:
    assert list(a) == list(b)
    for name in a:
        for x, y in zip(a[name], b[name], strict=True):
            assert x == y or (isinstance(x, float) and math.isnan(x) and math.isnan(y)), name


def test_parallel_run_equals_the_serial_one(params, test_logs):
    setup = MonitorSetup(params)
    snapshots = find_snapshots(test_logs)
    serial = run_monitor(setup, snapshots, workers=1)
    parallel = run_monitor(setup, snapshots, workers=2, batch_size=2)
    _same(serial.columns, parallel.columns)


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_a_resumed_run_equals_a_fresh_one(params, test_logs, tmp_path, suffix):
    setup = MonitorSetup(params)
    fresh = run_monitor(setup, find_snapshots(test_logs), out=tmp_path / f"fresh{suffix}")
    partial = tmp_path / "partial"
    partial.mkdir()
    for path in sorted(test_logs.glob("*.csv"))[:5]:
        shutil.copy(path, partial)
    out = tmp_path / f"resumed{suffix}"
    first = run_monitor(setup, find_snapshots(partial), out=out)
    assert first.new == 5
    resumed = run_monitor(setup, find_snapshots(test_logs), out=out)
    assert resumed.kept == 5 and resumed.new == len(fresh.columns["cycle"]) - 5
    _same(fresh.columns, resumed.columns)
    _same(read_table(tmp_path / f"fresh{suffix}"), read_table(out))
    again = run_monitor(setup, find_snapshots(test_logs), out=out)
    assert again.new == 0


def test_another_set_up_into_the_same_table_is_refused(params, test_logs, tmp_path, identified, capsys):
    out = tmp_path / "table.csv"
    run_monitor(MonitorSetup(params), find_snapshots(test_logs), out=out)
    before = out.read_bytes()
    status = main(
        [
            "monitor",
            "--baseline-min",
            "3",
            "--settle",
            "0",
            "--params",
            str(identified),
            "--log",
            str(test_logs),
            "--out",
            str(out),
            "--cutoff",
            "15",
        ]
    )
    assert status == 2 and "another set-up" in capsys.readouterr().err and out.read_bytes() == before
    assert (
        main(
            [
                "monitor",
                "--baseline-min",
                "3",
                "--settle",
                "0",
                "--params",
                str(identified),
                "--log",
                str(test_logs),
                "--out",
                str(out),
                "--cutoff",
                "15",
                "--restart",
            ]
        )
        == 1
    )


def test_the_command_writes_table_report_and_exits_1_on_an_active_alarm(test_logs, identified, tmp_path, capsys):
    out, report = tmp_path / "friction.csv", tmp_path / "report"
    status = main(
        [
            "monitor",
            "--baseline-min",
            "3",
            "--settle",
            "0",
            "--params",
            str(identified),
            "--log",
            str(test_logs),
            "--out",
            str(out),
            "--report",
            str(report),
            "--summary-format",
            "json",
            "--baseline",
            "500000:1000000",
        ]
    )
    assert status == 1
    import json

    summary = json.loads(capsys.readouterr().out)
    assert summary["alarm_active"] and summary["first_alarm"]["cycle"] == 1_750_000
    assert summary["first_alarm"]["hip_mu_change"] == pytest.approx(0.035, abs=0.004)
    assert summary["provenance"]["parameters"]
    table = read_table(out)
    assert {
        "cycle",
        "load_friction_mm",
        "load_friction_mm_std",
        "hip_mu_change",
        "hip_mu_change_std",
        "screw_coulomb_Nmm",
        "screw_coulomb_Nmm_std",
        "screw_viscous_Nmm_s_rad",
        "screw_viscous_Nmm_s_rad_std",
        "residual_rms_Nmm",
        "alarm",
    } <= set(table)
    page = (report / "index.html").read_text(encoding="utf-8")
    assert 'id="verdict"' in page and 'id="provenance"' in page and "ALARM" in page and "snap_01750000.csv" in page
    for stem in ("chart", "terms", "residuals"):
        assert (report / f"{stem}.png").stat().st_size > 0 and (report / f"{stem}.svg").stat().st_size > 0


def test_no_alarm_at_the_last_snapshot_exits_0(params, tmp_path, identified, capsys):
    write_test(tmp_path / "logs", params, every=250_000, last=1_500_000)
    assert (
        main(
            [
                "monitor",
                "--baseline-min",
                "3",
                "--settle",
                "0",
                "--params",
                str(identified),
                "--log",
                str(tmp_path / "logs"),
            ]
        )
        == 0
    )
    assert "state: OK at the last snapshot" in capsys.readouterr().out


def test_the_parser_defaults_are_the_library_s():
    assert monitor_cli.DEFAULT_ALARM_RISE == control_chart.DEFAULT_ALARM_RISE
    assert control_chart.parse_baseline(monitor_cli.DEFAULT_BASELINE) == control_chart.DEFAULT_BASELINE


# --- Bad input: one clear line naming the file, nothing written ------------------------------------


def _bad(tmp_path, identified, capsys, logs, params_file=None) -> str:
    out, report = tmp_path / "out.csv", tmp_path / "report"
    status = main(
        [
            "monitor",
            "--baseline-min",
            "3",
            "--settle",
            "0",
            "--params",
            str(params_file or identified),
            "--log",
            str(logs),
            "--out",
            str(out),
            "--report",
            str(report),
        ]
    )
    err = capsys.readouterr().err.strip()
    assert status == 2 and err.startswith("hipsim: error: ") and len(err.splitlines()) == 1
    assert not out.exists() and not report.exists()
    return err


@pytest.fixture
def one(params, tmp_path):
    folder = tmp_path / "logs"
    folder.mkdir()
    write_snapshot(folder / "a.csv", params, 0.1, 1000, np.random.default_rng(1))
    return folder


def test_a_snapshot_without_cycle(params, tmp_path, identified, capsys):
    folder = tmp_path / "logs"
    folder.mkdir()
    write_snapshot(folder / "nocycle.csv", params, 0.1, 0, np.random.default_rng(1), cycle_column=False)
    assert "nocycle.csv" in (err := _bad(tmp_path, identified, capsys, folder)) and "'cycle'" in err


def test_a_decreasing_counter(one, tmp_path, identified, capsys):
    path = one / "a.csv"
    lines = path.read_text().splitlines()
    k = lines[0].split(",").index("cycle")
    cells = lines[300].split(",")
    cells[k] = "5"
    lines[300] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n")
    err = _bad(tmp_path, identified, capsys, one)
    assert "a.csv" in err and "line 301" in err and "decreases" in err


def test_two_files_with_the_same_cycles(one, tmp_path, identified, capsys):
    # The copy is skipped and named (each cycle in one snapshot only); the original goes on.
    shutil.copy(one / "a.csv", one / "b.csv")
    status = main(["monitor", "--baseline-min", "3", "--settle", "0", "--params", str(identified), "--log", str(one)])
    captured = capsys.readouterr()
    assert status == 0 and "1 snapshots" in captured.out
    assert "skipped b.csv" in captured.err and "as does a.csv" in captured.err and "1000-1002" in captured.err


def test_a_snapshot_too_short_for_its_filter(params, tmp_path, identified, capsys):
    folder = tmp_path / "logs"
    folder.mkdir()
    path = write_snapshot(folder / "short.csv", params, 0.1, 0, np.random.default_rng(1))
    path.write_text("\n".join(path.read_text().splitlines()[:80]) + "\n")
    err = _bad(tmp_path, identified, capsys, folder)
    assert "short.csv" in err and "too short" in err


def test_a_parameter_file_without_identified_values(one, tmp_path, identified, capsys):
    published = hipsim.load_parameters().source
    err = _bad(tmp_path, identified, capsys, one, params_file=published)
    assert "hip_simulator.toml" in err and "identified" in err


def test_an_identification_table_is_accepted(one, tmp_path, capsys):
    published = Path(hipsim.load_parameters().source).read_text(encoding="utf-8")
    path = tmp_path / "with_table.toml"
    path.write_text(published + "\n[identification]\nlogs = ['rig.csv']\n", encoding="utf-8")
    from hipsim.rig.monitoring.reference import identified_file

    assert identified_file(path) is True


def test_a_long_log_in_windows_writes_no_temporary_file(params, tmp_path, monkeypatch):
    import builtins
    import hashlib
    import tempfile

    write_snapshot(tmp_path / "long.csv", params, 0.1, 100, np.random.default_rng(2), cycles=7)
    opened = []

    def reading_only(file, mode="r", *args, **kwargs):
        assert not set(mode) & set("wax+"), f"{file} opened to write"
        opened.append(str(file))
        return real_open(file, mode, *args, **kwargs)

    real_open = builtins.open
    monkeypatch.setattr(builtins, "open", reading_only)
    for name in ("TemporaryDirectory", "NamedTemporaryFile", "mkstemp", "mkdtemp"):
        monkeypatch.setattr(tempfile, name, None)  # calling any of them fails
    snapshots = find_snapshots(tmp_path, window=2)
    assert [(s.first_cycle, s.last_cycle) for s in snapshots] == [
        (100, 101),
        (102, 103),
        (104, 105),
    ]  # 106 waits for 107
    result = run_monitor(MonitorSetup(params, window=2), snapshots)
    monkeypatch.undo()
    f = params.friction
    truth = (f.hip_radius * 0.1 + f.thrust_radius * f.thrust_mu) * 1e3
    assert result.columns["file"] == ["long.csv[100-101]", "long.csv[102-103]", "long.csv[104-105]"]
    assert np.allclose(result.columns["load_friction_mm"], truth, rtol=0.02)
    # The finder reads the file twice (the reader's scan of its counter, one pass hashing each window's lines),
    # each window's estimate once (its lines).
    assert opened == [str(tmp_path / "long.csv")] * 5
    # A window's identity is the SHA-256 of its own lines: those of cycles 102-103 (the header not among them).
    lines = (tmp_path / "long.csv").read_text(encoding="utf-8").splitlines(keepends=True)
    cycle = [line.split(",")[1] for line in lines[1:]]
    window = "".join(line for line, c in zip(lines[1:], cycle) if c in ("102", "103"))
    assert snapshots[1].sha256 == hashlib.sha256(window.encode()).hexdigest()
    assert snapshots[1].size == len(window.encode())


def test_without_pandas_a_table_of_columns(params, test_logs, monkeypatch):
    import sys

    from hipsim.rig.monitoring.monitor_run import MonitorTable, monitor

    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas raises ImportError
    table = monitor(params, test_logs, baseline="500000:1000000", baseline_min=3)
    assert isinstance(table, MonitorTable) and len(table) == 9 and table["alarm"][-1] == 1
