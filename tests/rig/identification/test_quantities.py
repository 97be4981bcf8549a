"""hipsim.rig.identification.quantities: each identified quantity reads and writes its own parameter field."""

import numpy as np

import hipsim
from hipsim.rig.identification.quantities import (
    BLOCKS,
    BOUNDED,
    FRICTION,
    QUANTITIES,
    friction_unit,
    standard_values,
    with_values,
)


def _machine():
    params = hipsim.load_parameters()
    inertia = np.array([[300.0, 2.0, -1.0], [2.0, 310.0, 0.5], [-1.0, 0.5, 200.0]]) * 1e-6
    return params.replace(platform_inertia=inertia, **{q.name: 0.01 * (k + 1) for k, q in enumerate(FRICTION)})


def test_each_quantity_reads_its_own_field():
    params = _machine()
    theta = standard_values(params)
    assert theta[[q.key for q in QUANTITIES].index("platform.inertia_kgmm2[xy]")] == params.platform_inertia[0, 1]
    assert theta[[q.key for q in QUANTITIES].index("lever.mass_kg")] == params.lever_mass
    assert theta[[q.key for q in QUANTITIES].index("friction.guide_viscous_N_s_mm")] == params.friction.guide_viscous


def test_writing_one_quantity_changes_that_field_alone():
    params = _machine()
    theta = standard_values(params)
    for k, quantity in enumerate(QUANTITIES):
        moved = theta.copy()
        moved[k] += 1.0
        changed = standard_values(with_values(params, moved))
        assert np.flatnonzero(changed != theta).tolist() == [k], quantity.key
        assert quantity.read(with_values(params, moved)) == moved[k]
    np.testing.assert_array_equal(with_values(params, theta).platform_inertia, params.platform_inertia)


def test_groups_follow_from_the_quantities():
    assert [QUANTITIES[k].key for k in BLOCKS["lever"]] == [
        f"lever.inertia_kgmm2[{a}]" for a in ("xx", "yy", "zz", "xy", "xz", "yz")
    ]
    assert all(QUANTITIES[k].nonnegative and QUANTITIES[k].component is None for k in BOUNDED)
    unit = friction_unit(_machine(), "thrust_mu").friction
    assert unit.thrust_mu == 1.0 and all(getattr(unit, q.name) == 0.0 for q in FRICTION if q.name != "thrust_mu")
