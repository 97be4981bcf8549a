"""Tolerances before building: what manufacturing deviations of the chains do to each platform's attitude.

Each per-chain value (:mod:`hipsim.stations.deviations`) is drawn uniformly
within its family's band ±V (a tolerance says the value lies in the band, no
more), independently, around the drawing; each draw is a machine, commanded
as ``hipsim stations`` commands it (:func:`hipsim.stations.commands.station_commands`),
along the desired motion. Per draw and control, the RMS and the peak of each
platform's three angle errors; over the draws, their distribution (the 95th
percentile is what a lab plans with). The draws run on a dask cluster
(:func:`hipsim.analysis.cluster.map_batches`, as ``sweep`` does) or in this
process; each batch draws from its own seed, so the result does not depend on
how the batches were spread.

The sensitivity table is first order: for a small deviation δ the errors are
e(t) = S(t)·δ (:func:`error_sensitivity`), so a value p drawn within ±V_p adds
V_p²/3·mean_t S_k(t, p)² to the expected mean square error of angle k, exactly
additive over the values. That names the chain and the value that drive the
follower's error most.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..analytic.chain_kinematics import chain_positions_per_sample
from ..analytic.stations import carriages_for_platform
from ..arrays import readonly
from ..exceptions import ArgumentError, HipsimError, ParameterError, PoseError
from ..machine.chains import stackup_lift
from ..machine.parameters import Parameters
from . import deviations as dv
from .commands import CONTROLS, Positions, newton_from_close, own_command, station_commands
from .sensitivity import inverse3, reading_jacobian, reading_rate

__all__ = [
    "ToleranceResult",
    "error_sensitivity",
    "half_widths",
    "parse_tolerances",
    "sensitivity_table",
    "tolerance_batch",
    "tolerance_draws",
]

#: Draws per batch handed to a worker.
BATCH = 250


def parse_tolerances(text: str) -> dict[str, float]:
    """Tolerance bands in [m] by family, from ``KEY=±V,...`` in mm or a TOML file of such keys (``[tolerance]`` or top level).

    Keys: the families ujoint, slider, joint, lever, centre (the fields of
    :class:`~hipsim.machine.chains.ChainGeometry`), the intermediate chain's seat ``spline`` (named only: ``all``
    keeps the chains' families, so an ``all`` band means what it meant before the stack-up), and ``all`` (every chain
    family not named). A family not named (and no ``all``) is built exactly.

    Raises:
        ParameterError: an unknown key, a value that is not a finite number >= 0, an unreadable file.
    """
    source = "--bands"
    if "=" not in text and Path(text).suffix.lower() == ".toml":
        source = text
        try:
            data = tomllib.loads(Path(text).read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise ParameterError("no such tolerance file", source=text) from None
        except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as error:
            raise ParameterError(f"cannot read the tolerance file ({error})", source=text) from None
        entries = list(data.get("tolerance", data).items())
    else:
        entries = []
        for part in filter(None, (p.strip() for p in text.split(","))):
            key, sep, value = part.partition("=")
            if not sep:
                raise ParameterError(f"expected KEY=±V in mm, got '{part}'", source=source)
            entries.append((key.strip(), value.strip().replace("±", "").replace("+-", "")))
    if not entries:
        raise ParameterError("no tolerance given (e.g. all=0.1 or ujoint=0.1,lever=0.05, in mm)", source=source)
    bands: dict[str, float] = {}
    for key, value in entries:
        if key != "all" and key not in dv.FAMILIES:
            raise ParameterError(f"unknown tolerance (known: all, {', '.join(dv.FAMILIES)})", key=key, source=source)
        try:
            v = float(value)
        except (TypeError, ValueError):
            v = math.nan
        if not (math.isfinite(v) and v >= 0):
            raise ParameterError(f"expected a band ±V in mm (V >= 0), got '{value}'", key=key, source=source)
        bands[key] = v * 1e-3
    default = bands.pop("all", 0.0)
    out = {family: bands.get(family, default) for family in dv.FAMILIES if family != "spline"}
    if "spline" in bands:  # only when named: a band given before the stack-up reads back as it did
        out["spline"] = bands["spline"]
    return out


def half_widths(bands: Mapping[str, float]) -> np.ndarray:
    """Each per-chain value's half band in [m], (51,), from the bands by family."""
    return np.array([bands.get(dv.family(name), 0.0) for name in dv.names()])


