"""hipsim.rig.identification.quantities pinned against a parameter file: each quantity's key, component and unit.

A parameter file with full inertia matrices (off-diagonal terms) and every friction coefficient set to a value of
its own is read by :func:`hipsim.load_parameters`; each quantity's value in the machine (SI) must be the file's value
at its key and component times the SI value of its unit: kg·mm² 1e-6, N·mm and N·mm·s/rad 1e-3, N·s/mm 1e3.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

import hipsim
from hipsim.machine.toml_writer import table_toml
from hipsim.rig.identification.quantities import (
    AXES,
    BLOCKS,
    BOUNDED,
    FRICTION,
    QUANTITIES,
    standard_values,
    symmetric,
    with_values,
)

SI = {"kg·mm²": 1e-6, "kg": 1.0, "": 1.0, "N·mm": 1e-3, "N·mm·s/rad": 1e-3, "N": 1.0, "N·s/mm": 1e3}


@pytest.fixture(scope="module")
def file(tmp_path_factory):
    """The published machine's file with inertia matrices and friction coefficients of their own (its dict, path)."""
    with open(Path(hipsim.load_parameters().source), "rb") as f:  # the published machine
        data = tomllib.load(f)
    data["platform"]["inertia_kgmm2"] = [
        [248030.5, 1200.0, -300.0],
        [1200.0, 249940.25, 45.0],
        [-300.0, 45.0, 386502.35],
    ]
    data["lever"]["inertia_kgmm2"] = [[26395.81, 12.5, -7.0], [12.5, 26339.29, 3.25], [-7.0, 3.25, 480.07]]
    for k, q in enumerate(FRICTION):
        data["friction"][q.key.split(".")[1]] = 0.01 * (k + 2)
    path = tmp_path_factory.mktemp("quantities") / "machine.toml"
    path.write_text("\n".join(table_toml(name, entries) for name, entries in data.items()))
    return data, path


def file_value(data, q):
    section, _, rest = q.key.partition(".")
    name, _, axes = rest.partition("[")
    value = data[section][name]
    if axes:
        a, b = AXES[axes.rstrip("]")]
        return value[a][b]
    return value


def test_each_quantity_is_its_files_value_in_si(file):
    data, path = file
    params = hipsim.load_parameters(path)
    theta = standard_values(params)
    assert len(theta) == len(QUANTITIES) == 25
    for k, q in enumerate(QUANTITIES):
        assert q.scale == SI[q.unit], q.key
        assert theta[k] == pytest.approx(file_value(data, q) * SI[q.unit], rel=1e-12), q.key
        assert q.read(params) == theta[k]


def test_labels_parts_and_signs():
    labels = [q.label for q in QUANTITIES]
    assert len(set(labels)) == len(labels) and len({q.key for q in QUANTITIES}) == len(QUANTITIES)
    assert labels[:7] == ["I_m,xx", "I_m,yy", "I_m,zz", "I_m,xy", "I_m,xz", "I_m,yz", "m_L"]
    assert labels[7:9] == ["I_L", "I_l,xx"] and labels[14:17] == ["m_l", "μ_h", "μ_t"]
    parts = {"platform": "platforms", "slider": "sliders", "screw": "screws", "lever": "levers", "friction": "friction"}
    for q in QUANTITIES:
        assert q.part == parts[q.key.partition(".")[0]], q.key
        # Masses, rotor and principal inertias and friction coefficients are ≥ 0; products of inertia take any sign.
        assert q.nonnegative == (q.component is None or q.component[0] == q.component[1]), q.key
        assert q.nominal > 0
    assert [q.name for q in FRICTION][:2] == ["hip_mu", "thrust_mu"] and len(FRICTION) == 10


def test_blocks_and_bounds():
    assert BLOCKS == {"platform": [0, 1, 2, 3, 4, 5], "lever": [8, 9, 10, 11, 12, 13]}
    assert BOUNDED == [6, 7, 14] + list(range(15, 25))


def test_symmetric():
    np.testing.assert_array_equal(symmetric([1, 2, 3, 4, 5, 6]), [[1, 4, 5], [4, 2, 6], [5, 6, 3]])


def test_writing_theta_back_gives_the_same_machine(file):
    _, path = file
    params = hipsim.load_parameters(path)
    theta = standard_values(params)
    # Each value moved by its own amount: every field takes its own (an inertia's two off-diagonal cells alike).
    moved = theta + 0.001 * np.arange(1, len(theta) + 1)
    again = with_values(params, moved, source="moved")
    np.testing.assert_allclose(standard_values(again), moved, rtol=1e-15, atol=0)
    np.testing.assert_array_equal(again.platform_inertia, again.platform_inertia.T)
    assert again.platform_inertia[1, 0] == moved[3]
    assert again.source == "moved" and with_values(params, theta).source == params.source
    # Whole numbers are taken as floats.
    assert standard_values(with_values(params, np.round(moved * 0).astype(int)))[6] == 0.0


def test_theta_of_another_length_is_refused(file):
    _, path = file
    params = hipsim.load_parameters(path)
    theta = standard_values(params)
    for wrong in (theta[:-1], np.append(theta, 1.0)):
        with pytest.raises(ValueError, match=r"zip\(\) argument 2 is (shorter|longer)"):  # one value a quantity
            with_values(params, wrong)
