"""hipsim/stations/tolerance.py's laws: the bands as typed and as a file, each value's half band, the first-order table on
a sensitivity written by hand, and the draws (batched, for all controls at once) against the carriage commands run
one drawn machine at a time; ten samples of the ISO cycle and a few draws."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from hipsim.exceptions import ArgumentError, HipsimError, ParameterError
from hipsim.machine.parameters import load_parameters
from hipsim.motion.trajectories import iso14242
from hipsim.stations import deviations as dv
from hipsim.stations import tolerance as tolerance_module
from hipsim.stations.commands import station_commands
from hipsim.stations.tolerance import (
    ToleranceResult,
    error_sensitivity,
    half_widths,
    parse_tolerances,
    sensitivity_table,
    tolerance_batch,
    tolerance_draws,
)

CHAINS = ("ujoint", "slider", "joint", "lever", "centre")


@pytest.fixture(scope="module")
def drawing():
    return load_parameters()


@pytest.fixture(scope="module")
def cycle():
    iso = iso14242(rate=100)
    return iso.t[::10], iso.q[::10]


def test_bands_as_typed_in_mm():
    assert parse_tolerances("lever=+-0.05,ujoint=±0.2 ,") == {
        "ujoint": pytest.approx(2e-4),
        "slider": 0.0,
        "joint": 0.0,
        "lever": pytest.approx(5e-5),
        "centre": 0.0,
    }
    assert parse_tolerances(" all = 0 ") == dict.fromkeys(CHAINS, 0.0)  # a band of 0 is built exactly
    assert parse_tolerances("spline=0.3") == dict.fromkeys(CHAINS, 0.0) | {"spline": pytest.approx(3e-4)}
    assert "spline" not in parse_tolerances("all=0.1")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "--bands: no tolerance given (e.g. all=0.1 or ujoint=0.1,lever=0.05, in mm)"),
        (" , ", "--bands: no tolerance given (e.g. all=0.1 or ujoint=0.1,lever=0.05, in mm)"),
        ("lever0.1", "--bands: expected KEY=±V in mm, got 'lever0.1'"),
        (
            "spring=0.1",
            "--bands, key 'spring': unknown tolerance (known: all, ujoint, slider, joint, lever, centre, spline)",
        ),
        ("lever=-0.1", "--bands, key 'lever': expected a band ±V in mm (V >= 0), got '-0.1'"),
        ("lever=nan", "--bands, key 'lever': expected a band ±V in mm (V >= 0), got 'nan'"),
        ("lever=inf", "--bands, key 'lever': expected a band ±V in mm (V >= 0), got 'inf'"),
        ("lever=", "--bands, key 'lever': expected a band ±V in mm (V >= 0), got ''"),
        # The key ends at the first "=", and text with "=" is a band even when it ends in .toml.
        ("lever=0.1=2", "--bands, key 'lever': expected a band ±V in mm (V >= 0), got '0.1=2'"),
        ("lever=0.1.toml", "--bands, key 'lever': expected a band ±V in mm (V >= 0), got '0.1.toml'"),
    ],
)
def test_bad_bands_are_refused_by_key(text, message):
    with pytest.raises(ParameterError) as error:
        parse_tolerances(text)
    assert str(error.value) == message


def test_bands_from_a_toml_file(tmp_path):
    top = tmp_path / "top.TOML"
    top.write_text("all = 0.1\nlever = 0.02\n")
    assert parse_tolerances(str(top)) == dict.fromkeys(CHAINS, pytest.approx(1e-4)) | {"lever": pytest.approx(2e-5)}
    table = tmp_path / "tol.toml"
    table.write_text("other = 1\n[tolerance]\nslider = 0.3\n")
    assert parse_tolerances(str(table))["slider"] == pytest.approx(3e-4)
    with pytest.raises(ParameterError) as error:
        parse_tolerances(str(tmp_path / "missing.toml"))
    assert str(error.value) == f"{tmp_path / 'missing.toml'}: no such tolerance file"
    bad = tmp_path / "bad.toml"
    bad.write_text("lever = \n")
    with pytest.raises(ParameterError, match=r"bad\.toml: cannot read the tolerance file \("):
        parse_tolerances(str(bad))
    typed = tmp_path / "text.toml"
    typed.write_text("lever = 'wide'\n")
    with pytest.raises(
        ParameterError, match=r"text\.toml, key 'lever': expected a band ±V in mm \(V >= 0\), got 'wide'"
    ):
        parse_tolerances(str(typed))
    table.write_text("[tolerance]\n")
    with pytest.raises(ParameterError, match=r"tol\.toml: no tolerance given"):
        parse_tolerances(str(table))


def test_half_widths_by_family():
    widths = half_widths({"lever": 2e-4, "centre": 1e-4})
    names = dv.names()
    assert widths.shape == (dv.COUNT,)
    assert widths[names.index("lever_23")] == 2e-4 and widths[names.index("centre_z_1")] == 1e-4
    assert widths[names.index("ujoint_x_11")] == 0.0 and widths[names.index("spline_x_1")] == 0.0


def _sensitivity() -> np.ndarray:
    """Two samples; lever_11 moves m_1's α by 1 and 3 rad/m, lever_21 m_2's γ by 2 rad/m, the seat m_1's β by 4."""
    S = np.zeros((2, 2, 3, dv.COUNT))
    names = dv.names()
    S[:, 0, 0, names.index("lever_11")] = [1.0, 3.0]
    S[:, 1, 2, names.index("lever_21")] = 2.0
    S[:, 0, 1, names.index("spline_y_1")] = 4.0
    return S


