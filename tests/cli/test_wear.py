"""hipsim wear: the sources (stations output per platform, simulate output, trajectory file), the outputs, --compare, bad input."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest
from support import given

from hipsim.cli.main import main
from hipsim.motion.trajectories import Trajectory, iso14242, iso14242_angles, iso14242_load
from hipsim.records import Level
from hipsim.wear import cup_grid, wear_maps
from hipsim.wear.laws import WearFactor, predict_wear
from hipsim.wear.summary import wear_summary

GRID = "12x24"
ERR = ("alpha", "beta", "gamma")


def _stations(path, follower_gamma_deg=0.0, load=True, cycles=2, rate=500, closing=True):
    """A 'hipsim stations'-like CSV: platform 2 follows the ISO cycle, platform 1 adds an error about Z."""
    t = np.arange(int(cycles * rate) + closing) / rate  # with the closing sample: whole cycles, first to last sample
    q2 = np.degrees(iso14242_angles(t)[0])
    q1 = q2.copy()
    q1[:, 2] += follower_gamma_deg * np.sin(2 * math.pi * t + 0.7)
    columns = {"t_s": t}
    for j in (1, 2, 3):
        columns[f"L_1{j}_mm"] = 600.0 + 0 * t
    for p, q in ((1, q1), (2, q2)):
        for k, name in enumerate(ERR):
            columns[f"{name}_{p}_deg"] = q[:, k]
    for p, q in ((1, q1), (2, q2)):
        for k, name in enumerate(ERR):
            columns[f"err_{name}_{p}_deg"] = q[:, k] - q2[:, k]
    if load:
        columns["Fe_N"] = iso14242_load(t)
    names = list(columns)
    rows = np.column_stack([columns[n] for n in names])
    np.savetxt(path, rows, delimiter=",", header=",".join(names), comments="", fmt="%.9f")
    return path


def _follower(gamma_deg, rate=500):
    """Platform 1's motion as the stations file holds it, with exact rates: ISO plus γ error gamma_deg·sin(2πt + 0.7)."""
    base = iso14242(rate=rate)
    w = 2 * math.pi
    q, qd = base.q.copy(), base.qd.copy()
    q[:, 2] += math.radians(gamma_deg) * np.sin(w * base.t + 0.7)
    qd[:, 2] += math.radians(gamma_deg) * w * np.cos(w * base.t + 0.7)
    return Trajectory(base.t, q, qd, base.qdd, base.Fe, "follower", periodic=True)


def _run(capsys, *words):
    status = main(["wear", "--cup-grid", GRID, *map(str, words)])
    captured = capsys.readouterr()
    return status, captured.out, captured.err


@pytest.fixture(scope="module")
def stations(tmp_path_factory):
    folder = tmp_path_factory.mktemp("stations")
    return _stations(folder / "stations.csv", follower_gamma_deg=1.5), _stations(folder / "same.csv")


def test_a_stations_platform_is_read_and_matches_the_motion_it_holds(stations, tmp_path, capsys):
    """Platform 2 holds the ISO cycle: its numbers are the built-in cycle's (to the file's spline)."""
    out = tmp_path / "p2.csv"
    status, text, _ = _run(
        capsys,
        "--trajectory",
        f"{stations[0]}:2",
        "--wear-factor",
        "8e-8:local",
        "--out",
        out,
        "--summary-format",
        "json",
    )
    assert status == 0
    summary = json.loads(text)
    expected = wear_maps(iso14242(rate=500), 1.0, points=cup_grid(12, 24, 14.0))
    assert summary["cycles"] == pytest.approx(2.0, rel=1e-9)
    assert summary["force_track_mm"] == pytest.approx(expected.force_track_mm, rel=1e-4)
    table = np.genfromtxt(out, delimiter=",", names=True)
    assert set(("x", "y", "z", "sliding_mm", "work_N_per_mm", "cross_shear", "wear_mm3_per_Mc")) <= set(
        given(table.dtype.names)
    )
    np.testing.assert_allclose(table["work_N_per_mm"], expected.work_N_per_mm, rtol=1e-4, atol=1e-6)
    np.testing.assert_allclose(table["cross_shear"], expected.cross_shear, atol=1e-4)
    # V = 1e-3·k·ΣW·dA per cycle, by hand from the table's own columns
    by_hand = 1e-3 * 8e-8 * np.sum(table["work_N_per_mm"] * table["area_mm2"]) * 1e6
    assert summary["wear_mm3_per_Mc"] == pytest.approx(by_hand, rel=1e-9)
    # --platform 2 is the same source
    status, again, _ = _run(capsys, "--trajectory", stations[0], "--platform", "2", "--summary-format", "json")
    assert json.loads(again)["force_track_mm"] == summary["force_track_mm"]


