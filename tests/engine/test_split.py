"""Split-size resolution against CityEngine's documented examples (issue 3, section 3)."""

import pytest

from shapegen.engine.shapes.split import (
    FLOATING,
    RELATIVE,
    PieceLimitError,
    SplitPart,
    SplitRepeat,
    resolve_split,
)


def absolute(size, key):
    return SplitPart(size, key=key)


def floating(size, key):
    return SplitPart(size, FLOATING, key)


def relative(size, key):
    return SplitPart(size, RELATIVE, key)


def layout(total, pattern):
    return [(p.key, p.start, p.size) for p in resolve_split(total, pattern)]


# (pattern on a scope of 10, expected (key, size) in order); starts follow from the sizes.
CITYENGINE_EXAMPLES = [
    pytest.param(
        [absolute(3.3, "Z"), floating(3, "Y"), absolute(5, "X")],
        [("Z", 3.3), ("Y", 1.7), ("X", 5.0)],
        id="floating-fills-the-rest",
    ),
    pytest.param(
        [floating(0.5, "Z"), floating(0.1, "Y"), floating(0.2, "X")],
        [("Z", 6.25), ("Y", 1.25), ("X", 2.5)],
        id="floating-proportional",
    ),
    pytest.param(
        SplitRepeat((absolute(2, "X"), absolute(1, "Y"))),
        [("X", 2), ("Y", 1)] * 3 + [("X", 1)],
        id="absolute-repeat-last-cut",
    ),
    pytest.param(
        SplitRepeat((floating(2.1, "G"),)),
        [("G", 2.0)] * 5,
        id="floating-repeat-closest-count",
    ),
    pytest.param(
        [relative(0.5, "Z"), relative(0.1, "Y"), relative(0.2, "X")],
        [("Z", 5.0), ("Y", 1.0), ("X", 2.0)],
        id="relative-leaves-rest-empty",
    ),
]


@pytest.mark.parametrize("pattern, expected", CITYENGINE_EXAMPLES)
def test_cityengine_examples(pattern, expected):
    pieces = layout(10.0, pattern)
    assert [key for key, _, _ in pieces] == [key for key, _ in expected]
    assert [size for _, _, size in pieces] == pytest.approx([size for _, size in expected])
    # Pieces are contiguous from the scope's origin.
    cursor = 0.0
    for _, start, size in pieces:
        assert start == pytest.approx(cursor)
        cursor += size
    assert cursor <= 10.0 + 1e-9


def test_relative_split_leaves_the_rest_empty():
    pieces = layout(10.0, [relative(0.5, "Z"), relative(0.1, "Y"), relative(0.2, "X")])
    assert pieces[-1][1] + pieces[-1][2] == pytest.approx(8.0)


@pytest.mark.parametrize(
    "pattern, expected",
    [
        # CityEngine's "absolute values in a limited scope" example on a scope of 5:
        # Yellow is cut from 2 to 1 and the last Blue is not created.
        (
            [
                absolute(2, "G1"),
                absolute(1, "G2"),
                absolute(1, "B"),
                absolute(2, "Y"),
                absolute(1, "B2"),
            ],
            [("G1", 0, 2), ("G2", 2, 1), ("B", 3, 1), ("Y", 4, 1)],
        ),
        # Sizes <= 0 make no piece and take no room: Blue starts at 1.5, the last Green is cut.
        (
            [
                absolute(1.5, "G1"),
                absolute(-2, "Y1"),
                absolute(1.5, "B"),
                absolute(1.5, "G2"),
                absolute(0, "Y2"),
                absolute(1.5, "G3"),
            ],
            [("G1", 0, 1.5), ("B", 1.5, 1.5), ("G2", 3, 1.5), ("G3", 4.5, 0.5)],
        ),
        # A floating part with no room left is not created.
        ([absolute(3, "A"), absolute(2, "B"), floating(1, "F")], [("A", 0, 3), ("B", 3, 2)]),
        # One floating part between absolutes takes exactly the rest.
        (
            [absolute(1, "A"), floating(1, "F"), absolute(1, "B")],
            [("A", 0, 1), ("F", 1, 3), ("B", 4, 1)],
        ),
    ],
)
def test_limits_and_non_positive_sizes(pattern, expected):
    pieces = layout(5.0, pattern)
    assert [k for k, _, _ in pieces] == [k for k, _, _ in expected]
    assert [v for _, s, z in pieces for v in (s, z)] == pytest.approx(
        [v for _, s, z in expected for v in (s, z)]
    )


