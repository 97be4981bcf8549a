"""Design sweeps: one variant's metrics against the physics, the distributed engine against the serial run, resume and the command line (the variants themselves: test_variants.py)."""

import json
import math
import sys

import jsonschema
import numpy as np
import pytest

import hipsim
from hipsim.cli.documents import schema
from hipsim.cli.main import main
from hipsim.design import variants as v
from hipsim.design.sweep import (
    SweepSetup,
    evaluate,
    evaluate_batch,
    metric_columns,
    pareto_front,
    parse_objective,
    run_sweep,
)
from hipsim.design.sweep_table import read_table, write_table
from hipsim.exceptions import ArgumentError, MissingDependencyError

RATE = 100.0  # samples per second of the ISO cycle: the metrics' physics does not need more, and the tests stay quick


@pytest.fixture(scope="module")
def base():
    return hipsim.load_parameters()


@pytest.fixture(scope="module")
def iso():
    return hipsim.iso14242(rate=RATE)


def rows_equal(a: dict, b: dict) -> bool:
    """Equal to the last bit, NaN equal to NaN."""
    if a.keys() != b.keys():
        return False
    for key in a:
        x, y = a[key], b[key]
        if isinstance(x, float) and isinstance(y, float):
            if not (
                np.array_equal(np.float64(x).view(np.int64), np.float64(y).view(np.int64))
                or (math.isnan(x) and math.isnan(y))
            ):
                return False
        elif x != y:
            return False
    return True


# ---------------------------------------------------------------------------
# One variant's metrics


def test_the_nominal_variant_gives_exactly_what_analyse_gives(base, iso):
    keys = (v.key_ref("lever.length_mm"), v.key_ref("platform.heights_mm[2]"))
    row = evaluate(SweepSetup(base, iso, keys), v.nominal(base, keys))
    summary = hipsim.analyse(base, iso).summary()
    assert row["status"] == "ok" and row["rating"] == "unchecked"
    for i in ("1", "2", "3"):
        assert row[f"tau_peak_{i}_Nmm"] == summary.motors[i].tau_peak_Nmm
        assert row[f"tau_rms_{i}_Nmm"] == summary.motors[i].tau_rms_Nmm
        assert row[f"speed_peak_{i}_rpm"] == summary.motors[i].speed_peak_rpm
    for slider, s in summary.sliders.items():
        assert row[f"stroke_{slider}_mm"] == s.stroke_mm
    assert row["cond_inv_min"] == summary.cond_inv_min
    assert row["tau_peak_max_Nmm"] == max(m.tau_peak_Nmm for m in summary.motors.values())


def test_heavier_sliders_add_their_weight_through_the_screws(base):
    """At rest each screw lifts its two sliders: Δτ = 2·Δm·g·p/(2π) on every motor, whatever the pose."""
    n = 5
    q = np.tile(np.radians([10.0, 3.0, -5.0]), (n, 1))
    still = hipsim.Trajectory(np.arange(n) * 0.01, q, np.zeros((n, 3)), np.zeros((n, 3)), np.zeros(n), name="at rest")
    setup = SweepSetup(base, still, (v.key_ref("slider.mass_kg"),))
    light, heavy = evaluate(setup, [3.0]), evaluate(setup, [4.5])
    expected = 2 * 1.5 * base.gravity * base.lead / (2 * math.pi) * 1e3  # N·mm
    for i in (1, 2, 3):
        assert heavy[f"tau_peak_{i}_Nmm"] - light[f"tau_peak_{i}_Nmm"] == pytest.approx(expected, rel=1e-9)


def test_heavier_levers_need_more_torque_along_the_gait(base, iso):
    setup = SweepSetup(base, iso, (v.key_ref("lever.mass_kg"),))
    peaks = [evaluate(setup, [mass])["tau_peak_max_Nmm"] for mass in (0.5, 1.43, 3.0)]
    assert peaks[0] < peaks[1] < peaks[2]


def test_variants_that_cannot_assemble_or_leave_the_workspace_are_rows_with_their_reason(base, iso):
    keys = (v.key_ref("lever.length_mm"), v.key_ref("platform.home_offset_deg"))
    setup = SweepSetup(base, iso, keys)
    short = evaluate(setup, [150.0, 30.0])
    assert short["status"] == "cannot_assemble"
    assert "cannot reach" in short["reason"] and "lever.length_mm" in short["reason"]
    assert math.isnan(short["tau_peak_max_Nmm"]) and short["rating"] == ""
    # δ = 50° turns the legs so that the gait crosses a singularity (det J changes sign).
    singular = evaluate(setup, [210.0, 50.0])
    assert singular["status"] == "out_of_workspace"
    assert "singular" in singular["reason"] and "t = " in singular["reason"]