def test_the_follower_platform_differs_from_the_controlled_one(stations, tmp_path, capsys):
    """An error about Z on platform 1: its s, CS and V differ from platform 2's by what the motions themselves give
    (computed here from the angles with exact rates, not from the file); verdict DIFFERENT."""
    report = tmp_path / "page"
    status, text, _ = _run(
        capsys,
        "--compare",
        f"{stations[0]}:2",
        f"{stations[0]}:1",
        "--wear-factor",
        "8e-8:local",
        "--report",
        report,
        "--out",
        tmp_path / "diff.parquet",
        "--summary-format",
        "json",
        "--alike",
        "1",
    )
    document = json.loads(text)
    rows = {row["key"]: row for row in document["differences"]}
    grid = cup_grid(12, 24, 14.0)
    controlled = wear_maps(iso14242(rate=500), 1.0, points=grid)
    follower = wear_maps(_follower(1.5), 1.0, points=grid)
    law = WearFactor(8e-8)
    expected = {
        "sliding_mm_mean": (wear_summary(controlled), wear_summary(follower)),
        "cross_shear_mean": (wear_summary(controlled), wear_summary(follower)),
        "wear_mm3_per_Mc": (
            wear_summary(controlled, predict_wear(controlled, law)),
            wear_summary(follower, predict_wear(follower, law)),
        ),
    }
    for key, (a, b) in expected.items():
        x, y = getattr(a, key), getattr(b, key)
        assert abs(y - x) > 1e-3 * abs(x)  # a difference that shows
        assert rows[key]["difference"] == pytest.approx(y - x, rel=2e-3), key
    assert document["verdict"]["level"] == "DIFFERENT" and document["verdict"]["numbers"]["cross_shear_mean"] != 0
    assert status == 1  # DIFFERENT exits 1 (the exit rule)
    page = (report / "index.html").read_text()
    assert page.index('id="verdict"') < page.index('id="provenance"') and "SHA-256" in page
    assert (report / "difference_maps.png").exists() and (report / "slide_tracks_ab.svg").exists()
    import pyarrow.parquet as pq

    columns = pq.read_table(tmp_path / "diff.parquet").column_names
    assert "cross_shear_b_minus_a" in columns


def test_identical_platforms_compare_alike(stations, tmp_path, capsys):
    """The verdict on two runs of one motion, and the page's block of it (without drawing the page)."""
    from hipsim.present.wear_page import compare_block
    from hipsim.wear.summary import WearSummary, compare_summaries, compare_verdict

    runs = []
    for platform in ("1", "2"):
        status, text, _ = _run(
            capsys, "--trajectory", f"{stations[1]}:{platform}", "--summary-format", "json", "--out", tmp_path / "s.csv"
        )
        assert status == 0
        runs.append(json.loads(text))
    assert [run["verdict"]["level"] for run in runs] == ["NOT MADE", "NOT MADE"]  # one run is not rated
    summaries = [
        WearSummary(**{k: v for k, v in run.items() if k not in ("verdict", "notes", "table", "index")}) for run in runs
    ]
    rows = compare_summaries(*summaries)
    assert all(row.difference in (0.0, None) for row in rows)
    assert compare_verdict(rows, 0.0, ("1", "2")).level == Level.ALIKE
    shifted = replace(summaries[1], cross_shear_mean=summaries[1].cross_shear_mean * 1.02)
    verdict = compare_verdict(compare_summaries(summaries[0], shifted), 0.01, ("1", "2"))
    block = compare_block(verdict)
    assert block.word == "DIFFERENT" and block.state == "fail" and block.symbol == "✘"
    assert "Beyond ±1 %: mean CS (loaded area)." in block.lines[0] and block.lines == (verdict.judged,)


