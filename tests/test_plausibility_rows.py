"""Issue 38, row by row: every command checks what it reads, says what it did not check, and never rounds into a failure.

Each test is one row of the issue's table (the slip a busy lab makes, written
by the test from the ISO cycle by another route than the reader), plus the
shared layer's laws (:mod:`hipsim.plausibility`) pinned by hand-computed values.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from monitor_synthetic import write_snapshot
from support import given
from trajectory_files import csv_text

import hipsim
from hipsim.cli.main import main
from hipsim.design.feasibility import Limits, check_feasibility
from hipsim.motion.load_file import LoadScale
from hipsim.motion.trajectories import Trajectory, iso14242_angles, iso14242_load
from hipsim.plausibility import (
    below,
    beyond,
    drive_slip,
    epoch_warning,
    load_slip,
    radians_slip,
    time_slip,
    unit_slip,
)

DOCS = Path(__file__).resolve().parents[1] / "docs"
MODELS = Path(hipsim.__file__).resolve().parent.parent / "models"
EPOCH = 1_732_700_000.0  # 27 November 2024, 09:33:20 UTC


def iso_file(path: Path, rate=100.0, cycles=1.0, t_scale=1.0, t_offset=0.0, load_scale=1.0, load=True, fmt=repr):
    """The ISO cycle as hipsim's CSV: times × t_scale + t_offset, load × load_scale (None: no load column)."""
    t = np.arange(int(round(rate * cycles))) / rate
    q, _, _ = iso14242_angles(t)
    path.write_text(
        csv_text(t * t_scale + t_offset, q, iso14242_load(t) * load_scale if load else None, fmt=fmt), encoding="utf-8"
    )
    return path


def one_line_error(capsys, *words) -> str:
    err = capsys.readouterr().err
    assert err.startswith("hipsim: error: ") and err.count("\n") == 1, err
    for word in words:
        assert word in err, (word, err)
    return err


def warnings_of(err: str) -> list[str]:
    return [line for line in err.splitlines() if line.startswith("hipsim: warning:")]


# --- The shared layer's laws ------------------------------------------------------------------------------------------


def test_beyond_and_below_allow_a_relative_1e_9():
    assert not beyond(3000.0000000000005, 3000.0)  # --load-scale 300:3000's old peak: 1.5e-16 relative
    assert not beyond(3000.0 * (1 + 0.9e-9), 3000.0)
    assert beyond(3000.0 * (1 + 1.1e-9), 3000.0)
    assert beyond(3000.0001, 3000.0)  # 3.3e-8 relative: beyond
    assert not below(0.05 * (1 - 0.9e-9), 0.05) and below(0.05 * (1 - 1.1e-9), 0.05)
    np.testing.assert_array_equal(beyond(np.array([1.0, 1.0 + 2e-9, 2.0]), 1.0), [False, True, True])


def test_unit_slips_by_hand():
    assert unit_slip(1910.0, 0.01, 300.0) == 1e3  # 1910 "N·m": 1.91 N·m
    assert unit_slip(0.00191, 0.01, 300.0) == 1e-3
    assert unit_slip(5.0, 0.01, 300.0) is None and unit_slip(1e9, 0.01, 300.0) is None
    # A 1 s gait at 100 Hz in ms read as s: a step of 10 s over 990 s.
    t = np.arange(100) * 10.0
    assert "milliseconds" in given(time_slip(t, "s")) and time_slip(t / 1000, "s") is None
    # The same gait in s read as ms: 0.99 ms.
    assert "seconds" in given(time_slip(np.arange(100) * 1e-5, "ms")) and time_slip(np.arange(100) * 1e-2, "ms") is None
    # A 1 kHz log of an hour in s is plausible (a step of 1 ms).
    assert time_slip(np.arange(0, 3600, 1e-3)[:5000], "s") is None
    assert given(epoch_warning(EPOCH)).startswith("the times are Unix time stamps (from 2024-11-27 09:33:20 UTC)")
    assert epoch_warning(1500.0) is None
    assert "kN" in given(load_slip(3.0)[0]) and load_slip(3000.0) == (None, None)
    assert load_slip(50.0)[1] is not None and load_slip(9000.0)[1] is not None
    assert "1000 times" in given(load_slip(3e6, "kN")[0])
    # The ISO cycle's angle ranges (43°, 11°, 12°) written in radians: 0.75, 0.19, 0.21 "degrees".
    k, as_degrees = given(radians_slip(np.radians([43.0, 11.0, 12.0])))
    assert k == 0 and as_degrees == pytest.approx(43.0)
    assert radians_slip(np.array([43.0, 11.0, 12.0])) is None
    assert radians_slip(np.radians([2.0, 1.0, 1.0])) is None  # 2° as radians: no gait's range either
    assert (
        "1000 times" in given(drive_slip("peak_torque", [1910.0, 900.0], "Nm"))
        and drive_slip("peak_torque", [1.91], "Nm") is None
    )
    assert given(drive_slip("lead", 1e-5, "mm", 1e-3)).startswith("0.01 mm is 1/1000 of")