def error_sensitivity(params: Parameters, desired: np.ndarray, control: str, weights=(1.0, 1.0)) -> np.ndarray:
    """S = ∂e/∂δ of each platform's attitude error under a control, at the machine ``params``, (N, 2, 3, 51) [rad/m].

    With F_j = ∂f_j/∂θ and A_j = (∂f_j/∂q)⁻¹ at the attitude platform j takes: its error is
    e_j = A_j·(dL − F_j·dθ); control "1" or "2" sets dL = F_c·dθ, "both" the weighted least squares
    dL = H⁻¹·Σ w_j A_jᵀA_j F_j·dθ, H = Σ w_j A_jᵀA_j (Gauss–Newton: the residuals' curvature left out, exact
    on the drawing, where they vanish).
    """
    q_d = np.asarray(desired, dtype=float)
    n = len(q_d)
    # At the attitudes the platforms take (a deviated machine's follower is off the desired), first order in δ.
    q = station_commands(params, np.arange(n, dtype=float), q_d, control, weights).attitudes
    A, F = {}, {}
    for j in (1, 2):
        A[j] = inverse3(reading_rate(params, q[:, j - 1], j))
        F[j] = np.zeros((n, 3, dv.COUNT))
        F[j][:, :, dv.platform_columns(j)] = reading_jacobian(params, j, q[:, j - 1], q[:, 1])
    if control in ("1", "2"):
        dL = F[int(control)]
    else:
        H = sum(w * np.matmul(np.swapaxes(A[j], 1, 2), A[j]) for j, w in zip((1, 2), weights))
        rhs = sum(w * np.matmul(np.matmul(np.swapaxes(A[j], 1, 2), A[j]), F[j]) for j, w in zip((1, 2), weights))
        dL = np.matmul(inverse3(H), rhs)
    return np.stack([np.matmul(A[j], dL - F[j]) for j in (1, 2)], axis=1)


def sensitivity_table(S: np.ndarray, widths: np.ndarray, platforms=(0, 1)) -> list[dict]:
    """Each per-chain value's share of the expected mean square error of the given platforms, largest first.

    Args:
        S: the error sensitivity (N, 2, 3, 51) in [rad/m] (:func:`error_sensitivity`).
        widths: each value's half band in [m], (51,).
        platforms: the platforms (0-based) whose error counts (the follower's, or both).

    Returns:
        Rows: ``value`` (name), ``chain`` ("ji", "centre j" or "intermediate": the stack-up's seat), ``family``, ``rms_deg`` (the RMS error per angle
        α, β, γ in [deg] this value's band alone gives, root of the expected mean square over the platforms),
        ``share`` (its fraction of the expected mean square summed over the three angles).
    """
    variance = widths**2 / 3.0  # a uniform draw within ±V
    ms = (S[:, list(platforms)] ** 2).mean(axis=0).sum(axis=0) * variance  # (3, 51) [rad²]
    chain = dv.COUNT - 3  # the chains' values, summed first: without a seat band, the sums of before the stack-up
    total = ms[:, :chain].sum() + ms[:, chain:].sum()
    rows = []
    for p, name in enumerate(dv.names()):
        if p >= chain and not np.any(widths[chain:]):
            break  # no seat band: no seat rows
        tail = name.rsplit("_", 1)[1]
        rows.append(
            {
                "value": name,
                "chain": "intermediate" if name.startswith("spline") else tail if len(tail) == 2 else f"centre {tail}",
                "family": dv.family(name),
                "rms_deg": np.degrees(np.sqrt(ms[:, p])).tolist(),
                "share": float(ms[:, p].sum() / total) if total > 0 else 0.0,
            }
        )
    return sorted(rows, key=lambda row: -row["share"])