def test_a_simulate_output_reads_actual_or_desired_and_needs_a_load(tmp_path, capsys):
    t = np.arange(500) / 500
    q = np.degrees(iso14242_angles(t)[0])
    header = "t_s," + ",".join(f"{n}_des_deg,{n}_deg,err_{n}_deg" for n in ERR) + ",tau_1_Nmm"
    rows = [
        [t[k], *[v for j in range(3) for v in (q[k, j], q[k, j] * 1.05, q[k, j] * 0.05)], 0.0] for k in range(t.size)
    ]
    path = tmp_path / "sim.csv"
    np.savetxt(path, rows, delimiter=",", header=header, comments="", fmt="%.9f")
    status, _, err = _run(capsys, "--trajectory", path, "--out", tmp_path / "a.csv")
    assert status == 2 and "no load" in err and "--iso-load" in err and "Traceback" not in err
    forces = []
    for source in (f"{path}:desired", str(path)):
        status, text, _ = _run(
            capsys,
            "--trajectory",
            source,
            "--iso-load",
            "--cycle-time",
            "1",
            "--summary-format",
            "json",
            "--out",
            tmp_path / "b.csv",
        )
        assert status == 0
        forces.append(json.loads(text)["force_track_mm"])
    # the actual motion is the desired one scaled by 1.05: a force track 5 % longer
    assert forces[1] / forces[0] - 1 == pytest.approx(0.05, rel=2e-2)


def test_a_stations_output_without_a_platform_is_refused(stations, tmp_path, capsys):
    status, _, err = _run(capsys, "--trajectory", stations[0], "--out", tmp_path / "x.csv")
    assert status == 2 and ":1 or" in err and not (tmp_path / "x.csv").exists()


@pytest.mark.parametrize(
    ("words", "message"),
    [
        (["--head-diameter", "0"], "--head-diameter 0 mm: femoral head diameter must be at least 1 and at most 100 mm"),
        (
            ["--head-diameter", "150"],
            "--head-diameter 150 mm: femoral head diameter must be at least 1 and at most 100 mm",
        ),
        (["--cycles", "0.5"], "shorter than one cycle"),
        (["--sequence", "XXY"], "--sequence: expected a permutation"),
        (["--wear-factor=-1:local"], "--wear-factor -1 mm³/(N·m): Archard's wear factor k must be at least 0"),
        (["--wear-factor", "8e-8"], "--wear-factor: expected K:KIND in mm³/(N·m), KIND local"),
        (["--wear-factor", "8e-8:global"], "a value without its kind is ambiguous"),
        (["--cup-grid", "0x10"], "--cup-grid '0x10': 0 bands x sectors: the cup grid's polar bands"),
    ],
)
def test_bad_options_give_one_line(tmp_path, capsys, words, message):
    out = tmp_path / "t.csv"
    status, _, err = _run(capsys, *words, "--out", out)
    assert status == 2 and message in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            "cross_shear,k_mm3_per_Nm\n0,1e-7\n0.2,2e-7\n0.1,3e-7\n",
            "line 4, column 'cross_shear': CS 0.1 does not increase",
        ),
        ("cross_shear,k_mm3_per_Nm\n0,1e-7\n0.2,-2e-7\n", "line 3, column 'k_mm3_per_Nm': a negative wear factor"),
        ("cs,k\n0,1\n", "no column cross_shear, k_mm3_per_Nm"),
    ],
)
def test_bad_wear_law_tables_are_refused_by_line(tmp_path, capsys, text, message):
    law = tmp_path / "law.csv"
    law.write_text(text)
    status, _, err = _run(capsys, "--wear-law", law, "--out", tmp_path / "t.csv")
    assert status == 2 and message in err


def test_points_off_the_sphere_are_refused_by_line(tmp_path, capsys):
    points = tmp_path / "points.csv"
    points.write_text("x,y,z\n0,0,1\n# a comment\n0.5,0.5,0.5\n")
    status, _, err = _run(capsys, "--points", points, "--out", tmp_path / "t.csv")
    assert status == 2 and "line 4" in err and "unit sphere" in err


def test_a_wear_law_table_scales_with_cross_shear(tmp_path, capsys):
    """k(CS) constant in the table is the constant factor; points given one by one get depths, not a volume."""
    law = tmp_path / "law.csv"
    law.write_text("cross_shear,k_mm3_per_Nm\n0,1e-7\n0.5,1e-7\n")
    _, table_law, _ = _run(capsys, "--wear-law", law, "--summary-format", "json", "--out", tmp_path / "a.csv")
    _, constant, _ = _run(
        capsys, "--wear-factor", "1e-7:local", "--summary-format", "json", "--out", tmp_path / "b.csv"
    )
    assert json.loads(table_law)["wear_mm3_per_Mc"] == pytest.approx(json.loads(constant)["wear_mm3_per_Mc"], rel=1e-12)
    points = tmp_path / "points.csv"
    points.write_text("x,y,z\n0,0,1\n0.6,0,0.8\n")
    status, text, _ = _run(capsys, "--points", points, "--wear-factor", "1e-7:local", "--out", tmp_path / "c.csv")
    assert status == 0 and "no areas" in text
    assert "wear_depth_um_per_Mc" in (tmp_path / "c.csv").read_text().splitlines()[0]


