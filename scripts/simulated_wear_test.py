#!/usr/bin/env python3
"""A full simulated wear test through ``hipsim wear --test``: measured rates, fitted k and predictions against the truth.

Run:  .venv/bin/python scripts/simulated_wear_test.py [FOLDER] [--per-chain]

The test is made by tests/wear_test_synthetic.py (its own route: the truth
written down): two stations with different true wear factors, loads (station
2's steps up at 2.5 Mc) and soak uptake, bedding-in, balance noise of
0.05 mg; 20 snapshots of 3 cycles every 0.25 Mc. Prints, per station, the
measured steady-state rate against the true mean rate over the same cycles,
the fitted local k against the true k, and predicted against measured volume
per interval between stops.
"""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from wear_test_synthetic import TRUTH, platform_i0, write_simulated_test  # noqa: E402


def main() -> None:
    words = [word for word in sys.argv[1:] if word != "--per-chain"]
    folder = Path(words[0]) if words else Path(tempfile.mkdtemp(prefix="hipsim-wear-test-"))
    truth, geometry = TRUTH, None
    if "--per-chain" in sys.argv:
        from stations_synthetic import deviated

        geometry = deviated(3, 0.3)
        truth = dataclasses.replace(TRUTH, i0_local=platform_i0(geometry))
        print(
            f"per-chain machine: each platform's true ΣW·dA per cycle {truth.i0_local[0]:.4f}, {truth.i0_local[1]:.4f} N·m"
        )
    write_simulated_test(folder, truth, geometry=geometry)
    hipsim = str(Path(sys.executable).parent / "hipsim")
    start = time.perf_counter()
    run = subprocess.run(
        [
            hipsim,
            "wear",
            "--test",
            str(folder),
            "--workers",
            "2",
            "--summary-format",
            "json",
            "--out",
            str(folder / "stops.csv"),
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    seconds = time.perf_counter() - start
    result = json.loads(run.stdout)
    print(f"hipsim wear --test {folder} --workers 2: {seconds:.1f} s; verdict {result['verdict']}")
    for j, name in enumerate(("1", "2")):
        s = result["stations"][name]
        c0, c1 = s["from_cycle"], s["cycles"][-1]
        true_rate = truth.rate(j, c0, c1)
        low, high = s["wear_rate_ci95_mm3_per_Mc"]
        k = s["fitted"]["k_local_mm3_per_Nm"]
        klow, khigh = s["fitted"]["k_local_ci95"]
        print(
            f"station {name}: rate {s['wear_rate_mm3_per_Mc']:.3f} mm³/Mc [{low:.3f}, {high:.3f}] from {c0 / 1e6:g} Mc "
            f"({s['bedding_in']}); truth {true_rate:.3f} ({100 * (s['wear_rate_mm3_per_Mc'] / true_rate - 1):+.2f} %)"
        )
        print(
            f"  fitted k local {k:.4g} [{klow:.4g}, {khigh:.4g}] mm³/(N·m); truth {truth.k[j]:.4g} "
            f"({100 * (k / truth.k[j] - 1):+.2f} %); k force-track {s['fitted']['k_force_track_mm3_per_Nm']:.4g}"
        )
        errors = [row["predicted_mm3"] - row["measured_mm3"] for row in s["intervals"]]
        print("  predicted − measured per 0.5 Mc interval [mm³]: " + ", ".join(f"{e:+.2f}" for e in errors))
        rms = ", ".join(f"{x:.2g}" for x in s["motion_error"]["rms_deg"])
        print(f"  motion error against ISO, RMS α, β, γ: {rms} deg ({s['motion']})")
    d = result["differences"][0]
    truth_difference = truth.rate(1, result["stations"]["2"]["from_cycle"], 5e6) - truth.rate(
        0, result["stations"]["1"]["from_cycle"], 5e6
    )
    print(
        f"station 2 − 1: {d['difference_mm3_per_Mc']:+.3f} mm³/Mc [{d['ci95_mm3_per_Mc'][0]:+.3f}, "
        f"{d['ci95_mm3_per_Mc'][1]:+.3f}]; truth {truth_difference:+.3f}"
    )


if __name__ == "__main__":
    main()
