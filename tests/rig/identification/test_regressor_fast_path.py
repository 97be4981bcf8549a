"""The regressor's fast route (each column one torque part on the motion's terms, block by block) against the route
it replaced (the full inverse dynamics of the ten unit machines), bit for bit, and the pieces it rests on."""

from __future__ import annotations

import numpy as np
import pytest
from support import ALL_FRICTION, SmoothMotion

import hipsim
from hipsim.analytic.inverse_kinematics import kinematics
from hipsim.analytic.virtual_work import PARTS, inverse_dynamics, motion_terms, torques_of
from hipsim.motion.filtering import edge_samples, lowpass, minimum_samples
from hipsim.rig.identification.quantities import QUANTITIES, standard_values
from hipsim.rig.identification.regressor import (
    _column_machines,
    _regressor_by_unit_machines,
    _regressor_columns,
    _rows,
    decimation,
    regressor,
)
from hipsim.rig.logs.log import MeasuredLog
from hipsim.rig.logs.reversals import reversal_mask


def _published():
    return hipsim.load_parameters()


def _other():
    """Not the published machine: another geometry, every friction on, the axial-only thrust bearing, a wider ε."""
    params = hipsim.load_parameters()
    return params.replace(
        lever_length=params.lever_length * 1.04,
        lead=params.lead * 1.25,
        joint_radius=params.joint_radius * 0.97,
        lever_mass=params.lever_mass * 1.3,
        epsilon=params.friction.epsilon * 3.0,
        thrust_bearing_axial_only=True,
        **ALL_FRICTION,
    )


MACHINES = {"published": _published, "other": _other}


@pytest.fixture(scope="module")
def motion():
    """2.5 s of a random smooth motion at 1 kHz: enough samples for several blocks and chunks."""
    return SmoothMotion(seed=7)(np.arange(0, 2.5, 1e-3))


def _same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal numbers, zeros' signs included."""
    return a.shape == b.shape and np.array_equal(a, b) and np.array_equal(np.signbit(a), np.signbit(b))


@pytest.mark.parametrize("lever_spin", [True, False])
@pytest.mark.parametrize("machine", sorted(MACHINES))
def test_the_fast_regressor_is_the_unit_machines_bit_for_bit(machine, lever_spin, motion):
    params = MACHINES[machine]()
    kin = kinematics(params, motion)
    reference = _regressor_by_unit_machines(params, kin, motion.Fe, lever_spin)
    # Blocks that do not divide the samples, one block, and the default.
    for block in (977, len(motion), None):
        columns = (
            _regressor_columns(params, kin, motion.Fe, lever_spin)
            if block is None
            else _regressor_columns(params, kin, motion.Fe, lever_spin, block=block)
        )
        assert _same_bits(columns.transpose(2, 1, 0), reference), block
    assert _same_bits(regressor(params, motion, lever_spin), reference)
    # Not a vacuous equality: every column moves some motor.
    assert np.all(np.abs(reference).max(axis=(0, 1)) > 0)


@pytest.mark.parametrize("machine", sorted(MACHINES))
def test_the_columns_times_the_parameters_are_the_model(machine, motion):
    """Linearity, by another route than the columns' own: Y·θ is the full inverse dynamics of the machine."""
    params = MACHINES[machine]()
    kin = kinematics(params, motion)
    tau = inverse_dynamics(params, kin, motion.Fe, True).total
    Y = _regressor_columns(params, kin, motion.Fe, True)
    predicted = np.einsum("kin,k->ni", Y, standard_values(params))
    assert np.abs(predicted - tau).max() < 1e-12 * np.abs(tau).max()


def test_motion_terms_serve_every_machine_of_the_geometry_and_slice_into_views(motion):
    params = _other()
    kin = kinematics(params, motion)
    terms = motion_terms(params, kin, motion.Fe, True)
    heavier = params.replace(lever_mass=2.0, slider_mass=5.0, hip_mu=0.2)
    direct = inverse_dynamics(heavier, kin, motion.Fe, True)
    via_terms = torques_of(heavier, terms)
    for name in ("total", "platforms", "levers", "sliders", "screws", "friction", "friction_power"):
        assert _same_bits(np.asarray(getattr(via_terms, name)), np.asarray(getattr(direct, name))), name
    part = terms[100:400]
    assert len(part) == 300 and np.shares_memory(part.J_inv_T, terms.J_inv_T)
    for name, function in PARTS.items():
        assert _same_bits(function(heavier, part), function(heavier, terms)[:, 100:400]), name
    with pytest.raises(TypeError):
        terms[3]  # type: ignore[index]  # an index that must raise


def test_lowpass_along_the_last_axis_is_the_first_axis_bit_for_bit():
    x = np.random.default_rng(3).normal(size=(900, 3, 4))
    first = lowpass(x, 1000.0, 20.0, "x")
    last = lowpass(np.ascontiguousarray(x.transpose(2, 1, 0)), 1000.0, 20.0, "x", axis=-1)
    assert _same_bits(last.transpose(2, 1, 0), first)
    # The length checked is the filtered axis's: 900 samples pass along the first, 3 are refused along the last.
    assert lowpass(x[:, :, 0], 1000.0, 20.0, "x").shape == (900, 3)
    with pytest.raises(hipsim.TrajectoryError, match="3 samples"):
        lowpass(x[:, :, 0], 1000.0, 20.0, "x", axis=-1)


@pytest.mark.parametrize("machine", sorted(MACHINES))
def test_log_rows_are_the_route_before_bit_for_bit(machine, motion):
    """The rows a fit takes (regressor, low-pass, decimation, reversals), chunk by chunk, as the code before made them:
    the unit machines' regressor of each chunk with its margin, low-passed along its first axis."""
    params = MACHINES[machine]()
    rate, cutoff = 1000.0, 20.0
    tau = np.random.default_rng(1).normal(size=(len(motion), 3))
    log = MeasuredLog(motion, tau, cutoff, "synthetic", edge=edge_samples(rate, cutoff), sample_rate=rate)
    chunk = 700
    rows = list(_rows(params, log, True, chunk=chunk))
    # The route before, written out.
    step, margin, n = decimation(log), minimum_samples(rate, cutoff), len(log)
    first, stop = log.usable.start, log.usable.stop
    use = ~reversal_mask(params, log)
    chunk = max(step, chunk - chunk % step)
    expected = []
    for a in range(first, stop, chunk):
        b = min(a + chunk, stop)
        lo, hi = max(0, a - margin), min(n, b + margin)
        piece = motion.slice(slice(lo, hi))
        Y = lowpass(_regressor_by_unit_machines(params, kinematics(params, piece), piece.Fe, True), rate, cutoff)
        keep = np.arange(a, b, step)
        expected.append((Y[keep - lo], tau[keep], use[keep]))
    assert len(rows) == len(expected) > 2
    for (Y, t, u), (Y0, t0, u0) in zip(rows, expected):
        assert _same_bits(np.asarray(Y), Y0) and _same_bits(t, t0) and np.array_equal(u, u0)
    assert len(_column_machines(params)) == len(QUANTITIES)