def test_a_rig_log_is_read_as_the_rig_reads_it(tmp_path, capsys):
    """A log of three ISO cycles (angles, load, torques): read by the rig's reader, the filter's edges left out; its
    per-cycle force track is the built-in cycle's."""
    t = np.arange(1500) / 500
    q = np.degrees(iso14242_angles(t)[0])
    columns = {"t_s": t, "Fe_N": iso14242_load(t), "tau_1_Nmm": 0 * t, "tau_2_Nmm": 0 * t, "tau_3_Nmm": 0 * t}
    columns |= {f"{name}_deg": q[:, k] for k, name in enumerate(ERR)}
    path = tmp_path / "log.csv"
    np.savetxt(path, np.column_stack(list(columns.values())), delimiter=",", header=",".join(columns), comments="")
    status, text, _ = _run(capsys, "--trajectory", path, "--summary-format", "json", "--out", tmp_path / "t.csv")
    assert status == 0
    summary = json.loads(text)
    assert any("a rig log" in note for note in summary["notes"])
    assert summary["cycles"] == pytest.approx(3.0, abs=1e-12)  # three whole cycles, the last step closing them
    expected = wear_maps(iso14242(rate=500), 1.0, points=cup_grid(12, 24, 14.0))
    assert summary["force_track_mm"] == pytest.approx(expected.force_track_mm, rel=1e-2)


def test_pdf_needs_a_page_and_a_browser(tmp_path, capsys, monkeypatch):
    status, _, err = _run(capsys, "--pdf", "--out", tmp_path / "t.csv")
    assert status == 2 and "--report" in err
    monkeypatch.setattr("hipsim.present.pages.find_browser", lambda: None)
    status, _, err = _run(capsys, "--pdf", "--report", tmp_path / "page", "--out", tmp_path / "t.csv")
    assert status == 2 and "Chromium" in err and not (tmp_path / "page").exists()


def test_self_check_passes_and_finds_a_planted_error(capsys, monkeypatch):
    status, text, _ = _run(
        capsys, "--self-check", "--head-diameter", "32", "--cup-mount", "5,-3,20", "--summary-format", "json"
    )
    document = json.loads(text)
    assert (
        status == 0
        and document["passed"]
        and [c["name"] for c in document["checks"]]
        == [
            "pure flexion",
            "time reversal",
            "flexion arc",
        ]
    )
    import dataclasses

    import hipsim.wear.checks as checks

    real = checks.wear_maps

    def biased(*args, **kwargs):  # a cross-shear off by 1e-6 where there is work
        maps = real(*args, **kwargs)
        return dataclasses.replace(maps, cross_shear=maps.cross_shear + 1e-6)

    monkeypatch.setattr(checks, "wear_maps", biased)
    status, text, _ = _run(capsys, "--self-check")
    assert status == 1 and "pure flexion" in text and "FAIL" in text


def test_one_cycle_without_its_closing_sample_is_one_cycle(tmp_path, capsys):
    """As 'hipsim stations' writes the built-in cycle: 500 samples over [0, 0.998] s, one heel strike: the last step
    closes the cycle (it was 0.998 cycles, the values 0.2 % high), so the numbers are the built-in cycle's."""
    path = _stations(tmp_path / "one.csv", cycles=1, closing=False)
    status, text, _ = _run(capsys, "--trajectory", f"{path}:2", "--summary-format", "json", "--out", tmp_path / "t.csv")
    summary = json.loads(text)
    assert status == 0 and summary["cycles"] == pytest.approx(1.0, abs=1e-12)
    expected = wear_maps(iso14242(rate=500), 1.0, points=cup_grid(12, 24, 14.0))
    assert summary["force_track_load_Nm"] == pytest.approx(expected.force_track_load_Nm, rel=1e-6)
    assert any("taken as one cycle of 1 s" in note for note in summary["notes"])
