"""hipsim iso-check: the built-in cycle passes, α scaled by 1.2 fails naming α, 1.2 Hz fails naming the frequency; files written."""

import json

import numpy as np

from hipsim.cli.main import main
from hipsim.motion.trajectories import iso14242_angles, iso14242_load


def write_csv(path, t, q, load):
    with open(path, "w") as f:
        f.write("t_s,alpha_deg,beta_deg,gamma_deg,Fe_N\n")
        for k in range(t.size):
            a, b, g = np.degrees(q[k])
            f.write(f"{t[k]:.6f},{a:.6f},{b:.6f},{g:.6f},{load[k]:.6f}\n")
    return path


def test_the_built_in_cycle_passes_and_the_folder_is_written(tmp_path, capsys):
    out = tmp_path / "iso"
    assert main(["iso-check", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "verdict: PASS" in text and "assumed" in text
    summary = json.loads((out / "iso_check.json").read_text())
    assert summary["verdict"]["level"] == "PASS" and summary["cycles"] == 1 and "passed" not in summary
    assert summary["quantities"]["load"]["tolerance"] == 90.0
    assert (out / "index.html").exists() and (out / "cycles.png").exists() and (out / "cycles.svg").exists()


def test_alpha_scaled_by_1_2_fails_and_names_alpha(tmp_path, capsys, quick_figures):
    t = np.arange(3000) / 500.0
    q, _, _ = iso14242_angles(t)
    q[:, 0] *= 1.2
    path = write_csv(tmp_path / "alpha.csv", t, q, iso14242_load(t))
    assert main(["iso-check", "--log", str(path), "--out", str(tmp_path / "iso")]) == 1
    text = capsys.readouterr().out
    assert "verdict: FAIL: alpha" in text and "FAIL: alpha," not in text


def test_a_cycle_at_1_2_hz_fails_and_names_the_frequency(tmp_path, capsys, quick_figures):
    assert (
        main(
            [
                "iso-check",
                "--frequency",
                "1.2",
                "--cycles",
                "3",
                "--out",
                str(tmp_path / "iso"),
                "--summary-format",
                "json",
            ]
        )
        == 1
    )
    summary = json.loads(capsys.readouterr().out)
    assert summary["failing"] == ["frequency"] and summary["cycles"] == 3


def test_tolerances_are_options_and_bad_ones_one_line(tmp_path, capsys, quick_figures):
    assert (
        main(
            [
                "iso-check",
                "--frequency",
                "1.2",
                "--cycles",
                "3",
                "--iso-tolerance",
                "frequency=0.25",
                "--out",
                str(tmp_path / "iso"),
            ]
        )
        == 0
    )
    capsys.readouterr()
    assert main(["iso-check", "--iso-tolerance", "speed=3", "--out", str(tmp_path / "iso2")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("hipsim: error: --iso-tolerance:") and "\n" not in err


def test_the_page_opens_with_the_verdict_and_hashes_its_log(tmp_path, capsys, quick_figures):
    """Like every hipsim page: the verdict above the first table, the log's SHA-256 in the provenance (page and JSON)."""
    import hashlib

    t = np.arange(3000) / 500.0
    q, _, _ = iso14242_angles(t)
    q[:, 0] *= 1.2
    path = write_csv(tmp_path / "alpha.csv", t, q, iso14242_load(t))
    out = tmp_path / "iso"
    assert main(["iso-check", "--log", str(path), "--out", str(out), "--rig", "station 2"]) == 1
    capsys.readouterr()
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    page = (out / "index.html").read_text()
    assert digest in page and "station 2" in page
    assert page.index('class="verdict') < page.index("<table") and "FAIL" in page[: page.index("<table")]
    document = json.loads((out / "iso_check.json").read_text())
    assert document["verdict"]["level"] == "FAIL" and document["verdict"]["judged"].startswith(
        "alpha left the tolerance"
    )
    assert document["verdict"]["numbers"]["alpha_tolerance_deg"] == 3.0 and list(document)[:2] == [
        "verdict",
        "provenance",
    ]
    assert [entry["sha256"] for entry in document["provenance"]["inputs"] if entry["path"].endswith("alpha.csv")] == [
        digest
    ]
