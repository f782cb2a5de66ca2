"""The Inspector rows and the checks on attr values a client sends."""

import pytest

from shapegen import pipeline
from shapegen.editor.attrs import RequestError, attr_specs, checked_values


@pytest.fixture
def grammar(stack_file):
    return pipeline.load(str(stack_file))


def test_rows_list_every_attr_with_kind_range_free_and_description(grammar):
    rows = {row.name: row for row in attr_specs(grammar, {"offset": 0.3})}
    assert list(rows) == ["offset", "stone", "mortar", "courses"]
    offset = rows["offset"]
    assert (offset.kind, offset.value, offset.minimum, offset.maximum) == ("number", 0.3, 0, 0.9)
    assert offset.free and offset.description == "Shift of the upper block along x (m)"
    assert 0 < offset.step <= 0.9 / 500
    assert rows["stone"].kind == "string" and rows["stone"].minimum is None
    assert rows["mortar"].kind == "bool" and not rows["mortar"].free
    assert rows["courses"].kind == "number" and rows["courses"].step is None


def test_good_values_are_converted_to_the_attrs_kinds(grammar):
    values = checked_values(grammar, {}, {"offset": 1 - 0.5, "stone": "granite", "mortar": True})
    assert values == {"offset": 0.5, "stone": "granite", "mortar": True}
    assert type(values["offset"]) is float
    assert checked_values(grammar, {}, {"courses": 3}) == {"courses": 3.0}


@pytest.mark.parametrize(
    ("payload", "message"),
    [
        ({"ofset": 0.1}, "no attr 'ofset'; did you mean 'offset'?"),
        ({"offset": "abc"}, "attr 'offset' takes a number; got 'abc'"),
        ({"offset": "0.3"}, "attr 'offset' takes a number; got '0.3'"),
        ({"offset": True}, "attr 'offset' takes a number; got True"),
        ({"offset": None}, "attr 'offset' takes a number; got None"),
        ({"offset": [1]}, "attr 'offset' takes a number; got [1]"),
        ({"offset": float("nan")}, "attr 'offset' takes a finite number"),
        ({"offset": float("inf")}, "attr 'offset' takes a finite number"),
        ({"mortar": 1}, "attr 'mortar' takes true or false; got 1"),
        ({"stone": 3}, "attr 'stone' takes a string; got 3"),
        ({}, "no attr values given"),
        ([["offset", 0.1]], "send a JSON object of attr values"),
        ("offset=0.1", "send a JSON object of attr values"),
        (None, "send a JSON object of attr values"),
    ],
)
def test_bad_values_are_refused_with_one_line_naming_the_problem(grammar, payload, message):
    with pytest.raises(RequestError) as caught:
        checked_values(grammar, {}, payload)
    assert caught.value.status == 400
    assert message in str(caught.value)
    assert "\n" not in str(caught.value)