def test_repeat_that_fits_exactly_has_no_sliver():
    pieces = layout(9.0, SplitRepeat((absolute(2, "X"), absolute(1, "Y"))))
    assert len(pieces) == 6
    pieces = layout(1.0, SplitRepeat((absolute(0.1, "X"),)))
    assert len(pieces) == 10  # 0.1 is not exact in binary; rounding must not add an 11th piece


@pytest.mark.parametrize("total, count", [(10.0, 5), (10.4, 5), (11.0, 5), (11.6, 6), (1.0, 1)])
def test_floating_repeat_count_is_closest_to_nominal(total, count):
    # n minimises |total / n - 2.1| over whole n >= 1.
    pieces = layout(total, SplitRepeat((floating(2.1, "G"),)))
    assert len(pieces) == count
    assert [p[2] for p in pieces] == pytest.approx([total / count] * count)


def test_floating_repeat_with_absolute_parts():
    # { 1 : Wall | ~2 : Window }* on 10: nominal 3 per bay -> 3 bays of 10/3, windows absorb.
    pieces = layout(10.0, SplitRepeat((absolute(1, "Wall"), floating(2, "Window"))))
    assert [k for k, _, _ in pieces] == ["Wall", "Window"] * 3
    assert [z for _, _, z in pieces] == pytest.approx([1, 10 / 3 - 1] * 3)


def test_nested_repeat_takes_the_rest_between_absolutes():
    pattern = [absolute(1, "A"), SplitRepeat((floating(1, "B"),)), absolute(1, "C")]
    pieces = layout(10.0, pattern)
    assert [k for k, _, _ in pieces] == ["A"] + ["B"] * 8 + ["C"]
    assert [z for _, _, z in pieces] == pytest.approx([1] + [1] * 8 + [1])
    assert pieces[-1][1] == pytest.approx(9.0)


def test_nested_repeat_inside_repeat():
    # The inner group's nominal length is one repetition (0.5), so the outer period is 1.5 and
    # fits 4 times in 6; each inner group gets 0.5 and holds one piece.
    inner = SplitRepeat((absolute(0.5, "b"),))
    pieces = layout(6.0, SplitRepeat((absolute(1, "P"), inner)))
    assert [k for k, _, _ in pieces] == ["P", "b"] * 4
    # A longer inner span holds several inner pieces: ~4 weight takes 4 of each 5 m bay.
    pieces = layout(10.0, SplitRepeat((absolute(1, "P"), SplitRepeat((floating(4, "x"),)))))
    assert [z for _, _, z in pieces] == pytest.approx([1, 4] * 2)


def test_relative_sizes_refer_to_the_whole_scope_inside_repeats():
    pieces = layout(8.0, SplitRepeat((relative(0.25, "Q"),)))
    assert [z for _, _, z in pieces] == pytest.approx([2.0] * 4)


@pytest.mark.parametrize("total", [0.0, -1.0])
def test_empty_scope_gives_no_pieces(total):
    assert layout(total, [absolute(1, "A"), floating(1, "B")]) == []


def test_runaway_repeat_is_stopped():
    with pytest.raises(PieceLimitError):
        resolve_split(1000.0, SplitRepeat((absolute(1e-6, "A"),)), max_pieces=1000)


def test_non_finite_size_is_refused():
    with pytest.raises(ValueError):
        resolve_split(10.0, [absolute(float("nan"), "A")])


def test_a_layout_resolved_before_is_refused_under_a_smaller_piece_limit():
    # the same split again comes from the layouts already resolved: its pieces are equal, a
    # caller's list is its own, and a limit below what the layout needs still refuses it
    pattern = SplitRepeat((SplitPart(1.0, FLOATING, "tile"),))
    first = resolve_split(10.0, pattern, max_pieces=100)
    first.clear()
    again = resolve_split(10.0, pattern, max_pieces=100)
    assert [(p.key, p.start, p.size) for p in again] == [("tile", float(k), 1.0) for k in range(10)]
    with pytest.raises(PieceLimitError):
        resolve_split(10.0, pattern, max_pieces=9)