@dataclass(frozen=True)
class _Setup:
    drawing: Parameters
    t: np.ndarray
    desired: np.ndarray
    controls: tuple[str, ...]
    widths: np.ndarray
    weights: tuple[float, float]
    seed: int


def _out_of_reach(machine: Parameters, desired: np.ndarray) -> str | None:
    """The first chain "ji" that cannot reach the desired motion, or None."""
    for j in (1, 2):
        try:
            L = carriages_for_platform(machine, desired, j)
        except PoseError as error:
            return f"platform {j} ({error.reason})"
        bad = ~np.isfinite(L)
        if bad.any():
            return f"chain {j}{int(np.argmax(bad.any(axis=0))) + 1}"
    return None


def tolerance_batch(batch: tuple[int, int], setup: _Setup) -> tuple[int, np.ndarray, np.ndarray, str | None]:
    """One batch of draws: (first draw, RMS (count, controls, 2, 3) [rad], peaks alike, or the first failure's text).

    Controls "1" and "2" are solved for all the batch's draws at once (:func:`_followers`); control "both", and a
    draw that does not converge there, go through :func:`hipsim.stations.commands.station_commands` one by one.
    """
    first, count = batch
    rng = np.random.default_rng([setup.seed, first])
    theta0 = dv.deviation(setup.drawing)
    chain = dv.COUNT - 3  # the chains' and centres' values, drawn first (the stream as before the stack-up)
    deltas = np.zeros((count, dv.COUNT))
    deltas[:, :chain] = rng.uniform(-1.0, 1.0, (count, chain)) * setup.widths[:chain]  # one draw after the other
    if np.any(setup.widths[chain:]):
        deltas[:, chain:] = rng.uniform(-1.0, 1.0, (count, 3)) * setup.widths[chain:]
    rms = np.empty((count, len(setup.controls), 2, 3))
    peak = np.empty_like(rms)
    solved = np.zeros((count, len(setup.controls)), dtype=bool)
    thetas = theta0 + deltas
    chains = _draw_chains(setup.drawing, thetas)
    for c, control in enumerate(setup.controls):
        if control != "both":
            rms[:, c], peak[:, c], solved[:, c] = _followers(
                chains, setup.drawing.angle_signs, setup.desired, int(control), thetas[:, dv.COUNT - 3 :]
            )
    for k in range(count):
        if solved[k].all():
            continue
        machine = dv.machine(setup.drawing, theta0 + deltas[k])
        try:
            for c, control in enumerate(setup.controls):
                if solved[k, c]:
                    continue
                e = station_commands(machine, setup.t, setup.desired, control, setup.weights).errors
                rms[k, c] = np.sqrt((e**2).mean(axis=0))
                peak[k, c] = np.abs(e).max(axis=0)
        except (PoseError, np.linalg.LinAlgError) as error:
            where = _out_of_reach(machine, setup.desired) or str(error)
            return first, rms[:k], peak[:k], f"draw {first + k + 1}: {where} is out of reach"
        if not (np.all(np.isfinite(rms[k])) and np.all(np.isfinite(peak[k]))):
            where = _out_of_reach(machine, setup.desired) or "a platform"
            return first, rms[:k], peak[:k], f"draw {first + k + 1}: {where} is out of reach"
    return first, rms, peak, None


#: Each draw's chains of one platform: platform joints r⁰ (K, leg, xyz), o − c (K, leg, xyz), levers l (K, leg), in [m].
_DrawChains = tuple[np.ndarray, np.ndarray, np.ndarray]


