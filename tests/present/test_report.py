"""Design report (issue 7): sizing numbers, rating checks, figure files, the HTML page in a real browser."""

import base64
import dataclasses
import json
import math
import os
import re
import shutil
import sys
import xml.etree.ElementTree as ET
from html.parser import HTMLParser
from types import SimpleNamespace

import numpy as np
import pytest
from support import given

import hipsim
import hipsim.present.figures as figures
import hipsim.present.report as report
from hipsim import Run
from hipsim.cli import main
from hipsim.design.sizing import axial_screw_load, sizing
from hipsim.exceptions import HipsimError, OutputError, ParameterError
from hipsim.machine.drive import Drive, LeadScrew, Motor, TorqueSpeedCurve, load_drive
from hipsim.motion.trajectories import Trajectory, iso14242
from hipsim.present.browser import run_headless

BASE_FIGURES = (
    "input_motion",
    "slider_motion",
    "motor_torques",
    "load_friction",
    "singularity",
    "torque_speed",
    "axial_load",
)


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


@pytest.fixture(scope="module")
def iso():
    return iso14242(rate=500)


@pytest.fixture(scope="module")
def result(params, iso):
    return hipsim.analyse(params, iso)


def fake_simulations(t):
    """Two controllers' tracking errors in [rad], of known peak and RMS."""
    wave = np.sin(2 * np.pi * t)[:, None]
    return {
        "workspace PD": SimpleNamespace(
            t=t, err=np.radians(0.2) * wave * [1.0, 0.5, 0.25], tau=np.full((t.size, 3), 0.3)
        ),
        "augmented PD": SimpleNamespace(t=t, err=np.radians(0.02) * wave * [1.0, 0.5, 0.25]),
    }


def with_joint_forces(result: Run) -> Run:
    """The analytic run with made-up joint forces in [N] standing in for the Pinocchio model's."""
    n = len(result.trajectory)
    Fa = 100.0 + np.arange(6).reshape(1, 2, 3) * 10.0 + 50.0 * np.sin(2 * np.pi * result.trajectory.t)[:, None, None]
    Fo = np.column_stack([result.trajectory.Fe + 200.0, result.trajectory.Fe + 150.0])
    assert Fa.shape == (n, 2, 3)
    return dataclasses.replace(result, model="pinocchio", joint_forces=hipsim.JointForces(Fa, Fo))


@pytest.fixture(scope="module")
def written(tmp_path_factory, params, iso, result):
    """One full report: joint forces (stand-in), tracking, a failing rating check."""
    out = tmp_path_factory.mktemp("report")
    ratings = out / "motor.toml"
    ratings.write_text(
        "[motor]\nrated_torque_Nmm = 640\npeak_torque_Nmm = 400\nmax_speed_rpm = 3000\nstroke_mm = 200\naxial_force_N = 1000\n"
    )
    return report.write_report(
        out / "site", result, with_joint_forces(result), simulations=fake_simulations(iso.t), drive=load_drive(ratings)
    )


# ---------------------------------------------------------------------------
# Sizing


def test_sizing_equals_direct_computation(result):
    size = sizing(result)
    tau = result.torques.total * 1e3
    speed = result.torques.motor_speed
    for i, module in enumerate(size.modules):
        assert module.module == i + 1
        assert module.tau_peak_Nmm == pytest.approx(np.abs(tau[:, i]).max(), rel=1e-12)
        assert module.tau_rms_Nmm == pytest.approx(math.sqrt(np.mean(tau[:, i] ** 2)), rel=1e-12)
        assert module.speed_peak_rpm == pytest.approx(np.abs(result.columns()[f"speed_{i + 1}_rpm"]).max(), rel=1e-12)
        assert module.power_peak_W == pytest.approx(np.abs(result.torques.total[:, i] * speed[:, i]).max(), rel=1e-12)
        assert module.stroke_mm == pytest.approx(result.summary().sliders[f"1{i + 1}"].stroke_mm, rel=1e-12)
    assert size.joints is None and size.checks == () and size.passed is None


