"""When does the paper's observation appear? The intermediate chain's stack-up against the chains' own deviations.

The paper (its Fig. 7) sees the follower m_1 track worse than the controlled m_2, and the error about Z the
largest. This study drives the ISO 14242-1 cycle (100 Hz) on simulated machines as built and asks, per machine,
whether both hold. Two commands, as a lab has them:

- ``drawing``: the carriages from the drawing's inverse kinematics (encoder feedback through the drawing's model),
  so both platforms carry their own deviations;
- ``sensor``: the controlled platform's own inverse kinematics (its attitude sensor in the loop, perfect tracking
  of it), so the follower carries everything.

``--control 1`` controls m_1 instead (the follower is then m_2, and m_1's own inverse kinematics with a stack-up is
the fixed point through m_2's attitude). Machines: the six chains drawn uniformly within ±CHAINS mm per value (0 for
none), the stack-up's seat e drawn in a uniform random direction with |e| = SEAT mm (or along one axis).

``--closed-loop`` runs the servo loop instead, one ISO cycle at 1 kHz with the augmented PD, on one hidden machine
(chains ±0.3 mm, a seat of ``--seat`` mm in a random direction) as the exact analytic per-chain plant
(:class:`hipsim.control.chain_plant.ChainPlant`): the drawing and the machine calibrated from two sensor logs
(``hipsim.stations.calibrate``) as the controller's model, encoders (exact readings) and a noiseless attitude
sensor as feedback, m_2 and m_1 controlled; RMS per platform and angle beside the kinematic prediction. Usage:

    .venv/bin/python scripts/stackup_study.py [--draws 100] [--control 2]
    .venv/bin/python scripts/stackup_study.py --closed-loop [--seat 1.0]
"""

from __future__ import annotations

import argparse

import numpy as np

import hipsim
from hipsim.analytic.stations import carriages_for_platform
from hipsim.machine.chains import ChainGeometry
from hipsim.machine.parameters import Parameters
from hipsim.stations.commands import attitudes

PARAMS = hipsim.load_parameters()


def errors(machine: Parameters, q_d: np.ndarray, command: str, control: int = 2) -> np.ndarray:
    """RMS error in [deg] per platform and angle, (2, 3), of one machine under one command."""
    return predicted(machine, PARAMS if command == "drawing" else machine, q_d, control)


def predicted(machine: Parameters, model: Parameters, q_d: np.ndarray, control: int) -> np.ndarray:
    """RMS error [deg], (2, 3), when the carriages are the model's for the controlled platform at q_d."""
    L = carriages_for_platform(model, q_d, control)
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


def kinematic(draws: int, control: int) -> None:
    q_d = hipsim.iso14242(rate=100).q
    cases: list[tuple[float, float, int | None]] = [(c, s, None) for c in (0.1, 0.3) for s in (0.0, 0.1, 0.3, 0.5, 1.0)]
    cases += [(0.0, 0.3, None)] + [(0.3, 0.3, k) for k in range(3)]
    c, f = control - 1, 2 - control
    print(
        f"control = {control}: chains ±mm | seat mm (axis) | command | follower m_{f + 1} RMS α β γ [°] (median) | "
        f"controlled m_{c + 1} RMS α β γ [°] | follower worse | γ largest of the follower | both"
    )
    for chains_mm, seat_mm, axis in cases:
        for command in ("drawing", "sensor"):
            rms = np.array([errors(m, q_d, command, control) for m in machines(draws, chains_mm, seat_mm, axis, 1)])
            worse = np.linalg.norm(rms[:, f], axis=1) > np.linalg.norm(rms[:, c], axis=1)
            z_largest = np.argmax(rms[:, f], axis=1) == 2
            where = "random" if axis is None else "xyz"[axis]
            mf, mc = np.median(rms[:, f], axis=0), np.median(rms[:, c], axis=0)
            print(
                f"{chains_mm:g} | {seat_mm:g} ({where}) | {command} | "
                f"{mf[0]:.3f} {mf[1]:.3f} {mf[2]:.3f} | {mc[0]:.3f} {mc[1]:.3f} {mc[2]:.3f} | "
                f"{worse.mean():.0%} | {z_largest.mean():.0%} | {(worse & z_largest).mean():.0%}",
                flush=True,
            )


