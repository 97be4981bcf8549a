"""hipsim.rig.identification.regressor pinned by parts on tiny motions (tens of samples, fast without numba).

The law: a machine's motor torque is linear in its dynamic parameters θ (the
QUANTITIES), τ(θ) = Y·θ, so column k of Y is the torque's change per unit of
θ_k: built here directly, by finite differences of the full inverse dynamics
of machines that differ in that one parameter (exact for a linear law), not
through the regressor's unit machines. The rows of a log: the regressor along
its usable samples, low-passed like the log, every D-th sample, the samples
near each motor's reversals marked out of that motor's rows; a log read in
windows gives the rows of the whole.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest
from support import ALL_FRICTION, SmoothMotion

import hipsim
from hipsim.analytic.inverse_kinematics import kinematics
from hipsim.analytic.virtual_work import inverse_dynamics
from hipsim.motion.filtering import edge_samples, lowpass
from hipsim.motion.trajectories import Trajectory
from hipsim.rig.identification.quantities import FRICTION, QUANTITIES, standard_values, with_values
from hipsim.rig.identification.regressor import (
    BLOCK,
    CHUNK,
    _column_machines,
    _regressor_by_unit_machines,
    _regressor_columns,
    _rows,
    _unit_machines,
    log_rows,
    regressor,
    regressor_from_kinematics,
)
from hipsim.rig.logs.log import Log, MeasuredLog
from hipsim.rig.logs.reversals import reversal_mask

P = len(QUANTITIES)
INDEX = {q.label: k for k, q in enumerate(QUANTITIES)}


def _other():
    """Not the published machine: another geometry, every friction on, the axial-only thrust bearing, a wider ε."""
    params = hipsim.load_parameters()
    return params.replace(
        lever_length=params.lever_length * 1.04,
        lead=params.lead * 1.25,
        lever_mass=params.lever_mass * 1.3,
        epsilon=params.friction.epsilon * 3.0,
        thrust_bearing_axial_only=True,
        **ALL_FRICTION,
    )


@pytest.fixture(scope="module")
def machine():
    return _other()


@pytest.fixture(scope="module")
def motion():
    """30 samples of a smooth motion at 1 kHz with a varying load."""
    return SmoothMotion(seed=11)(np.arange(30) * 1e-3)


def _tau(params, motion, lever_spin):
    return inverse_dynamics(params, kinematics(params, motion), motion.Fe, lever_spin).total


def _finite_columns(params, motion, lever_spin):
    """Y by finite differences of the full inverse dynamics: (τ(θ + h·e_k) − τ(θ))/h, (N, 3, P)."""
    theta = standard_values(params)
    tau = _tau(params, motion, lever_spin)
    Y = np.empty((len(motion), 3, P))
    for k, quantity in enumerate(QUANTITIES):
        h = quantity.nominal
        Y[:, :, k] = (_tau(with_values(params, theta + h * np.eye(P)[k]), motion, lever_spin) - tau) / h
    return Y


@pytest.mark.parametrize("lever_spin", [True, False])
def test_each_column_is_the_torque_per_unit_of_its_parameter(machine, motion, lever_spin):
    Y = regressor(machine, motion, lever_spin)
    assert Y.shape == (30, 3, P)
    expected = _finite_columns(machine, motion, lever_spin)
    scale = np.abs(expected).max(axis=(0, 1))
    # Every parameter moves some motor, but the levers' spin inertia without their spin.
    unseen = [] if lever_spin else [INDEX["I_l,zz"]]
    assert (scale > 1e-12 * scale.max()).sum() == P - len(unseen) and np.all(scale[unseen] < 1e-12 * scale.max())
    # Each column to round-off of the torques' differences (their size over the step).
    error = np.abs(Y - expected).max(axis=(0, 1))
    assert np.all(error <= 1e-9 * scale + 1e-15 * scale.max()), error / scale
    # Y·θ is the whole machine's torque, for the machine and for another set of values on the same geometry.
    for theta in (standard_values(machine), standard_values(machine) * np.linspace(0.5, 1.5, P)):
        tau = _tau(with_values(machine, theta), motion, lever_spin)
        assert np.abs(Y @ theta - tau).max() < 1e-12 * np.abs(tau).max()


def test_the_lever_spin_changes_the_lever_columns_only(machine, motion):
    on, off = regressor(machine, motion, True), regressor(machine, motion, False)
    changed = np.abs(on - off).max(axis=(0, 1)) > 0
    levers = [k for k, q in enumerate(QUANTITIES) if q.part == "levers"]
    assert changed[levers].any()
    # The regressor's default is the model with lever spin.
    np.testing.assert_array_equal(regressor(machine, motion), on)


@pytest.mark.parametrize("lever_spin", [True, False])
def test_the_unit_machines_route_is_the_same_regressor(machine, motion, lever_spin):
    kin = kinematics(machine, motion)
    reference = _regressor_by_unit_machines(machine, kin, motion.Fe, lever_spin)
    np.testing.assert_array_equal(regressor_from_kinematics(machine, kin, motion.Fe, lever_spin), reference)
    if lever_spin:  # the default: the model with lever spin
        np.testing.assert_array_equal(_regressor_by_unit_machines(machine, kin, motion.Fe), reference)
    expected = _finite_columns(machine, motion, lever_spin)
    np.testing.assert_allclose(reference, expected, rtol=0, atol=1e-6 * np.abs(expected).max())


def test_the_unit_machines_by_hand(machine):
    """Ten machines: the s-th parameter of each body group at one (the groups in the order of QUANTITIES)."""
    groups = {
        "platforms": [INDEX[f"I_m,{a}"] for a in ("xx", "yy", "zz", "xy", "xz", "yz")],
        "sliders": [INDEX["m_L"]],
        "screws": [INDEX["I_L"]],
        "levers": [INDEX[f"I_l,{a}"] for a in ("xx", "yy", "zz", "xy", "xz", "yz")] + [INDEX["m_l"]],
        "friction": [INDEX[q.label] for q in FRICTION],
    }
    machines = _unit_machines(machine)
    assert len(machines) == 10 == len(groups["friction"])
    for s, (unit, columns) in enumerate(machines):
        expected = {part: group[s] for part, group in groups.items() if s < len(group)}
        assert columns == expected, s
        theta = np.zeros(P)
        theta[list(expected.values())] = 1.0
        np.testing.assert_array_equal(standard_values(unit), theta)
        # The geometry and what the friction law keeps are the machine's.
        assert unit.lever_length == machine.lever_length and unit.friction.epsilon == machine.friction.epsilon


def test_each_column_machine_carries_its_parameter_alone(machine):
    machines = _column_machines(machine)
    assert [part for part, _ in machines] == [q.part for q in QUANTITIES]
    for k, (_, unit) in enumerate(machines):
        np.testing.assert_array_equal(standard_values(unit), np.eye(P)[k])
        assert unit.lead == machine.lead and unit.platform_mass == machine.platform_mass


def test_blocks_and_layout_change_no_number(machine, motion):
    kin = kinematics(machine, motion)
    whole = _regressor_columns(machine, kin, motion.Fe, True)
    assert whole.shape == (P, 3, 30) and BLOCK > 30
    np.testing.assert_array_equal(_regressor_columns(machine, kin, motion.Fe), whole)  # with lever spin by default
    for block in (1, 7, 29, 30):
        np.testing.assert_array_equal(_regressor_columns(machine, kin, motion.Fe, True, block=block), whole)
    # Machines made once serve again; the lever spin reaches the columns.
    made = _column_machines(machine)
    np.testing.assert_array_equal(_regressor_columns(machine, kin, motion.Fe, True, made, 7), whole)
    np.testing.assert_array_equal(
        _regressor_columns(machine, kin, motion.Fe, False, block=7),
        regressor(machine, motion, False).transpose(2, 1, 0),
    )
    # (N, 3, P), samples first and contiguous.
    Y = regressor_from_kinematics(machine, kin, motion.Fe)
    assert Y.shape == (30, 3, P) and Y.flags.c_contiguous
    np.testing.assert_array_equal(Y, whole.transpose(2, 1, 0))


# --- The rows of a log ----------------------------------------------------------------------------------------

RATE, CUTOFF = 800.0, 100.0  # decimation ⌊800/400⌋ = 2, edges of 32 samples, chunk margins of 128


def _reversing(n: int, rate: float = RATE) -> Trajectory:
    """Angles swinging at 6-9 Hz (every slider reverses within a log of a few hundred samples) and a varying load."""
    t = np.arange(n) / rate
    f = np.array([6.0, 7.5, 9.0])
    w = 2 * np.pi * f
    a = np.radians([6.0, -5.0, 4.0])
    q = a * np.sin(w * t[:, None] + [0.3, 1.1, 2.0])
    qd = a * w * np.cos(w * t[:, None] + [0.3, 1.1, 2.0])
    qdd = -a * w**2 * np.sin(w * t[:, None] + [0.3, 1.1, 2.0])
    return Trajectory(t, q, qd, qdd, 1500.0 + 600.0 * np.sin(2 * np.pi * 3.0 * t), name="swing")


@pytest.fixture(scope="module")
def filtered_log(machine):
    trajectory = _reversing(400)
    tau = np.random.default_rng(5).normal(size=(400, 3))
    return MeasuredLog(trajectory, tau, CUTOFF, "swing.csv", edge=edge_samples(RATE, CUTOFF), sample_rate=RATE)


def _joined(rows) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    Y, tau, use = zip(*rows)
    return np.concatenate(Y), np.concatenate(tau), np.concatenate(use)


def test_an_unfiltered_log_gives_every_usable_sample(machine, motion):
    tau = np.arange(90.0).reshape(30, 3)
    log = MeasuredLog(motion, tau, None, "exact", edge=3)
    Y, t, use = _joined(log_rows(machine, log, True))
    np.testing.assert_array_equal(Y, regressor(machine, motion, True)[3:27])
    np.testing.assert_array_equal(t, tau[3:27])
    assert use.shape == (24, 3) and use.all()
    # Chunks of any size give the same rows; the lever spin reaches them.
    for chunk in (1, 5, 24):
        small = _joined(_rows(machine, log, True, chunk=chunk))
        assert all(np.array_equal(a, b) for a, b in zip(small, (Y, t, use)))
    np.testing.assert_array_equal(_joined(log_rows(machine, log, False))[0], regressor(machine, motion, False)[3:27])


def test_a_filtered_log_is_low_passed_decimated_and_masked_at_reversals(machine, filtered_log):
    log = filtered_log
    assert log.usable == slice(32, 368) and CHUNK > len(log)
    Y, t, use = _joined(log_rows(machine, log, True))
    keep = np.arange(32, 368, 2)  # every second usable sample
    whole = lowpass(regressor(machine, log.trajectory, True), RATE, CUTOFF)
    np.testing.assert_allclose(Y, whole[keep], rtol=0, atol=1e-12 * np.abs(whole).max())
    np.testing.assert_array_equal(t, log.tau[keep])
    mask = reversal_mask(machine, log)
    assert mask[keep].any(axis=0).all() and (~mask[keep]).any(axis=0).all()  # each motor reverses, and runs
    np.testing.assert_array_equal(use, ~mask[keep])
    # In chunks (whole decimation steps, margins beyond the filter's reach): the same rows to round-off.
    for chunk in (61, 100):
        Yc, tc, uc = _joined(_rows(machine, log, True, chunk=chunk))
        np.testing.assert_allclose(Yc, Y, rtol=0, atol=1e-9 * np.abs(Y).max())
        np.testing.assert_array_equal(tc, t)
        np.testing.assert_array_equal(uc, use)


def test_a_span_starts_a_whole_number_of_steps_after_its_origin(machine, filtered_log):
    """span = (first, stop, origin): rows at origin + 2k within [first, stop)."""
    log = filtered_log
    Y, t, _ = _joined(log_rows(machine, log, True))
    for first, stop in ((101, 160), (100, 160), (33, 40)):
        Ys, ts, _ = _joined(_rows(machine, log, True, chunk=50, span=(first, stop, 32)))
        rows = np.arange(32, 368, 2)
        picked = (rows >= first) & (rows < stop)
        np.testing.assert_array_equal(ts, log.tau[rows[picked]])
        np.testing.assert_allclose(Ys, Y[picked], rtol=0, atol=1e-9 * np.abs(Y).max())


class _Windowed(Log):
    """A log in memory served in windows: cores of ``core`` samples, each with ``halo`` samples of log around it."""

    def __init__(self, log: MeasuredLog, core: int, halo: int):
        self.log, self.core, self.halo = log, core, halo
        self.name, self.cutoff, self.motion_from, self.notes, self.edge = log.name, log.cutoff, "exact", (), log.edge

    def __len__(self) -> int:
        return len(self.log)

    @property
    def rate(self) -> float:
        return self.log.rate

    @property
    def t(self) -> np.ndarray:
        return self.log.t

    def windows(self) -> Iterator[tuple[MeasuredLog, slice, int]]:
        n = len(self.log)
        for start in range(0, n, self.core):
            stop = min(start + self.core, n)
            lo, hi = max(0, start - self.halo), min(n, stop + self.halo)
            piece = self.log.trajectory.slice(slice(lo, hi))
            window = MeasuredLog(piece, self.log.tau[lo:hi], self.cutoff, self.name, sample_rate=self.log.rate)
            yield window, slice(start - lo, stop - lo), start

    def filtered_angles(self, most=None):
        return self.log.filtered_angles(most)


def test_a_log_in_windows_gives_the_rows_of_the_whole(machine, filtered_log):
    whole = _joined(log_rows(machine, filtered_log, True))
    # Cores of 97 samples (odd: each window's first row is not its core's first sample), halos beyond the margins.
    pieces = _joined(log_rows(machine, _Windowed(filtered_log, 97, 150), True))
    assert len(pieces[1]) == len(whole[1]) == 168
    np.testing.assert_allclose(pieces[0], whole[0], rtol=0, atol=1e-9 * np.abs(whole[0]).max())
    np.testing.assert_array_equal(pieces[1], whole[1])
    np.testing.assert_array_equal(pieces[2], whole[2])
    # A core wholly inside an edge gives no rows; the lever spin reaches every window.
    assert len(list(log_rows(machine, _Windowed(filtered_log, 30, 150), True))) == 12
    off = _joined(log_rows(machine, _Windowed(filtered_log, 97, 150), False))
    np.testing.assert_allclose(
        off[0], _joined(log_rows(machine, filtered_log, False))[0], atol=1e-9 * np.abs(off[0]).max()
    )


@pytest.fixture(scope="module")
def log_in_threes(machine):
    """1200 Hz low-passed at 100 Hz: every third sample kept, edges of 48 samples, chunk margins of 192."""
    trajectory = _reversing(400, 1200.0)
    tau = np.random.default_rng(6).normal(size=(400, 3))
    return MeasuredLog(trajectory, tau, CUTOFF, "threes.csv", edge=edge_samples(1200.0, CUTOFF), sample_rate=1200.0)


def test_rows_every_third_sample_in_chunks_spans_and_windows(machine, log_in_threes):
    log = log_in_threes
    assert log.usable == slice(48, 352)
    rows = np.arange(48, 352, 3)
    Y, t, use = _joined(log_rows(machine, log, True))
    np.testing.assert_array_equal(t, log.tau[rows])
    whole = lowpass(regressor(machine, log.trajectory, True), 1200.0, CUTOFF)
    np.testing.assert_allclose(Y, whole[rows], rtol=0, atol=1e-12 * np.abs(whole).max())
    # Chunks of 100 samples are cut to 99, whole steps: the kept samples line up across them.
    chunked = _joined(_rows(machine, log, True, chunk=100))
    np.testing.assert_array_equal(chunked[1], t)
    assert [len(tau) for _, tau, _ in _rows(machine, log, True, chunk=100)] == [33, 33, 33, 3]
    # A span from 101: its first row is 102 = 48 + 18·3.
    _, ts, _ = _joined(_rows(machine, log, True, span=(101, 160, 48)))
    np.testing.assert_array_equal(ts, log.tau[np.arange(102, 160, 3)])
    # Windows whose cores start off the step: the rows of the whole.
    pieces = _joined(log_rows(machine, _Windowed(log, 97, 200), True))
    np.testing.assert_array_equal(pieces[1], t)
    np.testing.assert_allclose(pieces[0], Y, rtol=0, atol=1e-9 * np.abs(Y).max())


def test_a_log_too_short_to_filter_is_named(machine):
    """A log built from arrays, shorter than the filter needs (128 samples at 800 Hz and 100 Hz): its name in the error."""
    short = MeasuredLog(_reversing(100), np.zeros((100, 3)), CUTOFF, "short.csv", edge=32, sample_rate=RATE)
    with pytest.raises(hipsim.TrajectoryError, match="short.csv"):
        list(log_rows(machine, short, True))
