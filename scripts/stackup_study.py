"""When does the paper's observation appear? The intermediate chain's stack-up against the chains' own deviations.

The paper (its Fig. 7) sees the follower m_1 track worse than the controlled m_2, and the error about Z the
largest. This study drives the ISO 14242-1 cycle (100 Hz) on simulated machines as built and asks, per machine,
whether both hold. Two commands, as a lab has them:

- ``drawing``: the carriages from the drawing's inverse kinematics (encoder feedback through the drawing's model),
  so both platforms carry their own deviations;
- ``sensor``: m_2's own inverse kinematics (its attitude sensor in the loop, perfect tracking of m_2), so m_1
  carries everything.

Machines: the six chains drawn uniformly within ±CHAINS mm per value (0 for none), the stack-up's seat e drawn in a
uniform random direction with |e| = SEAT mm (or along one axis). Usage:

    .venv/bin/python scripts/stackup_study.py [--draws 100]
"""

from __future__ import annotations

import argparse

import numpy as np

import hipsim
from hipsim.analytic.stations import carriages_for_platform
from hipsim.machine.chains import ChainGeometry
from hipsim.stations.commands import attitudes

PARAMS = hipsim.load_parameters()


def errors(machine, q_d: np.ndarray, command: str) -> np.ndarray:
    """RMS error in [deg] per platform and angle, (2, 3), of one machine under one command."""
    L = carriages_for_platform(PARAMS if command == "drawing" else machine, q_d, 2)
    q = attitudes(machine, L, guess=q_d)
    return np.degrees(np.sqrt(((q - q_d[:, None]) ** 2).mean(axis=0)))


def machines(draws: int, chains_mm: float, seat_mm: float, axis: int | None, seed: int):
    rng, turn = np.random.default_rng(seed), np.random.default_rng(seed + 1)  # the same chains in every case
    for _ in range(draws):
        chains = rng.uniform(-chains_mm, chains_mm, 48) * 1e-3
        if axis is None:
            direction = turn.normal(size=3)
            direction /= np.linalg.norm(direction)
        else:
            direction = np.eye(3)[axis]
        geometry = ChainGeometry.from_vector(np.concatenate([chains, seat_mm * 1e-3 * direction]))
        yield PARAMS.replace(geometry=None if geometry.is_drawing() else geometry)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--draws", type=int, default=100, help="machines per case (default 100)")
    args = parser.parse_args()
    q_d = hipsim.iso14242(rate=100).q
    cases: list[tuple[float, float, int | None]] = [(c, s, None) for c in (0.1, 0.3) for s in (0.0, 0.1, 0.3, 0.5, 1.0)]
    cases += [(0.0, 0.3, None)] + [(0.3, 0.3, k) for k in range(3)]
    print(
        "chains ±mm | seat mm (axis) | command | m_1 RMS α β γ [°] (median) | m_2 RMS α β γ [°] | "
        "m_1 worse | γ largest of m_1 | both"
    )
    for chains_mm, seat_mm, axis in cases:
        for command in ("drawing", "sensor"):
            rms = np.array([errors(m, q_d, command) for m in machines(args.draws, chains_mm, seat_mm, axis, 1)])
            worse = np.linalg.norm(rms[:, 0], axis=1) > np.linalg.norm(rms[:, 1], axis=1)
            z_largest = np.argmax(rms[:, 0], axis=1) == 2
            where = "random" if axis is None else "xyz"[axis]
            m1, m2 = np.median(rms[:, 0], axis=0), np.median(rms[:, 1], axis=0)
            print(
                f"{chains_mm:g} | {seat_mm:g} ({where}) | {command} | "
                f"{m1[0]:.3f} {m1[1]:.3f} {m1[2]:.3f} | {m2[0]:.3f} {m2[1]:.3f} {m2[2]:.3f} | "
                f"{worse.mean():.0%} | {z_largest.mean():.0%} | {(worse & z_largest).mean():.0%}",
                flush=True,
            )


if __name__ == "__main__":
    main()
