"""hipsim.rig.identification.prior and the rows' independence factors pinned by hand.

The prior: each standard parameter's default standard deviation is 30 % of an
inertial parameter's size and 50 % of a friction coefficient's (the size a
typical value where the value is 0), overridden per entry; the base
parameters' standard deviation is s_b,k = √(Σ_j T_kj²·s_j²) (each folded
parameter's variance weighted by the square of its coefficient).
The rows: a log low-passed at f_c and sampled at f_s keeps every
D = ⌊f_s/(4·f_c)⌋-th sample; those rows are f_s/D/(2·f_c) per independent one
(the filter), and at least f_s/D/(2·min(f_c, 10 Hz)) (the model error's floor).
"""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import cast

import numpy as np
import pytest

import hipsim
from hipsim.exceptions import HipsimError, ParameterError
from hipsim.rig.identification.base import BaseParameters
from hipsim.rig.identification.prior import (
    DEFAULT_RELATIVE,
    HELD,
    Prior,
    parse_prior_option,
    prior,
    prior_table,
    standard_std,
)
from hipsim.rig.identification.quantities import QUANTITIES
from hipsim.rig.identification.regressor import (
    MODEL_ERROR_BANDWIDTH,
    decimation,
    inflation,
    rows_per_independent_row,
)
from hipsim.rig.logs.log import Log

INDEX = {q.label: k for k, q in enumerate(QUANTITIES)}


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


def stand_in_base(transform: np.ndarray) -> BaseParameters:
    """A stand-in for the base parameters of which the prior reads only the transform."""
    return cast(BaseParameters, SimpleNamespace(transform=transform))


def stand_in_log(rate: float, cutoff: float | None) -> Log:
    """A stand-in for a log of which the decimation reads only the rate [Hz] and the cutoff [Hz]."""
    return cast(Log, SimpleNamespace(rate=rate, cutoff=cutoff))


def test_default_prior_by_hand(params):
    assert DEFAULT_RELATIVE == {"inertial": 0.30, "friction": 0.50}
    s = standard_std(params)
    # Slider mass 3 kg: 30 % → 0.9 kg. Lever mass 1.43 kg: 0.429 kg. μ_h = 0.095: 50 % → 0.0475.
    assert s[INDEX["m_L"]] == pytest.approx(0.9, rel=1e-12)
    assert s[INDEX["m_l"]] == pytest.approx(0.429, rel=1e-12)
    assert s[INDEX["μ_h"]] == pytest.approx(0.0475, rel=1e-12)
    # Zero values take the typical size: I_m,xy 0 → 0.3 kg·m² × 30 % = 0.09; screw Coulomb 0 → 0.05 N·m × 50 %.
    assert s[INDEX["I_m,xy"]] == pytest.approx(0.09, rel=1e-12)
    assert s[INDEX["τ_c,screw"]] == pytest.approx(0.025, rel=1e-12)


def test_prior_entries_absolute_relative_and_held(params):
    entries = {"μ_h": 0.02, "friction.screw_coulomb_Nmm": 3.0, "lever": "10 %", "slider.mass_kg": 0}
    s = standard_std(params, entries)
    # Absolute, in the file's unit: 0.02 (μ_h, no unit); 3 N·mm = 0.003 N·m.
    assert s[INDEX["μ_h"]] == pytest.approx(0.02, rel=1e-12)
    assert s[INDEX["τ_c,screw"]] == pytest.approx(0.003, rel=1e-12)
    # A key prefix: every lever parameter at 10 % of its size (m_l 1.43 kg → 0.143; I_l,xy 0 → 0.003 of 0.03).
    assert s[INDEX["m_l"]] == pytest.approx(0.143, rel=1e-12)
    assert s[INDEX["I_l,xy"]] == pytest.approx(0.003, rel=1e-12)
    # 0 holds the slider mass: HELD (1e-9) of its size, 3e-9 kg.
    assert HELD == 1e-9
    assert s[INDEX["m_L"]] == pytest.approx(3e-9, rel=1e-12)
    # Untouched: the platform's defaults.
    assert s[INDEX["I_m,xy"]] == pytest.approx(0.09, rel=1e-12)


@pytest.mark.parametrize(
    ("name", "value", "message"),
    [
        ("μ_h", "10", "expected a number in the parameter's unit or a percentage such as '10 %', got '10'"),
        ("μ_h", "ten %", "expected a percentage such as '10 %', got 'ten %'"),
        ("μ_h", "-5 %", "the uncertainty must be a non-negative percentage, got '-5 %'"),
        ("μ_h", "nan %", "the uncertainty must be a non-negative percentage, got 'nan %'"),
        ("μ_h", -0.1, "the uncertainty must be a non-negative number, got -0.1"),
        ("μ_h", True, "the uncertainty must be a non-negative number, got True"),
        ("μ_h", math.inf, "the uncertainty must be a non-negative number, got inf"),
    ],
)
def test_bad_prior_entries(params, name, value, message):
    # Each names the file it came from and the entry.
    with pytest.raises(ParameterError) as refused:
        standard_std(params, {name: value}, source="start.toml")
    assert str(refused.value) == f"start.toml: prior of '{name}': {message}"
    assert refused.value.source == "start.toml"


