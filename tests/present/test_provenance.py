"""Where a page's numbers came from (hipsim.present.provenance): hashes, the parameter origin of each key, the
one-sentence summary, the block's fields. An identified file read back whole: present/test_pages.py."""

from __future__ import annotations

import hashlib
import shutil
from typing import Any

import pytest

from hipsim.machine.parameters import default_parameters_path
from hipsim.present.provenance import (
    IdentifiedValue,
    InputFile,
    ParameterOrigin,
    file_sha256,
    parameter_origin,
    provenance,
)

FILE = InputFile("parameters", "p.toml", "ab" * 32, 10)


def test_a_files_hash_read_in_pieces_is_the_hash_of_its_bytes(tmp_path):
    path = tmp_path / "big.bin"
    data = bytes(range(256)) * 6000  # 1.46 MiB: more than one 1 MiB piece
    path.write_bytes(data)
    assert file_sha256(path) == hashlib.sha256(data).hexdigest()
    empty = tmp_path / "empty"
    empty.write_bytes(b"")
    assert file_sha256(empty) == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"


def identified_origin(**changes: Any) -> ParameterOrigin:
    fields: dict[str, Any] = dict(
        file=FILE,
        kind="identified",
        start="drawing.toml",
        logs=("fit.csv",),
        identified=(IdentifiedValue("platform.inertia_kgmm2[xy]", "I_xy", 1.0, 0.1, "kg·mm²"),),
        combined=("lever.mass_kg",),
        held=(("slider.mass_kg", "not excited"),),
        overrides=("friction.hip_mu = 0.1",),
    )
    return ParameterOrigin(**(fields | changes))


def test_each_keys_origin_in_order_of_precedence():
    origin = identified_origin()
    assert origin.origin_of("friction.hip_mu") == ("--set", [])  # the override's key as typed, spaces stripped
    kind, found = origin.origin_of("platform.inertia_kgmm2")  # a component names its key
    assert kind == "identified" and [v.label for v in found] == ["I_xy"]
    assert origin.origin_of("lever.mass_kg") == ("start value, in an identified combination", [])
    assert origin.origin_of("slider.mass_kg") == ("start value, not identified", [])
    assert origin.origin_of("lever.length_mm") == ("start value", [])
    assert ParameterOrigin(FILE, "published").origin_of("lever.length_mm") == ("published", [])
    overridden = identified_origin(overrides=("platform.inertia_kgmm2=[1,2,3]",))
    assert overridden.origin_of("platform.inertia_kgmm2") == ("--set", [])  # --set wins over identified


def test_the_summary_in_one_sentence():
    assert ParameterOrigin(FILE, "published").summary() == "published values"
    assert ParameterOrigin(FILE, "file", overrides=("a.b=1", "c.d=2")).summary() == (
        "values as written in the file; overridden with --set a.b=1, c.d=2"
    )
    bare = ParameterOrigin(FILE, "identified")
    assert bare.summary() == (
        "identified from logs not named; starting parameters not named; no held-out log (the file names no validation)"
    )
    held_out = identified_origin(
        overrides=(), validation=(("iso.csv", ((1.444, 59.06), (1.41, 63.8), (1.88, 52.7))),), made="Made by hipsim 1"
    )
    assert held_out.summary() == (
        "identified from fit.csv; starting parameters drawing.toml; held-out error on iso.csv: M1 1.44, M2 1.41, "
        "M3 1.88 N·mm RMS (starting parameters: 59.1, 63.8, 52.7); made by hipsim 1"
    )
    document = held_out.as_dict()
    assert document["validation"][0]["rms_error_Nmm"][0] == {"identified": 1.444, "starting": 59.06}
    assert document["identified"][0]["combination"] is None and document["made"] == "Made by hipsim 1"


def test_the_published_file_by_any_path_is_published_and_a_copy_is_a_users_file(tmp_path):
    assert parameter_origin(None).kind == "published"
    assert parameter_origin(default_parameters_path(), ["a.b=1"]).kind == "published"
    copy = tmp_path / "mine.toml"
    shutil.copy(default_parameters_path(), copy)
    origin = parameter_origin(copy)
    assert origin.kind == "file" and origin.file.path == str(copy) and origin.file.size == copy.stat().st_size


def test_the_block_lists_the_parameters_first_and_cleans_the_labs_fields(tmp_path):
    log = tmp_path / "log one.csv"
    log.write_bytes(b"t\n0\n")
    hashed = InputFile("x", "kept.csv", "cd" * 32, 5)
    block = provenance(
        {"log": [log, hashed], "drive": None},
        ParameterOrigin(FILE, "published"),
        ["hipsim", "report", "--out", "my dir"],
        title="  ",
        author=" A. Author ",
        created="2026-01-01T00:00:00Z",
        warnings=["w"],
    )
    assert [f.path for f in block.inputs] == ["p.toml", str(log), "kept.csv"]
    assert [f.role for f in block.inputs] == ["parameters", "log", "log"]  # an InputFile takes its role here
    assert block.inputs[2].sha256 == "cd" * 32 and block.inputs[1].size == 4
    assert block.command == "hipsim report --out 'my dir'"
    assert (block.title, block.author, block.rig) == (None, "A. Author", None)
    document = block.as_dict()
    assert document["created_utc"] == "2026-01-01T00:00:00Z" and document["warnings"] == ["w"]
    assert document["inputs"][0] == {"role": "parameters", "path": "p.toml", "sha256": "ab" * 32, "bytes": 10}
    assert provenance().command == "(called from Python, not the command line)"
    assert provenance(command="as typed").command == "as typed"
    created = provenance().created
    assert len(created) == 20 and created.endswith("Z") and created[10] == "T"  # 2026-11-29T07:30:00Z


@pytest.mark.parametrize("value", [None, "", "  \t"])
def test_an_empty_field_is_none(value):
    assert provenance(rig=value).rig is None