def test_the_rating_is_checked_against_each_variants_motor_table(iso):
    peak = hipsim.analyse(hipsim.load_parameters(), iso).summary().motors
    largest = max(m.tau_peak_Nmm for m in peak.values())
    machine = hipsim.load_parameters(overrides={"motor.peak_torque_Nmm": largest * 1.001})
    setup = SweepSetup(machine, iso, (v.key_ref("motor.peak_torque_Nmm"),))
    passes, fails = evaluate(setup, [largest * 1.001]), evaluate(setup, [largest * 0.999])
    assert passes["rating"] == "pass" and fails["rating"] == "fail"
    assert passes["binding"].startswith("peak_curve") and passes["margin"] == pytest.approx(1 - 1 / 1.001)


def test_the_pinocchio_model_adds_the_joint_forces(base, iso):
    short = iso.slice(slice(0, 20))
    keys = (v.key_ref("lever.length_mm"),)
    row = evaluate(SweepSetup(base, short, keys, model="pinocchio"), v.nominal(base, keys))
    joints = hipsim.analyse(base, short, model="pinocchio").summary().joints
    assert row["Fa_12_peak_N"] == joints["Fa_12"].peak_N
    assert row["Fo_peak_max_N"] == max(joints["Fo_1"].peak_N, joints["Fo_2"].peak_N)


# ---------------------------------------------------------------------------
# The engine


def test_a_real_dask_cluster_gives_the_serial_rows_to_the_last_bit(base, iso):
    distributed = pytest.importorskip("distributed")
    variants = v.grid({"lever.length_mm": (150.0, 390.0, 60.0), "platform.home_offset_deg": (30.0, 50.0, 20.0)})
    setup = SweepSetup(base, iso, variants.keys)
    serial = dict(row for batch in run_sweep(setup, variants, workers=1, batch_size=3) for row in batch)
    assert len(serial) == len(variants)
    assert {r["status"] for r in serial.values()} >= {"ok", "cannot_assemble", "out_of_workspace"}
    # One worker process here (each costs seconds of imports): the rows still cross a process boundary; the
    # default path below shares the batches between two.
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        seen = []
        remote = dict(
            row
            for batch in run_sweep(
                setup,
                variants,
                scheduler=cluster.scheduler_address,
                batch_size=3,
                progress=lambda n, t: seen.append((n, t)),
            )
            for row in batch
        )
    assert remote.keys() == serial.keys()
    assert all(rows_equal(remote[k], serial[k]) for k in serial)
    assert seen[-1] == (len(variants), len(variants))
    # The default path: a local cluster of its own, two worker processes.
    local = dict(row for batch in run_sweep(setup, variants, workers=2) for row in batch)
    assert local.keys() == serial.keys() and all(rows_equal(local[k], serial[k]) for k in serial)


