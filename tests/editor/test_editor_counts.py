"""Attrs that count (bays, courses, towers): found from how the rules use them, stepped by 1 on
the page and refused as fractions by the API."""

import pytest

from shapegen import parse_grammar, pipeline
from shapegen.editor.attrs import RequestError, attr_specs, checked_values
from shapegen.editor.counts import count_attrs

LOT = "@StartRule @Lot(4, 1)\n"
COLUMN = 'Lot --> extrude(3) i("column", courses = drums)'


@pytest.mark.parametrize(
    ("text", "counts"),
    [
        # an int parameter of a primitive
        ('@Range(1, 8)\nattr drums = 3\n' + LOT + COLUMN, {"drums"}),
        # ... reached through a rule's parameter, a const and +
        ('attr drums = 3\nconst more = drums + 1\n' + LOT
         + 'Lot --> extrude(3) Column(more)\nColumn(n) --> i("column", courses = n)',
         {"drums"}),
        # a recursion counter: Row(k - 1)
        ('@Range(1, 9)\nattr bays = 4\n' + LOT + 'Lot --> extrude(2) Row(bays)\n'
         'Row(k) --> case k > 1 : split(x) { 1 : Bay | ~1 : Row(k - 1) } else : Bay\n'
         'Bay --> i("box")',
         {"bays"}),
        # compared with a recursion counter, through a function's case values and max()
        ('attr towers = 2\n@Range(10, 100)\nattr length = 40\nattr span = 10\n'
         'spans = case towers >= 2 : towers - 1 else : max(1, floor(length / span))\n' + LOT
         + 'Lot --> extrude(2) Tower(0)\n'
         'Tower(k) --> case k <= spans : [ t(k * span, 0, 0) s(1, 1, 1) i("box") ] Tower(k + 1)'
         ' else : NIL',
         {"towers"}),
        # a count made of lengths (floor, *, /) leaves the lengths real
        ('attr height = 6\nattr course = 2\n' + LOT
         + 'Lot --> extrude(height) i("column", courses = floor(height / course))',
         set()),
        ('attr n = 2\n' + LOT + 'Lot --> extrude(2) i("column", courses = 2 * n)', set()),
        # a whole number the rules only measure with is no count
        ('@Range(1, 9)\nattr height = 4\n' + LOT + 'Lot --> extrude(height) i("box")', set()),
        # a count whose default or range is not whole is not taken for one
        ('@Range(1, 8)\nattr drums = 2.5\n' + LOT + COLUMN, set()),
        ('@Range(0.5, 8)\nattr drums = 2\n' + LOT + COLUMN, set()),
        # a parameter of a rule that shadows an attr is not the attr
        ('attr k = 2\nattr m = 3\n' + LOT + 'Lot --> extrude(2) Row(m)\n'
         'Row(k) --> case k > 0 : Row(k - 1) else : NIL',
         {"m"}),
    ],
)  # fmt: skip
def test_counts_are_found_from_how_the_rules_use_them(text, counts):
    assert count_attrs(parse_grammar(text)) == counts


@pytest.fixture(scope="module")
def cluny():
    return pipeline.load("cluny.grammar")


def test_clunys_counts_step_by_one_and_its_lengths_do_not(cluny):
    expected = {
        "bays", "nave_vault_segments", "aisle_vault_segments", "vault_courses",
        "arcade_segments", "window_segments", "flyer_segments", "buttress_courses",
    }  # fmt: skip
    assert count_attrs(cluny) == expected
    rows = {row.name: row for row in attr_specs(cluny, cluny.attrs)}
    for name, row in rows.items():
        assert row.whole == (name in expected), name
        if name in expected:
            assert row.step == 1
        else:
            assert row.step < 1, name  # bay_length, flyer_angle, nave_height... stay fine-grained


@pytest.mark.parametrize(
    ("grammar", "values", "message"),
    [
        (
            "cluny.grammar",
            {"bays": 5.4},
            "attr 'bays' is a count: it takes a whole number; got 5.4",
        ),
        ("cluny.grammar", {"vault_courses": 9.26}, "'vault_courses' is a count"),
        ("suspension_bridge.grammar", {"towers": 2.5}, "'towers' is a count"),
    ],
)
def test_a_fraction_for_a_count_is_refused_with_422(grammar, values, message):
    loaded = pipeline.load(grammar)
    with pytest.raises(RequestError) as caught:
        checked_values(loaded, {}, values)
    assert caught.value.status == 422 and message in str(caught.value)


def test_whole_values_for_counts_and_fractions_for_lengths_pass(cluny):
    values = checked_values(cluny, {}, {"bays": 6, "vault_courses": 8.0, "bay_length": 5.55})
    assert values == {"bays": 6.0, "vault_courses": 8.0, "bay_length": 5.55}


def test_a_number_beyond_a_float_is_refused_not_raised(cluny):
    with pytest.raises(RequestError, match="takes a finite number"):
        checked_values(cluny, {}, {"bays": 10**400})