def calibrated_model(hidden: Parameters, seed: int) -> Parameters:
    """The hidden machine calibrated from two logs (2.4 s at 500 Hz each, 0.05° sensor noise), as a lab would."""
    from hipsim.stations import CalibrationLog, calibrate

    rng = np.random.default_rng(seed)
    logs = []
    for k in range(2):
        t = np.arange(1200) / 500.0
        q = np.zeros((t.size, 3))
        for f in (0.31, 0.73, 1.17, 1.91):
            q += np.radians(rng.uniform(2.0, 5.0, 3)) * np.sin(
                2 * np.pi * f * t[:, None] + rng.uniform(0, 2 * np.pi, 3)
            )
        L = carriages_for_platform(hidden, q, 2)
        sensors = attitudes(hidden, L, guess=q) + rng.normal(0.0, np.radians(0.05), (t.size, 2, 3))
        logs.append(CalibrationLog(f"log{k}", t, L, sensors))
    return calibrate(logs, PARAMS).machine


def closed_loop(seat_mm: float, seed: int, duration: float = 1.0) -> None:
    from hipsim.control.chain_plant import ChainPlant
    from hipsim.control.feedback import EncoderFeedback, SensorFeedback
    from hipsim.control.machine_loop import ModelPD, controlled_machine, model_feedforward, run_machine
    from hipsim.motion.trajectories import iso14242_at

    rng = np.random.default_rng(seed)
    direction = rng.normal(size=3)
    seat = seat_mm * 1e-3 * direction / np.linalg.norm(direction)
    hidden = PARAMS.replace(
        geometry=ChainGeometry.from_vector(np.concatenate([rng.uniform(-0.3, 0.3, 48) * 1e-3, seat]))
    )
    calibrated = calibrated_model(hidden, seed + 1)
    assert calibrated.geometry is not None
    print(
        f"seat e = {np.round(seat * 1e3, 3).tolist()} mm; calibrated {np.round(calibrated.geometry.spline * 1e3, 3).tolist()} mm"
    )
    print("control | model | feedback | m_1 RMS α β γ [°] | m_2 RMS α β γ [°] | kinematic prediction m_1 | m_2")
    q_d = iso14242_at(np.arange(round(duration * 1000)) / 1000.0).q
    for control in (2, 1):
        plant = ChainPlant(controlled_machine(hidden, control))
        for name, model in (("drawing", PARAMS), ("calibrated", calibrated)):
            ff = model_feedforward(model, control, iso14242_at, 1000.0, duration)
            for feedback in (
                EncoderFeedback(model, control, step=0.0),
                SensorFeedback(control, noise=0.0, encoder_step=0.0),
            ):
                run = run_machine(
                    plant, ModelPD(model, control), feedback, iso14242_at, duration, feedforward=ff, step=1e-3
                )
                rms = np.degrees(np.sqrt((run.errors**2).mean(axis=0)))
                expected = predicted(hidden, model if feedback.name == "encoders" else hidden, q_d, control)
                print(
                    f"{control} | {name} | {feedback.name} | {' '.join(f'{v:.3f}' for v in rms[0])} | "
                    f"{' '.join(f'{v:.3f}' for v in rms[1])} | {' '.join(f'{v:.3f}' for v in expected[0])} | "
                    f"{' '.join(f'{v:.3f}' for v in expected[1])}",
                    flush=True,
                )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--draws", type=int, default=100, help="machines per case (default 100)")
    parser.add_argument("--control", type=int, choices=[1, 2], default=2, help="the controlled platform (default 2)")
    parser.add_argument("--closed-loop", action="store_true", help="the servo loop on one hidden machine instead")
    parser.add_argument("--seat", type=float, default=1.0, help="with --closed-loop: |e| in [mm] (default 1)")
    parser.add_argument("--seed", type=int, default=7, help="with --closed-loop: the hidden machine's seed")
    parser.add_argument("--duration", type=float, default=1.0, help="with --closed-loop: [s] (default 1: a cycle)")
    args = parser.parse_args()
    if args.closed_loop:
        closed_loop(args.seat, args.seed, args.duration)
    else:
        kinematic(args.draws, args.control)


if __name__ == "__main__":
    main()