# --- Row: one snapshot of nine with torques in N·m, through the monitor ----------------------------------------------


def test_a_snapshot_in_newton_metres_is_an_error_the_monitor_names(tmp_path):
    from hipsim.rig.monitoring.monitor_fit import MonitorSetup, estimate_batch
    from hipsim.rig.monitoring.snapshots import Skipped, find_snapshots

    params = hipsim.load_parameters()
    rng = np.random.default_rng(3)
    write_snapshot(tmp_path / "a_good.csv", params, 0.1, 0, rng)
    bad = write_snapshot(tmp_path / "b_nm.csv", params, 0.1, 1000, rng)
    lines = bad.read_text().splitlines()
    names = lines[0].split(",")
    columns = [names.index(f"tau_{i}_Nmm") for i in (1, 2, 3)]
    out = [lines[0]]
    for line in lines[1:]:
        cells = line.split(",")
        for c in columns:
            cells[c] = repr(float(cells[c]) / 1e3)  # N·m under _Nmm
        out.append(",".join(cells))
    bad.write_text("\n".join(out) + "\n")
    snapshots, _ = find_snapshots(tmp_path)
    results = estimate_batch(snapshots, MonitorSetup(params))
    assert isinstance(results[0], dict) and isinstance(results[1], Skipped), results
    reason = results[1].reason
    assert "b_nm" in reason and "like N·m" in reason and "1/1000" in reason


# --- Row: a drive file with a data sheet's N·mm under _Nm keys, through size and feasible ----------------------------


@pytest.mark.parametrize("command", ["size", "feasible"])
def test_a_drive_in_newton_millimetres_under_nm_keys_is_refused(command, tmp_path, capsys):
    text = (MODELS / "drive_example.toml").read_text(encoding="utf-8")
    drive = tmp_path / "nmm.toml"
    drive.write_text(text.replace("s1_torque_Nmm", "s1_torque_Nm").replace("peak_torque_Nmm", "peak_torque_Nm"))
    assert main([command, "--drive", str(drive)]) == 2
    one_line_error(capsys, "nmm.toml", "motor.s1_torque_Nm", "640 Nm is 1000 times")


# --- Rows: milliseconds under t_s, seconds under :ms, a load in kN under Fe_N -----------------------------------------


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("rows")
    return {
        "ms": iso_file(folder / "ms.csv", t_scale=1e3),
        "kn": iso_file(folder / "kn.csv", load_scale=1e-3),
        "s": iso_file(folder / "s.csv"),
        "s1k": iso_file(folder / "s1k.csv", rate=1000.0),
        "epoch": iso_file(folder / "epoch.csv", rate=1000.0, t_offset=EPOCH, fmt=lambda v: f"{v:.17g}"),
        "noload": iso_file(folder / "noload.csv", load=False),
        "three": iso_file(folder / "three.csv", cycles=3.0),
        "half": iso_file(folder / "half.csv", cycles=0.5),
    }


