"""Gait files as labs have them, at the command line: --cutoff and the noise warning, --load from a second file, OpenSim planar files."""

import json

import numpy as np
import pytest

from hipsim.cli.main import main
from hipsim.motion.trajectories import iso14242_angles, iso14242_load

RATE = 60.0


def write_csv(path, t, q, load=None):
    """hipsim's CSV columns, written out here (not by the code under test)."""
    with open(path, "w") as f:
        f.write("t_s,alpha_deg,beta_deg,gamma_deg" + (",Fe_N" if load is not None else "") + "\n")
        for k in range(t.size):
            a, b, g = np.degrees(q[k])
            f.write(f"{t[k]:.6f},{a:.6f},{b:.6f},{g:.6f}" + (f",{load[k]:.6f}" if load is not None else "") + "\n")
    return path


def iso_at(rate=RATE, cycles=5, noise_deg=0.0, seed=1):
    t = np.arange(int(cycles * rate)) / rate
    q, _, _ = iso14242_angles(t)
    q = q + np.radians(np.random.default_rng(seed).normal(0.0, noise_deg, q.shape))
    return t, q, iso14242_load(t)


def torques(capsys, *args):
    assert main(["torques", *args, "--summary-format", "json"]) == 0
    captured = capsys.readouterr()
    summary = json.loads(captured.out)
    return {i: (m["tau_peak_Nmm"], m["tau_rms_Nmm"]) for i, m in summary["motors"].items()}, captured.err


def test_cutoff_brings_a_noisy_60_hz_file_back_to_the_noise_free_torques(tmp_path, capsys):
    clean = write_csv(tmp_path / "clean.csv", *iso_at())
    noisy = write_csv(tmp_path / "noisy.csv", *iso_at(noise_deg=0.05))
    reference, err = torques(capsys, "--trajectory", str(clean), "--out", str(tmp_path / "a.csv"))
    assert "warning" not in err  # the noise-free file is not warned of
    raw, err = torques(capsys, "--trajectory", str(noisy), "--out", str(tmp_path / "b.csv"))
    assert err.count("hipsim: warning:") == 1 and "--cutoff 6" in err and "60 Hz" in err
    assert max(raw[i][0] / reference[i][0] for i in raw) > 1.5  # unfiltered, the noise swamps the torques
    filtered, err = torques(capsys, "--trajectory", str(noisy), "--cutoff", "6", "--out", str(tmp_path / "c.csv"))
    assert "warning" not in err
    for i in reference:
        for got, want in zip(filtered[i], reference[i]):
            assert got == pytest.approx(want, rel=0.02), (i, got, want)