def test_axial_force_is_the_thrust_of_the_parts_the_nut_carries(result, params):
    force = axial_screw_load(result)
    t = result.torques
    # Frictionless screw: the thrust is everything but the rotor's inertia.
    np.testing.assert_allclose(
        force * params.lead / (2 * math.pi), t.platforms + t.levers + t.sliders + t.friction, rtol=1e-12, atol=1e-15
    )
    assert sizing(result).modules[1].axial_force_peak_N == pytest.approx(np.abs(force[:, 1]).max())


def test_screw_friction_changes_the_torque_but_not_the_axial_force(params, iso):
    rough = params.replace(screw_coulomb=0.05, screw_viscous=2e-4)  # 50 N·mm and 0.2 N·mm·s/rad
    smooth_run, rough_run = hipsim.analyse(params, iso), hipsim.analyse(rough, iso)
    assert np.abs(rough_run.torques.total - smooth_run.torques.total).max() > 0.04
    np.testing.assert_allclose(axial_screw_load(rough_run), axial_screw_load(smooth_run), rtol=1e-10, atol=1e-9)


def test_axial_force_at_rest_carries_both_sliders_weight(params):
    # Standing still, no load, weightless levers: each nut holds its two sliders, 2·m_L·g.
    machine = params.replace(lever_mass=0.0, lever_inertia=np.zeros((3, 3)))
    q = np.tile(np.radians([10.0, -3.0, -5.0]), (6, 1))
    still = Trajectory(np.arange(6) * 0.01, q, np.zeros_like(q), np.zeros_like(q), np.zeros(6), name="still")
    force = axial_screw_load(hipsim.analyse(machine, still))
    np.testing.assert_allclose(force, 2 * params.slider_mass * params.gravity, rtol=1e-12)


def flat(torque_Nmm):
    return TorqueSpeedCurve(np.array([0.0]), np.array([torque_Nmm * 1e-3]))


def test_joint_sizing_and_rating_checks(result):
    drive = Drive(
        Motor("test", continuous=flat(640.0), peak=flat(400.0)), screw=LeadScrew("test", stroke=0.090), source="test"
    )
    size = sizing(with_joint_forces(result), drive)
    forces = with_joint_forces(result).joint_forces
    Fa, Fo = forces.Fa, forces.Fo
    joints = {j.joint: j for j in given(size.joints)}
    assert set(joints) == {"a_11", "a_12", "a_13", "a_21", "a_22", "a_23", "o_1", "o_2"}
    assert joints["a_23"].peak_N == pytest.approx(Fa[:, 1, 2].max())
    assert joints["o_1"].rms_N == pytest.approx(math.sqrt(np.mean(Fo[:, 0] ** 2)))
    made = [c for c in size.checks if c.passed is not None]
    assert {c.name for c in made} == {"peak_curve", "s1_rms", "stroke", "winding_rise"}  # the S1 stall torque sets R_th
    for check in made:
        module = size.modules[check.module - 1]
        if check.name in ("s1_rms", "stroke"):
            demand = {"s1_rms": module.tau_rms_Nmm, "stroke": module.stroke_mm}[check.name]
            assert check.value == pytest.approx(demand, rel=1e-12)
        if check.name == "peak_curve":  # a flat curve: the worst point is the peak torque
            assert check.value == pytest.approx(module.tau_peak_Nmm, rel=1e-12)
        value, limit = given(check.value), given(check.limit)  # a check made has both
        assert check.margin == pytest.approx(1 - value / limit)
        assert check.passed == (value <= limit)
    # Motor 1 needs 431 N·mm peak and module 2 a 95 mm stroke: both fail; the RMS torque passes.
    failed = {(c.module, c.name) for c in made if not c.passed}
    assert (1, "peak_curve") in failed and (2, "stroke") in failed
    assert all(c.passed for c in made if c.name == "s1_rms")
    assert size.passed is False
    assert given(size.binding).name == "peak_curve" and given(size.binding).module == 1


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("[motor]\npeak_torque = 3\n", "motor.peak_torque"),
        ("[motor]\npeak_torque_Nmm = -3\n", "must not be negative"),
        ("[motor]\nstroke_mm = 'long'\n", "motor.stroke_mm"),
        ("[drive]\nstroke_mm = 100\n", "drive"),
        ("[motor]\n", "[motor] table"),
        ("motor = [", "not valid TOML"),
    ],
)
def test_bad_rating_files_name_the_key(tmp_path, text, message):
    path = tmp_path / "motor.toml"
    path.write_text(text)
    with pytest.raises(ParameterError, match=re.escape(message)) as error:
        load_drive(path)
    assert str(path) in str(error.value)