@pytest.mark.parametrize(
    ("command", "output"),
    [("torques", ["--out", "{dir}/t.csv"]), ("feasible", []), ("view", ["--html", "{dir}/v.html"])],
)
def test_milliseconds_under_t_s_are_refused_and_nothing_is_written(command, output, files, tmp_path, capsys):
    args = [a.format(dir=tmp_path) for a in output]
    assert main([command, "--trajectory", str(files["ms"]), *args]) == 2
    one_line_error(capsys, "ms.csv", "column 't_s'", "look like milliseconds", "10 s over 990 s")
    assert list(tmp_path.iterdir()) == []


def test_seconds_under_ms_are_refused(files, tmp_path, capsys):
    columns = "time=t_s:ms,alpha=alpha_deg,beta=beta_deg,gamma=gamma_deg,load=Fe_N"
    assert (
        main(["torques", "--trajectory", str(files["s"]), "--columns", columns, "--out", str(tmp_path / "t.csv")]) == 2
    )
    one_line_error(capsys, "look like seconds", "0.99 ms")
    assert not (tmp_path / "t.csv").exists()


def test_a_load_in_kilonewtons_under_fe_n_is_refused(files, tmp_path, capsys):
    assert main(["torques", "--trajectory", str(files["kn"]), "--out", str(tmp_path / "t.csv")]) == 2
    one_line_error(capsys, "column 'Fe_N'", "looks like kN", "peak is 3 N")
    assert not (tmp_path / "t.csv").exists()


# --- Row: Unix-epoch time stamps --------------------------------------------------------------------------------------


def test_epoch_time_stamps_are_read_relative_with_every_digit(files, tmp_path, capsys):
    import pandas as pd

    assert main(["torques", "--trajectory", str(files["s1k"]), "--out", str(tmp_path / "s.csv")]) == 0
    assert main(["torques", "--trajectory", str(files["epoch"]), "--out", str(tmp_path / "e.csv")]) == 0
    err = capsys.readouterr().err
    assert "the times are Unix time stamps (from 2024-11-27 09:33:20 UTC): read relative to the first" in err
    plain, stamped = (pd.read_csv(tmp_path / name, comment="#") for name in ("s.csv", "e.csv"))
    assert stamped["t_s"].nunique() == len(stamped) == 1000  # was 101 distinct times
    np.testing.assert_allclose(stamped["t_s"], plain["t_s"], rtol=0, atol=1e-6)
    # The stamps hold 2.4e-7 s of float rounding: the torques agree to a thousandth of a N·mm (were 10.5 N·mm off).
    assert np.abs(stamped["tau_1_Nmm"] - plain["tau_1_Nmm"]).max() < 1e-3


# --- Row: rig torques doubled by a 2:1 belt, through identify ---------------------------------------------------------


@pytest.fixture(scope="module")
def belt_identified(tmp_path_factory):
    """A log of the published machine with its torques doubled (a 2:1 belt), identified: (stderr, the file)."""
    folder = tmp_path_factory.mktemp("belt")
    run = hipsim.analyse(hipsim.load_parameters(), hipsim.iso14242(rate=250, cycles=3))
    traj = run.trajectory
    header = "t_s,Fe_N,alpha_deg,beta_deg,gamma_deg,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm"
    values = np.column_stack([traj.t, traj.Fe, np.degrees(traj.q), 2e3 * run.torques.total])
    (folder / "belt.csv").write_text(
        header + "\n" + "\n".join(",".join(f"{v:.9g}" for v in row) for row in values) + "\n"
    )
    from io import StringIO

    old, sys.stderr = sys.stderr, StringIO()
    try:
        code = main(["identify", "--log", str(folder / "belt.csv"), "--out", str(folder / "belt.toml")])
        err = sys.stderr.getvalue()
    finally:
        sys.stderr = old
    assert code == 0, err
    return err, folder / "belt.toml"


def test_a_belt_is_named_by_the_log_check_and_by_the_priors(belt_identified):
    err, path = belt_identified
    lines = warnings_of(err)
    assert any("all three 2" in line and "a constant factor of 2" in line for line in lines), err
    far = [line for line in lines if "prior standard deviations, all up" in line]
    assert len(far) == 1 and "transmission ratio" in far[0] and "m_L +" in far[0], err
    assert path.exists()  # a warning: the file is written


