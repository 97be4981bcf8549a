"""Pages a lab can sign (issue 29): provenance with the inputs' SHA-256, the verdict first, units on every value, the PDF."""

import hashlib
import json
import os
import re
import shutil
from html.parser import HTMLParser

import jsonschema
import numpy as np
import pytest
from conftest import figures_undrawn

import hipsim
from hipsim.cli.documents import schema
from hipsim.cli.main import main
from hipsim.machine.parameters import default_parameters_path
from hipsim.present import pages
from hipsim.present.numbers import quantity, significant, with_uncertainty
from hipsim.present.provenance import parameter_origin
from hipsim.records import Level, Verdict


def sha256(path) -> str:
    """The file's SHA-256, read whole: another route than the library's piecewise reading."""
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


def chromium():
    for name in ("chromium", "chromium-browser"):
        path = shutil.which(name)
        if path:
            return path
    if os.environ.get("HIPSIM_REQUIRE_BROWSER") == "1":
        pytest.fail("HIPSIM_REQUIRE_BROWSER=1 but chromium is not on PATH")
    pytest.skip("chromium is not on PATH (set HIPSIM_REQUIRE_BROWSER=1 to make this a failure)")


class Page(HTMLParser):
    """The page's headings, its tables (header and cells), and where the verdict and the first table start."""

    def __init__(self, text: str):
        super().__init__()
        self.headings: list[str] = []
        self.tables: list[dict[str, list]] = []  # {"header": cells, "rows": lists of cells}
        self.order: list[str] = []
        self._heading: str | None = None
        self._cell: str | None = None
        self._row: list[tuple[str, str]] | None = None  # (td or th, text) of each cell
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if attrs.get("id") == "verdict":
            self.order.append("verdict")
        if tag == "table":
            self.order.append("table")
            self.tables.append({"header": [], "rows": []})
        elif tag in ("h1", "h2", "h3"):
            self._heading = ""
        elif tag == "tr" and self.tables:
            self._row = []
        elif tag in ("td", "th") and self._row is not None:
            self._cell = ""

    def handle_endtag(self, tag):
        if tag in ("h1", "h2", "h3") and self._heading is not None:
            self.headings.append(" ".join(self._heading.split()))
            self._heading = None
        elif tag in ("td", "th") and self._cell is not None and self._row is not None:
            self._row.append((tag, " ".join(self._cell.split())))
            self._cell = None
        elif tag == "tr" and self._row is not None:
            table = self.tables[-1]
            if all(kind == "th" for kind, _ in self._row):
                table["header"] = [text for _, text in self._row]
            else:
                table["rows"].append([text for _, text in self._row])
            self._row = None

    def handle_data(self, data):
        if self._heading is not None:
            self._heading += data
        if self._cell is not None:
            self._cell += data


NUMBER = re.compile(r"^[−+-]?[\d,]+(\.\d+)?( × 10[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+)?$")


def assert_every_value_has_a_unit(page: Page):
    """A cell that is a bare number must sit in a column whose header names a unit ([...]) or in a table with a unit column."""
    for table in page.tables:
        header = table["header"]
        if "unit" in header:
            continue
        for row in table["rows"]:
            for column, cell in enumerate(row[1:], start=1):
                if NUMBER.match(cell):
                    assert re.search(r"\[.+\]", header[column]), (header, cell)


# ---------------------------------------------------------------------------
# Numbers


def test_numbers_have_three_to_four_figures_or_their_uncertainty():
    assert significant(431.123) == "431.1" and significant(1638.9) == "1,639" and significant(0.35874) == "0.3587"
    assert significant(561.98) == "562.0" and significant(0.0199999, 3, zeros=False) == "0.02"
    assert significant(1.2345e8, 3) == "1.23 × 10⁸" and significant(-12.345) == "−12.35" and significant(None) == "—"
    assert with_uncertainty(0.0509655485571888, 0.00012) == "0.05097 ± 0.00012"
    assert with_uncertainty(12345.6, 230) == "12,350 ± 230" and with_uncertainty(1.5, None) == "1.500"
    assert quantity(5.23, ":1") == "5.230:1" and quantity(431.1, "N·mm") == "431.1 N·mm"


# ---------------------------------------------------------------------------
# The design report


