"""The monitor's page: traceable (every snapshot's SHA-256, the parameter file listed once), printable (--pdf as
report --pdf, no column lost), the axis in million cycles."""

from __future__ import annotations

import json
import os
import re
import shutil

import numpy as np
import pytest
from monitor_synthetic import write_identified, write_snapshot
from support import given

import hipsim
from hipsim.cli.main import main
from hipsim.present import pages

CYCLES = (0, 250_000, 500_000, 750_000, 1_000_000, 1_250_000)


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    params = hipsim.load_parameters()
    folder = tmp_path_factory.mktemp("logs")
    rng = np.random.default_rng(4)
    for cycle in CYCLES:
        write_snapshot(folder / f"snap_{cycle:08d}.csv", params, 0.1, cycle, rng)
    return folder


def _monitor(tmp_path, logs, *more):
    params = write_identified(tmp_path / "identified.toml")
    report = tmp_path / "report"
    argv = [
        "monitor",
        "--baseline-min",
        "3",
        "--settle",
        "0",
        "--params",
        str(params),
        "--log",
        str(logs),
        "--report",
        str(report),
        *more,
    ]
    return main(argv), report


def test_the_page_is_traceable_and_its_axis_in_million_cycles(tmp_path, logs):
    status, report = _monitor(tmp_path, logs)
    assert status == 0
    document = json.loads((report / "monitor.json").read_text(encoding="utf-8"))
    assert list(document)[:2] == ["verdict", "provenance"] and document["verdict"]["level"] == "OK"  # records.Verdict
    assert document["verdict"]["judged"] == "no alarm at the last snapshot (cycle 1,250,002)"  # its last cycle
    inputs = [item["path"] for item in document["provenance"]["inputs"]]
    assert inputs.count(str(tmp_path / "identified.toml")) == 1  # the parameter file once
    page = (report / "index.html").read_text(encoding="utf-8")
    for item in document["files"]:
        assert item["sha256"] in page and item["bytes"] == (logs / item["file"]).stat().st_size
    assert '<details id="files">' in page
    assert "✔ OK</span>" in page and "<p>No alarm at the last snapshot (cycle 1,250,002).</p>" in page
    # The table holds every number the JSON has for a snapshot: the weight term, EWMA and both limits, flag and note.
    header = given(re.search(r'<table class="snapshots"><thead>\s*<tr>(.*?)</tr>', page, re.S)).group(1)
    names = re.findall(r"<th[^>]*>([^<]*)</th>", header)
    for name in ("Mc", "weight_friction_Nmm", "ewma_mm", "lcl_mm", "ucl_mm", "flag", "note"):
        assert name in names
    assert "1.250" in page  # 1,250,000 cycles as Mc
    svg = (report / "chart.svg").read_text(encoding="utf-8")
    assert "million cycles" in svg or "Mc" in svg


def test_pdf_without_chromium_is_a_clear_error_and_writes_nothing(tmp_path, logs, monkeypatch, capsys):
    monkeypatch.setattr(pages, "find_browser", lambda: None)
    status, report = _monitor(tmp_path, logs, "--pdf")
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1 and "--pdf needs Chromium" in err and not report.exists()


def test_pdf_is_the_page_with_every_column(tmp_path, logs):
    if not any(shutil.which(name) for name in ("chromium", "chromium-browser")):
        if os.environ.get("HIPSIM_REQUIRE_BROWSER") == "1":
            pytest.fail("HIPSIM_REQUIRE_BROWSER=1 but chromium is not on PATH")
        pytest.skip("chromium is not on PATH (set HIPSIM_REQUIRE_BROWSER=1 to make this a failure)")
    status, report = _monitor(tmp_path, logs, "--pdf")
    assert status == 0
    from pypdf import PdfReader

    text = re.sub(r"\s+", "", "".join(page.extract_text() for page in PdfReader(report / "report.pdf").pages))
    for name in ("load_friction_mm", "ucl_mm", "flag", "note", "SHA-256"):
        assert name.replace("_", "") in text.replace("_", ""), name