def _draw_chains(drawing: Parameters, thetas: np.ndarray) -> dict[int, _DrawChains]:
    """Each draw's chains, by platform (1, 2), for per-chain values θ in [m], (K, 51).

    :meth:`hipsim.machine.chains.Chains.build` adds the values to the drawing's, so the chains are affine in θ: they
    are found from the chains at θ = 0 and at each unit θ, rather than by building a machine a draw.
    """

    def fields(theta: np.ndarray) -> np.ndarray:
        ch = dv.machine(drawing, theta).chains
        offsets = ch.centres[:, None, :] - ch.screw_points
        return np.concatenate([ch.platform_points.ravel(), offsets.ravel(), ch.lever_lengths.ravel()])

    zero = fields(np.zeros(dv.COUNT))
    slope = np.stack([fields(unit) - zero for unit in np.eye(dv.COUNT)], axis=1)  # (fields, 51)
    values = zero + thetas @ slope.T
    P, offsets, levers = np.split(values, [18, 36], axis=1)
    P, offsets, levers = P.reshape(-1, 2, 3, 3), offsets.reshape(-1, 2, 3, 3), levers.reshape(-1, 2, 3)
    return {j: (P[:, j - 1], offsets[:, j - 1], levers[:, j - 1]) for j in (1, 2)}


