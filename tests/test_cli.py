"""The hipsim command line: defaults, options, and one-line errors."""

import csv
import io
import json
import math
import subprocess
import sys
import warnings
from contextlib import redirect_stderr, redirect_stdout

import jsonschema
import numpy as np
import pytest
from fake_clock import FakeClock

from hipsim.cli.main import main
from hipsim.results import column_names


def run_process(*args):
    """Run the console script in a process of its own and return (status, stdout, stderr)."""
    done = subprocess.run([sys.executable, "-m", "hipsim", *args], capture_output=True, text=True, timeout=120)
    return done.returncode, done.stdout, done.stderr


#: Warnings a fresh ``python -m hipsim`` does not print (Python's default filters).
_HIDDEN = (DeprecationWarning, PendingDeprecationWarning, ImportWarning, ResourceWarning)


def run(*args):
    """``hipsim`` with these arguments in this process: (status, stdout, stderr), as :func:`run_process` returns them.

    A process a command costs 1–2 s of imports and numba cache loads, most of
    this file's time; the console script itself runs as a process in
    test_torques_defaults and test_pose_errors_read_alike_in_torques_and_view.
    Warnings go to stderr as a fresh process would print them, so that "one
    line" still means one line.
    """
    out, err = io.StringIO(), io.StringIO()
    with warnings.catch_warnings(record=True) as caught, redirect_stdout(out), redirect_stderr(err):
        warnings.simplefilter("default")
        for category in _HIDDEN:
            warnings.simplefilter("ignore", category)
        try:
            status = main(list(args))
        except SystemExit as exit:  # argparse: --help, or a usage error
            status = exit.code if isinstance(exit.code, int) else (0 if exit.code is None else 1)
    shown = "".join(warnings.formatwarning(w.message, w.category, w.filename, w.lineno) for w in caught)
    return status, out.getvalue(), err.getvalue() + shown