def test_rating_file_round_trip(tmp_path):
    path = tmp_path / "motor.toml"
    path.write_text("[motor]\nmax_speed_rpm = 3000\nstroke_mm = 150.5\n")
    drive = load_drive(path)
    assert drive.motor.max_speed == pytest.approx(3000.0 * 2 * math.pi / 60) and given(
        drive.screw
    ).stroke == pytest.approx(0.1505)
    assert drive.motor.peak is None


def test_a_parameter_file_serves_as_a_rating_file(tmp_path):
    """Its [motor] table is read, its other tables ignored (they are known sections, not typos)."""
    from hipsim.machine.parameters import default_parameters_path

    path = tmp_path / "machine.toml"
    path.write_text(default_parameters_path().read_text() + "\n[motor]\npeak_torque_Nmm = 1910\n")
    assert given(load_drive(path).motor.peak).at(1000.0) == pytest.approx(1.910)
    path.write_text(default_parameters_path().read_text())  # no [motor] table at all
    with pytest.raises(ParameterError, match=re.escape("[motor] table")):
        load_drive(path)


# ---------------------------------------------------------------------------
# The written report


class _Page(HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.links, self.tables = [], [], 0

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "img":
            self.images.append(attrs)
        elif tag == "a":
            self.links.append(attrs["href"])
        elif tag == "table":
            self.tables += 1


def test_every_figure_exists_and_is_non_trivial(written):
    expected = set(BASE_FIGURES) | {"joint_forces", "tracking_errors"}
    assert set(written.figures) == expected
    for stem in expected:
        png, svg = written.folder / f"{stem}.png", written.folder / f"{stem}.svg"
        assert written.figures[stem] == (png, svg)
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000, stem
        root = ET.parse(svg).getroot()
        assert root.tag == "{http://www.w3.org/2000/svg}svg" and svg.stat().st_size > 20_000, stem


@pytest.mark.parametrize(
    "plot",
    ["input_motion", "slider_motion", "torque_parts", "load_friction", "joint_forces", "singularity", "tracking"],
)
def test_figures_have_units_and_legends(result, plot):
    function = getattr(figures, f"plot_{plot}")
    fig = function(fake_simulations(result.trajectory.t) if plot == "tracking" else with_joint_forces(result))
    for ax in fig.axes:
        assert re.search(r"\[.+\]", ax.get_ylabel()), (plot, ax.get_ylabel())
        assert ax.get_legend() is not None or any(other.get_legend() for other in fig.axes)
    assert re.search(r"\[s\]", fig.axes[-1].get_xlabel())
    assert fig.get_suptitle()


def test_page_is_self_contained_and_references_every_figure(written):
    page = written.index.read_text(encoding="utf-8")
    parser = _Page()
    parser.feed(page)
    assert not re.search(r"(src|href)=['\"]?(https?:)?//", page)  # nothing fetched from the network
    embedded = {img["alt"].split(":")[0]: img["src"] for img in parser.images}
    assert set(embedded) == set(written.figures)
    for stem, (png, svg) in written.figures.items():
        prefix = "data:image/png;base64,"
        assert embedded[stem].startswith(prefix)
        assert base64.b64decode(embedded[stem][len(prefix) :]) == png.read_bytes()
        assert svg.name in parser.links and png.name in parser.links
    assert parser.tables >= 8  # sliders, motors, sizing, joints, checks, tracking, torques, parameters, drive


def test_page_and_json_carry_the_numbers(written, params, iso):
    page = written.index.read_text(encoding="utf-8")
    document = json.loads((written.folder / "report.json").read_text())
    size = written.sizing
    assert document["sizing"]["modules"][0]["tau_peak_Nmm"] == pytest.approx(size.modules[0].tau_peak_Nmm)
    assert f"{size.modules[0].tau_peak_Nmm:,.1f}" in page
    assert f"{size.modules[2].axial_force_peak_N:,.1f}" in page
    assert "FAIL" in page and document["sizing"]["passed"] is False
    assert "estimate" in page  # the platform mass is not published
    tracking = document["tracking"]
    assert tracking["workspace PD"]["alpha_err_peak_deg"] == pytest.approx(0.2, rel=1e-3)
    assert tracking["augmented PD"]["beta_err_rms_deg"] == pytest.approx(0.01 / math.sqrt(2), rel=1e-3)
    assert tracking["workspace PD"]["tau_peak_2_Nmm"] == pytest.approx(300.0)
    assert "workspace PD" in page and "augmented PD" in page
    assert (written.folder / "torques.csv").stat().st_size > 10_000


@pytest.mark.usefixtures("quick_figures")
def test_missing_pinocchio_model_falls_back_with_a_note(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "hipsim.closed_chain.engine", None)  # importing it raises ImportError
    assert main(["report", "--rate", "100", "--out", str(tmp_path / "auto")]) == 0
    page = (tmp_path / "auto" / "index.html").read_text(encoding="utf-8")
    assert "Pinocchio model is not available" in page
    assert not (tmp_path / "auto" / "joint_forces.png").exists()
    assert main(["report", "--rate", "100", "--engine", "pinocchio", "--out", str(tmp_path / "pin")]) == 2
    assert "Pinocchio model is not available" in capsys.readouterr().err
    assert not (tmp_path / "pin").exists()


@pytest.mark.usefixtures("quick_figures")
def test_simulations_are_plotted_and_bad_ones_refused(result, tmp_path):
    short = result
    files = report.write_report(tmp_path / "a", short, simulations=fake_simulations(short.t))
    assert "tracking_errors" in files.figures
    with pytest.raises(HipsimError, match="err"):
        report.write_report(
            tmp_path / "b", short, simulations={"PD": SimpleNamespace(t=short.t, err=np.zeros((short.t.size, 2)))}
        )
    with pytest.raises(HipsimError, match="mapping"):
        report.write_report(tmp_path / "c", short, simulations={})
    assert not (tmp_path / "b").exists() and not (tmp_path / "c").exists()


def test_joint_forces_must_come_from_a_run_along_the_same_trajectory(result, params, iso, tmp_path):
    other = hipsim.analyse(params, iso.slice(slice(0, 50)))
    with pytest.raises(HipsimError, match="trajectory"):
        report.write_report(tmp_path / "x", result, with_joint_forces(other))
    with pytest.raises(HipsimError, match="no joint forces"):
        report.write_report(tmp_path / "x", result, result.__class__(**{**result.__dict__, "model": "other"}))
    assert not (tmp_path / "x").exists()


# ---------------------------------------------------------------------------
# A real browser


def _chromium():
    for name in ("chromium", "chromium-browser"):
        path = shutil.which(name)
        if path:
            return path
    if os.environ.get("HIPSIM_REQUIRE_BROWSER") == "1":
        pytest.fail("HIPSIM_REQUIRE_BROWSER=1 but chromium is not on PATH")
    pytest.skip("chromium is not on PATH (set HIPSIM_REQUIRE_BROWSER=1 to make this a failure)")


def test_page_renders_in_headless_chromium(written, tmp_path):
    browser = _chromium()
    # Moved away from its folder, the page must still show its figures: they are embedded.
    page = tmp_path / "moved" / "index.html"
    page.parent.mkdir()
    shutil.copy(written.index, page)
    shot = tmp_path / "shot.png"
    errors = run_headless(
        browser, page.as_uri(), (f"--screenshot={shot}", "--window-size=1280,4000"), "screenshot", 120
    )
    assert shot.exists(), errors
    from matplotlib.image import imread

    pixels = imread(shot)[..., :3]
    assert pixels.shape[:2] == (4000, 1280)
    assert pixels.std() > 0.05  # not a blank page
    # The lower part of the page is the figures: coloured curves, not only black text on white.
    figures = pixels[2500:]
    saturation = figures.max(axis=-1) - figures.min(axis=-1)
    assert np.mean(saturation > 0.3) > 0.002


def test_a_failed_report_leaves_no_folder_behind(tmp_path, capsys):
    """The folder is made only once there is something to write: a bad trajectory leaves nothing."""
    bad = tmp_path / "bad.csv"
    rows = [f"{k * 0.01:.2f},0,0,{-150 + 40 * k}" for k in range(8)]  # γ far out of reach
    bad.write_text("t_s,alpha_deg,beta_deg,gamma_deg\n" + "\n".join(rows) + "\n")
    out = tmp_path / "deep" / "report"
    assert main(["report", "--trajectory", str(bad), "--out", str(out)]) == 2
    assert "t = " in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.csv"]


def refuse_to_write(*args, **kwargs):
    """A figure write that fails, as on a full disk: after the folder is made, before anything is in it."""
    raise HipsimError("slider_motion.png: cannot write (No space left on device)")


def test_a_report_failing_at_its_first_write_takes_back_the_folders_it_made(tmp_path, params, iso, monkeypatch):
    monkeypatch.setattr(report, "save_figure", refuse_to_write)
    with pytest.raises(HipsimError, match="No space left"):
        report.write_report(tmp_path / "deep" / "report", hipsim.analyse(params, iso.slice(slice(0, 50))))
    assert list(tmp_path.iterdir()) == []


def test_a_failing_report_never_removes_a_folder_that_was_there(tmp_path, params, iso, monkeypatch):
    monkeypatch.setattr(report, "save_figure", refuse_to_write)
    out = tmp_path / "report"
    out.mkdir()
    with pytest.raises(HipsimError, match="No space left"):
        report.write_report(out, hipsim.analyse(params, iso.slice(slice(0, 50))))
    assert out.is_dir() and list(out.iterdir()) == []


# ---------------------------------------------------------------------------
# A folder from one run (issue 15)


def snapshot(folder):
    return {p.name: p.read_bytes() for p in folder.iterdir()}


@pytest.fixture(scope="module")
def short_runs(params, iso):
    """Two different runs along 50 samples: the second with heavier sliders, so every figure differs."""
    part = iso.slice(slice(0, 50))
    return hipsim.analyse(params, part), hipsim.analyse(params.replace(slider_mass=6.0), part)


@pytest.mark.usefixtures("quick_figures")
def test_an_interrupted_rerun_leaves_the_earlier_report_whole(tmp_path, short_runs, monkeypatch):
    first, second = short_runs
    out = tmp_path / "report"
    report.write_report(out, first, with_joint_forces(first))
    before = snapshot(out)
    saved: list = []

    def interrupted(fig, folder, stem, **kwargs):
        if len(saved) == 2:
            raise KeyboardInterrupt
        saved.append(stem)
        return figures.save_figure(fig, folder, stem, **kwargs)

    monkeypatch.setattr(report, "save_figure", interrupted)
    with pytest.raises(KeyboardInterrupt):
        report.write_report(out, second)
    assert len(saved) == 2
    assert snapshot(out) == before  # not one file of the second run, not one of the first missing
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report"]  # no temporary folder left beside it


@pytest.mark.usefixtures("quick_figures")
def test_a_rerun_leaves_no_figure_of_the_earlier_run(tmp_path, short_runs):
    first, second = short_runs
    out = tmp_path / "report"
    report.write_report(out, first, with_joint_forces(first))
    assert (out / "joint_forces.png").exists()
    files = report.write_report(out, second)  # no joint forces this time
    assert not (out / "joint_forces.png").exists() and not (out / "joint_forces.svg").exists()
    assert {p.name for p in out.iterdir() if p.suffix == ".png"} == {f"{stem}.png" for stem in files.figures}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report"]


def test_a_folder_of_other_files_is_never_replaced(tmp_path, short_runs):
    out = tmp_path / "thesis"
    out.mkdir()
    (out / "chapter1.tex").write_text("precious")
    with pytest.raises(OutputError, match="chapter1.tex") as error:
        report.write_report(out, short_runs[0])
    assert error.value.path == out and str(error.value).startswith(f"{out}: the folder holds other files")
    assert snapshot(out) == {"chapter1.tex": b"precious"}


@pytest.mark.usefixtures("quick_figures")
def test_a_report_through_a_symbolic_link_keeps_the_link(tmp_path, short_runs):
    real = tmp_path / "real"
    real.mkdir()
    link = tmp_path / "link"
    link.symlink_to(real, target_is_directory=True)
    report.write_report(link, short_runs[0])
    assert link.is_symlink() and (real / "index.html").exists()


# ---------------------------------------------------------------------------
# What a new user found (issue 14, item 5)


@pytest.mark.usefixtures("quick_figures")
def test_page_escapes_what_it_did_not_write(tmp_path, short_runs):
    run = short_runs[0]
    odd = dataclasses.replace(run, trajectory=dataclasses.replace(run.trajectory, name="<script>alert(1)</script>"))
    page = report.write_report(tmp_path / "r", odd, notes=("a & b <i>",)).index.read_text(encoding="utf-8")
    assert "<script>alert" not in page and "&lt;script&gt;alert(1)&lt;/script&gt;" in page
    assert "a &amp; b &lt;i&gt;" in page


def test_small_tracking_errors_are_printed_not_rounded_to_zero(written):
    page = written.index.read_text(encoding="utf-8")
    rows = re.findall(r"<tr><td class=\"l\">augmented PD</td>(.*?)</tr>", page)
    assert rows, "no tracking row for the augmented PD"
    cells = re.findall(r"<td>(.*?)</td>", rows[0])
    assert cells[0] == "0.02" and "0.0000" not in rows[0]  # α peak of 0.02°, to three significant figures


def test_joint_forces_are_credited_to_the_model_that_gave_them(result):
    fig = figures.plot_joint_forces(
        with_joint_forces(result).__class__(**{**with_joint_forces(result).__dict__, "model": "analytic"}), "pinocchio"
    )
    assert "Pinocchio" in fig.get_suptitle() and "analytic" not in fig.get_suptitle()


def test_page_names_the_two_screw_forces_apart_and_lists_every_parameter(written, params):
    from hipsim.machine.parameters import file_values

    page = written.index.read_text(encoding="utf-8")
    assert (
        "motor thrust</b> = 2πτ/p" in page
        and "axial screw load</b> = 2π(τ − τ<sub>L</sub> − τ<sub>screw friction</sub>)/p" in page
    )
    assert "peak motor thrust [N]" in page and "peak axial screw load [N]" in page
    for key in file_values(params):
        assert f'<td class="l">{key}</td>' in page, key
    assert "Joint reaction forces (from the Pinocchio closed-chain model)" in page
    assert "input_motion" in written.figures


@pytest.mark.usefixtures("quick_figures")
def test_report_simulate_takes_a_mismatch(tmp_path, monkeypatch, capsys):
    import importlib

    cli = importlib.import_module("hipsim.cli.report")

    seen = {}

    def fake_simulate_both(params, desired_at, duration, mismatch=None):
        seen["mismatch"] = mismatch
        t = np.linspace(0.0, duration, 50, endpoint=False)
        return fake_simulations(t)

    monkeypatch.setattr(cli, "_simulate_both", fake_simulate_both)
    out = tmp_path / "r"
    assert (
        main(
            [
                "report",
                "--rate",
                "100",
                "--engine",
                "analytic",
                "--simulate",
                "--mismatch",
                "friction=+20%",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    assert seen["mismatch"] == {"friction": pytest.approx(0.2)}
    assert "off from the controllers&#39; model: friction +20%" in (out / "index.html").read_text(encoding="utf-8")
    assert main(["report", "--mismatch", "friction=+20%", "--out", str(tmp_path / "x")]) == 2
    assert "--simulate" in capsys.readouterr().err and not (tmp_path / "x").exists()
    assert main(["report", "--simulate", "--mismatch", "mass=1", "--out", str(tmp_path / "y")]) == 2
    assert not (tmp_path / "y").exists()