def test_the_first_order_table_by_hand():
    """Bands ±√3 mm on the levers, ±√3/2 mm on the seat: V²/3 = 1e-6 and 0.25e-6 m². Mean squares: lever_11
    (1 + 9)/2·1e-6 = 5e-6 in α, lever_21 4e-6 in γ, spline_y_1 16·0.25e-6 = 4e-6 in β; 13e-6 in all."""
    widths = half_widths({"lever": math.sqrt(3) * 1e-3, "spline": math.sqrt(3) / 2 * 1e-3})
    rows = sensitivity_table(_sensitivity(), widths, (0, 1))
    assert [r["value"] for r in rows[:3]] == ["lever_11", "lever_21", "spline_y_1"]  # largest first, then δ's order
    lever, other, seat = rows[:3]
    assert lever["chain"] == "11" and lever["family"] == "lever" and lever["share"] == pytest.approx(5 / 13)
    assert lever["rms_deg"] == pytest.approx([math.degrees(math.sqrt(5e-6)), 0.0, 0.0])
    assert other["chain"] == "21" and other["share"] == pytest.approx(4 / 13)
    assert other["rms_deg"] == pytest.approx([0.0, 0.0, math.degrees(2e-3)])
    assert seat["chain"] == "intermediate" and seat["family"] == "spline" and seat["share"] == pytest.approx(4 / 13)
    assert len(rows) == dv.COUNT and sum(r["share"] for r in rows) == pytest.approx(1.0)
    centre = next(r for r in rows if r["value"] == "centre_y_2")
    assert centre["chain"] == "centre 2" and centre["family"] == "centre" and centre["share"] == 0.0
    # Only the follower m_1: lever_21 moves m_2 alone.
    follower = {r["value"]: r["share"] for r in sensitivity_table(_sensitivity(), widths, (0,))}
    assert follower["lever_11"] == pytest.approx(5 / 9) and follower["lever_21"] == 0.0
    assert follower["spline_y_1"] == pytest.approx(4 / 9)


def test_no_seat_band_no_seat_rows_and_no_error_no_share():
    widths = half_widths({"lever": 1e-3})
    rows = sensitivity_table(_sensitivity(), widths)
    assert len(rows) == dv.COUNT - 3 and not any(r["value"].startswith("spline") for r in rows)
    assert rows[0]["value"] == "lever_11" and rows[0]["share"] == pytest.approx(2.5 / (2.5 + 4 / 3 * 1.5))
    quiet = sensitivity_table(np.zeros((2, 2, 3, dv.COUNT)), widths)
    assert all(r["share"] == 0.0 for r in quiet)


