"""A sweep's output is keyed by its set-up: a rerun of another set-up into the same file is refused, the same set-up resumes."""

import json

import pytest
from support import given

from hipsim.cli.main import main
from hipsim.design.sweep_table import CSV_METADATA, read_metadata, read_table, write_table

RATE = 100.0
GRID = ("--grid", "lever.length_mm=320:330:10")


def sweep(capsys, *options):
    code = main(["sweep", "--workers", "1", "--summary-format", "json", *options])
    captured = capsys.readouterr()
    return code, (json.loads(captured.out) if code != 2 else None), captured.err


@pytest.fixture(scope="module", params=[".csv", ".parquet"])
def first(request, tmp_path_factory):
    """A first sweep's file (written once per format), copied by each test."""
    folder = tmp_path_factory.mktemp("first")
    out = folder / f"s{request.param}"
    assert (
        main(["sweep", "--workers", "1", "--summary-format", "json", "--rate", str(RATE), *GRID, "--out", str(out)])
        == 0
    )
    return out


@pytest.fixture
def out(first, tmp_path, capsys):
    capsys.readouterr()
    copy = tmp_path / first.name
    copy.write_bytes(first.read_bytes())
    return copy


def test_the_file_records_the_set_up_fingerprint(out):
    metadata = given(read_metadata(out))
    fingerprints = metadata["fingerprints"]
    assert set(fingerprints) == {"parameters", "trajectory", "model", "drive", "cycles", "keys", "setup"}
    assert all(len(value) == 64 for value in fingerprints.values())
    if out.suffix == ".csv":
        assert out.read_text().startswith(CSV_METADATA)


def test_the_same_set_up_resumes(out, capsys):
    code, summary, _ = sweep(capsys, "--rate", str(RATE), "--grid", "lever.length_mm=320:340:10", "--out", str(out))
    assert code == 0 and (summary["new"], summary["skipped"], summary["rows"]) == (1, 2, 3)
    assert summary["fingerprints"]["setup"] == given(read_metadata(out))["fingerprints"]["setup"]


@pytest.mark.parametrize(
    ("options", "what"),
    [
        (("--rate", "200"), "the trajectory"),
        (("--rate", str(RATE), "--set", "slider.mass_kg=3.5"), "the machine (--params, --set) differs"),
        (
            ("--rate", str(RATE), "--cycles", "2"),
            "the trajectory (--trajectory, --rate, --cycles, --frequency …), the test cycles (--cycles) differ",
        ),
        (("--rate", str(RATE), "--engine", "pinocchio"), "holds other columns"),
        (("--rate", str(RATE), "--set", "motor.peak_torque_Nmm=500"), "the machine"),
    ],
)
def test_another_set_up_into_the_same_file_is_refused_and_nothing_written(out, capsys, options, what):
    before = out.read_bytes()
    code, _, err = sweep(capsys, *options, *GRID, "--out", str(out))
    assert code == 2 and err.count("\n") == 1
    assert what in err and "give another --out, or --restart to replace it" in err
    assert out.read_bytes() == before


def test_restart_replaces_the_file_with_the_new_set_up(out, capsys):
    code, summary, _ = sweep(capsys, "--rate", "200", *GRID, "--out", str(out), "--restart")
    assert code == 0 and (summary["new"], summary["skipped"], summary["rows"]) == (2, 0, 2)
    assert given(read_metadata(out))["fingerprints"]["setup"] == summary["fingerprints"]["setup"]
    assert sweep(capsys, "--rate", "200", *GRID, "--out", str(out))[1]["skipped"] == 2  # and now resumes


def test_a_file_that_records_no_set_up_is_refused(out, capsys):
    write_table(out, read_table(out))  # the same rows, without the description (another program's file)
    assert "fingerprints" not in (read_metadata(out) or {})
    code, _, err = sweep(capsys, "--rate", str(RATE), *GRID, "--out", str(out))
    assert code == 2 and "records no set-up" in err and "--restart" in err


def test_the_same_values_by_another_route_are_the_same_set_up(out, capsys):
    """--set of the machine's own value changes nothing that determines a row: it resumes."""
    code, summary, _ = sweep(capsys, "--rate", str(RATE), "--set", "slider.mass_kg=3", *GRID, "--out", str(out))
    assert code == 0 and summary["skipped"] == 2


def test_sample_without_range_or_tolerance_says_what_is_missing_not_both(tmp_path, capsys):
    code, _, err = sweep(capsys, "--sample", "5", "--out", str(tmp_path / "s.csv"))
    assert code == 2 and "--sample needs either --range" in err and "not both" not in err
    code, _, err = sweep(
        capsys,
        "--sample",
        "5",
        "--range",
        "lever.length_mm=300:360",
        "--spread",
        "lever.length_mm=0.1",
        "--out",
        str(tmp_path / "s.csv"),
    )
    assert code == 2 and "not both" in err


def test_a_nul_byte_or_a_terminal_escape_in_a_file_is_printed_escaped(tmp_path, capsys):
    variants = tmp_path / "v.csv"
    variants.write_bytes(b"lever.length_mm\n330\n3\x001\x1b[31m\n")
    code, _, err = sweep(capsys, "--variants", str(variants), "--out", str(tmp_path / "s.csv"))
    assert code == 2 and err.count("\n") == 1
    assert "\x00" not in err and "\x1b" not in err and "got '3\\x001\\x1b[31m'" in err