@pytest.fixture(scope="module")
def design(tmp_path_factory):
    """``hipsim report`` on a trajectory file with a drive file that fails, with the lab's fields."""
    folder = tmp_path_factory.mktemp("design")
    trajectory = folder / "cycle.csv"
    t = np.arange(0, 1, 0.01)
    rows = [
        f"{x:.2f},{20 * np.sin(2 * np.pi * x):.6f},{5 * np.sin(2 * np.pi * x):.6f},{8 * np.cos(2 * np.pi * x):.6f},"
        f"{1500 + 1000 * np.sin(2 * np.pi * x):.3f}"
        for x in t
    ]
    trajectory.write_text("t_s,alpha_deg,beta_deg,gamma_deg,Fe_N\n" + "\n".join(rows) + "\n")
    drive = folder / "motor.toml"
    drive.write_text(
        '[motor]\nname = "small motor"\nrated_torque_Nmm = 200\npeak_torque_Nmm = 400\nmax_speed_rpm = 3000\n'
        'rotor_inertia_kgcm2 = 1.2\n[lead_screw]\nname = "screw"\nlead_mm = 10\nroot_diameter_mm = 12\nfree_length_mm = 400\n'
    )
    out = folder / "site"
    with figures_undrawn():  # the page's text is tested here, the figures drawn in tests/present/test_report.py
        status = main(
            [
                "report",
                "--trajectory",
                str(trajectory),
                "--motor",
                str(drive),
                "--engine",
                "analytic",
                "--out",
                str(out),
                "--set",
                "lever.length_mm=330",
                "--title",
                "Drive review",
                "--author",
                "A. Tester",
                "--rig",
                "HS-2 #0042",
            ]
        )
    return {"status": status, "out": out, "trajectory": trajectory, "drive": drive}


def test_report_page_and_json_carry_the_provenance(design):
    page = (design["out"] / "index.html").read_text(encoding="utf-8")
    document = json.loads((design["out"] / "report.json").read_text())
    block = document["provenance"]
    hashes = {f["role"]: (f["path"], f["sha256"]) for f in block["inputs"]}
    assert hashes["trajectory"] == (str(design["trajectory"]), sha256(design["trajectory"]))
    assert hashes["drive"] == (str(design["drive"]), sha256(design["drive"]))
    assert hashes["parameters"][1] == sha256(default_parameters_path())
    for _, digest in hashes.values():
        assert digest in page
    assert block["hipsim"] == hipsim.__version__ and f"hipsim {hipsim.__version__}" in page
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ", block["created_utc"])
    assert block["command"].startswith("hipsim report --trajectory") and "--rig 'HS-2 #0042'" in block["command"]
    assert (block["title"], block["author"], block["rig"]) == ("Drive review", "A. Tester", "HS-2 #0042")
    assert block["parameters"]["kind"] == "published" and block["parameters"]["overrides"] == ["lever.length_mm=330"]
    assert "<h1>Drive review</h1>" in page and "HS-2 #0042" in page and "A. Tester" in page
    assert ">--set</td>" in page  # the overridden key's origin


def test_report_verdict_comes_first_and_names_the_binding_check(design):
    assert design["status"] == 1  # the small motor fails
    page_text = (design["out"] / "index.html").read_text(encoding="utf-8")
    page = Page(page_text)
    assert page.order[0] == "verdict" and "table" in page.order
    document = json.loads((design["out"] / "report.json").read_text())
    verdict = document["verdict"]  # the drive's verdict, as the sizing's own
    assert verdict["level"] == "FAIL" and verdict == document["sizing"]["verdict"]
    binding = document["sizing"]["binding"]
    assert verdict["numbers"]["binding_margin"] == binding["margin"] and f"LN{binding['module']}" in verdict["judged"]
    start = page_text.index('id="verdict"')
    block = page_text[start : page_text.index("</section>", start)]
    assert binding["label"] in block and f"LN{binding['module']}" in block
    assert f"{100 * binding['margin']:+.1f} %".replace("-", "−") in block
    assert "✘ FAIL" in block  # a symbol and a word: readable in black and white


def test_report_values_carry_units_and_no_si(design):
    text = (design["out"] / "index.html").read_text(encoding="utf-8")
    assert "(SI)" not in text and "SI inside" not in text
    page = Page(text)
    assert len(page.tables) >= 7
    assert_every_value_has_a_unit(page)
    drive_table = next(t for t in page.tables if t["header"] == ["part", "figure", "value"])
    for part, figure, value in drive_table["rows"]:
        if figure not in ("name", "end fixing"):
            assert re.search(r"\d ?(mm|N·mm|kg·mm²|rpm|A|J|W|N|%|N·m/A|Ω|s|K/W)\b|:1$", value), (figure, value)