def test_torques_defaults(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    status, out, err = run_process("torques")
    assert status == 0, err
    header = next(csv.reader(open(tmp_path / "hipsim_torques.csv")))
    assert header == column_names()
    for word in ("Sliders", "S11", "S23", "Motor torques", "M3", "RMS", "rpm", "singularity"):
        assert word in out


def test_torques_json_summary_and_options(tmp_path, capsys):
    out = tmp_path / "fast.csv"
    assert (
        main(
            [
                "torques",
                "--rate",
                "500",
                "--cycles",
                "2",
                "--frequency",
                "2",
                "--out",
                str(out),
                "--summary-format",
                "json",
                "--set",
                "platform.mass_kg=30",
            ]
        )
        == 0
    )
    summary = json.loads(capsys.readouterr().out)
    assert summary["samples"] == 500
    assert "mass_kg=30" in summary["parameters"]
    rows = list(csv.reader(open(out)))
    t = np.array([float(r[0]) for r in rows[1:]])
    np.testing.assert_allclose(np.diff(t), 1 / 500)


def test_torques_from_trajectory_file(tmp_path, capsys):
    path = tmp_path / "gait.csv"
    t = np.arange(0, 0.5, 0.002)
    with open(path, "w") as stream:
        stream.write("t_s,alpha_deg,beta_deg,gamma_deg,Fe_N\n")
        for x in t:
            stream.write(f"{x},{10 * np.sin(2 * np.pi * x)},{2 * np.sin(4 * np.pi * x)},-3,1000\n")
    assert main(["torques", "--trajectory", str(path), "--out", str(tmp_path / "o.csv")]) == 0
    assert "gait.csv" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["torques", "--set", "lever.length_mm=100"], "key 'lever.length_mm': lever of 100 mm cannot reach"),
        (["torques", "--set", "lever.colour=3"], "key 'lever.colour': unknown key"),
        (["torques", "--params", "missing.toml"], "missing.toml: no such parameter file"),
        (["torques", "--trajectory", "missing.csv"], "missing.csv: no such trajectory file"),
        (["torques", "--trajectory", "x.csv", "--rate", "10"], "--rate applies to the built-in cycle"),
        (["torques", "--rate", "-5"], "--rate -5 Hz: sample rate must be above 0 and at most 1e+06 Hz"),
        (["torques", "--out", "no/such/dir/x.csv"], "folder 'no/such/dir' does not exist"),
        (["torques", "--trajectory", "{far}"], "far.csv, t = 0.02 s, line 4: pose out of reach"),
        (["torques", "--trajectory", "{allfar}", "--flag-bad-poses"], "all 7 samples are out of reach or singular"),
        (["torques", "--out", "{tmp}"], "it is a folder"),
        (["torques", "--rate", "1e9"], "--rate 1e+09 Hz: sample rate must be above 0 and at most 1e+06 Hz"),
        (["torques", "--set", "platform.heights_mm=[490, 899]"], "platform 1 must be the upper one"),
        (["simulate", "--servo-rate", "0"], "--servo-rate 0 Hz: servo rate must be above 0"),
        (["simulate", "--torque-limit", "-1"], "--torque-limit -1 N·mm: motor torque limit must be above 0 N·mm"),
        (["simulate", "--step", "5"], "longer than the servo period"),
        (["simulate", "--rate", "7"], "--rate does not apply to simulate"),
        (["simulate", "--cycles", "0"], "--cycles 0 cycles: number of built-in cycles must be above 0"),
        (["workspace", "--gamma", "a,b"], "--gamma 'a,b': expected a number in deg"),
        (["workspace", "--deltas", "0:nan:1"], "--deltas '0:nan:1': nan deg: the offsets"),
        (["workspace", "--deltas", "0:180:1e-9"], "asks for more than 100,000 offsets"),
        (
            ["workspace", "--deltas=-1e300:1e300:1e299"],
            "the offsets δ A:B:STEP must be at least -180 and at most 180 deg",
        ),
        (["workspace", "--gamma", "1e9"], "the rotations γ must be at least -180 and at most 180 deg"),
        (["workspace", "--gamma", ""], "--gamma '': expected a number in deg"),
        (["workspace", "--gamma", "1_0"], "--gamma '1_0': expected a number in deg"),
        (["workspace", "--out", "/proc/hipsim"], "cannot make the output folder"),
        (["report", "--out", "/proc/hipsim"], "cannot make the output folder"),
        # (0.003 cycles, shorter than one frame's step, is shown as its first and last samples: present/test_motion_frames.py)
        (
            ["view", "--cycles", "0.001", "--html", "{tmp}/x.html"],
            "0.001 cycle(s) of 1.0 Hz sampled at 1000.0 Hz give fewer than 2",
        ),
    ],
)
def test_errors_are_one_line(tmp_path, args, message):
    args = [
        a.replace("{far}", str(far_trajectory(tmp_path)))
        .replace("{allfar}", str(far_trajectory(tmp_path, [180] * 8)))
        .replace("{tmp}", str(tmp_path))
        for a in args
    ]
    status, out, err = run(*args, *([] if "--out" in args or "--html" in args else ["--out", str(tmp_path / "x.csv")]))
    assert status == 2
    lines = error_lines(err)
    assert len(lines) == 1 and lines[0].startswith("hipsim: error:"), err
    assert message in lines[0]
    assert "Traceback" not in err


def error_lines(err: str) -> list[str]:
    """Standard error's lines but for warnings and the note a machine's first run gives while numba compiles (its cache is cold)."""
    return [
        line
        for line in err.strip().splitlines()
        if not line.endswith("compiling (first run only) ...") and not line.startswith("hipsim: warning:")
    ]


def far_trajectory(folder, gamma=(0, 60, 120, 180, 120, 60, 30, 10)):
    """Rotation about Z that turns the platform joints away from their screws, out of reach from t = 0.02 s."""
    path = folder / ("far.csv" if gamma[0] == 0 else "allfar.csv")
    # With a load: a file without one is warned of (issue 38), and these tests are about poses.
    path.write_text(
        "t_s,alpha_deg,beta_deg,gamma_deg,Fe_N\n" + "".join(f"{k / 100},0,0,{g},1000\n" for k, g in enumerate(gamma))
    )
    return path


