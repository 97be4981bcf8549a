"""hipsim.rig.identification.identified_file pinned on small files written here: the tables read back, the reasons
and combinations derived from them, an old file's comment header, and each malformed table named by file and key.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from support import given

import hipsim
from hipsim.exceptions import ParameterError
from hipsim.rig.identification.identified_file import (
    IDENTIFIED_MARK,
    FileEstimate,
    FileProvenance,
    InputRecord,
    identified_toml,
    read_identified_file,
    write_identified_file,
)

PARAMS = hipsim.load_parameters()
MADE = FileProvenance(
    "9.9",
    "2026-11-27T00:00:00Z",
    "hipsim identify --log a.csv",
    (InputRecord("log", "a.csv", "ab" * 32, 12), InputRecord("parameters", "p.toml", "cd" * 32)),
    "Wear test 7",
    "A. Lab",
    "rig 2",
)
TABLE = {
    "logs": ["a.csv", "b.csv"],
    "start": "p.toml",
    "lever_spin": False,
    "base": ["m_L", "μ_h", "b_S"],
    "keys": ["slider.mass_kg", "friction.hip_mu", "friction.sjoint_viscous_Nmm_s_rad"],
    "units": ["kg", "", "N·mm·s/rad"],
    "value": [3.5, 0.08, 0.25],
    "std": [0.01, 0.002, 0.5],
    "determined": [True, True, False],
    "definitions": ["m_L + 0.5·m_l + 2·I_L", "μ_h", "b_S + 1·b_U"],
    "validation_logs": ["c.csv"],
    "validation_rms_error_Nmm": [[1.0, 2.0, 3.0]],
    "validation_start_rms_error_Nmm": [[4.0, 5.0, 6.0]],
}


def test_the_provenance_in_words_and_as_a_table():
    assert MADE.made() == "Made by hipsim 9.9 on 2026-11-27T00:00:00Z (UTC): hipsim identify --log a.csv"
    assert MADE.comments() == [
        "# Made by hipsim 9.9 on 2026-11-27T00:00:00Z (UTC): hipsim identify --log a.csv",
        f"#   log a.csv: SHA-256 {'ab' * 32}",
        f"#   parameters p.toml: SHA-256 {'cd' * 32}",
        "# Title: Wear test 7",
        "# Author: A. Lab",
        "# Rig: rig 2",
    ]
    assert InputRecord("log", "a.csv", "ab", 12).table() == {
        "role": "log",
        "path": "a.csv",
        "sha256": "ab",
        "bytes": 12,
    }
    assert InputRecord("log", "a.csv", "ab").table() == {"role": "log", "path": "a.csv", "sha256": "ab"}
    block = {
        "hipsim": "9.9",
        "created_utc": "2026-11-27T00:00:00Z",
        "command": "hipsim identify --log a.csv",
        "inputs": [{"role": "log", "path": "a.csv", "sha256": "ab" * 32, "bytes": 12}],
    }
    assert FileProvenance.from_dict(block) == FileProvenance(
        "9.9", "2026-11-27T00:00:00Z", "hipsim identify --log a.csv", (InputRecord("log", "a.csv", "ab" * 32, 12),)
    )


def test_written_and_read_back(tmp_path):
    path = write_identified_file(tmp_path / "id.toml", PARAMS, TABLE, MADE, ["fitted on the rig", "# as is"])
    text = path.read_text()
    lines = text.splitlines()
    # The mark first, then the provenance's lines, then the caller's (a "#" added where missing).
    assert lines[0] == IDENTIFIED_MARK + ": a parameter file every hipsim command accepts (--params)."
    assert lines[1:7] == MADE.comments()
    assert lines[7:9] == ["# fitted on the rig", "# as is"]
    found = given(read_identified_file(path))
    assert found.source == str(path) and not found.from_comments
    assert found.provenance == MADE
    assert (found.lever_spin, found.logs, found.start) == (False, ("a.csv", "b.csv"), "p.toml")
    assert found.estimates == (
        FileEstimate("m_L", "slider.mass_kg", "kg", 3.5, 0.01, True, "m_L + 0.5·m_l + 2·I_L"),
        FileEstimate("μ_h", "friction.hip_mu", "", 0.08, 0.002, True, "μ_h"),
        FileEstimate("b_S", "friction.sjoint_viscous_Nmm_s_rad", "N·mm·s/rad", 0.25, 0.5, False, "b_S + 1·b_U"),
    )
    # What a determined combination folds in keeps its start; an undetermined one is held near its prior, and so is
    # what it folds in.
    assert found.estimates[0].terms == ["m_l", "I_L"]
    assert found.combined == ("lever.mass_kg", "screw.inertia_kgmm2")
    assert found.held == (
        ("friction.sjoint_viscous_Nmm_s_rad", "not determined by these logs: near its prior (0.25 ± 0.5 N·mm·s/rad)"),
        ("friction.ujoint_viscous_Nmm_s_rad", "folded into b_S, not determined by these logs"),
    )
    assert found.validation == (("c.csv", ((1.0, 4.0), (2.0, 5.0), (3.0, 6.0))),)
    assert found.table["base"] == TABLE["base"]


def test_defaults_of_a_bare_table(tmp_path):
    # Only the base parameters: every one determined, defined as itself, lever spin on, no logs, no validation.
    table = {k: TABLE[k] for k in ("base", "keys", "units", "value", "std")}
    found = given(read_identified_file(write_identified_file(tmp_path / "bare.toml", PARAMS, table)))
    assert found.lever_spin is True and found.logs == () and found.start == "" and found.provenance is None
    assert [e.determined for e in found.estimates] == [True] * 3
    assert [e.definition for e in found.estimates] == ["m_L", "μ_h", "b_S"]
    assert found.held == () and found.combined == () and found.validation == ()
    # A unitless held estimate reads without a blank before its bracket.
    table |= {"determined": [True, False, True]}
    found = given(read_identified_file(write_identified_file(tmp_path / "held.toml", PARAMS, table)))
    assert found.held == (("friction.hip_mu", "not determined by these logs: near its prior (0.08 ± 0.002)"),)


def test_the_writer_keeps_its_mark_and_provenance_to_itself():
    text = identified_toml(PARAMS, {"logs": []}, comments=[IDENTIFIED_MARK + " long ago"])
    assert text.startswith(IDENTIFIED_MARK + " long ago\n\n")
    for table, tables in (({"provenance": 1}, None), ({}, {"provenance": {}})):
        with pytest.raises(ParameterError) as refused:
            identified_toml(PARAMS, table, tables=tables)
        assert str(refused.value) == (
            "key 'identification.provenance': is written by the identified file's writer itself"
        )


@pytest.mark.parametrize(
    ("change", "key", "words"),
    [
        ({"base": "m_L"}, "identification.base", "expected a list, got 'm_L'"),
        ({"std": [0.1]}, "identification.std", "expected a list of 3 (one per base parameter), got [0.1]"),
        ({"determined": [True]}, "identification.determined", "expected a list of 3 (one per base parameter)"),
        ({"definitions": "m_L"}, "identification.definitions", "expected a list of 3 (one per base parameter)"),
        ({"value": ["a", 1.0, 2.0]}, "identification", "value and std: expected numbers"),
        ({"validation_logs": ["c.csv", "d.csv"]}, "identification", "validation_logs, validation_rms_error_Nmm and"),
        (
            {"validation_rms_error_Nmm": [["x", 1.0, 2.0]]},
            "identification.validation_rms_error_Nmm",
            "expected three numbers per log",
        ),
    ],
)
def test_a_malformed_table_is_named(tmp_path, change, key, words):
    path = write_identified_file(tmp_path / "bad.toml", PARAMS, TABLE | change)
    with pytest.raises(ParameterError) as refused:
        read_identified_file(path)
    assert str(refused.value).startswith(f"{path}, key '{key}': {words}")
    assert (refused.value.key, refused.value.source) == (key, str(path))


@pytest.mark.parametrize(
    ("provenance", "key"),
    [
        ('hipsim = "9.9"\ncreated_utc = "x"\n', "identification.provenance"),
        ('hipsim = "9.9"\ncreated_utc = "x"\ncommand = 3\n', "identification.provenance"),
        ('hipsim = "9.9"\ncreated_utc = "x"\ncommand = "c"\ninputs = 3\n', "identification.provenance.inputs"),
        (
            'hipsim = "9.9"\ncreated_utc = "x"\ncommand = "c"\n[[identification.provenance.inputs]]\nrole = "log"\n'
            'path = "a.csv"\n',
            "identification.provenance.inputs",
        ),
    ],
)
def test_a_malformed_provenance_is_named(tmp_path, provenance, key):
    path = tmp_path / "bad.toml"
    path.write_text(identified_toml(PARAMS, {"logs": ["a.csv"]}) + "\n[identification.provenance]\n" + provenance)
    with pytest.raises(ParameterError) as refused:
        read_identified_file(path)
    assert refused.value.key == key and refused.value.source == str(path)
    expected = (
        "expected [[inputs]] tables with role, path and sha256"
        if key.endswith("inputs")
        else "expected a table with hipsim, created_utc and command (text)"
    )
    assert str(refused.value) == f"{path}, key '{key}': {expected}"


def test_an_old_files_comment_header(tmp_path):
    # The lines the identify of the previous versions wrote, with what each says.
    published = Path(PARAMS.source).read_text()
    path = tmp_path / "old.toml"
    path.write_text(
        f"{IDENTIFIED_MARK}: a parameter file every hipsim command accepts (--params).\n"
        "# Made by hipsim 0.1.0 on 2026-01-02T03:04:05Z (UTC): hipsim identify --log a.csv --log b.csv\n"
        f"#   log a.csv: SHA-256 {'ab' * 32}\n"
        f"#   log b.csv: SHA-256 {'ef' * 32}\n"
        "# From the logs: a (1).csv, b.csv (1000 samples per motor after filtering and decimation).\n"
        "# Starting parameters: start_X.\n"
        "# Model: analytic, lever spin on; regressor condition number 12.\n"
        "# Identified (value, relative standard deviation):\n"
        "#  m_L + 0.5·m_l = 3.5 ± 0.01 kg (±0.3 %)\n"
        "#  μ_h = 0.08 ± 0.002 (±2.5 %)\n"
        "#  nothing = 1 ± 2 kg (±200 %)\n"
        "#  μ_t = x ± 0.1 (±1 %)\n"
        "#  not a quantity line\n"
        "# Not identified (kept at the starting value):\n"
        "#  b_S = 0 N·mm·s/rad: not determined by these logs\n"
        "#  zz = 0 kg: unknown\n"
        "# Validation (RMS torque error, identified vs starting):\n"
        "#  d.csv: M1 x vs 4 N·mm\n"
        "#  no validation line\n"
        "# e.csv: M1 1 vs 2 N·mm\n"
        "#  c.csv: M1 1.5 vs 4 M2 2 vs 5 M3 3 vs 6 N·mm\n" + published
    )
    found = given(read_identified_file(path))
    assert found.from_comments and found.table == {} and found.source == str(path)
    assert found.lever_spin is True and found.logs == ("a (1).csv", "b.csv") and found.start == "start_X"
    assert found.provenance == FileProvenance(
        "0.1.0",
        "2026-01-02T03:04:05Z",
        "hipsim identify --log a.csv --log b.csv",
        (InputRecord("log", "a.csv", "ab" * 32), InputRecord("log", "b.csv", "ef" * 32)),
    )
    assert found.estimates == (
        FileEstimate("m_L", "slider.mass_kg", "kg", 3.5, 0.01, True, "m_L + 0.5·m_l"),
        FileEstimate("μ_h", "friction.hip_mu", "", 0.08, 0.002, True, "μ_h"),
    )
    assert found.combined == ("lever.mass_kg",)
    assert found.held == (("friction.sjoint_viscous_Nmm_s_rad", "not determined by these logs"),)
    assert found.validation == (("c.csv", ((1.5, 4.0), (2.0, 5.0), (3.0, 6.0))),)


def test_not_an_identified_file(tmp_path):
    plain = tmp_path / "plain.toml"
    plain.write_text(Path(PARAMS.source).read_text())
    assert read_identified_file(plain) is None
    # The mark must open the file; lines after the comments are not the header's.
    late = tmp_path / "late.toml"
    late.write_text("# a comment\n" + IDENTIFIED_MARK + "\n" + Path(PARAMS.source).read_text())
    assert read_identified_file(late) is None
    stops = tmp_path / "stops.toml"
    stops.write_text(
        f"{IDENTIFIED_MARK}\n# From the logs: a.csv (1 sample).\n\n# Starting parameters: late.toml.\n"
        + Path(PARAMS.source).read_text()
    )
    found = given(read_identified_file(stops))
    assert found.logs == ("a.csv",) and found.start == "" and found.provenance is None


def test_sub_tables_a_bare_header_and_logs_that_are_no_list(tmp_path):
    path = write_identified_file(
        tmp_path / "cal.toml", PARAMS, TABLE | {"logs": "a.csv"}, tables={"calibration": {"torque_constant": [0.1]}}
    )
    found = given(read_identified_file(path))
    assert found.table["calibration"] == {"torque_constant": [0.1]} and found.table["base"] == TABLE["base"]
    assert found.logs == ()  # not a list: no logs named
    # A header of the mark alone: no logs, no start, lever spin on (the analytic model's default for identify).
    bare = tmp_path / "bare.toml"
    bare.write_text(f"{IDENTIFIED_MARK}\n\n" + Path(PARAMS.source).read_text())
    found = given(read_identified_file(bare))
    assert (found.logs, found.start, found.lever_spin, found.estimates, found.provenance) == ((), "", True, (), None)


def test_a_table_without_its_provenance_takes_the_headers(tmp_path):
    # Files of the version between: the [identification] table, the provenance still in the comments.
    path = write_identified_file(tmp_path / "mid.toml", PARAMS, TABLE, comments=MADE.comments())
    assert given(read_identified_file(path)).provenance == FileProvenance(
        MADE.version, MADE.created, MADE.command, tuple(replace(f, size=None) for f in MADE.inputs)
    )
    plain = write_identified_file(tmp_path / "plain.toml", PARAMS, TABLE)
    assert given(read_identified_file(plain)).provenance is None
    # A provenance without inputs has none.
    path.write_text(
        identified_toml(PARAMS, TABLE)
        + '\n[identification.provenance]\nhipsim = "1"\ncreated_utc = "x"\ncommand = "c"\n'
    )
    assert given(read_identified_file(path)).provenance == FileProvenance("1", "x", "c")
    assert FileProvenance.from_dict({"hipsim": "1", "created_utc": "x", "command": "c"}).inputs == ()


def test_a_header_after_a_byte_order_mark(tmp_path):
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + f"{IDENTIFIED_MARK}\n# From the logs: a.csv (1).\n\n".encode())
    found = given(read_identified_file(path))
    assert found is not None and found.logs == ("a.csv",)


def test_a_prior_alone_is_no_identification(tmp_path):
    path = tmp_path / "start.toml"
    path.write_text(Path(PARAMS.source).read_text() + '\n[identification.prior]\n"μ_h" = 0.02\n')
    assert read_identified_file(path) is None


def test_identification_that_is_no_table(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text("identification = 3\n")
    with pytest.raises(ParameterError) as refused:
        read_identified_file(path)
    assert str(refused.value) == f"{path}, key 'identification': expected a table"
    assert (refused.value.key, refused.value.source) == ("identification", str(path))


def test_a_long_bad_value_is_quoted_in_200_characters(tmp_path):
    path = write_identified_file(tmp_path / "long.toml", PARAMS, TABLE | {"std": list(range(100))})
    with pytest.raises(ParameterError) as refused:
        read_identified_file(path)
    prefix = f"{path}, key 'identification.std': "
    assert str(refused.value).startswith(prefix + "expected a list of 3 (one per base parameter), got [0, 1, 2,")
    assert len(str(refused.value)) == len(prefix) + 200


@pytest.mark.parametrize(
    "drop",
    [("validation_start_rms_error_Nmm",), ("validation_rms_error_Nmm",), ("validation_logs",)],
)
def test_validation_needs_all_three_lists(tmp_path, drop):
    table = {k: v for k, v in TABLE.items() if k not in drop}
    assert given(read_identified_file(write_identified_file(tmp_path / "v.toml", PARAMS, table))).validation == ()