@pytest.mark.usefixtures("quick_figures")
def test_built_in_cycle_unrated_says_so_first(tmp_path):
    out = tmp_path / "r"
    assert main(["report", "--rate", "100", "--engine", "analytic", "--out", str(out)]) == 0
    page = Page((out / "index.html").read_text(encoding="utf-8"))
    assert page.order[0] == "verdict"
    verdict = json.loads((out / "report.json").read_text())["verdict"]
    text = (out / "index.html").read_text(encoding="utf-8")
    start = text.index('id="verdict"')
    block = text[start : text.index("</section>", start)]
    assert verdict["level"] == "NOT MADE" and "– NOT RATED" in block and "N·mm peak" in block


@pytest.mark.usefixtures("quick_figures")
def test_identified_parameters_are_marked_with_their_uncertainty(tmp_path):
    published = default_parameters_path().read_text()
    identified = tmp_path / "identified.toml"
    identified.write_text(
        "# Identified by hipsim identify: a parameter file every hipsim command accepts (--params).\n"
        "# From the logs: fit.csv (1000 samples per motor after filtering and decimation).\n"
        "# Starting parameters: published.\n"
        "# Identified (value, relative standard deviation); each combination is what the data determine,\n"
        "#  m_L + 0.501·m_l = 3.94518 ± 0.0015 kg (±0.039 %)\n"
        "#  μ_t = 0.0250965548 ± 0.00012 (±0.48 %)\n"
        "# Validation (RMS error of the motor torque, identified vs starting parameters):\n"
        "#   iso.csv: M1 1.44 vs 59.1 N·mm, M2 1.41 vs 63.8 N·mm, M3 1.88 vs 52.7 N·mm\n\n"
        + published.replace("thrust_mu = 0.025", "thrust_mu = 0.0250965548")
    )
    origin = parameter_origin(identified)
    assert origin.kind == "identified" and origin.logs == ("fit.csv",)
    assert origin.validation == (("iso.csv", ((1.44, 59.1), (1.41, 63.8), (1.88, 52.7))),)
    assert "held-out error on iso.csv: M1 1.44" in origin.summary()
    out = tmp_path / "r"
    assert (
        main(["report", "--params", str(identified), "--rate", "100", "--engine", "analytic", "--out", str(out)]) == 0
    )
    page = (out / "index.html").read_text(encoding="utf-8")
    assert "0.02510 ± 0.00012" in page and "0.0250965548" not in page
    assert re.search(r"<tr class=\"identified\"><td class=\"l\">friction.thrust_mu</td>", page)
    assert "start value, in an identified combination" in page  # m_l
    document = json.loads((out / "report.json").read_text())
    assert document["provenance"]["parameters"]["file"]["sha256"] == sha256(identified)