def _followers(
    chains: dict[int, _DrawChains],
    signs: np.ndarray,
    desired: np.ndarray,
    control: int,
    seats: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Control "1" or "2" on many per-chain machines at once, as :func:`station_commands` computes it for each.

    Every machine's samples are stacked, each sample with its own machine's chains
    (:func:`hipsim.analytic.chain_kinematics.chain_positions_per_sample`): the controlled platform's own command,
    the follower's linear prediction and its Newton steps (:func:`hipsim.stations.commands.newton_from_close`).

    Args:
        chains: each machine's chains (:func:`_draw_chains`).
        signs: the angle signs, (3,).
        desired: the desired attitude in [rad], (N, 3).
        control: the platform commanded exactly, 1 or 2.
        seats: each machine's stack-up seat e in [m], (K, 3), or None for none. Under control 2, m_1 sees the
            carriages lowered by Δz(q_d) (m_2 is exact); under control 1 a machine with a seat is left to
            :func:`station_commands` (its command is the stack-up's fixed point).

    Returns:
        RMS and peak error per machine, platform and angle in [rad], (K, 2, 3) each, and per machine whether every
        sample converged (K,) bool (the others are left to :func:`station_commands`).
    """
    n, count = len(desired), len(chains[1][0])
    q_d = np.tile(desired, (count, 1))

    def positions(j: int) -> Positions:
        P, offsets, levers = (np.repeat(x, n, axis=0) for x in chains[j])
        return lambda p, rows: chain_positions_per_sample(P[rows], offsets[rows], levers[rows], p)

    follower = 3 - control
    L, _ = own_command(positions(control), signs, q_d, False)
    own, rate = own_command(positions(follower), signs, q_d, True)
    assert rate is not None
    stacked = np.zeros(count, dtype=bool) if seats is None else np.any(seats != 0.0, axis=1)
    if control == 2 and stacked.any():  # m_1's centre rides Δz(q_2) = Δz(q_d) up: it sees L − Δz
        L = L - stackup_lift(np.repeat(np.asarray(seats, dtype=float), n, axis=0), q_d * signs)[:, None]
    guess = q_d + np.matmul(inverse3(rate), (L - own)[..., None])[..., 0]
    q, converged = newton_from_close(positions(follower), signs, L, guess)
    e = (q - q_d).reshape(count, n, 3)
    ok = converged.reshape(count, n).all(axis=1)
    if control == 1:
        ok &= ~stacked
    ok &= np.isfinite(L).reshape(count, -1).all(axis=1) & np.isfinite(own).reshape(count, -1).all(axis=1)
    rms, peak = np.zeros((count, 2, 3)), np.zeros((count, 2, 3))  # the controlled platform is exact
    rms[:, follower - 1] = np.sqrt((e**2).mean(axis=1))
    peak[:, follower - 1] = np.abs(e).max(axis=1)
    return rms, peak, ok


@dataclass(frozen=True, eq=False)
class ToleranceResult:
    """The distribution of the attitude errors over the draws.

    Attributes:
        bands: the half bands in [m] by family.
        controls: the controls, in the order of the arrays' second axis.
        rms, peak: per draw, control, platform and angle, the error's RMS and peak over the motion in [rad],
            (draws, controls, 2, 3).
        sensitivity: per control, the first-order sensitivity table (:func:`sensitivity_table`) of the follower
            (control "1": platform 2, "2": platform 1, "both": both platforms).
        seed: the draws' seed.
    """

    bands: dict[str, float]
    controls: tuple[str, ...]
    rms: np.ndarray
    peak: np.ndarray
    sensitivity: dict[str, list[dict]]
    seed: int

    def percentile(self, which: str = "rms", q: float = 95.0) -> np.ndarray:
        """The q-th percentile over the draws of the RMS (``which="rms"``) or peak error in [rad], (controls, 2, 3)."""
        return np.percentile(self.rms if which == "rms" else self.peak, q, axis=0)


def tolerance_draws(
    drawing: Parameters,
    t: np.ndarray,
    desired: np.ndarray,
    bands: Mapping[str, float],
    controls=("2",),
    draws: int = 1000,
    seed: int = 0,
    weights=(1.0, 1.0),
    workers: int = 2,
    scheduler: str | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> ToleranceResult:
    """Monte Carlo of the manufacturing deviations (module docstring).

    Args:
        drawing: the machine as drawn (the draws are centred on its deviations, none for the drawing).
        t: sample times in [s], (N,); desired: the desired attitude in [rad], (N, 3).
        bands: half band in [m] per family (:func:`parse_tolerances`).
        controls: the controls to evaluate, each of "1", "2", "both".
        draws: how many machines to draw.
        seed: the draws' seed.
        weights: (w_1, w_2) of control "both".
        workers: worker processes of a local dask cluster; 0 runs the draws in this process.
        scheduler: a running dask scheduler's address (instead of a local cluster).
        progress: called with (draws done, draws) as batches complete.

    Raises:
        HipsimError: a draw puts a chain out of reach (naming the draw and the chain).
    """
    controls = tuple(controls)
    for control in controls:
        if control not in CONTROLS:
            raise ArgumentError("control", control, "one of 1, 2, both")
    if draws < 1:
        raise ArgumentError("draws", draws, "at least 1")
    desired = np.asarray(desired, dtype=float)
    widths = half_widths(bands)
    setup = _Setup(drawing, np.asarray(t, dtype=float), desired, controls, widths, tuple(weights), seed)
    batches = [(first, min(BATCH, draws - first)) for first in range(0, draws, BATCH)]
    results: Iterable[Any]
    if workers == 0 and scheduler is None:
        results = (tolerance_batch(batch, setup) for batch in batches)
    else:
        from ..analysis.cluster import map_batches

        results = map_batches(tolerance_batch, batches, setup, workers, scheduler, "hipsim stations")
    rms = np.empty((draws, len(controls), 2, 3))
    peak = np.empty_like(rms)
    done = 0
    for first, batch_rms, batch_peak, failure in results:
        if failure is not None:
            raise HipsimError(
                f"--bands: {failure} on the desired motion: the band is too wide for this machine (nothing written)"
            )
        rms[first : first + len(batch_rms)] = batch_rms
        peak[first : first + len(batch_peak)] = batch_peak
        done += len(batch_rms)
        if progress is not None:
            progress(done, draws)
    follower = {"1": (1,), "2": (0,), "both": (0, 1)}
    sensitivity = {
        control: sensitivity_table(error_sensitivity(drawing, desired, control, weights), widths, follower[control])
        for control in controls
    }
    return ToleranceResult(dict(bands), controls, readonly(rms), readonly(peak), sensitivity, seed)
