"""One lot's work, in this process: warnings and failures land in its row."""

from __future__ import annotations

from pathlib import Path

from shapegen.city.work import CitySettings, LotTask, run_lot
from shapegen.search.search_options import SearchOptions

HOUSE = Path(__file__).resolve().parents[2] / "docs" / "data" / "house.grammar"
RECTANGLE = ((0.0, 0.0), (12.0, 0.0), (12.0, 8.0), (0.0, 8.0))


def _settings(**changes) -> CitySettings:
    return CitySettings(HOUSE.read_text(encoding="utf-8"), str(HOUSE), **changes)


def test_a_warning_goes_to_the_lots_row():
    settings = _settings(search=SearchOptions(max_iter=3))
    record = run_lot(settings, LotTask("w", RECTANGLE, {"jetty": 0.9}))
    assert any("outside its @Range" in w for w in record["warnings"]), record


def test_a_lot_whose_upper_walls_float_is_an_error_row_of_one_line():
    record = run_lot(_settings(), LotTask("f", RECTANGLE, {"jetty": 0.9}))
    assert record["status"] == "error" and record["stands"] is None
    assert "touch no support" in record["error"] and "\n" not in record["error"]
    assert "model" not in record


def test_a_built_lot_carries_its_building_and_what_set_its_attrs():
    record = run_lot(_settings(attrs={"storeys": 1}), LotTask("b", RECTANGLE, {"jetty": 0.2}))
    assert record["status"] == "ok" and record["from_properties"] == ["jetty"]
    assert record["attrs"] == {"jetty": 0.2} and record["left_out"] == 0
    assert record["model"].blocks and record["blocks"] == len(record["model"].blocks)


def test_a_solver_without_an_answer_leaves_the_verdict_empty_and_says_why(monkeypatch):
    import dataclasses

    import shapegen.pipeline as pipeline

    real = pipeline.design

    def ended_without_an_answer(*args, **kwargs):
        outcome = real(*args, **kwargs)
        assessment = dataclasses.replace(
            outcome.assessment, stands=False, measure=float("nan"), status="numerical_error"
        )
        return dataclasses.replace(outcome, assessment=assessment)

    monkeypatch.setattr(pipeline, "design", ended_without_an_answer)
    record = run_lot(_settings(attrs={"storeys": 1}), LotTask("n", RECTANGLE, {"jetty": 0.2}))
    assert record["status"] == "ok" and record["stands"] is None, record
    assert any("the solver ended with numerical_error" in w for w in record["warnings"])