def test_an_unknown_parameter_lists_the_known_ones(params):
    known = ", ".join(q.label for q in QUANTITIES)
    assert known.startswith("I_m,xx, I_m,yy, ") and ", μ_h, " in known
    with pytest.raises(ParameterError) as refused:
        standard_std(params, {"nothing": 1.0}, source="start.toml")
    assert str(refused.value) == (
        f"start.toml: prior of 'nothing': no such parameter (known: {known}, or a key prefix such as 'lever')"
    )


def test_the_prior_names_its_source(params):
    # Without a file the entries are the command line's: "prior" (standard_std and prior alike).
    base = stand_in_base(np.eye(len(QUANTITIES)))
    for call in (
        lambda **k: standard_std(params, {"μ_h": -1.0}, **k),
        lambda **k: prior(base, params, {"μ_h": -1.0}, **k),
    ):
        with pytest.raises(ParameterError, match=r"^prior: prior of 'μ_h'"):
            call()
        with pytest.raises(ParameterError, match=r"^given\.toml: prior of 'μ_h'"):
            call(source="given.toml")


def test_percentages_with_or_without_a_space_and_zero(params):
    # "10%" as "10 %": 10 % of μ_h's 0.095; "0 %" holds it (HELD of its size).
    assert standard_std(params, {"μ_h": "10%"})[INDEX["μ_h"]] == pytest.approx(0.0095, rel=1e-12)
    assert standard_std(params, {"μ_h": " 10 % "})[INDEX["μ_h"]] == pytest.approx(0.0095, rel=1e-12)
    assert standard_std(params, {"μ_h": "0 %"})[INDEX["μ_h"]] == pytest.approx(HELD * 0.095, rel=1e-12)


def test_parse_prior_option():
    assert parse_prior_option("μ_h=0.02, lever=10 %,") == {"μ_h": 0.02, "lever": "10 %"}
    # An empty item is skipped, not the end of the list.
    assert parse_prior_option("μ_h=0.02,,lever=10 %") == {"μ_h": 0.02, "lever": "10 %"}
    assert parse_prior_option("") == {}
    for bad in ("μ_h", "=3", "μ_h="):
        with pytest.raises(HipsimError) as refused:
            parse_prior_option(f"lever=10 %,{bad} ")
        assert str(refused.value) == f"--prior: expected NAME=STD or NAME=PERCENT %, comma-separated, got '{bad}'"
    # The first "=" splits: "μ_h=0.02=3" is μ_h with the value "0.02=3", no number.
    for text, name, value in (("μ_h=abc", "μ_h", "abc"), ("μ_h=0.02=3", "μ_h", "0.02=3")):
        with pytest.raises(HipsimError) as refused:
            parse_prior_option(text)
        assert str(refused.value) == f"--prior: {name}: expected a number or a percentage, got '{value}'"


def test_the_prior_propagates_through_the_base_map(params):
    # Two base parameters: m_L + 0.5·m_l, and μ_h − 2·m_l (coefficients whose squares differ from
    # their absolute values). With s(m_L) = 0.9, s(m_l) = 0.2, s(μ_h) = 0.05, the rest 0:
    #   s_b0 = √(0.9² + 0.5²·0.2²) = √0.82,  s_b1 = √(0.05² + 2²·0.2²) = √0.1625;
    #   means 3 + 0.5·1.43 = 3.715 and 0.095 − 2·1.43 = −2.765.
    T = np.zeros((2, len(QUANTITIES)))
    T[0, INDEX["m_L"]], T[0, INDEX["m_l"]] = 1.0, 0.5
    T[1, INDEX["μ_h"]], T[1, INDEX["m_l"]] = 1.0, -2.0
    standard = np.zeros(len(QUANTITIES))
    standard[[INDEX["m_L"], INDEX["m_l"], INDEX["μ_h"]]] = 0.9, 0.2, 0.05
    p = Prior(stand_in_base(T), params, standard)
    np.testing.assert_allclose(p.std, [math.sqrt(0.82), math.sqrt(0.1625)], rtol=1e-12)
    np.testing.assert_allclose(p.mean, [3.715, -2.765], rtol=1e-12)
    assert p.standard is standard
    # prior(): the same with the standard deviations of the entries (all held but three).
    entries = {q.key: 0 for q in QUANTITIES} | {"slider.mass_kg": 0.9, "lever.mass_kg": 0.2, "friction.hip_mu": 0.05}
    q = prior(stand_in_base(T), params, entries)
    np.testing.assert_allclose(q.std, [math.sqrt(0.82), math.sqrt(0.1625)], rtol=1e-6)


