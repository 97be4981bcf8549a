"""The ISO check's page (hipsim.present.iso_figures): the verdict block's sentences and the figure's cycles coloured
by their own verdict, on two cycles of the built-in motion, one of them moved off the waveform here."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hipsim.motion.iso_compliance import iso_check
from hipsim.motion.trajectories import iso14242
from hipsim.present.iso_figures import iso_summary, iso_verdict, plot_iso_check


@pytest.fixture(scope="module")
def run():
    iso = iso14242(rate=50.0, cycles=2)
    return iso.t, iso.q.copy(), iso.Fe


def test_a_run_on_the_waveform_passes_and_names_the_closest_quantity(run):
    t, q, load = run
    q[:, 1] += math.radians(1.0)  # β 1° off everywhere: the quantity closest to its tolerance
    check = iso_check(t, q, load, periodic=True)
    verdict = iso_verdict(iso_summary(check))
    assert (verdict.state, verdict.word) == ("pass", "PASS")
    assert verdict.lines[0].startswith("Every one of 2 whole cycle(s) kept every angle")
    assert verdict.lines[1] == (
        f"Closest: beta, worst deviation {check.worst('beta'):.3g} deg against ±3 deg "
        "(tolerances assumed: confirm them against your copy of ISO 14242-1)."
    )


def test_a_cycle_off_the_waveform_fails_and_is_drawn_red(run):
    t, q, load = run
    q[t >= 1.0, 0] += math.radians(10.0)  # the second cycle's α 10° off
    check = iso_check(t, q, load, periodic=True)
    verdict = iso_verdict(iso_summary(check))
    assert (verdict.state, verdict.word) == ("fail", "FAIL")
    assert verdict.lines[0] == f"alpha left the tolerance; alpha in 1 of {len(check.cycles)} cycle(s)."
    assert verdict.lines[1] == f"Worst alpha: {check.worst('alpha'):.3g} deg against ±3 deg."
    fig = plot_iso_check(check, t, q, load)
    alpha = fig.axes[0]
    colours = [line.get_color() for line in alpha.get_lines()[: len(check.cycles)]]
    assert colours == ["tab:red" if not ok else "tab:blue" for ok in check.passes("alpha")]
    assert "FAIL in 1 of" in alpha.get_title()
    phase = np.asarray(alpha.get_lines()[0].get_xdata())
    np.testing.assert_allclose(np.diff(phase), 2.0, rtol=1e-9)  # % of the cycle: 50 samples a cycle
    assert 0.0 <= phase[0] < 2.0 and phase[-1] < 100.0
