#!/usr/bin/env python3
"""Speed of hipsim's models, each next to a baseline measured in the same run.

Run:  .venv/bin/python scripts/bench.py [--quick]

Figures are wall-clock on this machine, best of a few repeats, one process
(NumPy may use its BLAS threads; the 3x3 work here is not BLAS-bound).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import hipsim
from hipsim.dynamics import inverse_dynamics
from hipsim.kinematics import kinematics


def best_time(function, repeats: int = 5) -> float:
    """Smallest wall time of ``repeats`` calls, in [s]."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def analytic(params, trajectory):
    kin = kinematics(params, trajectory)
    return inverse_dynamics(params, kin, trajectory.Fe)


def bench_analytic(params, quick: bool) -> None:
    print("Analytic kinematics + inverse dynamics on the ISO 14242-1 cycle")
    print(f"  {'rate':>8}  {'vectorised [samples/s]':>24}  {'per-sample loop [samples/s]':>28}  {'speed-up':>8}")
    for rate in (1000, 10000):
        trajectory = hipsim.iso14242(rate=rate)
        vectorised = len(trajectory) / best_time(lambda: analytic(params, trajectory))
        # Baseline: the same functions called one sample at a time from Python.
        subset = trajectory.slice(slice(0, 200 if quick else 1000))
        singles = [subset.slice(slice(k, k + 1)) for k in range(len(subset))]
        looped = len(singles) / best_time(lambda: [analytic(params, s) for s in singles], repeats=2)
        print(f"  {rate:>6} Hz  {vectorised:>24,.0f}  {looped:>28,.0f}  {vectorised / looped:>7.0f}x")
    print("  target: >= 500,000 samples/s at 10 kHz")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer samples in the slow baselines")
    args = parser.parse_args()
    params = hipsim.load_parameters()
    bench_analytic(params, args.quick)


if __name__ == "__main__":
    main()