def test_the_percentile_of_the_peaks_or_the_rms():
    rms = np.arange(1.0, 11.0)[:, None, None, None] * np.ones((1, 1, 2, 3))
    result = ToleranceResult({}, ("2",), rms, 10 * rms, {}, 0)
    assert result.percentile()[0, 0, 0] == pytest.approx(9.55)
    assert result.percentile("peak", 50.0)[0, 1, 2] == pytest.approx(55.0)


def _expected(drawing, t, q, bands, controls, draws, seed, weights=(1.0, 1.0)):
    """Each draw's machine made and commanded one at a time: its RMS and peak error per control, platform, angle."""
    rng = np.random.default_rng([seed, 0])
    widths = half_widths(bands)
    deltas = np.zeros((draws, dv.COUNT))
    deltas[:, :48] = rng.uniform(-1.0, 1.0, (draws, 48)) * widths[:48]
    if np.any(widths[48:]):
        deltas[:, 48:] = rng.uniform(-1.0, 1.0, (draws, 3)) * widths[48:]
    rms = np.empty((draws, len(controls), 2, 3))
    peak = np.empty_like(rms)
    for k in range(draws):
        machine = dv.machine(drawing, deltas[k])
        for c, control in enumerate(controls):
            e = station_commands(machine, t, q, control, weights).errors
            rms[k, c], peak[k, c] = np.sqrt((e**2).mean(axis=0)), np.abs(e).max(axis=0)
    return rms, peak


