"""The workspace command's own text (hipsim.cli.workspace): the sweep table's picks (every
tenth δ, the last, the built machine, the best margin and torque) and the reasons of infeasible ones, from a sweep
made by hand. The maps and the sweep themselves: design/test_workspace.py; the JSON (null for NaN):
design/test_workspace_summary.py."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np

from hipsim.cli.workspace import _sweep_table


def test_the_sweep_table_picks_and_explains_its_rows():
    n = 21  # δ = 10 … 30: every other row picked (21 // 10 = 2), the last, and the marked ones
    deltas = np.arange(10.0, 31.0)
    cond = np.linspace(0.1, 0.3, n)
    cond[7] = 0.9  # the largest margin, at δ = 17 (an odd row: picked for it)
    torque = np.full(n, 500.0)
    torque[9] = 100.0  # the lowest peak torque, at δ = 19
    feasible = np.ones(n, bool)
    feasible[[20, 4]] = False
    sweep: Any = SimpleNamespace(
        deltas_deg=deltas,
        feasible=feasible,
        built_index=5,
        cond_inv_min=cond,
        tau_peak_Nmm=torque,
        stroke_max_mm=np.full(n, 40.0),
        out_of_reach=np.where(np.arange(n) == 20, 3, 0),
        singular=np.zeros(n, int),
        crossings=np.where(np.arange(n) == 4, 2, 0),
    )
    lines = _sweep_table(sweep).splitlines()[2:]
    shown = [float(line.split()[0]) for line in lines]
    assert shown == [10, 12, 14, 15, 16, 17, 18, 19, 20, 22, 24, 26, 28, 30]
    by_delta = dict(zip(shown, lines))
    assert by_delta[15].endswith("built") and by_delta[17].endswith("largest margin")
    assert by_delta[19].endswith("lowest peak torque") and "100.0" in by_delta[19]
    assert by_delta[14].endswith("passes through a singularity 2×") and "—" in by_delta[14]
    assert by_delta[30].endswith("out of reach at 3 samples")