def test_far_from_priors_by_hand():
    from types import SimpleNamespace as E

    from hipsim.rig.plausibility import far_from_priors

    def est(name, shift, determined=True):
        return E(name=name, shift=shift, determined=determined)

    assert far_from_priors([est("a", 3.5), est("b", 4.0), est("c", 0.2)])[0].startswith(
        "2 of 3 base parameters moved more than 3 prior standard deviations, all up (b +4, a +3.5)"
    )
    assert far_from_priors([est("a", 3.5), est("b", -4.0)]) == []  # two ways: the machine's own spread
    assert far_from_priors([est("a", 3.5), est("b", 2.9)]) == []  # one alone
    assert far_from_priors([est("a", -3.5), est("b", -5.0, determined=False)]) == []  # a prior-held one does not count


# --- Row: feasible on the published machine says what it did not check -------------------------------------------------


def test_feasible_without_drive_data_covers_only_what_it_checked(capsys):
    assert main(["feasible", "--frequency", "2.5", "--summary-format", "json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["feasible"] is None and summary["crossings"] == []
    assert summary["not_checked"] == ["stroke", "motor speed", "motor torque"]
    assert "within every machine limit" not in summary["verdict"] and "give --drive" in summary["verdict"]
    assert main(["feasible", "--drive", str(MODELS / "drive_example.toml")]) == 0
    out = capsys.readouterr().out
    assert "within every machine limit (stroke, motor speed, motor torque, singularity measure, load range)" in out
    assert "give --drive" not in out


def test_a_drive_without_a_stroke_names_it_unchecked_without_asking_for_drive(tmp_path, capsys):
    drive = tmp_path / "no_stroke.toml"
    text = (MODELS / "drive_example.toml").read_text(encoding="utf-8")
    drive.write_text("\n".join(line for line in text.splitlines() if not line.startswith("stroke_mm")) + "\n")
    assert main(["feasible", "--drive", str(drive)]) == 0
    out = capsys.readouterr().out
    assert "not checked: stroke (not in the drive file or the parameter file's [motor] table)" in out, out
    assert "give --drive" not in out


# --- Row: --load-scale 300:3000, and the docs' gait example ----------------------------------------------------------


def test_a_load_mapped_onto_its_range_lands_exactly_on_it():
    raw = np.array([0.5, 3.0, 1.7, 4.1, 2.2]) * 736.0  # a contact force in N, any level
    mapped = LoadScale(1.0, 300.0, 3000.0).apply(raw)
    assert mapped.max() == 3000.0 and mapped.min() == 300.0
    np.testing.assert_allclose(mapped, 300.0 + (raw - raw.min()) * 2700.0 / np.ptp(raw), rtol=1e-14)


def test_load_scale_onto_the_machine_s_range_fits(tmp_path, capsys):
    t = np.arange(101) / 100.0
    q, _, _ = iso14242_angles(t)
    motion = tmp_path / "walk.csv"
    motion.write_text(csv_text(t, q))
    # A JointReaction resultant in body weights (×2.37 and offset: the mapping must not care).
    fl = 2.37 * iso14242_load(t) + 55.0
    direction = np.array([0.3, -0.9, 0.2]) / np.linalg.norm([0.3, -0.9, 0.2])
    rows = ["JointReaction", "version=1", f"nRows={t.size}", "nColumns=4", "inDegrees=no", "endheader"]
    rows.append("\t".join(["time", *(f"hip_r_on_pelvis_in_pelvis_f{a}" for a in "xyz")]))
    rows += ["\t".join(f"{v:.12g}" for v in (t[k], *(fl[k] * direction))) for k in range(t.size)]
    (tmp_path / "jr.sto").write_text("\n".join(rows) + "\n")
    args = ["--trajectory", str(motion), "--load", str(tmp_path / "jr.sto")]
    args += ["--load-column", "hip_r_on_pelvis_in_pelvis", "--load-scale", "300:3000"]
    assert main(["feasible", *args]) == 0
    out = capsys.readouterr().out
    assert "within the limits checked" in out and "does not fit" not in out, out


def test_the_docs_gait_example_prints_no_limit_warning(tmp_path, capsys):
    columns = (
        "time=Cycle [%]:%,flexion=Hip Flexion [deg],adduction=Hip Adduction [deg],"
        "rotation=Hip Int. Rotation [deg],load=F res [%BW]"
    )
    args = ["--trajectory", str(DOCS / "examples" / "gait_lab_export.csv"), "--period", "1", "--body-weight", "75"]
    assert main(["torques", *args, "--columns", columns, "--out", str(tmp_path / "t.csv")]) == 0
    err = capsys.readouterr().err
    assert "limit" not in err and "warning" not in err, err


def test_a_load_at_its_limit_within_rounding_is_not_a_crossing():
    params = hipsim.load_parameters()
    base = hipsim.iso14242(rate=100)

    def at(peak):
        Fe = base.Fe * (peak / base.Fe.max())
        return hipsim.analyse(params, Trajectory(base.t, base.q, base.qd, base.qdd, Fe, "at", base.periodic))

    limits = Limits()
    assert check_feasibility(at(3000.0 * (1 + 5e-10)), limits) == []
    crossing = check_feasibility(at(3000.0 * (1 + 1e-6)), limits)
    assert [c.limit for c in crossing] == ["load_max"]
    assert "needs a load of 3,000.003 N" in crossing[0].message() and "1e-06 beyond it" in crossing[0].message()


# --- Rows: no load; several strides or half of one under --frequency; noisy IK through feasible ------------------------


def test_a_file_without_load_says_what_the_iso_load_would_add(files, tmp_path, capsys):
    assert main(["torques", "--trajectory", str(files["noload"]), "--out", str(tmp_path / "t.csv")]) == 0
    lines = warnings_of(capsys.readouterr().err)
    assert any("no load column: F_e = 0 N" in line for line in lines), lines
    note = next(line for line in lines if "with ISO 14242-1's load" in line)
    bare_hi, iso_lo = (
        float(x)
        for x in (
            note.split("peak at ")[1].split(" N·mm")[0].split("–")[1],
            note.split("would peak at ")[1].split("–")[0],
        )
    )
    # The load's friction (μ_h·r_h·F_e ≈ 0.095 × 15 mm × 3000 N ≈ 4 N·m at the hip) dwarfs the unloaded machine's.
    assert iso_lo > 5 * bare_hi


def test_several_strides_or_half_of_one_under_frequency_are_warned_of(files, tmp_path, capsys):
    out = str(tmp_path / "t.csv")
    assert main(["torques", "--trajectory", str(files["three"]), "--frequency", "1", "--out", out]) == 0
    lines = warnings_of(capsys.readouterr().err)
    assert any("holds about 3 strides (one alpha cycle every 1 s of its time, over 2.99 s)" in x for x in lines), lines
    assert main(["torques", "--trajectory", str(files["half"]), "--frequency", "1", "--out", out]) == 0
    lines = warnings_of(capsys.readouterr().err)
    assert any("does not come back to its start" in x and "part of a stride" in x for x in lines), lines
    assert main(["torques", "--trajectory", str(files["s"]), "--frequency", "1", "--out", out]) == 0
    assert not [x for x in warnings_of(capsys.readouterr().err) if "stride" in x]


def test_feasibility_on_a_noisy_motion_says_so(tmp_path, capsys):
    t = np.arange(60) / 60.0  # raw 60 Hz inverse kinematics
    q, _, _ = iso14242_angles(t)
    q = q + np.random.default_rng(5).normal(0.0, math.radians(0.3), q.shape)
    path = tmp_path / "ik60.csv"
    path.write_text(csv_text(t, q, iso14242_load(t)))
    assert main(["feasible", "--trajectory", str(path), "--summary-format", "json"]) in (0, 1)
    summary = json.loads(capsys.readouterr().out)
    assert summary["noise_flagged"] is True and "the noise check flagged" in summary["verdict"]


# --- Rows: report and torques with an identified file -------------------------------------------------------------------


def test_torques_labels_its_band_as_the_model_s(belt_identified, tmp_path, capsys):
    _, identified = belt_identified
    assert main(["torques", "--params", str(identified), "--rate", "100", "--out", str(tmp_path / "t.csv")]) == 0
    out = capsys.readouterr().out
    assert "the model's 95 % band on the motor torques" in out and "not a band for measured torques" in out


def test_strict_writes_nothing_when_a_limit_is_crossed(tmp_path, capsys):
    out = tmp_path / "t.csv"
    assert main(["torques", "--set", "motor.max_speed_rpm=1000", "--strict", "--out", str(out)]) == 1
    assert capsys.readouterr().err.startswith("hipsim: error: the motion crosses")
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_the_guide_shows_the_verdict_feasible_prints(capsys):
    """docs/guide/gait-checks.md quotes the verdict on the published machine: it must be what the command prints."""
    page = (DOCS / "guide" / "gait-checks.md").read_text(encoding="utf-8")
    quoted = next(line for line in page.splitlines() if line.startswith("within the limits checked"))
    assert main(["feasible"]) == 0
    assert quoted in capsys.readouterr().out.splitlines()


# --- The smaller points ---------------------------------------------------------------------------------------------


def test_excel_s_sep_line_is_read(files, tmp_path):
    plain = hipsim.read_trajectory(files["s"])
    text = files["s"].read_text(encoding="utf-8").replace(",", ";")
    lines = text.splitlines()
    excel = tmp_path / "excel.csv"
    excel.write_text("sep=;\n" + "\n".join(line + ";" for line in lines) + "\n")  # and a trailing separator
    read = hipsim.read_trajectory(excel)
    np.testing.assert_array_equal(read.q, plain.q)
    np.testing.assert_array_equal(read.Fe, plain.Fe)


def test_a_sweep_to_a_folder_it_cannot_write_is_refused_before_the_variants(capsys):
    # /proc takes no new files, even for root (whom permission bits let write anywhere).
    assert main(["sweep", "--grid", "lever.length_mm=300:340:3", "--out", "/proc/hipsim_sweep.parquet"]) == 2
    one_line_error(capsys, "cannot write in folder '/proc'")


def test_iso_check_hashes_the_load_file(tmp_path, capsys):
    import hashlib

    t = np.arange(101) / 100.0
    q, _, _ = iso14242_angles(t)
    motion = tmp_path / "walk.csv"
    motion.write_text(csv_text(t, q))
    load = tmp_path / "load.csv"
    load.write_text("time,F\n" + "".join(f"{x:.17g},{f:.17g}\n" for x, f in zip(t, iso14242_load(t))))
    args = ["iso-check", "--trajectory", str(motion), "--load", str(load), "--load-column", "F"]
    assert main([*args, "--out", str(tmp_path / "iso")]) in (0, 1)
    capsys.readouterr()
    document = json.loads((tmp_path / "iso" / "iso_check.json").read_text(encoding="utf-8"))
    digest = hashlib.sha256(load.read_bytes()).hexdigest()
    assert digest in json.dumps(document["provenance"]), document["provenance"]


def test_a_load_file_in_milliseconds_is_refused(tmp_path, capsys):
    t = np.arange(101) / 100.0
    q, _, _ = iso14242_angles(t)
    motion = tmp_path / "walk.csv"
    motion.write_text(csv_text(t, q))
    load = tmp_path / "load_ms.csv"
    load.write_text("time,F\n" + "".join(f"{1e3 * x:.17g},{f:.17g}\n" for x, f in zip(t, iso14242_load(t))))
    args = ["torques", "--trajectory", str(motion), "--load", str(load), "--load-column", "F"]
    assert main([*args, "--out", str(tmp_path / "t.csv")]) == 2
    one_line_error(capsys, "load_ms.csv, column 'time'", "look like milliseconds")
    assert not (tmp_path / "t.csv").exists()