def test_without_dask_the_sweep_says_how_to_install_it(base, iso, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed now raises ImportError
    variants = v.grid({"lever.length_mm": (320.0, 330.0, 10.0)})
    with pytest.raises(MissingDependencyError, match=r"pip install -U 'hipsim\[sweep\]'"):
        list(run_sweep(SweepSetup(base, iso, variants.keys), variants, workers=2))
    # One worker runs in this process and needs no dask.
    assert len([r for b in run_sweep(SweepSetup(base, iso, variants.keys), variants, workers=1) for r in b]) == 2


def test_batches_cover_every_chosen_variant_once(base, iso):
    variants = v.grid({"lever.length_mm": (300.0, 360.0, 5.0)})
    setup = SweepSetup(base, iso, variants.keys)
    rows = dict(
        row for batch in run_sweep(setup, variants, indices=[0, 5, 12], workers=1, batch_size=2) for row in batch
    )
    assert sorted(rows) == [0, 5, 12]
    assert rows_equal(rows[5], dict(evaluate_batch((np.array([5]), variants.values[[5]]), setup))[5])


# ---------------------------------------------------------------------------
# Pareto front, output files


def test_pareto_front_of_a_hand_made_set():
    points = np.array([[1.0, 5.0], [2.0, 3.0], [3.0, 4.0], [4.0, 1.0], [np.nan, 0.0], [2.0, 3.0]])
    assert pareto_front(points, (False, False)).tolist() == [True, True, False, True, False, True]
    # Larger y better: (1, 5) is both the smallest x and the largest y.
    assert pareto_front(points, (False, True)).tolist() == [True, False, False, False, False, False]
    assert parse_objective("-cond_inv_min", metric_columns()) == ("cond_inv_min", True)
    with pytest.raises(ArgumentError, match="numeric column"):
        parse_objective("status", metric_columns())


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_the_table_reads_back_to_the_same_bits(tmp_path, suffix):
    columns: dict[str, list] = {
        "lever.length_mm": [330.0, 0.1 + 0.2],
        "status": ["ok", "cannot_assemble"],
        "reason": ["", "a, b"],
        "cond_inv_min": [1 / 3, math.nan],
    }
    path = write_table(tmp_path / f"t{suffix}", columns, {"model": "analytic"})
    back = read_table(path)
    assert list(back) == list(columns)
    assert back["lever.length_mm"] == columns["lever.length_mm"] and back["reason"] == columns["reason"]
    assert back["cond_inv_min"][0] == 1 / 3 and math.isnan(back["cond_inv_min"][1])


# ---------------------------------------------------------------------------
# The command line


def sweep(tmp_path, capsys, *options):
    code = main(["sweep", "--rate", str(RATE), "--workers", "1", "--summary-format", "json", *options])
    captured = capsys.readouterr()
    return code, (json.loads(captured.out) if code != 2 else None), captured.err


def test_a_rerun_skips_the_variants_already_in_the_output(tmp_path, capsys):
    out = tmp_path / "s.parquet"
    code, first, _ = sweep(tmp_path, capsys, "--grid", "lever.length_mm=320:340:10", "--out", str(out))
    assert code == 0 and (first["new"], first["skipped"], first["rows"]) == (3, 0, 3)
    before = read_table(out)
    # A wider grid: 310 and 350 are new; 320, 330, 340 were run (written 320.0 …; given as 3.2e2 here).
    code, second, _ = sweep(
        tmp_path,
        capsys,
        "--grid",
        "lever.length_mm=310:350:10",
        "--out",
        str(out),
        "--pareto",
        "tau_peak_max_Nmm,-cond_inv_min",
    )
    assert code == 0 and (second["new"], second["skipped"], second["rows"]) == (2, 3, 5)
    after = read_table(out)
    assert after["lever.length_mm"] == [320.0, 330.0, 340.0, 310.0, 350.0]
    assert after["tau_peak_max_Nmm"][:3] == before["tau_peak_max_Nmm"]
    assert (tmp_path / "s_pareto.png").stat().st_size > 0 and (tmp_path / "s_pareto.svg").exists()
    assert second["best"]["tau_peak_max_Nmm"]["value"] == min(after["tau_peak_max_Nmm"])
    assert len(second["pareto_front"]) >= 1 and second["figure"][0].endswith("s_pareto.png")
    jsonschema.Draft202012Validator(schema("sweep")).validate(second)
    code, third, _ = sweep(tmp_path, capsys, "--grid", "lever.length_mm=310:350:10", "--out", str(out))
    assert (third["new"], third["skipped"]) == (0, 5)


def test_an_output_of_another_sweep_is_not_mixed_in(tmp_path, capsys):
    out = tmp_path / "s.csv"
    assert sweep(tmp_path, capsys, "--grid", "lever.length_mm=320:330:10", "--out", str(out))[0] == 0
    code, _, err = sweep(tmp_path, capsys, "--grid", "slider.mass_kg=3:4:1", "--out", str(out))
    assert code == 2 and "other columns" in err


def test_exit_status_says_whether_any_variant_passes_the_rating(tmp_path, capsys):
    grid = ("--grid", "lever.length_mm=320:330:10")
    code, summary, err = sweep(
        tmp_path, capsys, *grid, "--set", "motor.peak_torque_Nmm=100", "--out", str(tmp_path / "a.csv")
    )
    assert code == 1 and summary["fail"] == 2 and "no variant passes the rating" in err
    assert summary["verdict"]["level"] == "NOT FEASIBLE" and "pareto_front" not in summary
    jsonschema.Draft202012Validator(schema("sweep")).validate(summary)
    code, summary, _ = sweep(
        tmp_path, capsys, *grid, "--set", "motor.peak_torque_Nmm=5000", "--out", str(tmp_path / "b.csv")
    )
    assert code == 0 and summary["pass"] == 2 and summary["best"]["margin"]["goal"] == "max"


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (("--grid", "lever.length_mm=300:360"), "--grid: expected KEY=START:STOP:STEP"),
        (("--grid", "lever.lenght_mm=300:360:5"), "did you mean"),
        (("--sample", "5"), "--sample needs either --range"),
        (("--range", "lever.length_mm=300:360"), "--range needs --sample"),
        (("--sample", "5", "--range", "lever.length_mm=360:300"), "--range lever.length_mm: expected LOW:HIGH"),
        (("--grid", "lever.length_mm=300:360:5", "--variants", "v.csv"), "choose one kind"),
        (("--pareto", "tau_peak_max_Nmm"), "--pareto: expected two columns"),
        (("--pareto", "tau_peak_max_Nmm,-cond_inv"), "--pareto: expected a numeric column"),
        (("--out", "results.txt"), "unknown suffix"),
    ],
)
def test_bad_input_is_one_line_and_status_2(tmp_path, capsys, options, message):
    code, _, err = sweep(tmp_path, capsys, *options)
    assert code == 2
    assert message in err and err.count("\n") == 1


