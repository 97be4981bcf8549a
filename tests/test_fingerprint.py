"""hipsim.fingerprint: equal set-ups give equal fingerprints, any change another, whatever the order or the source."""

import dataclasses
import hashlib
import json

import numpy as np
import pytest

import hipsim
from hipsim.fingerprint import canonical_json, changed_parts, file_fingerprint, fingerprint, part_fingerprints, plain


def test_the_fingerprint_is_the_sha256_of_sorted_compact_json():
    setup = {"model": "analytic", "rate_Hz": 1000.0, "keys": ["lever.length_mm"]}
    text = '{"keys":["lever.length_mm"],"model":"analytic","rate_Hz":1000.0}'  # written by hand: sorted, no spaces
    assert canonical_json(setup) == text
    assert fingerprint(setup) == hashlib.sha256(text.encode()).hexdigest()
    assert fingerprint({"rate_Hz": 1000.0, "keys": ["lever.length_mm"], "model": "analytic"}) == fingerprint(setup)


def test_one_ulp_one_sample_or_one_flag_changes_it():
    a = np.linspace(0.0, 1.0, 11)
    b = a.copy()
    b[3] = np.nextafter(b[3], 2.0)
    assert fingerprint({"t": a}) != fingerprint({"t": b})
    assert fingerprint({"t": a}) != fingerprint({"t": a[:-1]})
    assert fingerprint({"t": a, "periodic": True}) != fingerprint({"t": a, "periodic": False})
    assert fingerprint({"x": 1.0}) != fingerprint({"x": 1.0 + 2**-52})
    assert plain(float("nan")) == "nan" and plain(np.float32(0.5)) == 0.5


def test_a_machine_is_fingerprinted_by_its_values_not_its_source():
    params = hipsim.load_parameters()
    renamed = dataclasses.replace(params, source="elsewhere.toml")
    assert fingerprint(params) == fingerprint(renamed)
    assert fingerprint(params) != fingerprint(params.replace(lever_length=params.lever_length + 1e-9))


def test_a_set_up_of_parts_names_the_parts_that_changed(tmp_path):
    first = part_fingerprints({"model": "analytic", "rate": 100.0})
    second = part_fingerprints({"model": "pinocchio", "rate": 100.0})
    assert first["setup"] == fingerprint({"model": first["model"], "rate": first["rate"]})
    assert changed_parts(first, second) == ["model"] and changed_parts(first, first) == []
    assert changed_parts(first, part_fingerprints({"model": "analytic", "rate": 100.0, "drive": None})) == ["drive"]
    path = tmp_path / "f.toml"
    path.write_bytes(b"a = 1\n")
    assert file_fingerprint(path) == hashlib.sha256(b"a = 1\n").hexdigest()


def test_what_is_not_data_is_refused():
    with pytest.raises(TypeError, match="a set-up holds data"):
        fingerprint({"f": print})
    json.loads(canonical_json({"x": float("inf")}))  # valid JSON even for infinities
