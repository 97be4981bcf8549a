"""A bad file is a skipped snapshot, not a stopped test: a cut file, a missing snapshot, a file still being written,
time stamps too coarse, a snapshot cut short; each named, the run goes on. One reader: a snapshot with a comment line,
';' separators and decimal commas reads as the rig-log reader reads any log."""

from __future__ import annotations

import json
import os
import shutil
import time

import pytest
from monitor_synthetic import write_identified, write_test

import hipsim
from hipsim.cli.main import main

RATE = 250.0  # the synthetic snapshots' sample rate: 3 cycles, 750 samples


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


@pytest.fixture(scope="module")
def clean(tmp_path_factory, params):
    folder = tmp_path_factory.mktemp("clean")
    write_test(folder, params, last=2_000_000)
    return folder


def _lines(path):
    return path.read_text(encoding="utf-8").splitlines(keepends=True)


@pytest.fixture
def damaged(tmp_path, clean):
    """The test with every kind of damage; the files' times set back an hour but the one still being written."""
    logs = tmp_path / "logs"
    shutil.copytree(clean, logs)
    cut = _lines(logs / "snap_00750000.csv")  # cut mid-row: line 401 has 3 of its 9 cells
    (logs / "snap_00750000.csv").write_text("".join(cut[:400]) + ",".join(cut[400].split(",")[:3]), encoding="utf-8")
    short = _lines(logs / "snap_01500000.csv")  # cut mid-number in the last cell: 449 samples of 750, all numbers
    (logs / "snap_01500000.csv").write_text("".join(short[:449]) + short[449][:-4], encoding="utf-8")
    (logs / "snap_01250000.csv").unlink()  # missing
    coarse = _lines(logs / "snap_01750000.csv")  # stamps with 9 significant digits at 1e6 s: 0.004 s steps repeat
    header = coarse[0].split(",")
    k = header.index("t_s")
    rows = []
    for line in coarse[1:]:
        cells = line.split(",")
        cells[k] = f"{1e6 + float(cells[k]):.9g}"
        rows.append(",".join(cells))
    (logs / "snap_01750000.csv").write_text(coarse[0] + "".join(rows), encoding="utf-8")
    european = _lines(logs / "snap_00500000.csv")  # one reader: comment, ';' and decimal commas
    (logs / "snap_00500000.csv").write_text(
        "# rig 2, station A+B, logged by the controller\n"
        + "".join(line.replace(",", ";").replace(".", ",") for line in european),
        encoding="utf-8",
    )
    hour_ago = time.time() - 3600
    for path in logs.glob("*.csv"):
        os.utime(path, (hour_ago, hour_ago))
    growing = _lines(logs / "snap_02000000.csv")  # still being written: half of it, just now
    (logs / "snap_02000000.csv").write_text("".join(growing[:380]), encoding="utf-8")
    return logs


def _run(tmp_path, logs, capsys, *more, page=True):
    report = tmp_path / "report"
    status = main(
        [
            "monitor",
            "--params",
            str(write_identified(tmp_path / "identified.toml")),
            "--log",
            str(logs),
            *(["--report", str(report)] if page else []),
            "--summary-format",
            "json",
            "--settle",
            "0.4",
            *more,
        ]
    )
    captured = capsys.readouterr()
    written = (report / "index.html").read_text(encoding="utf-8") if page else None
    return status, json.loads(captured.out), captured.err, written


def test_the_run_goes_on_and_names_each_bad_file(tmp_path, damaged, capsys):
    status, summary, err, page = _run(tmp_path, damaged, capsys)
    assert status == 0
    skipped = {item["file"]: item for item in summary["skipped"]}
    assert set(skipped) == {"snap_00750000.csv", "snap_01750000.csv"}
    cut = skipped["snap_00750000.csv"]
    assert cut["line"] == 401 and "line 401" in cut["reason"] and "3 cells, the header has 9" in cut["reason"]
    assert "--rate HZ" in skipped["snap_01750000.csv"]["reason"] and "t_s" in skipped["snap_01750000.csv"]["reason"]
    # The file still being written: a batch run waited (--settle 0.4 s at most), then read it: not skipped, incomplete.
    assert summary["waiting"] == [] and "snap_02000000.csv" in summary["table"]["file"]
    # The ones not readable and the one never written (2,000,000 read, the sequence reaches it).
    assert summary["missing"] == [750_000, 1_250_000, 1_750_000]
    assert summary["incomplete"] == ["snap_01500000.csv", "snap_02000000.csv"]
    table = summary["table"]
    k = table["file"].index("snap_01500000.csv")
    assert table["samples"][k] == 449 and "incomplete: 449 of 750 samples" in table["note"][k]
    assert "no line end after its last line" in table["note"][k]
    # The snapshot with a comment, ';' and decimal commas is read like the others.
    assert (
        "snap_00500000.csv" in table["file"] and table["phase"][table["file"].index("snap_00500000.csv")] == "baseline"
    )
    for name in ("snap_00750000.csv", "snap_01750000.csv"):
        assert name in err and name in page
    # A skipped file keeps its identity: size and SHA-256 in the JSON, the text and the page.
    import hashlib

    for name in ("snap_00750000.csv", "snap_01750000.csv"):
        data = (damaged / name).read_bytes()
        assert skipped[name]["bytes"] == len(data) and skipped[name]["sha256"] == hashlib.sha256(data).hexdigest()
        assert skipped[name]["sha256"] in page
    assert "line 401" in page and "missing: 750,000, 1,250,000" in page and "incomplete: 449 of 750 samples" in page
    # Every snapshot's identity: its size and SHA-256, in the JSON and on the page.
    files = {item["file"]: item for item in summary["files"]}
    assert files["snap_00000000.csv"]["bytes"] == (damaged / "snap_00000000.csv").stat().st_size
    digest = hashlib.sha256((damaged / "snap_00000000.csv").read_bytes()).hexdigest()
    assert files["snap_00000000.csv"]["sha256"] == digest and digest in page


def test_coarse_time_stamps_are_read_from_the_sample_index_with_rate(tmp_path, damaged, capsys):
    status, summary, _, _ = _run(tmp_path, damaged, capsys, "--rate", str(RATE), page=False)
    assert status == 0 and "snap_01750000.csv" in summary["table"]["file"]
    assert summary["missing"] == [750_000, 1_250_000]


def test_nothing_usable_is_exit_2_naming_why(tmp_path, clean, capsys):
    logs = tmp_path / "logs"
    logs.mkdir()
    lines = _lines(clean / "snap_00000000.csv")
    (logs / "snap_00000000.csv").write_text("".join(lines[:200]) + "1,2\n", encoding="utf-8")
    status = main(
        ["monitor", "--settle", "0", "--params", str(write_identified(tmp_path / "p.toml")), "--log", str(logs)]
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and err[-1].startswith("hipsim: error: ") and "no usable snapshot" in err[-1]
    assert "snap_00000000.csv" in err[-1] and "line 201" in err[-1]


def test_a_rate_that_is_not_the_log_s_is_refused(clean, params):
    from hipsim.exceptions import TrajectoryError
    from hipsim.rig.monitoring.snapshot_log import read_snapshot
    from hipsim.rig.monitoring.snapshots import find_snapshots

    snapshot = find_snapshots(clean / "snap_00000000.csv")[0][0]
    assert read_snapshot(snapshot, params, rate=RATE).log.rate == pytest.approx(RATE)
    with pytest.raises(TrajectoryError, match="the times span 2.996 s, the 750 samples at 500 Hz 1.498 s"):
        read_snapshot(snapshot, params, rate=2 * RATE)
