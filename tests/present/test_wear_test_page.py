"""The wear test's page (hipsim.present.wear_test_page): the verdict's block rendered from its records.Verdict
(DIFFERENT fail, ALIKE pass, NOT MADE open and said ONE STATION), its lines the result's, the summary's JSON written with the notes and provenance; a test of no stations made
here, its figure left out (figures: test_wear_test_figures.py). The summary itself (the stations' contexts merged
in): wear/test_test_summary.py. A whole test: cli/test_wear_test.py."""

from __future__ import annotations

import json
from types import SimpleNamespace
from typing import Any

import pytest

from hipsim.present import wear_test_page
from hipsim.present.provenance import provenance
from hipsim.records import Level, Verdict


def result(level: Level, word: str) -> Any:
    gravimetry = SimpleNamespace(source="w.csv", density_stated="0.94 g/cm³", differences=[])
    return SimpleNamespace(
        verdict=Verdict(level, "judged"),
        lines=(f"the stations are {word}",),
        word=word,
        to_json=lambda: {"verdict": word, "stations": {"A": {"rate": 1.0}}},
        gravimetry=gravimetry,
        given=None,
        reference=None,
        fitted_law=None,
        stations=[],
    )


@pytest.mark.parametrize(
    ("level", "word", "state"),
    [
        (Level.DIFFERENT, "DIFFERENT", "fail"),
        (Level.ALIKE, "ALIKE", "pass"),
        (Level.NOT_MADE, "ONE STATION", "open"),
    ],
)
def test_the_verdict_words_state_on_the_page(tmp_path, monkeypatch, level, word, state):
    monkeypatch.setattr(wear_test_page, "plot_measured_predicted", lambda result: None)  # no figure drawn here
    monkeypatch.setattr(wear_test_page, "_figures", lambda out, figures: ([], []))
    context: Any = SimpleNamespace(station="A", to_json=lambda: {"friction": "steady"})
    summarised = []

    def summary(result, contexts):  # the summary's own test: wear/test_test_summary.py
        summarised.append(contexts)
        return SimpleNamespace(
            to_json=lambda: {"verdict": word, "stations": {"A": {"rate": 1.0, "friction": "steady"}}}
        )

    monkeypatch.setattr(wear_test_page, "wear_test_summary", summary)
    page = wear_test_page.write_wear_test_page(
        tmp_path / "page", result(level, word), (context,), provenance(created="2026-01-01T00:00:00Z"), notes=("n1",)
    )
    html = page.index.read_text(encoding="utf-8")
    assert f'class="verdict {state}-box"' in html and f"the stations are {word}" in html and "judged" not in html
    assert (
        f'<span class="word">{ {"pass": "✔", "fail": "✘"}.get(state, "–") } {word}</span>' in html
        and "<li>n1</li>" in html
    )
    document = json.loads(page.json.read_text(encoding="utf-8"))
    assert summarised == [(context,)]  # the stations' contexts handed to the summary
    assert document["verdict"] == word and document["stations"]["A"] == {"rate": 1.0, "friction": "steady"}
    assert document["notes"] == ["n1"] and document["provenance"]["created_utc"] == "2026-01-01T00:00:00Z"
    assert page.pdf is None and page.figures == ()
