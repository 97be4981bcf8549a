"""The models' cross-check summary and its verdict, by hand (hipsim/analysis/crosscheck_summary.py): PASS when every
configuration that must agree does; an informational one does not decide."""

from __future__ import annotations

import jsonschema
import pytest

from hipsim.analysis.crosscheck import TOLERANCE, Comparison
from hipsim.analysis.crosscheck_summary import ColumnDifference, CrossCheckSummary, crosscheck_summary
from hipsim.records import Level, exit_status

AGREE = Comparison("a", "analytic vs pinocchio", True, (("tau_1_Nmm", 1e-9, 1e-12), ("tau_2_Nmm", 2e-9, TOLERANCE)))
APART = Comparison("b", "with and without lever spin", False, (("tau_1_Nmm", 3.0, 0.02),))
OFF = Comparison("c", "mujoco", True, (("tau_3_Nmm", 1e-3, 2 * TOLERANCE),))


def test_the_summary_by_hand():
    s = crosscheck_summary("iso", 200, "published", [AGREE, APART])
    assert (s.trajectory, s.samples, s.parameters, s.tolerance) == ("iso", 200, "published", TOLERANCE)
    assert s.agree is True and s.level == Level.PASS and exit_status([s]) == 0  # the informational one is apart
    first, second = s.comparisons
    assert (first.name, first.description, first.required, first.ok, first.worst) == (
        "a", "analytic vs pinocchio", True, True, TOLERANCE
    )  # fmt: skip
    assert first.columns == (ColumnDifference("tau_1_Nmm", 1e-9, 1e-12), ColumnDifference("tau_2_Nmm", 2e-9, TOLERANCE))
    assert (second.name, second.required, second.ok, second.worst) == ("b", False, False, 0.02)
    doc = s.to_json()
    jsonschema.validate(doc, CrossCheckSummary.json_schema())
    assert doc["comparisons"][1]["columns"] == [{"column": "tau_1_Nmm", "max_abs_diff": 3.0, "max_rel_diff": 0.02}]


@pytest.mark.parametrize(
    ("comparisons", "agree"),
    [([AGREE, OFF], False), ([OFF], False), ([APART], True), ([], True), ([AGREE], True), ([APART, OFF, AGREE], False)],
)
def test_every_required_configuration_must_agree(comparisons, agree):
    s = crosscheck_summary("iso", 10, "published", comparisons)
    assert s.agree is agree and s.level == (Level.PASS if agree else Level.FAIL)
    assert exit_status([s]) == (0 if agree else 1) and len(s.comparisons) == len(comparisons)