@pytest.mark.parametrize("bands", ["all=0.3", "all=0.2,spline=0.5"])
def test_the_draws_are_the_machines_commanded_one_by_one(drawing, cycle, bands, monkeypatch):
    """Batches of 2 over 3 draws; controls 1 and 2 solved for all the batch at once (with a seat, control 1 by the
    commands): each draw's RMS and peak are those of its machine commanded alone."""
    monkeypatch.setattr(tolerance_module, "BATCH", 2)
    t, q = cycle
    tol = parse_tolerances(bands)
    seen = []
    result = tolerance_draws(
        drawing,
        t,
        q,
        tol,
        ("1", "2", "both"),
        draws=3,
        seed=4,
        weights=(1.0, 2.0),
        workers=0,
        progress=lambda *a: seen.append(a),
    )
    assert seen == [(2, 3), (3, 3)]
    # Batch 2 draws from its own seed [4, 2]: the expected draws are batch by batch.
    first = _expected(drawing, t, q, tol, ("1", "2", "both"), 2, 4, (1.0, 2.0))
    rng = np.random.default_rng([4, 2])
    widths = half_widths(tol)
    delta = np.zeros(dv.COUNT)
    delta[:48] = rng.uniform(-1.0, 1.0, (1, 48))[0] * widths[:48]
    if np.any(widths[48:]):
        delta[48:] = rng.uniform(-1.0, 1.0, (1, 3))[0] * widths[48:]
    machine = dv.machine(drawing, delta)
    e = station_commands(machine, t, q, "2").errors
    np.testing.assert_allclose(result.rms[:2], first[0], rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(result.peak[:2], first[1], rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(result.rms[2, 1], np.sqrt((e**2).mean(axis=0)), rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(result.peak[2, 1], np.abs(e).max(axis=0), rtol=1e-9, atol=1e-15)
    assert result.controls == ("1", "2", "both") and result.seed == 4 and result.bands == tol
    assert not result.rms.flags.writeable
    assert set(result.sensitivity) == {"1", "2", "both"}
    # The follower's table, under the weights: control 1's is m_2's, control 2's m_1's, both's of the two.
    for control, platforms in (("1", (1,)), ("2", (0,)), ("both", (0, 1))):
        S = error_sensitivity(drawing, q, control, (1.0, 2.0))
        assert result.sensitivity[control] == sensitivity_table(S, widths, platforms)


@pytest.mark.parametrize(("bands", "controls"), [("all=0.3", ("1", "2")), ("all=0.2,spline=0.5", ("2",))])
def test_controls_1_and_2_are_solved_for_the_whole_batch(drawing, cycle, bands, controls, monkeypatch):
    """Small bands: every draw converges in the batched path (with a seat, control 2's m_1 sees the carriages lowered
    by the lift), none is left to the commands one machine at a time, and each is its machine commanded alone."""
    t, q = cycle
    tol = parse_tolerances(bands)
    rms, peak = _expected(drawing, t, q, tol, controls, 2, 4)

    def one_at_a_time(*args, **kwargs):
        raise AssertionError("a draw was left to the commands one machine at a time")

    monkeypatch.setattr(tolerance_module, "station_commands", one_at_a_time)
    setup = tolerance_module._Setup(drawing, t, q, controls, half_widths(tol), (1.0, 1.0), 4)
    first, batch_rms, batch_peak, failure = tolerance_batch((0, 2), setup)
    assert first == 0 and failure is None
    np.testing.assert_allclose(batch_rms, rms, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(batch_peak, peak, rtol=1e-9, atol=1e-15)


def test_a_batch_names_the_draw_and_chain_out_of_reach(drawing, cycle):
    t, q = cycle
    setup = tolerance_module._Setup(drawing, t, q, ("2",), half_widths({"lever": 0.045}), (1.0, 1.0), 0)
    first, rms, peak, failure = tolerance_batch((10, 3), setup)
    assert first == 10 and len(rms) == len(peak) < 3
    assert (
        failure is not None and failure.startswith(f"draw {11 + len(rms)}: ") and failure.endswith(" is out of reach")
    )
    # The desired motion is within reach of each platform alone, so the commands' own refusal is what is named.
    assert ": platform 1: no platform orientation gives the slider heights (" in failure
    with pytest.raises(HipsimError) as error:
        tolerance_draws(drawing, t, q, {"lever": 0.045}, draws=2, workers=0)
    assert re.match(r"--bands: draw [12]: ", str(error.value))
    assert str(error.value).endswith(
        " is out of reach on the desired motion: the band is too wide for this machine (nothing written)"
    )


def test_controls_and_draws_are_checked(drawing, cycle):
    t, q = cycle
    with pytest.raises(ArgumentError, match="control: expected one of 1, 2, both, got 'all'"):
        tolerance_draws(drawing, t, q, {}, ("2", "all"), workers=0)
    with pytest.raises(ArgumentError, match="draws: expected at least 1, got 0"):
        tolerance_draws(drawing, t, q, {}, draws=0, workers=0)
    one = tolerance_draws(drawing, t, q, {"lever": 1e-4}, ("2",), draws=1, workers=0)
    assert one.rms.shape == (1, 1, 2, 3) and np.all(one.rms[0, 0, 1] < 1e-12) and one.rms[0, 0, 0].max() > 0


@pytest.mark.parametrize(
    ("name", "chain"), [("lever_22", "chain 22"), ("lever_13", "chain 13"), ("ujoint_x_21", "chain 21")]
)
def test_the_chain_out_of_reach_is_named(drawing, cycle, name, chain):
    """A lever 0.3 m short (or a U-joint 0.3 m off) cannot reach: that chain is named, platform 1's looked at first."""
    delta = np.zeros(dv.COUNT)
    delta[dv.names().index(name)] = -0.3 if name.startswith("lever") else 0.3
    assert tolerance_module._out_of_reach(dv.machine(drawing, delta), cycle[1]) == chain
    assert tolerance_module._out_of_reach(drawing, cycle[1]) is None


def test_the_table_is_a_mean_over_the_samples():
    """The same samples twice: the same table (a sum over them would double it)."""
    widths = half_widths({"lever": 1e-3, "spline": 1e-3})
    twice = sensitivity_table(np.concatenate([_sensitivity()] * 3), widths)
    assert twice == sensitivity_table(_sensitivity(), widths)
