"""Work limits: each one stops the work it bounds with a message naming it and how to raise it,
raising it lets the same work through, and a bad limit is refused in one line."""

from __future__ import annotations

import numpy as np
import pytest

import shapegen
from shapegen.errors import GeometryError, GrammarError, OptionError
from shapegen.limits import DEFAULT_LIMITS, WorkLimits, current_limits, work_limits
from shapegen.model.block import Block
from shapegen.model.scope import Scope
from shapegen.primitives import insert


def _grammar(body: str, head: str = "") -> shapegen.Grammar:
    return shapegen.parse_grammar(f"{head}@StartRule @Lot(10, 1)\nLot --> extrude(5) {body}\n")


# (limit, a value small enough to be reached, grammar head, rule body)
CASES = [
    # the recursion reads the shape: a function of its arguments alone keeps its values
    ("max_calls", 50, "f(n) = case n > 0 : f(n - 1) + f(n - 1) else : scope.sx\n",
     "t(f(8), 0, 0) A"),
    ("max_call_depth", 10, "f(n) = case n > 0 : f(n - 1) + 1 else : 1\n", "t(f(20), 0, 0) A"),
    ("max_string_length", 100, 'd(x) = x + x\ns(n) = case n > 0 : d(s(n - 1)) else : "x"\n',
     'report("k", s(8))'),
    ("max_string_chars", 1000, "", 'split(x) { 0.1 : [ report("k", "0123456789" + "x") ] A }*'),
    ("max_shapes", 50, "", "split(x) { 0.1 : A }*"),
    ("max_depth", 5, "", "Grow\nGrow --> Grow"),
    ("max_primitive_blocks", 10, "", 'i("dome", rings = 4, meridians = 8)'),
    ("max_blocks", 10, "", "split(x) { 0.5 : A }*"),
]  # fmt: skip


@pytest.mark.parametrize(("name", "small", "head", "body"), CASES, ids=[c[0] for c in CASES])
def test_a_limit_reached_names_itself_and_raising_it_lets_the_work_through(name, small, head, body):
    grammar = _grammar(body, head)
    with work_limits(**{name: small}), pytest.raises((GrammarError, GeometryError)) as caught:
        grammar.build()
    message = str(caught.value).splitlines()[0]
    assert f"limit {name} = {small}" in message or f"({name})" in message
    assert f"work_limits({name}=...)" in message
    if name != "max_depth":  # an endless rule stays endless
        grammar.build()  # the defaults are far above


def test_the_clock_stops_a_long_derivation():
    grammar = _grammar("split(x) { 0.001 : A }*")
    with work_limits(max_seconds=1e-6), pytest.raises(GrammarError, match="max_seconds"):
        grammar.build()


def test_build_arguments_override_the_context_for_one_build():
    grammar = _grammar("split(x) { 0.1 : A }*")
    with work_limits(max_shapes=10):
        assert len(grammar.build(max_shapes=1000).blocks) == 100
    with pytest.raises(GrammarError, match="max_shapes"):
        grammar.build(max_shapes=10)


def test_limits_are_restored_after_the_block_and_nest():
    assert current_limits() is DEFAULT_LIMITS
    with work_limits(max_blocks=7):
        with work_limits(max_calls=3) as inner:
            assert (inner.max_blocks, inner.max_calls) == (7, 3)
        assert current_limits().max_calls == DEFAULT_LIMITS.max_calls
    assert current_limits() is DEFAULT_LIMITS


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"max_block": 5}, "unknown work limit 'max_block'"),
        ({"max_blocks": 0}, "max_blocks must be a whole number >= 1"),
        ({"max_blocks": 2.5}, "max_blocks must be a whole number >= 1"),
        ({"max_blocks": True}, "max_blocks must be a whole number >= 1"),
        ({"max_seconds": -1}, "max_seconds must be a positive number of seconds or None"),
        ({"max_seconds": float("nan")}, "max_seconds must be a positive"),
    ],
)
def test_a_bad_limit_is_one_clear_error(changes, message):
    with pytest.raises(OptionError, match=message), work_limits(**changes):
        pass


def test_no_time_limit_is_allowed():
    with work_limits(max_seconds=None) as limits:
        assert limits.max_seconds is None
        assert len(_grammar("split(x) { 1 : A }*").build().blocks) == 10


def test_every_default_is_above_every_bundled_rule():
    # The largest bundled model: Cluny, 1 072 blocks from 662 shapes, a 14 kB file.
    assert DEFAULT_LIMITS.max_blocks >= 40 * 1072
    assert DEFAULT_LIMITS.max_shapes >= 200 * 662
    assert DEFAULT_LIMITS.max_source_chars >= 7 * 14_277
    assert WorkLimits() == DEFAULT_LIMITS


def test_count_parameters_are_bounded_before_the_primitive_runs():
    scope = Scope.axis_aligned((0, 0, 0), (4, 2, 1))
    with pytest.raises(GeometryError, match=r"'segments' is 1e\+16, more than 20000"):
        insert("arch", scope, segments=1e16)
    with pytest.raises(GeometryError, match="a number beyond float range"):
        insert("arch", scope, thickness=10**400)
    with work_limits(max_primitive_blocks=4):
        assert len(insert("arch", scope, segments=4)) == 4
        with pytest.raises(GeometryError, match="'segments' is 5, more than 4"):
            insert("arch", scope, segments=5)


def test_a_plug_in_primitive_is_held_to_the_limit_after_the_fact():
    from shapegen.primitives.registry import REGISTRY, primitive

    @primitive("many_boxes_for_a_test")
    def many_boxes(scope, *, count: float = 3.0):
        return [Block.box((k, 0, 0), (k + 1, 1, 1)) for k in range(int(count))]

    try:
        scope = Scope.axis_aligned((0, 0, 0), (1, 1, 1))
        with work_limits(max_primitive_blocks=5):
            assert len(insert("many_boxes_for_a_test", scope, count=5)) == 5
            with pytest.raises(GeometryError, match="would make 6 blocks"):
                insert("many_boxes_for_a_test", scope, count=6)
    finally:
        REGISTRY.pop("many_boxes_for_a_test")


def test_a_wall_of_tiny_blocks_is_refused_by_the_count_it_implies():
    scope = Scope.axis_aligned((0, 0, 0), (10, 5, 1))
    for block_length in (1e-9, 5e-324):
        with pytest.raises(GeometryError, match="primitive 'wall' would make"):
            insert("wall", scope, block_length=block_length)
    assert np.isclose(sum(b.volume for b in insert("wall", scope)), 50.0)
