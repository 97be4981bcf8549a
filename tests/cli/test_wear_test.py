"""hipsim wear --weighings / --test: a simulated test through the command (rates, fitted k, report, provenance),
motions per station from a stations output, and bad input refused in one line with nothing written."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import numpy as np
import pytest
from wear_test_synthetic import I0_LOCAL, TRUTH, platform_i0, write_simulated_test

from hipsim.cli.documents import schema
from hipsim.cli.main import main

GRID = "12x24"


def _run(capsys, *words):
    status = main(["wear", "--cup-grid", GRID, *map(str, words)])
    captured = capsys.readouterr()
    return status, captured.out, captured.err


@pytest.fixture(scope="module")
def test_folder(tmp_path_factory):
    """Stops every 0.5 Mc to 2 Mc, three snapshots: station 2's load steps up at 1 Mc."""
    truth = TRUTH.__class__(step_cycle=1_000_000)
    folder = write_simulated_test(
        tmp_path_factory.mktemp("wear_test") / "test",
        truth,
        stops=np.arange(0, 2_000_001, 500_000),
        snapshots=np.array([0, 750_000, 1_500_000]),
    )
    return folder, truth


def test_a_simulated_test_through_the_report(test_folder, tmp_path, capsys):
    folder, truth = test_folder
    report = tmp_path / "report"
    status, text, err = _run(
        capsys,
        "--test",
        folder,
        "--report",
        report,
        "--out",
        tmp_path / "stops.csv",
        "--summary-format",
        "json",
        "--wear-factor",
        "4e-7:local",
        "--from",
        "500000",
    )
    assert status == 1, err  # DIFFERENT exits 1 (the exit rule, docs/guide/outputs.md)
    result = json.loads(text)
    jsonschema.Draft202012Validator(schema("wear-test")).validate(result)
    assert result["index"].endswith("index.html") and result["table"].endswith("stops.csv")
    assert ("wear_law" in result) == (result["fitted_wear_law"] is not None)  # the law file only with a law
    assert result["verdict"]["level"] == "DIFFERENT" and result["wear_factor"] == {
        "k_mm3_per_Nm": 4e-7,
        "kind": "local",
    }
    assert result["density_mg_per_mm3"] == 0.935 and "default" in result["density"]
    one, two = result["stations"]["1"], result["stations"]["2"]
    # station 1: load scale 1 throughout, k = 4e-7: 4e-7·I0·1e6 mm³/Mc from 0.5 Mc on (bedding-in before)
    assert one["wear_rate_mm3_per_Mc"] == pytest.approx(truth.rate(0, 500_000, 2_000_000), rel=0.01)
    assert one["fitted"]["k_local_mm3_per_Nm"] == pytest.approx(4e-7, rel=0.01)
    assert one["predicted_mm3_per_Mc"] == pytest.approx(4e-7 * I0_LOCAL * 1e6, rel=0.01)
    assert two["fitted"]["k_local_mm3_per_Nm"] == pytest.approx(truth.k[1], rel=0.03)
    low, high = two["wear_rate_ci95_mm3_per_Mc"]
    assert low < two["wear_rate_mm3_per_Mc"] < high
    assert two["wear_rate_mg_per_Mc"] == pytest.approx(0.935 * two["wear_rate_mm3_per_Mc"], rel=1e-12)
    # the load steps from 1.1 to 1.3 at 1 Mc: the snapshots at 0.75 and 1.5 Mc carry it (boundary 1.125 Mc)
    rows = two["intervals"]
    assert rows[-1]["predicted_mm3"] > rows[0]["predicted_mm3"] * 1.1
    document = json.loads((report / "wear_test.json").read_text())
    roles = {item["role"]: item for item in document["provenance"]["inputs"]}
    assert len(roles["weighings"]["sha256"]) == 64 and any(role.startswith("snapshots") for role in roles)
    assert document["provenance"]["parameters"] is not None
    page = (report / "index.html").read_text()
    assert page.index("DIFFERENT") < page.index("Per station") and "local" in page
    stops = (tmp_path / "stops.csv").read_text().splitlines()
    assert stops[0] == "station,cycle,loss_mg,volume_mm3,predicted_mm3" and len(stops) == 1 + 2 * 5


