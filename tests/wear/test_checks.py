"""hipsim.wear.checks: a check holds up to its tolerance included (a NaN deviation fails), and the three analytic checks
hold on a coarse grid for a moving cup and a moving head."""

from __future__ import annotations

import math

import pytest

from hipsim.wear.checks import SelfCheck, self_checks
from hipsim.wear.kinematics import CupSetup
from hipsim.wear.points import cup_grid


@pytest.mark.parametrize(
    ("deviation", "passed"), [(0.0, True), (1e-9, True), (1.0000001e-9, False), (math.inf, False), (math.nan, False)]
)
def test_a_check_holds_up_to_its_tolerance(deviation, passed):
    assert SelfCheck("c", "law", deviation, 1e-9).passed is passed


@pytest.mark.parametrize(
    ("moving", "mount"), [("cup", (0.0, 0.0, 0.0)), ("head", (0.0, 0.0, 0.0)), ("cup", (0.1, 0.2, 0.3))]
)
def test_the_analytic_checks_hold(moving, mount):
    checks = self_checks(CupSetup(moving=moving, cup_mount_rad=mount), cup_grid(6, 12))
    assert [c.name for c in checks] == ["pure flexion", "time reversal", "flexion arc"]
    assert all(c.passed for c in checks), checks
    assert [c.tolerance for c in checks] == [1e-9, 1e-9, 1e-5]
    arc = checks[2].law
    assert ("with the head moving" in arc) is (moving == "head")


@pytest.mark.parametrize(
    ("moving", "mount"), [("cup", (0.0, 0.0, 0.0)), ("head", (0.0, 0.0, 0.0)), ("cup", (0.3, 0, 0))]
)
def test_the_analytic_checks_on_a_few_points(moving, mount):
    """The same checks on 2 × 4 points (the mutation run's, faster without numba): each holds, and the flexion arc
    names r·(range of α)·2 from the built-in cycle's α (0 with the head moving)."""
    import numpy as np

    from hipsim.motion.trajectories import iso14242_angles

    setup = CupSetup(32.0, moving=moving, cup_mount_rad=mount)
    checks = self_checks(setup, cup_grid(2, 4, 16.0))
    assert [c.name for c in checks] == ["pure flexion", "time reversal", "flexion arc"]
    assert all(c.passed for c in checks), checks
    assert [c.tolerance for c in checks] == [1e-9, 1e-9, 1e-5]
    alpha = iso14242_angles(np.arange(1000) / 1000)[0][:, 0]
    arc = 16.0 * float(alpha.max() - alpha.min()) * 2
    if moving == "cup":
        assert checks[2].law == f"force track = r·(range of α)·2 = {arc:.6g} mm (relative difference)"
    else:
        assert checks[2].law == "force track = 0 mm with the head moving (mm)"
    assert checks[0].law == "CS = 0 at every loaded point"
    assert checks[1].law.startswith("the same s, W and CS at every point")