@pytest.mark.parametrize(
    ("cutoff", "message"),
    [
        ("-1", "--cutoff -1 Hz: zero-phase low-pass cutoff must be above 0"),
        ("30.5", "the low-pass cutoff 30.5 Hz is not below the Nyquist frequency 30 Hz"),
        ("45", "the low-pass cutoff 45 Hz is not below the Nyquist frequency 30 Hz"),
    ],
)
def test_bad_cutoffs_are_one_line(tmp_path, capsys, cutoff, message):
    path = write_csv(tmp_path / "clean.csv", *iso_at())
    out = tmp_path / "o.csv"
    assert main(["torques", "--trajectory", str(path), "--cutoff", cutoff, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("hipsim: error:") and message in err and "\n" not in err
    assert not out.exists()


def test_cutoff_applies_to_files_only(capsys):
    assert main(["torques", "--cutoff", "6", "--out", "-"]) == 2
    assert "--cutoff applies to a --trajectory file" in capsys.readouterr().err


def write_sto(path, t, columns):
    lines = [
        "JointReaction",
        "version=1",
        f"nRows={t.size}",
        f"nColumns={len(columns) + 1}",
        "inDegrees=no",
        "endheader",
        "\t".join(["time", *columns]),
    ]
    lines += ["\t".join(f"{v:.9g}" for v in (t[k], *(c[k] for c in columns.values()))) for k in range(t.size)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_a_load_file_shifted_and_sampled_otherwise_gives_the_merged_files_torques(tmp_path, capsys):
    t, q, load = iso_at(rate=200.0, cycles=2)
    merged = write_csv(tmp_path / "merged.csv", t, q, load)
    motion = write_csv(tmp_path / "motion.csv", t, q)
    # The load at 1 kHz from 0.5 s before the motion to 0.5 s after, as a JointReaction resultant of three components.
    tl = np.arange(-500, 2501) / 1000.0
    fl = iso14242_load(tl)
    direction = np.array([0.3, -0.9, 0.2]) / np.linalg.norm([0.3, -0.9, 0.2])
    sto = write_sto(
        tmp_path / "jr.sto", tl, {f"hip_r_on_pelvis_in_pelvis_f{a}": fl * d for a, d in zip("xyz", direction)}
    )
    reference, _ = torques(capsys, "--trajectory", str(merged), "--out", str(tmp_path / "a.csv"))
    got, err = torques(
        capsys,
        "--trajectory",
        str(motion),
        "--load",
        str(sto),
        "--load-column",
        "hip_r_on_pelvis_in_pelvis",
        "--out",
        str(tmp_path / "b.csv"),
    )
    assert "warning" not in err
    for i in reference:
        for a, b in zip(got[i], reference[i]):
            assert a == pytest.approx(b, rel=2e-3)
    # The same load as a CSV column, scaled: half of it, times 2.
    csv = tmp_path / "load.csv"
    csv.write_text("time,F\n" + "".join(f"{a:.6f},{b / 2:.6f}\n" for a, b in zip(tl, fl)))
    got, _ = torques(
        capsys,
        "--trajectory",
        str(motion),
        "--load",
        str(csv),
        "--load-column",
        "F",
        "--load-scale",
        "2",
        "--out",
        str(tmp_path / "c.csv"),
    )
    for i in reference:
        assert got[i][0] == pytest.approx(reference[i][0], rel=2e-3)


def test_a_load_file_covering_part_of_the_motion_cuts_it_with_a_warning(tmp_path, capsys):
    t, q, load = iso_at(rate=200.0, cycles=2)
    motion = write_csv(tmp_path / "motion.csv", t, q)
    tl = np.arange(0, 901) / 1000.0  # 0 to 0.9 s: 181 of the motion's samples
    csv = tmp_path / "load.csv"
    csv.write_text("t_s,F\n" + "".join(f"{a:.6f},{b:.6f}\n" for a, b in zip(tl, iso14242_load(tl))))
    assert (
        main(
            [
                "torques",
                "--trajectory",
                str(motion),
                "--load",
                str(csv),
                "--load-column",
                "F",
                "--out",
                str(tmp_path / "o.csv"),
            ]
        )
        == 0
    )
    err = capsys.readouterr().err
    assert "motion samples outside the overlap left out" in err
    assert sum(1 for _ in open(tmp_path / "o.csv")) - 1 == 181


@pytest.mark.parametrize(
    ("case", "message"),
    [
        ("no overlap", "no overlapping time: the motion"),
        (
            "missing column",
            "no load column 'hip_r_on_pelvis_in_pelvi' (nor 'hip_r_on_pelvis_in_pelvi_fx', '_fy', '_fz' for a resultant); did you mean 'hip_r_on_pelvis_in_pelvis'?",
        ),
        ("gap", "a gap in the load from"),
    ],
)
def test_bad_load_files_are_one_line(tmp_path, capsys, case, message):
    t, q, _ = iso_at(rate=200.0, cycles=2)
    motion = write_csv(tmp_path / "motion.csv", t, q)
    tl = np.arange(0, 2001) / 1000.0 + (10.0 if case == "no overlap" else 0.0)
    if case == "gap":
        tl = np.concatenate([tl[:500], tl[900:]])
    fl = iso14242_load(tl)
    sto = write_sto(tmp_path / "jr.sto", tl, {f"hip_r_on_pelvis_in_pelvis_f{a}": fl / np.sqrt(3) for a in "xyz"})
    column = "hip_r_on_pelvis_in_pelvi" if case == "missing column" else "hip_r_on_pelvis_in_pelvis"
    out = tmp_path / "o.csv"
    assert (
        main(["torques", "--trajectory", str(motion), "--load", str(sto), "--load-column", column, "--out", str(out)])
        == 2
    )
    err = capsys.readouterr().err.strip()
    assert err.startswith("hipsim: error:") and message in err and "\n" not in err, err
    assert not out.exists()


def test_a_planar_opensim_file_reads_with_zero_columns(tmp_path, capsys):
    t = np.arange(0, 101) / 100.0
    flexion = 20.0 * np.cos(2 * np.pi * t)
    lines = [
        "Coordinates",
        "version=1",
        "nRows=250",
        "nColumns=3",
        "inDegrees=yes",
        "endheader",
        "time\thip_flexion_r\tknee_angle_r",
    ]
    lines += [f"{a:.6f}\t{b:.6f}\t10" for a, b in zip(t, flexion)]
    path = tmp_path / "planar.mot"
    path.write_text("\n".join(lines) + "\n")
    assert main(["torques", "--trajectory", str(path), "--out", str(tmp_path / "o.csv")]) == 2
    assert (
        "a planar model? read it with --columns time=time,flexion=hip_flexion_r,adduction=zero,rotation=zero"
        in capsys.readouterr().err
    )
    assert (
        main(
            [
                "torques",
                "--trajectory",
                str(path),
                "--columns",
                "time=time,flexion=hip_flexion_r,adduction=zero,rotation=zero",
                "--out",
                str(tmp_path / "o.csv"),
            ]
        )
        == 0
    )
    err = capsys.readouterr().err
    assert "the header says 250 rows, the file has 101: the rows are read" in err
    rows = np.loadtxt(tmp_path / "o.csv", delimiter=",", skiprows=1, usecols=(1, 2, 3))
    assert np.allclose(rows[:, 0], flexion[:-1], atol=1e-6) and np.allclose(rows[:, 1:], 0.0, atol=1e-9)