def test_a_drive_that_names_its_screw_lead_refuses_a_sweep_of_the_lead(base, iso, tmp_path):
    from hipsim.machine.drive import load_drive

    path = tmp_path / "drive.toml"
    path.write_text("[motor]\npeak_torque_Nmm = 1000\n[lead_screw]\nlead_mm = 16\n")
    drive = load_drive(path)
    with pytest.raises(ArgumentError, match="screw.lead_mm"):
        SweepSetup(base, iso, (v.key_ref("screw.lead_mm"),), drive=drive)
    # The drive's lead is the machine's: a variant runs with it (faster screws, less torque than at 10 mm).
    setup = SweepSetup(base, iso, (v.key_ref("lever.length_mm"),), drive=drive)
    row, plain = evaluate(setup, [328.0]), evaluate(SweepSetup(base, iso, setup.keys), [328.0])
    assert row["speed_peak_1_rpm"] == pytest.approx(plain["speed_peak_1_rpm"] * 10 / 16, rel=1e-12)


def test_an_interrupted_sweep_keeps_what_is_done_and_a_rerun_resumes(tmp_path, capsys, monkeypatch):
    import hipsim.design.sweep as engine

    real = engine.run_sweep

    def interrupted(*args, **kwargs):
        for k, batch in enumerate(real(*args, **kwargs)):
            if k == 1:
                raise KeyboardInterrupt  # Ctrl-C after the first batch
            yield batch

    out = tmp_path / "s.csv"
    grid = ("--grid", "lever.length_mm=300:350:10", "--batch-size", "2", "--out", str(out))
    monkeypatch.setattr(engine, "run_sweep", interrupted)
    assert main(["sweep", "--rate", str(RATE), "--workers", "1", *grid]) == 130
    assert "rerun the same command to resume" in capsys.readouterr().err
    assert read_table(out)["lever.length_mm"] == [300.0, 310.0]
    monkeypatch.setattr(engine, "run_sweep", real)
    code, summary, _ = sweep(tmp_path, capsys, *grid)
    assert code == 0 and (summary["new"], summary["skipped"], summary["rows"]) == (4, 2, 6)


# ---------------------------------------------------------------------------
# Where to look next (issue 29): a best variant on the edge of the swept range (the summary's own logic:
# cli/test_sweep.py)


def test_the_sweep_says_its_best_variant_is_on_the_edge(tmp_path, capsys):
    """Heavier levers need more torque: the lightest lever of the grid is the best, on its lower edge."""
    out = tmp_path / "s.csv"
    assert (
        main(["sweep", "--rate", str(RATE), "--workers", "1", "--grid", "lever.mass_kg=0.5:1.5:0.5", "--out", str(out)])
        == 0
    )
    text = capsys.readouterr().out
    assert "tau_peak_max_Nmm" in text and "lies on the lower edge of lever.mass_kg (0.5, swept 0.5…1.5)" in text
    assert "lever.mass_kg=0.25:1.5:0.5" in text
    code, summary, _ = sweep(tmp_path, capsys, "--grid", "lever.mass_kg=0.5:1.5:0.5", "--out", str(out))
    assert code == 0 and summary["best"]["tau_peak_max_Nmm"]["edges"][0]["side"] == "lower"
    assert {"goal", "value", "row", "variant", "rating"} <= set(summary["best"]["tau_peak_max_Nmm"])
