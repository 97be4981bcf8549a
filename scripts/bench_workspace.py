#!/usr/bin/env python3
"""Speed of the default singularity map, next to a per-orientation Python loop measured in the same run.

Run:  .venv/bin/python scripts/bench_workspace.py [--quick]

One core: the BLAS/OpenMP thread counts are pinned to 1 before NumPy loads
(the map's 3x3 arithmetic is element-wise and does not use BLAS anyway).
Target (issue 7): the default map (≥ 100 × 100 orientations × 5 rotations) in under 2 s.
"""

from __future__ import annotations

import os

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import hipsim  # noqa: E402
from hipsim import workspace  # noqa: E402


def best_time(function, repeats: int = 5) -> float:
    """Smallest wall time of ``repeats`` calls, in [s]."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def bench_workspace(quick: bool = False) -> None:
    """Print the default map's time and the extrapolated time of a per-orientation loop."""
    params = hipsim.load_parameters()
    smap = workspace.singularity_map(params)  # warm-up, and the grid size
    n = smap.orientations
    vectorised = best_time(lambda: workspace.singularity_map(params, progress=False))

    # Baseline: the same orientations one at a time from Python, J from positions
    # and its singular values from LAPACK, as a straightforward script would do.
    alpha, beta, gamma = smap.alpha_deg, smap.beta_deg, smap.gamma_deg
    subset = 500 if quick else 3000
    rng = np.random.default_rng(0)
    picks = np.column_stack([rng.choice(alpha, subset), rng.choice(beta, subset), rng.choice(gamma, subset)])
    q = np.radians(picks)

    def loop():
        out = np.empty(subset)
        for k in range(subset):
            J, reachable = workspace.pose_jacobian(params, q[k : k + 1])
            s = np.linalg.svd(J[0], compute_uv=False) if reachable[0] else None
            out[k] = s[-1] / s[0] if s is not None else np.nan
        return out

    looped = best_time(loop, repeats=2) / subset * n
    print("Singularity map, default grid")
    print(
        f"  {smap.alpha_deg.size} α × {smap.beta_deg.size} β × {smap.gamma_deg.size} γ = {n:,} orientations: "
        f"vectorised {vectorised:.3f} s ({n / vectorised:,.0f} orientations/s)"
    )
    print(f"  per-orientation Python loop (measured on {subset:,}, extrapolated): {looped:.1f} s  -> {looped / vectorised:.0f}x")
    print(f"  target: < 2 s   {'OK' if vectorised < 2.0 else 'MISSED'}")

    sweep_time = best_time(lambda: workspace.offset_sweep(params, progress=False), repeats=2)
    print(f"  offset sweep, {workspace.DEFAULT_DELTAS_DEG.size} δ values × ISO cycle at 1 kHz: {sweep_time:.2f} s")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer orientations in the slow baseline")
    args = parser.parse_args()
    bench_workspace(args.quick)


if __name__ == "__main__":
    main()