def test_bad_pose_writes_no_file_and_flag_mode_marks_rows(tmp_path, capsys):
    out = tmp_path / "x.csv"
    assert main(["torques", "--trajectory", str(far_trajectory(tmp_path)), "--out", str(out)]) == 2
    assert not out.exists()
    assert main(["torques", "--trajectory", str(far_trajectory(tmp_path)), "--out", str(out), "--flag-bad-poses"]) == 0
    assert "WARNING" in capsys.readouterr().out
    rows = list(csv.DictReader(open(out)))
    flagged = [float(r["flagged"]) for r in rows]
    assert flagged[0] == 0 and flagged[3] == 1 and len(rows) == 8


def test_params_prints_units(capsys):
    assert main(["params", "--set", "lever.length_mm=330"]) == 0
    out = capsys.readouterr().out
    assert "length_mm = 330" in out and "[mm]" in out and "estimate" in out


def test_help_reads_well():
    status, out, _ = run("--help")
    assert status == 0 and "torques" in out and "examples:" in out
    status, out, _ = run("torques", "--help")
    assert status == 0 and "--trajectory" in out and "--summary-format" in out


def test_check_passes_and_shows_every_configuration(capsys):
    assert main(["check", "--rate", "200"]) == 0
    out = capsys.readouterr().out
    for section in ("exact:", "published:", "published+spin:"):
        assert section in out
    assert "tau_l_1_Nmm" in out and "Fe_N" not in out.split("trajectory:")[0]
    assert out.count("within tolerance") == 2  # exact and published+spin; the published paper model is shown outside it


def test_check_fails_when_required_models_disagree(monkeypatch, capsys):
    import hipsim.analysis.crosscheck as crosscheck

    real = crosscheck.Differences.rows

    def skewed(self):
        return tuple((name, a, r + 1e-6) for name, a, r in real(self))  # a disagreement above 1e-8

    monkeypatch.setattr(crosscheck.Differences, "rows", skewed)
    assert main(["check", "--rate", "100"]) == 1
    assert "disagree" in capsys.readouterr().err


def test_urdf_command_follows_the_parameters(tmp_path):
    import yourdfpy

    out = tmp_path / "long.urdf"
    assert main(["urdf", "--set", "lever.length_mm=340", "--out", str(out)]) == 0
    robot = yourdfpy.URDF.load(str(out))
    assert robot.validate()
    tip = robot.joint_map["lever_11_tip_fixed"].origin[:3, 3]
    np.testing.assert_allclose(tip, [0.0, 0.0, 0.34], atol=1e-15)  # the lever tip sits at z = l