def test_pdf_without_chromium_is_a_clear_error_and_writes_nothing(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(pages, "find_browser", lambda: None)
    out = tmp_path / "r"
    assert main(["report", "--rate", "100", "--engine", "analytic", "--pdf", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--pdf needs Chromium" in err
    assert not out.exists()


def test_pdf_is_the_same_page(design, tmp_path):
    chromium()
    out = tmp_path / "r"
    assert (
        main(["report", "--rate", "100", "--engine", "analytic", "--pdf", "--out", str(out), "--title", "PDF review"])
        == 0
    )
    from pypdf import PdfReader

    reader = PdfReader(out / "report.pdf")
    text = "".join(page.extract_text() for page in reader.pages)
    squeezed = re.sub(r"\s+", "", text)
    headings = Page((out / "index.html").read_text(encoding="utf-8")).headings
    assert headings[0] == "PDF review" and "Parameters in use" in headings
    for heading in headings:
        assert re.sub(r"\s+", "", heading) in squeezed, heading
    # In the rendered page the verdict comes before the first table's header.
    assert squeezed.index("NOTRATED") < squeezed.index("inputfileSHA-256")


# ---------------------------------------------------------------------------
# compare and identify


@pytest.fixture(scope="module")
def log(tmp_path_factory):
    """A rig log made from the analytic model's own torques along four ISO cycles (a log the model explains)."""
    params = hipsim.load_parameters()
    run = hipsim.analyse(params, hipsim.iso14242(rate=500, cycles=4))
    traj = run.trajectory
    angles = np.degrees(traj.q)
    tau = run.torques.total * 1e3
    path = tmp_path_factory.mktemp("log") / "iso.csv"
    lines = ["t_s,Fe_N,alpha_deg,beta_deg,gamma_deg,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm"]
    lines += [",".join(f"{v:.9g}" for v in (traj.t[k], traj.Fe[k], *angles[k], *tau[k])) for k in range(len(traj))]
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.usefixtures("quick_figures")
def test_compare_page_and_json_carry_provenance_and_verdict(log, tmp_path, capsys):
    out = tmp_path / "cmp"
    assert main(["compare", "--log", str(log), "--out", str(out), "--accept", "5", "--rig", "HS-2 #0042"]) == 0
    printed = capsys.readouterr().out
    assert printed.startswith("PASS: ")
    summary = json.loads((out / "comparison.json").read_text())
    jsonschema.validate(summary, schema("compare"))  # the published contract (hipsim schema compare)
    hashes = {f["role"]: f["sha256"] for f in summary["provenance"]["inputs"]}
    assert hashes == {"parameters": sha256(default_parameters_path()), "log": sha256(log)}
    assert summary["verdict"]["level"] == "PASS" and summary["provenance"]["rig"] == "HS-2 #0042"
    assert summary["verdict"]["numbers"]["accept"] == 0.05
    text = (out / "index.html").read_text(encoding="utf-8")
    page = Page(text)
    assert page.order[0] == "verdict" and sha256(log) in text and "(SI)" not in text
    assert_every_value_has_a_unit(page)
    # Without a threshold the verdict is not judged, and says what would judge it.
    assert main(["compare", "--log", str(log), "--out", str(tmp_path / "open")]) == 0
    assert json.loads((tmp_path / "open" / "comparison.json").read_text())["verdict"]["level"] == "NOT MADE"
    assert "– NOT JUDGED" in (tmp_path / "open" / "index.html").read_text(encoding="utf-8")
    capsys.readouterr()


def test_identify_writes_provenance_to_its_json_and_its_file(log, tmp_path, capsys):
    out, report = tmp_path / "id.toml", tmp_path / "id.json"
    assert main(["identify", "--log", str(log), "--out", str(out), "--json", str(report), "--author", "A. Tester"]) == 0
    capsys.readouterr()
    block = json.loads(report.read_text())["provenance"]
    assert {f["role"]: f["sha256"] for f in block["inputs"]} == {
        "parameters": sha256(default_parameters_path()),
        "log": sha256(log),
    }
    text = out.read_text()
    assert (
        text.startswith("# Identified by hipsim identify")
        and f"SHA-256 {sha256(log)}" in text
        and "# Author: A. Tester" in text
    )
    origin = parameter_origin(out)
    assert origin.kind == "identified" and origin.identified and origin.made.startswith("Made by hipsim")
    assert ("log", str(log), sha256(log)) in origin.log_hashes


@pytest.mark.usefixtures("quick_figures")
def test_compare_exits_1_when_a_motor_exceeds_the_accepted_error(log, tmp_path, capsys):
    argv = ["compare", "--log", str(log), "--out", str(tmp_path / "c"), "--set", "friction.hip_mu=0.12"]
    assert main([*argv, "--accept", "0.001"]) == 1
    assert capsys.readouterr().out.startswith("FAIL: ")
    assert main([*argv, "--out", str(tmp_path / "d")]) == 0  # no threshold: nothing judged


@pytest.mark.parametrize(
    ("level", "state", "symbol"),
    [
        (Level.PASS, "pass", "✔"),
        (Level.ALIKE, "pass", "✔"),
        (Level.FAIL, "fail", "✘"),
        (Level.DIFFERENT, "fail", "✘"),
        (Level.NOT_MADE, "open", "–"),
    ],
)
def test_a_pages_block_is_its_verdicts_level(level, state, symbol):
    """The page decides nothing: state, symbol and word are the level's; its own word only for NOT MADE."""
    verdict = Verdict(level, "every motor's RMS error is within 5 %")
    block = pages.Verdict.of(verdict, not_made="NOT JUDGED")
    word = "NOT JUDGED" if level is Level.NOT_MADE else level.value
    assert (block.state, block.symbol, block.word) == (state, symbol, word)
    assert block.lines == ("Every motor's RMS error is within 5 %.",)  # what it judged, as a sentence
    assert pages.Verdict.of(verdict, ("Worst: motor 2.",)).lines == ("Worst: motor 2.",)
    assert pages.Verdict.of(verdict).word == level.value


def test_a_sentence_keeps_its_own_stop():
    assert pages.sentence("b against a: 3 %.") == "B against a: 3 %."
    assert pages.sentence("why?") == "Why?" and pages.sentence("") == ""