def test_station_motions_from_a_stations_output(tmp_path, capsys):
    """Each station its platform of a stations output: its k from its own motion, the motion error in the summary."""
    assert main(["stations", "--out", str(tmp_path / "st"), "--summary-format", "json"]) == 0
    capsys.readouterr()
    weighings = tmp_path / "w.csv"
    weighings.write_text(
        "cycle,station,mass_mg,soak_mg\n"
        + "".join(
            f"{c},{s},{30000 - r * c / 1e6:.4f},{29000 + 0.1 * c / 1e6:.4f}\n"
            for c in range(0, 2_000_001, 500_000)
            for s, r in (("1", 10.0), ("2", 12.0))
        )
    )
    stations = tmp_path / "st" / "stations.csv"
    status, text, err = _run(
        capsys,
        "--weighings",
        weighings,
        "--station",
        f"1={stations}:1",
        "--station",
        f"2={stations}:2",
        "--density",
        "0.94",
        "--summary-format",
        "json",
        "--out",
        tmp_path / "t.csv",
    )
    result = json.loads(text)
    assert status == (1 if result["verdict"]["level"] == "DIFFERENT" else 0), err  # the exit rule
    jsonschema.Draft202012Validator(schema("wear-test")).validate(result)
    assert "index" not in result and result["stations"]["1"]["friction"] is None  # no --report, no monitor table
    one = result["stations"]["1"]
    # the soak control gains 0.1 mg/Mc and the cups are written without uptake: the corrected loss is (r + 0.1)·c
    assert one["wear_rate_mg_per_Mc"] == pytest.approx(10.1, rel=1e-9)
    assert one["wear_rate_mm3_per_Mc"] == pytest.approx(10.1 / 0.94, rel=1e-9)
    assert one["motion_error"]["rms_deg"] == pytest.approx([0.0, 0.0, 0.0], abs=1e-9)
    assert two_motions_differ(result) is False  # both platforms follow the drawing's ISO cycle
    integrals = one["fitted"]["motion"]
    assert one["fitted"]["k_local_mm3_per_Nm"] == pytest.approx(
        10.1 / 0.94 / (integrals["load_slide_integral_Nm"] * 1e6)
    )
    assert one["fitted"]["k_force_track_mm3_per_Nm"] == pytest.approx(
        10.1 / 0.94 / (integrals["force_track_load_Nm"] * 1e6)
    )


def test_each_platform_its_own_motion_on_a_per_chain_machine(tmp_path, capsys):
    """A machine 0.3 mm off the drawing, its logs of carriages: each station's integral is its own platform's (the
    truth by tests/stations_synthetic.py's forward kinematics), platform 2 (controlled) on ISO, platform 1 off it."""
    from stations_synthetic import deviated

    geometry = deviated(3, 0.3)
    folder = write_simulated_test(
        tmp_path / "test", stops=np.arange(0, 1_000_001, 500_000), snapshots=np.array([0, 500_000]), geometry=geometry
    )
    status, text, err = _run(capsys, "--test", folder, "--summary-format", "json", "--out", tmp_path / "t.csv")
    assert status == 0, err
    result = json.loads(text)
    one, two = result["stations"]["1"], result["stations"]["2"]
    assert "platform 1's own motion" in one["motion"] and "platform 2's own motion" in two["motion"]
    i1, i2 = platform_i0(geometry, rate=250.0, grid=(12, 24))
    measured = one["fitted"]["motion"]["load_slide_integral_Nm"] / two["fitted"]["motion"]["load_slide_integral_Nm"]
    assert i1 != pytest.approx(i2, rel=1e-3)  # the platforms differ
    assert measured == pytest.approx(i1 * 1.0 / (i2 * 1.1), rel=5e-4)  # loads 1.0 and 1.1 times ISO's
    assert max(two["motion_error"]["rms_deg"]) < 1e-3 < 0.03 < max(one["motion_error"]["rms_deg"])