@pytest.mark.parametrize(
    ("rate", "cutoff", "D", "filter_ratio", "rows"),
    [
        # 1 kHz, 20 Hz: D = ⌊1000/80⌋ = 12; 1000/12/40 = 2.083; the floor 1000/12/(2·10) = 4.167.
        (1000.0, 20.0, 12, 1000 / 12 / 40, 1000 / 12 / 20),
        # 1 kHz, 5 Hz: D = 50; 1000/50/10 = 2; floor with f_c below 10 Hz: 1000/50/(2·5) = 2.
        (1000.0, 5.0, 50, 2.0, 2.0),
        # 200 Hz, 90 Hz: D = ⌊200/360⌋ = 0 → 1; 200/180 = 1.11; floor 200/20 = 10.
        (200.0, 90.0, 1, 200 / 180, 10.0),
        # 200 Hz, 99 Hz: 200/198 = 1.0101 (at least 1).
        (200.0, 99.0, 1, 200 / 198, 10.0),
        # No filter: every sample, each independent by the filter; the floor 1000/20 = 50.
        (1000.0, None, 1, 1.0, 50.0),
    ],
)
def test_rows_per_independent_row_by_hand(rate, cutoff, D, filter_ratio, rows):
    assert MODEL_ERROR_BANDWIDTH == 10.0
    log = stand_in_log(rate, cutoff)
    assert decimation(log) == D
    assert inflation(log) == pytest.approx(filter_ratio, rel=1e-12)
    assert rows_per_independent_row(log) == pytest.approx(rows, rel=1e-12)


def test_the_filter_ratio_is_never_below_one():
    # 100 Hz, 49 Hz: D = 1, 100/98 = 1.02. A 10 Hz log "filtered" at 6 Hz (above its Nyquist frequency,
    # which the reader refuses) would give 10/12 < 1: held at 1.
    assert inflation(stand_in_log(100.0, 49.0)) == pytest.approx(100 / 98, rel=1e-12)
    assert inflation(stand_in_log(10.0, 6.0)) == 1.0


# --- A starting file's [identification.prior] table, read from tiny TOML files ----------------------------------------


def test_prior_table_of_a_starting_file(tmp_path):
    path = tmp_path / "start.toml"
    path.write_text('[identification.prior]\n"μ_h" = 0.02\nlever = "10 %"\n')
    assert prior_table(path) == {"μ_h": 0.02, "lever": "10 %"}
    assert prior_table(str(path)) == {"μ_h": 0.02, "lever": "10 %"}


def test_no_file_no_table_or_an_identified_file_bring_no_prior_table(tmp_path):
    assert prior_table(None) == {}
    plain = tmp_path / "plain.toml"
    plain.write_text("[lever]\nlength_mm = 100.0\n")
    assert prior_table(plain) == {}
    empty = tmp_path / "empty.toml"
    empty.write_text("[identification]\nlever_spin = true\n")
    assert prior_table(empty) == {}
    # An identified file's own `prior` column (one mean per base parameter, beside `base`): no table of uncertainties.
    identified = tmp_path / "identified.toml"
    identified.write_text('[identification]\nbase = ["b1", "b2"]\nprior = [1.0, 2.0]\n')
    assert prior_table(identified) == {}


@pytest.mark.parametrize(
    "text",
    [
        "[identification]\nprior = 3.0\n",
        # A list without the identified file's `base` beside it is no prior table either.
        "[identification]\nprior = [1.0, 2.0]\n",
        "[identification]\nbase = 3\nprior = [1.0, 2.0]\n",
    ],
)
def test_a_prior_that_is_no_table_names_the_file_and_key(tmp_path, text):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ParameterError) as refused:
        prior_table(path)
    assert str(refused.value) == f"{path}, key 'identification.prior': expected a table of parameter = uncertainty"
    assert (refused.value.key, refused.value.source) == ("identification.prior", str(path))


def test_the_prior_table_drives_the_prior(params, tmp_path):
    # The file's 0.02 for μ_h reaches the standard deviations, and a bad entry's message names the file.
    path = tmp_path / "start.toml"
    path.write_text('[identification.prior]\n"μ_h" = 0.02\n')
    assert standard_std(params, prior_table(path), str(path))[INDEX["μ_h"]] == pytest.approx(0.02, rel=1e-12)
    path.write_text('[identification.prior]\n"μ_h" = "2"\n')
    with pytest.raises(ParameterError) as refused:
        standard_std(params, prior_table(path), str(path))
    assert str(refused.value) == (
        f"{path}: prior of 'μ_h': expected a number in the parameter's unit or a percentage such as '10 %', got '2'"
    )
