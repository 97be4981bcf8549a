"""The check command's tables (hipsim.cli.check._print_comparisons): a row at the tolerance is ok, above it FAILS; a
comparison for information has no verdict. The cross-check itself: analysis/test_crosscheck.py."""

from __future__ import annotations

from types import SimpleNamespace

from hipsim.analysis.crosscheck import TOLERANCE
from hipsim.cli.check import _print_comparisons


def test_a_row_at_the_tolerance_passes_and_one_above_fails(capsys):
    rows = [("tau_1", 1e-9, TOLERANCE), ("tau_2", 2e-9, TOLERANCE * 1.01)]
    comparison = SimpleNamespace(
        name="pinocchio", description="closed chain", required=True, rows=rows, ok=False, worst=TOLERANCE * 1.01
    )
    _print_comparisons([comparison])
    out = capsys.readouterr().out
    tau_1 = next(line for line in out.splitlines() if line.lstrip().startswith("tau_1"))
    tau_2 = next(line for line in out.splitlines() if line.lstrip().startswith("tau_2"))
    assert tau_1.rstrip().endswith("ok") and tau_2.rstrip().endswith("FAILS")
    assert "pinocchio: closed chain (must agree)" in out and "≤ 1e-08" in out
    assert "-> pinocchio: largest relative difference 1.010e-08, OUT OF tolerance 1e-08" in out


def test_a_comparison_for_information_has_no_verdict(capsys):
    comparison = SimpleNamespace(
        name="mujoco", description="soft closures", required=False, rows=[("tau_1", 0.5, 0.01)], ok=True, worst=0.01
    )
    _print_comparisons([comparison])
    out = capsys.readouterr().out
    assert "(for information: not a check)" in out and "ok" not in out and "FAILS" not in out
    assert "-> mujoco: largest relative difference 1.000e-02 (for information" in out