def two_motions_differ(result) -> bool:
    a, b = (result["stations"][name]["fitted"]["motion"] for name in ("1", "2"))
    return abs(a["load_slide_integral_Nm"] - b["load_slide_integral_Nm"]) > 1e-9 * a["load_slide_integral_Nm"]


def test_a_test_folder_with_a_stations_output(tmp_path, capsys):
    """--test DIR: weighings.csv and stations.csv (stations 1 and 2 its platforms); the report in DIR/report."""
    folder = tmp_path / "test"
    assert main(["stations", "--out", str(folder), "--summary-format", "json"]) == 0
    capsys.readouterr()
    (folder / "index.html").unlink()
    other = GOOD.replace(",1,", ",2,").replace(",30000\n", ",30100\n").replace(",29990\n", ",30090\n")
    other = other.replace(",29981\n", ",30081\n")  # another cup: the same masses twice would be one cup given twice
    (folder / "weighings.csv").write_text(other + GOOD.replace("soak", "soak_1").split("\n", 1)[1])
    status, text, err = _run(capsys, "--test", folder, "--summary-format", "json", "--out", tmp_path / "t.csv")
    assert status == 0, err
    result = json.loads(text)
    assert any("stations named 1 and 2 take its platforms" in note for note in result["notes"])
    assert result["stations"]["2"]["soak_control"] == "soak" and result["stations"]["1"]["soak_control"] == "soak_1"
    assert result["stations"]["1"]["motion_error"]["source"].endswith("platform 1")
    assert (folder / "report" / "index.html").is_file() and result["index"] == str(folder / "report" / "index.html")


GOOD = "cycle,station,mass_mg\n0,1,30000\n0,soak,29000\n500000,1,29990\n500000,soak,29000.5\n1000000,1,29981\n1000000,soak,29000.7\n"


@pytest.mark.parametrize(
    ("text", "words", "message"),
    [
        (GOOD.replace("500000,1,29990", "1500000,1,29990"), (), "weighings out of order"),
        (GOOD.replace("soak", "spare"), (), "station 1 has no soak control"),
        (GOOD, ("--density=-0.9",), "--density -0.9 mg/mm³: the cups' density must be above 0 and at most 25 mg/mm³"),
        (GOOD.replace("29990", "29.990"), (), "a change larger than the cup weighs"),
        (GOOD, ("--from", "0.5"), "--from '0.5': expected a whole number in cycles"),
        (GOOD, ("--wear-factor", "4e-7"), "a value without its kind is ambiguous"),
        (GOOD, ("--workers", "0"), "--workers 0 processes: worker processes (1: in this process) must be at least 1"),
        (GOOD, ("--station", "3=iso"), "--station: no station '3' in the weighings"),
        (GOOD, ("--area-law", "1e-5"), "with --weighings a law is given as --wear-factor K:KIND"),
        (GOOD, ("--out", "stops.parquet"), "the table of stops is CSV"),
    ],
)
def test_bad_input_one_line_nothing_written(tmp_path, capsys, monkeypatch, text, words, message):
    monkeypatch.chdir(tmp_path)
    weighings = tmp_path / "w.csv"
    weighings.write_text(text)
    out, report = tmp_path / "t.csv", tmp_path / "report"
    status, _, err = _run(capsys, "--weighings", weighings, "--out", out, "--report", report, *words)
    assert status == 2 and message in err and len(err.strip().splitlines()) == 1, err
    assert sorted(path.name for path in tmp_path.iterdir()) == ["w.csv"]


