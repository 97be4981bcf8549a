"""hipsim.rig.identification.identified_file: one writer and one reader of identified files; identify reads each log once.

The logs are made by the analytic model along a Fourier motion, with noise: what
is tested here is the file and the reading, not the fit's accuracy (tests/test_identification*.py).
"""

from __future__ import annotations

import builtins
import hashlib
import io
import json
import re
from pathlib import Path
from typing import Any

import jsonschema
import numpy as np
import pytest
from support import given

import hipsim
from hipsim.analytic import inverse_dynamics, kinematics
from hipsim.cli.documents import schema
from hipsim.cli.main import main
from hipsim.exceptions import ParameterError
from hipsim.machine.parameters import file_values
from hipsim.present.provenance import parameter_origin
from hipsim.rig.identification.identified_file import (
    IDENTIFIED_MARK,
    FileProvenance,
    InputRecord,
    identified_toml,
    read_identified_file,
    write_identified_file,
)
from hipsim.rig.monitoring.monitor_fit import identified_file

PARAMS = hipsim.load_parameters()


def _write_log(path: Path, seconds: float, seed: int) -> Path:
    """A 1 kHz log of the analytic model along five harmonics of 0.5 Hz, torques and angles with noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(seconds * 1000)) / 1000.0
    w = 2 * np.pi * 0.5 * np.arange(1, 6)
    amplitude = np.radians(rng.uniform(1.0, 4.0, (5, 3))) / np.arange(1, 6)[:, None]
    phase = rng.uniform(0, 2 * np.pi, (5, 3))
    arg = w[None, :, None] * t[:, None, None] + phase
    q = np.sum(amplitude * np.sin(arg), axis=1)
    qd = np.sum(amplitude * w[:, None] * np.cos(arg), axis=1)
    qdd = -np.sum(amplitude * w[:, None] ** 2 * np.sin(arg), axis=1)
    load = 1650 + 1300 * np.sin(2 * np.pi * 0.5 * t)
    true = PARAMS.replace(screw_coulomb=0.04, screw_viscous=2e-4)
    tau = inverse_dynamics(true, kinematics(true, hipsim.Trajectory(t, q, qd, qdd, load)), load, True).total
    columns = np.column_stack(
        [t, load, tau * 1e3 + rng.normal(0, 3, tau.shape), np.degrees(q) + rng.normal(0, 0.003, q.shape)]
    )
    with open(path, "w") as stream:
        stream.write("t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,alpha_deg,beta_deg,gamma_deg\n")
        np.savetxt(stream, columns, delimiter=",", fmt="%.10g")
    return path


def _sha256(path: Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


class _CountingOpener:
    """Counts every opening of the watched files, through ``open`` and ``io.open`` (pathlib's) alike."""

    def __init__(self, monkeypatch, *paths: Path):
        self.counts = {Path(p).resolve(): 0 for p in paths}
        real = builtins.open

        def counting(file, *args, **kwargs):
            if isinstance(file, (str, Path)) and Path(file).resolve() in self.counts:
                self.counts[Path(file).resolve()] += 1
            return real(file, *args, **kwargs)

        monkeypatch.setattr(builtins, "open", counting)
        monkeypatch.setattr(io, "open", counting)

    def __getitem__(self, path) -> int:
        return self.counts[Path(path).resolve()]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """Two logs, and the file ``hipsim identify`` makes of them with levers without spin (the monitor's old trap)."""
    folder = tmp_path_factory.mktemp("identified_file")
    fit, held = _write_log(folder / "fit.csv", 8.0, 1), _write_log(folder / "held.csv", 6.0, 2)
    out = folder / "id.toml"
    args = [
        "identify",
        "--log",
        str(fit),
        "--validate",
        str(held),
        "--out",
        str(out),
        "--json",
        str(folder / "id.json"),
    ]
    assert main([*args, "--spin-free-levers", "--author", "A. Tester"]) == 0
    bare = folder / "bare.toml"
    bare.write_text("".join(line for line in out.read_text().splitlines(True) if not line.startswith("#")))
    return {"folder": folder, "fit": fit, "held": held, "out": out, "bare": bare}


def test_identify_opens_each_log_once(files, tmp_path, monkeypatch, capsys):
    """Scanned, checked for plausibility, hashed and fitted from one read of each file (it was three: check, fit, hash)."""
    opener = _CountingOpener(monkeypatch, files["fit"], files["held"])
    out = tmp_path / "again.toml"
    argv = ["identify", "--log", str(files["fit"]), "--validate", str(files["held"]), "--out", str(out)]
    assert main([*argv, "--summary-format", "json"]) == 0
    document = json.loads(capsys.readouterr().out)
    block = document["provenance"]
    assert (opener[files["fit"]], opener[files["held"]]) == (1, 1)
    # The hashes made on the way through the read are the files' (hashlib over the bytes, read here on purpose).
    hashes = {f["role"]: (f["sha256"], f["bytes"]) for f in block["inputs"]}
    assert hashes["log"] == (_sha256(files["fit"]), files["fit"].stat().st_size)
    assert hashes["validate"] == (_sha256(files["held"]), files["held"].stat().st_size)
    # What it prints, and the --json file, are the document ``hipsim schema identify`` describes.
    validator = jsonschema.Draft202012Validator(schema("identify"))
    validator.validate(document)
    written = json.loads((files["folder"] / "id.json").read_text(encoding="utf-8"))
    validator.validate(written)
    assert document["self_check"]["verdict"]["level"] == "PASS" and written["json"] == str(files["folder"] / "id.json")
    assert document["validation"][0]["identified"]["1"]["rms_error_Nmm"] > 0 and document["toml"] == str(out)


def test_compare_opens_its_log_once(files, tmp_path, monkeypatch, capsys, quick_figures):
    opener = _CountingOpener(monkeypatch, files["held"])
    argv = ["compare", "--log", str(files["held"]), "--out", str(tmp_path / "c"), "--summary-format", "json"]
    assert main(argv) == 0
    capsys.readouterr()
    assert opener[files["held"]] == 1
    block = json.loads((tmp_path / "c" / "comparison.json").read_text())["provenance"]
    assert [f["sha256"] for f in block["inputs"] if f["role"] == "log"] == [_sha256(files["held"])]


def test_the_file_carries_its_provenance_in_a_table(files):
    """[identification.provenance]: version, time, command, each input with SHA-256 and size; the comments say the same."""
    found = given(read_identified_file(files["out"]))
    made = found.provenance
    assert made is not None and made.author == "A. Tester" and "--spin-free-levers" in made.command
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ", made.created)
    inputs = {f.role: f for f in made.inputs}
    assert (inputs["log"].sha256, inputs["log"].size) == (_sha256(files["fit"]), files["fit"].stat().st_size)
    assert inputs["validate"].sha256 == _sha256(files["held"])
    assert inputs["parameters"].sha256 == _sha256(Path(PARAMS.source))
    assert found.lever_spin is False and found.logs == ("fit.csv",) and not found.from_comments
    assert f"# {made.made()}" in files["out"].read_text().splitlines()


def _same(files, full: str, bare: str) -> None:
    """Two outputs equal once the bare file's name, hash and size are the full file's."""
    for a, b in (
        (str(files["bare"]), str(files["out"])),
        (_sha256(files["bare"]), _sha256(files["out"])),
        (f'"bytes": {files["bare"].stat().st_size}', f'"bytes": {files["out"].stat().st_size}'),
        (f"bytes = {files['bare'].stat().st_size}", f"bytes = {files['out'].stat().st_size}"),
        ("bare.toml", "id.toml"),
        ("/bare/", "/out/"),  # the output folders
    ):
        bare = bare.replace(a, b)
    assert bare == full


@pytest.mark.usefixtures(
    "quick_figures"
)  # outputs compared as text: the figures are drawn in tests/present/test_report.py
def test_a_file_without_comments_behaves_like_the_file_with_them(files, tmp_path, capsys):
    """Every command that reads the file: the same outputs, comments or none (the monitor read lever spin from one)."""
    assert identified_file(files["bare"]) is identified_file(files["out"]) is False
    origins = [parameter_origin(files[name]).as_dict() for name in ("out", "bare")]
    assert origins[0]["kind"] == "identified" and origins[0]["made"].startswith("Made by hipsim")
    assert [{k: v for k, v in o.items() if k != "file"} for o in origins][0] == {
        k: v for k, v in origins[1].items() if k != "file"
    }
    outputs: dict[tuple[str, str], Any] = {}  # a command's text, or the files' texts
    for name in ("out", "bare"):
        folder = tmp_path / name
        folder.mkdir()
        params = str(files[name])
        runs = {
            "torques": ["torques", "--params", params, "--rate", "100", "--out", str(folder / "torques.csv")],
            "compare": ["compare", "--params", params, "--log", str(files["held"]), "--out", str(folder / "c")],
            "report": [
                "report",
                "--params",
                params,
                "--rate",
                "100",
                "--engine",
                "analytic",
                "--out",
                str(folder / "r"),
            ],
            "identify": ["identify", "--params", params, "--log", str(files["fit"]), "--out", str(folder / "i.toml")],
        }
        for command, argv in runs.items():
            assert main(argv) in (0, 1), command
            outputs[name, command] = re.sub(r"\d+\.\d+ s\b", "(time) s", capsys.readouterr().out)
        outputs[name, "files"] = [
            (folder / "torques.csv").read_text(),
            json.dumps({k: v for k, v in json.loads((folder / "c" / "comparison.json").read_text()).items()}),
            json.dumps(json.loads((folder / "r" / "report.json").read_text())["provenance"]["parameters"]),
            # The identification's own provenance names its time and command: the rest must agree.
            "".join(
                line
                for line in (folder / "i.toml").read_text().splitlines(True)
                if not line.startswith(("# Made by", "created_utc", "command", "#   parameters"))
            ),
        ]
    for key in ("torques", "compare", "report", "identify"):
        _same(files, outputs["out", key], outputs["bare", key])
    for full, bare in zip(outputs["out", "files"], outputs["bare", "files"]):
        _same(files, re.sub(r'"created_utc": "[^"]*"', "", full), re.sub(r'"created_utc": "[^"]*"', "", bare))


def test_a_file_of_the_previous_version_reads_its_provenance_from_its_comments(files, tmp_path):
    """Written before [identification.provenance]: the `# Made by` line and the hashes in the header still read."""
    text = files["out"].read_text()
    old = tmp_path / "old.toml"
    old.write_text(text[: text.index("[identification.provenance]")])
    found, new = given(read_identified_file(old)), given(read_identified_file(files["out"]))
    assert given(found.provenance).made() == given(new.provenance).made()
    assert [(f.role, f.path, f.sha256) for f in given(found.provenance).inputs] == [
        (f.role, f.path, f.sha256) for f in given(new.provenance).inputs
    ]
    assert found.estimates == new.estimates and found.lever_spin is False


def test_a_header_only_file_is_read_from_its_comments(tmp_path):
    """The oldest files: no table, the header's lines (lever spin from the `# Model:` line)."""
    published = Path(PARAMS.source).read_text()
    path = tmp_path / "old.toml"
    path.write_text(
        f"{IDENTIFIED_MARK}: a parameter file every hipsim command accepts (--params).\n"
        "# Made by hipsim 0.1.0 on 2026-01-02T03:04:05Z (UTC): hipsim identify --log a.csv --out old.toml\n"
        f"#   log a.csv: SHA-256 {'ab' * 32}\n"
        "# From the logs: a.csv (1000 samples per motor after filtering and decimation).\n"
        "# Model: analytic, lever spin off; regressor condition number 12.\n"
        "# Identified (value, relative standard deviation):\n"
        "#  μ_t = 0.025 ± 0.0001 (±0.4 %)\n\n" + published
    )
    found = given(read_identified_file(path))
    assert found.from_comments and found.lever_spin is False and found.logs == ("a.csv",)
    assert found.provenance == FileProvenance(
        "0.1.0",
        "2026-01-02T03:04:05Z",
        "hipsim identify --log a.csv --out old.toml",
        (InputRecord("log", "a.csv", "ab" * 32),),
    )
    assert [(e.key, e.value, e.std) for e in found.estimates] == [("friction.thrust_mu", 0.025, 0.0001)]
    assert identified_file(path) is False


def test_the_writer_takes_a_callers_tables_and_provenance(tmp_path):
    """The API another command (calibrate) writes through: its table, sub-tables and provenance, read back as written."""
    made = FileProvenance(
        "9.9", "2026-11-27T00:00:00Z", "hipsim calibrate --log s.csv", (InputRecord("log", "s.csv", "cd" * 32, 12),)
    )
    path = write_identified_file(
        tmp_path / "cal.toml",
        PARAMS,
        {"logs": ["s.csv"], "lever_spin": True, "stations": [1, 2]},
        made,
        ["calibrated on the rig"],
        {"calibration": {"torque_constant": [0.1, 0.2, 0.3]}},
    )
    text = path.read_text()
    assert text.startswith(IDENTIFIED_MARK) and "# calibrated on the rig" in text
    found = given(read_identified_file(path))
    assert found.provenance == made and found.table["calibration"] == {"torque_constant": [0.1, 0.2, 0.3]}
    assert found.table["stations"] == [1, 2]
    assert file_values(hipsim.load_parameters(path)) == file_values(PARAMS)
    with pytest.raises(ParameterError, match="identification.provenance"):
        identified_toml(PARAMS, {"provenance": {}})


def test_a_starting_file_with_only_a_prior_is_not_identified(tmp_path):
    path = tmp_path / "start.toml"
    path.write_text(Path(PARAMS.source).read_text() + "\n[identification.prior]\nm_L = 0.1\n")
    assert read_identified_file(path) is None
    assert parameter_origin(path).kind == "file"