def test_simulate_writes_errors_and_tables(tmp_path, capsys):
    out = tmp_path / "sim.csv"
    assert main(["simulate", "--cycles", "0.05", "--mismatch", "friction=+20%", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "Tracking errors" in text and "augmented-pd" in text and "friction +20%" in text
    for name in ("sim_pd.csv", "sim_augmented-pd.csv"):
        rows = list(csv.DictReader(open(tmp_path / name)))
        assert len(rows) == 50
        assert {"err_alpha_deg", "err_beta_deg", "err_gamma_deg", "tau_1_Nmm", "alpha_des_deg"} <= set(rows[0])
    single = tmp_path / "one.csv"
    assert (
        main(["simulate", "--cycles", "0.01", "--controller", "pd", "--plant", "analytic", "--out", str(single)]) == 0
    )
    assert single.exists()


def test_simulate_bad_mismatch_is_one_line(tmp_path):
    status, _, err = run("simulate", "--mismatch", "mass=10%", "--out", str(tmp_path / "x.csv"))
    assert status == 2 and err.strip().startswith("hipsim: error: --mismatch") and "Traceback" not in err


def test_simulate_help_does_not_offer_rate(capsys):
    """simulate samples at the servo rate: --rate is refused (above), so its help must not offer it."""
    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    out = capsys.readouterr().out
    assert "--servo-rate" in out and "--rate" not in out.replace("--servo-rate", "")


def test_simulate_says_when_it_rounds_the_step(tmp_path, capsys):
    out = tmp_path / "sim.csv"
    assert (
        main(
            [
                "simulate",
                "--cycles",
                "0.01",
                "--controller",
                "pd",
                "--plant",
                "analytic",
                "--step",
                "0.3",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    assert "RK4 step 0.25 ms, the 0.3 ms asked for rounded down" in capsys.readouterr().out
    assert (
        main(
            [
                "simulate",
                "--cycles",
                "0.01",
                "--controller",
                "pd",
                "--plant",
                "analytic",
                "--step",
                "0.25",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    assert "rounded down" not in capsys.readouterr().out


def test_simulate_refuses_a_folder_before_running(tmp_path, capsys):
    assert main(["simulate", "--out", str(tmp_path)]) == 2
    assert "is a folder" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []  # nothing written beside it either


def test_an_output_over_its_own_input_is_refused(tmp_path, capsys):
    trajectory = tmp_path / "motion.csv"
    trajectory.write_text(
        "t_s,alpha_deg,beta_deg,gamma_deg\n" + "".join(f"{k * 0.01:.2f},{k},1,-2\n" for k in range(8))
    )
    before = trajectory.read_text()
    assert main(["torques", "--trajectory", str(trajectory), "--out", str(trajectory)]) == 2
    assert "is the --trajectory file itself" in capsys.readouterr().err
    assert trajectory.read_text() == before


def test_negative_sweep_values_need_no_equals_sign(tmp_path, quick_figures):
    argv = ["workspace", "--deltas", "-10:10:10", "--gamma", "-4,0", "--summary-format", "json"]
    status, out, err = run(*argv, "--out", str(tmp_path / "ws"))
    assert status == 0, err
    sweep = json.loads((tmp_path / "ws" / "workspace.json").read_text())
    assert "-10" in json.dumps(sweep)
    printed = json.loads(out)  # the file's document with the files written
    assert printed.pop("files")[-1].endswith("workspace.json") and printed == sweep
    assert [row["delta_deg"] for row in sweep["offset_sweep"]] == [-10.0, 0.0, 10.0]
    assert sweep["grid"]["gamma_deg"] == [-4.0, 0.0] and set(sweep["reachable_fraction"]) == {"-4", "0"}
    from hipsim.cli.documents import schema

    jsonschema.Draft202012Validator(schema("workspace")).validate(json.loads(out))


def test_params_prints_no_empty_tables(capsys):
    assert main(["params"]) == 0
    lines = capsys.readouterr().out.splitlines()
    headers = [k for k, line in enumerate(lines) if line.startswith("[")]
    for k in headers:  # every [section] is followed by at least one key
        assert k + 1 < len(lines) and "=" in lines[k + 1], lines[k]


# --------------------------------------------------------------------------- issue 15: what a new user hit


def test_pose_errors_read_alike_in_torques_and_view(tmp_path, monkeypatch):
    """Path as typed, the sample's time and the file's line, whichever command meets the pose."""
    (tmp_path / "data").mkdir()
    far_trajectory(tmp_path / "data")
    expected = (
        "hipsim: error: data/far.csv, t = 0.02 s, line 4: pose out of reach"  # t = 0.02 s is the third row, on line 4
    )
    monkeypatch.chdir(tmp_path)
    # The first in a process of its own, as typed in a shell; the others in this one (same main()).
    for start, args in (
        (run_process, ["torques", "--out", "x.csv"]),
        (run, ["view", "--html", "x.html"]),
        (run, ["check"]),
    ):
        status, _, err = start(*args, "--trajectory", "data/far.csv")
        assert status == 2, (args, err)
        lines = error_lines(err)
        assert len(lines) == 1 and lines[0].startswith(expected), (args, err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data"]


def test_pose_error_carries_what_it_documents():
    from hipsim.exceptions import PoseError

    error = PoseError("pose out of reach", 0.25, 7, source="runs/gait.csv", line=9)
    assert (error.reason, error.time, error.index, error.source, error.line) == (
        "pose out of reach",
        0.25,
        7,
        "runs/gait.csv",
        9,
    )
    assert str(error) == "runs/gait.csv, t = 0.25 s, line 9: pose out of reach"
    assert str(PoseError("singular pose", 1.5, 3)) == "t = 1.5 s: singular pose"


def test_summary_gives_the_cycle_of_the_smallest_singularity_measure(tmp_path, capsys):
    out = tmp_path / "x.csv"
    assert (
        main(
            [
                "torques",
                "--cycles",
                "600",
                "--rate",
                "100",
                "--frequency",
                "2",
                "--out",
                str(out),
                "--summary-format",
                "json",
            ]
        )
        == 0
    )
    summary = json.loads(capsys.readouterr().out)
    t = summary["cond_inv_min_t_s"]
    cycle = summary["cond_inv_min_cycle"]
    assert cycle == math.floor(t * 2 + 1e-9) + 1 and 1 <= cycle <= 600
    assert summary["cond_inv_min_t_in_cycle_s"] == pytest.approx(t - (cycle - 1) / 2, abs=1e-12)
    assert main(["torques", "--cycles", "600", "--rate", "100", "--frequency", "2", "--out", str(out)]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("smallest singularity"))
    assert f"(cycle {cycle}, " in line and "s into it)" in line


def test_cycle_of_a_time_late_in_a_long_run():
    from hipsim.cli.torques import _cycle_of
    from hipsim.motion.trajectories import iso14242

    long_run = iso14242(rate=10, cycles=600)
    late = _cycle_of(395.123, long_run, 1.0)
    assert late.cond_inv_min_cycle == 396 and late.cond_inv_min_t_in_cycle_s == pytest.approx(0.123, abs=1e-9)
    assert _cycle_of(395.0, long_run, 1.0).cond_inv_min_cycle == 396  # the start of cycle 396, not the end of 395
    assert _cycle_of(0.5, iso14242(rate=10, cycles=1), 1.0) is None  # one cycle: nothing to add
    assert _cycle_of(3.5, long_run, None) is None  # no known cycle length


def test_check_words_informational_rows_so_they_cannot_be_read_as_failures(capsys):
    assert main(["check", "--rate", "100"]) == 0
    out = capsys.readouterr().out
    assert "OUT OF" not in out and "FAIL" not in out
    informational = out[out.index("published:") : out.index("published+spin:")]
    assert "for information" in informational and "no tolerance applies" in informational
    assert out.count("within tolerance") == 2


def test_radians_under_a_degree_header_are_refused(tmp_path):
    """A gait's flexion in radians under alpha_deg: spans 0.75 "°", 43° as radians: a clear slip (issue 38), exit 2."""
    path = tmp_path / "rad_as_deg.csv"
    t = np.arange(100) / 100
    q = [float(np.radians(3.5 + 21.5 * np.cos(2 * np.pi * x))) for x in t]  # radians, written under alpha_deg
    path.write_text(
        "t_s,alpha_deg,beta_deg,gamma_deg,Fe_N\n" + "".join(f"{x},{a!r},0.02,-0.07,1000\n" for x, a in zip(t, q))
    )
    status, out, err = run("torques", "--trajectory", str(path), "--out", str(tmp_path / "o.csv"))
    assert status == 2, err
    lines = error_lines(err)
    assert len(lines) == 1 and "column 'alpha_deg': the angles look like radians" in lines[0] and "43°" in lines[0]
    assert not (tmp_path / "o.csv").exists()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--columns", "time=t"], "--columns applies to a --trajectory file, not to the built-in cycle"),
        (["--resample", "100", "--side", "left"], "--side, --resample apply to a --trajectory file"),
        (["--trajectory", "{csv}", "--rate", "100"], "(to resample a file, use --resample)"),
        (
            ["--trajectory", "{csv}", "--side", "left"],
            "the side (left or right hip) applies to OpenSim .mot/.sto files",
        ),
        (["--trajectory", "{csv}", "--frequency", "2", "--period", "0.5"], "give --frequency or --period, not both"),
        (["--trajectory", "{csv}", "--frequency", "-1"], "--frequency -1 Hz: cycle frequency must be above 0"),
        (["--trajectory", "{csv}", "--resample", "0"], "--resample 0 Hz: even sample rate for a file must be above 0"),
        (
            ["--trajectory", "{csv}", "--load-column", "Fe_N", "--body-weight", "736"],
            "more than 500 kg; for a weight in newtons write 736N",
        ),
        (["--trajectory", "{csv}", "--body-weight", "heavy"], "--body-weight: expected a positive mass"),
        (
            ["--trajectory", "{csv}", "--columns", "time=t_s,alpha=alpha_deg,beta=beta_deg,gamma=gamma_deg:grad"],
            "'grad' is not a unit of gamma",
        ),
        (
            ["--trajectory", "{csv}", "--columns", "time=t_s,alpha=FE,beta=beta_deg,gamma=gamma_deg"],
            "no column 'FE' (mapped to alpha)",
        ),
        (["--trajectory", "{csv}", "--load-column", "Fz"], "both 'Fe_N' and the load column 'Fz' are given"),
        (["--period", "0"], "--period 0 s: cycle period must be above 0"),
    ],
)
def test_trajectory_option_mistakes_are_one_line(tmp_path, args, message):
    csv_path = tmp_path / "gait.csv"
    csv_path.write_text(
        "t_s,alpha_deg,beta_deg,gamma_deg,Fe_N\n" + "".join(f"{k / 100},{10 + k},2,-3,500\n" for k in range(10))
    )
    args = [a.replace("{csv}", str(csv_path)) for a in args]
    status, _, err = run("torques", *args, "--out", str(tmp_path / "x.csv"))
    assert status == 2
    lines = error_lines(err)
    assert len(lines) == 1 and lines[0].startswith("hipsim: error:") and message in lines[0], err
    assert not (tmp_path / "x.csv").exists()


def test_frequency_and_period_rescale_a_recorded_cycle(tmp_path, capsys):
    """A cycle recorded at 1 Hz run at 2 Hz: the same angles in half the time, rates doubled, accelerations ×4."""
    path = tmp_path / "cycle.csv"
    t = np.arange(101) / 100  # one closed cycle: the last row repeats the first
    alpha = 3.5 + 21.5 * np.cos(2 * np.pi * t)
    path.write_text(
        "t_s,alpha_deg,beta_deg,gamma_deg,Fe_N\n"
        + "".join(f"{float(x)!r},{float(a)!r},2.0,-3.0,800\n" for x, a in zip(t, alpha))
    )
    columns: dict[tuple, dict[str, np.ndarray]] = {}
    for extra in ([], ["--frequency", "2"], ["--period", "0.5"]):
        out = tmp_path / f"o{len(columns)}.csv"
        assert main(["torques", "--trajectory", str(path), "--out", str(out), *extra]) == 0
        rows = list(csv.DictReader(open(out)))
        columns[tuple(extra)] = {
            k: np.array([float(r[k]) for r in rows]) for k in ("t_s", "alpha_deg", "Ld_11_mm_s", "Ldd_11_mm_s2", "Fe_N")
        }
    capsys.readouterr()
    base, fast, short = columns[()], columns[("--frequency", "2")], columns[("--period", "0.5")]
    np.testing.assert_allclose(fast["t_s"], base["t_s"] / 2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(fast["alpha_deg"], base["alpha_deg"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(fast["Ld_11_mm_s"], 2 * base["Ld_11_mm_s"], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(fast["Ldd_11_mm_s2"], 4 * base["Ldd_11_mm_s2"], rtol=1e-9, atol=1e-6)
    np.testing.assert_array_equal(fast["Fe_N"], base["Fe_N"])
    for key in fast:
        np.testing.assert_allclose(short[key], fast[key], rtol=1e-12, atol=1e-12)


def test_opensim_file_with_a_flipped_load_column_in_percent_body_weight(tmp_path, capsys):
    """--load-column -COL (no '=' needed) with --body-weight: a compressive force component in % body weight as F_e in N."""
    t = np.arange(101) / 100
    flexion, force = 20 * np.cos(2 * np.pi * t), 250 + 150 * np.sin(np.pi * t) ** 2  # degrees, % body weight
    lines = [
        "ik",
        "inDegrees=yes",
        "endheader",
        "time\thip_flexion_l\thip_adduction_l\thip_rotation_l\thip_l_on_pelvis_fy",
    ]
    lines += ["\t".join(repr(float(v)) for v in (t[k], flexion[k], 0.0, 0.0, -force[k])) for k in range(101)]
    path = tmp_path / "walk.mot"
    path.write_text("\n".join(lines) + "\n")
    out = tmp_path / "o.csv"
    args = [
        "torques",
        "--trajectory",
        str(path),
        "--side",
        "left",
        "--load-column",
        "-hip_l_on_pelvis_fy",
        "--body-weight",
        "80kg",
    ]
    assert main([*args, "--out", str(out)]) == 0
    rows = list(csv.DictReader(open(out)))
    np.testing.assert_allclose([float(r["Fe_N"]) for r in rows], force[:100] / 100 * 80 * 9.80665, rtol=1e-11)
    np.testing.assert_allclose(
        [float(r["alpha_deg"]) for r in rows], flexion[:100], rtol=0, atol=1e-9
    )  # flexion alone is α
    assert str(path) in capsys.readouterr().out  # the summary names the file as typed


def test_a_slow_pinocchio_warm_up_is_announced_as_compiling(monkeypatch, capsys):
    """The closure kernels' first-run compile is said on standard error; a quick load says nothing (on an injected
    clock: the warm-up takes 1.5 s of it, or none)."""
    import hipsim.closed_chain.dynamics as closed_chain
    from hipsim.cli.common import load_pinocchio_kernels as _load_pinocchio_kernels

    clock = FakeClock()
    monkeypatch.setattr(closed_chain, "warm_up", lambda: clock.advance(1.5))  # as long as a compilation, for the note
    _load_pinocchio_kernels(clock)
    assert capsys.readouterr().err == "Pinocchio model: compiling (first run only) ...\n"
    monkeypatch.setattr(closed_chain, "warm_up", lambda: clock.advance(0.5))
    _load_pinocchio_kernels(clock)
    assert capsys.readouterr().err == ""


def test_warm_up_loads_what_a_run_uses():
    """After warm_up, a Pinocchio run compiles nothing new: every kernel already has the run's argument types (a fresh process)."""
    code = """
import hipsim
from hipsim.closed_chain import closure_kernel
from hipsim.closed_chain.dynamics import warm_up
# The kernels the solver calls from Python (the others run inside them).
kernels = [closure_kernel.predict, closure_kernel.gaps_and_chord_step, closure_kernel.closed_sample,
           closure_kernel.closure_frames, closure_kernel.actuator_and_closure_forces]
warm_up()
before = [len(kernel.signatures) for kernel in kernels]
hipsim.analyse(None, hipsim.iso14242(rate=200), model="pinocchio")
import json
print(json.dumps([before, [len(kernel.signatures) for kernel in kernels]]))
"""
    before, after = json.loads(
        subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    )
    assert all(before) and after == before


def test_the_log_options_defaults_are_the_librarys():
    """--cutoff and --tolerance print their defaults without loading SciPy: the CLI's copies must be the library's values."""
    from hipsim.cli import rig
    from hipsim.rig.logs import DEFAULT_CUTOFF, DEFAULT_TOLERANCE_DEG

    assert (rig.DEFAULT_CUTOFF, rig.DEFAULT_TOLERANCE_DEG) == (DEFAULT_CUTOFF, DEFAULT_TOLERANCE_DEG)


def test_import_and_the_parser_load_no_computing():
    """``import hipsim`` and building the parser (--help, --version) load neither NumPy nor anything heavier; a name loads on use."""
    code = """
import sys
import hipsim
heavy = ("numpy", "scipy", "numba", "pinocchio", "xacro", "matplotlib", "hipsim.analysis.runs", "hipsim.analysis.streaming", "hipsim.analytic")
after_import = [m for m in heavy if m in sys.modules]
from hipsim.cli.main import build_parser
build_parser()
after_parser = [m for m in heavy if m in sys.modules]
hipsim.iso14242
print(after_import, after_parser, "hipsim.motion" in sys.modules, sorted(set(hipsim.__all__) - set(dir(hipsim))))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["[]", "[]", "True", "[]"]


def test_every_public_name_imports_lazily():
    import hipsim
    import hipsim.analysis.runs
    import hipsim.machine.parameters

    for name in hipsim.__all__:
        assert getattr(hipsim, name) is not None
    assert (
        hipsim.analyse is hipsim.analysis.runs.analyse
        and hipsim.load_parameters is hipsim.machine.parameters.load_parameters
    )
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        hipsim.nothing
