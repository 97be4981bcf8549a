"""The report command's own words (hipsim.cli.report): the note on the margins' 95 % confidence, from bands made
by hand (the rating check's word is the drive's verdict, tests/analysis/test_streaming.py). The page through the command line: present/test_report.py."""

from __future__ import annotations

from types import SimpleNamespace

from hipsim.cli.report import _bands_note
from hipsim.design.checks import Check


def band(confident, margin=0.2, interval=(0.1, 0.3), module=1):
    return SimpleNamespace(
        confident=confident, check=Check(module, "s1_rms", 1.0, 1.0, margin, True), interval=interval
    )


def test_the_note_counts_the_confident_margins_and_names_the_others():
    head = "Sizing margins with the uncertainty of the identified parameters (the parameter file's covariance): "
    assert _bands_note([band(True), band(None)]) == (
        head + "1 of 1 checks pass with 95 % confidence (margin at least 1.645 of its standard deviations)."
    )
    note = _bands_note([band(True), band(False, 0.02, (-0.013, 0.053), module=3)])
    assert note.startswith(head + "1 of 2 checks pass with 95 % confidence")
    assert note.endswith(
        "; not: RMS torque under the S1 curve at the mean speed, LN3: margin +2.0 % (95 %: -1.3 % to +5.3 %)."
    )
