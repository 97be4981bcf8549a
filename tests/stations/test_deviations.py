"""hipsim.stations.deviations by hand: δ's entries (7 a chain × 3 chains × 2 platforms, 3 a centre × 2, the stack-up's seat), families,
platforms, and the machine a δ makes."""

from __future__ import annotations

import numpy as np
import pytest

import hipsim
from hipsim.exceptions import ArgumentError
from hipsim.stations.deviations import COUNT, FAMILIES, deviation, family, machine, names, platform_columns, platform_of


def test_the_vector_has_an_entry_a_chain_value_and_a_centre_coordinate():
    chains_and_centres = (2 + 1 + 3 + 1) * 3 * 2 + 3 * 2  # 48
    # The intermediate chain's seat (spline_x_1 ... spline_z_1, issue 44's stack-up) follows them where the package has it.
    assert COUNT == chains_and_centres + (3 if "spline" in FAMILIES else 0)
    assert len(set(names())) == COUNT
    assert names()[0] == "ujoint_x_11" and names()[47] == "centre_z_2"


def test_families_and_platforms_by_name():
    assert family("joint_z_21") == "joint"
    assert family("centre_x_1") == "centre"
    assert platform_of("lever_13") == 1  # chain 13: platform 1, module 3
    assert platform_of("lever_23") == 2
    assert platform_of("centre_z_2") == 2
    for bad in ("joint_w_21", "bogus_11", "lever_33"):
        with pytest.raises(ArgumentError, match="an entry of the per-chain vector"):
            family(bad)


def test_the_platforms_columns_split_the_vector():
    one, two = platform_columns(1), platform_columns(2)
    assert len(two) == (2 + 1 + 3 + 1) * 3 + 3  # its three chains and its centre: 24
    assert sorted([*one, *two]) == list(range(COUNT))
    assert all(names()[k].endswith(("_1", "_11", "_12", "_13")) for k in one)


def test_the_drawing_is_zero_and_a_delta_makes_a_per_chain_machine():
    params = hipsim.load_parameters()
    assert params.geometry is None
    assert np.array_equal(deviation(params), np.zeros(COUNT))
    delta = np.zeros(COUNT)
    delta[names().index("lever_21")] = 0.0005  # 0.5 mm longer lever on platform 2, chain 1
    built = machine(params, delta)
    assert built.geometry is not None
    assert np.array_equal(deviation(built), delta)
    assert machine(params, np.zeros(COUNT)).geometry is not None  # δ = 0 too: one code path
    with pytest.raises(ArgumentError) as error:
        machine(params, np.zeros(COUNT - 1))
    assert str(error.value) == f"delta: expected shape ({COUNT},), got shape ({COUNT - 1},)"


def test_platform_1s_columns_hold_its_chains_its_centre_and_the_seat():
    one = platform_columns(1)
    assert len(one) == COUNT - 24  # 21 of its chains, 3 of its centre and, with the stack-up, the seat's 3
    assert [names()[k] for k in one[:3]] == ["ujoint_x_11", "ujoint_y_11", "ujoint_x_12"]
    assert list(one) == sorted(one)
    assert [names()[k] for k in platform_columns(2)][-3:] == ["centre_x_2", "centre_y_2", "centre_z_2"]


def test_a_delta_keeps_the_files_controlled_platform():
    params = hipsim.load_parameters()
    delta = np.zeros(COUNT)
    delta[names().index("slider_12")] = -2e-4
    built = machine(params, delta)
    assert built.geometry is not None and built.geometry.control == 2  # the drawing's default
    file = built.replace(geometry=built.geometry.replace(control=1))
    again = machine(file, 2 * delta)
    assert again.geometry is not None and again.geometry.control == 1
    assert deviation(again)[names().index("slider_12")] == pytest.approx(-4e-4)
    with pytest.raises(ArgumentError) as error:
        family("lever_1")
    assert str(error.value) == "name: expected an entry of the per-chain vector (see names()), got 'lever_1'"