def test_stations_that_differ_in_cross_shear_give_a_wear_law_table(tmp_path, capsys):
    """Station 1 on ISO (CS 0.16), station 2 on flexion alone (CS 0): their local k at their CS, a table --wear-law
    reads, each row the station's rate over its ΣW·dA."""
    from hipsim.motion.trajectories import iso14242

    cycle = iso14242(rate=200, cycles=2)
    flexion = tmp_path / "flexion.csv"
    rows = np.column_stack([cycle.t, np.degrees(cycle.q[:, 0]), 0 * cycle.t, 0 * cycle.t, cycle.Fe])
    np.savetxt(flexion, rows, delimiter=",", header="t_s,alpha_deg,beta_deg,gamma_deg,Fe_N", comments="")
    weighings = tmp_path / "w.csv"
    weighings.write_text(
        GOOD + GOOD.replace(",1,", ",2,").replace("soak", "soak_2").replace("29990", "29995").split("\n", 1)[1]
    )
    report = tmp_path / "report"
    status, text, err = _run(
        capsys,
        "--weighings",
        weighings,
        "--station",
        "1=iso",
        "--station",
        f"2={flexion}",
        "--report",
        report,
        "--summary-format",
        "json",
        "--out",
        tmp_path / "t.csv",
    )
    assert status == 0, err
    result = json.loads(text)
    # its error against ISO: β and γ missing, RMS √(1.5² + 5.5²/2) and √(4² + 6²/2) deg (spec §7.2's means and
    # amplitudes); α none
    error = result["stations"]["2"]["motion_error"]
    assert error["rms_deg"] == pytest.approx([0.0, (1.5**2 + 5.5**2 / 2) ** 0.5, (4**2 + 6**2 / 2) ** 0.5], abs=1e-6)
    assert result["stations"]["1"]["motion_error"] is None  # the built-in cycle: nothing to compare
    law = result["fitted_wear_law"]
    one, two = (result["stations"][n]["fitted"] for n in ("1", "2"))
    assert law["cross_shear"] == pytest.approx(
        [two["motion"]["cross_shear_work_weighted"], one["motion"]["cross_shear_work_weighted"]]
    )
    assert law["cross_shear"][0] < 0.01 < law["cross_shear"][1]
    assert law["k_mm3_per_Nm"] == pytest.approx([two["k_local_mm3_per_Nm"], one["k_local_mm3_per_Nm"]])
    from hipsim.wear.laws import read_wear_law

    table = read_wear_law(report / "fitted_wear_law.csv")  # as --wear-law reads it
    assert table.k.tolist() == pytest.approx(law["k_mm3_per_Nm"], rel=1e-15)


def test_the_report_prints_to_pdf(tmp_path, capsys, monkeypatch):
    """--pdf: the page printed by the browser (a stand-in here) to wear_test.pdf; without a browser, refused first."""
    weighings = tmp_path / "w.csv"
    weighings.write_text(GOOD)
    monkeypatch.setattr("hipsim.present.pages.find_browser", lambda: None)
    status, _, err = _run(
        capsys, "--weighings", weighings, "--pdf", "--report", tmp_path / "page", "--out", tmp_path / "t.csv"
    )
    assert status == 2 and "Chromium" in err and not (tmp_path / "page").exists()
    printed = []

    def fake_print(page, out, browser=None, timeout_s=120.0):
        printed.append(page)
        Path(out).write_bytes(b"%PDF-1.4 stand-in")
        return Path(out)

    monkeypatch.setattr("hipsim.present.pages.find_browser", lambda: "chromium")
    monkeypatch.setattr("hipsim.present.wear_test_page.print_pdf", fake_print)
    status, text, err = _run(
        capsys,
        "--weighings",
        weighings,
        "--pdf",
        "--report",
        tmp_path / "page",
        "--out",
        tmp_path / "t.csv",
        "--summary-format",
        "json",
    )
    assert status == 0, err
    assert json.loads(text)["pdf"] == str(tmp_path / "page" / "wear_test.pdf")
    assert json.loads(text)["verdict"]["level"] == "NOT MADE"  # ONE STATION on the page: exits 0
    assert printed == [tmp_path / "page" / "index.html"]
