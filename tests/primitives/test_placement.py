"""Primitive blocks made once per (size, parameters) and moved into each scope are the blocks the
primitive makes in that scope, are new objects each time, and stay under the work limits."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from shapegen.engine.grammar_api import load_grammar
from shapegen.errors import GeometryError
from shapegen.limits import work_limits
from shapegen.model.block import Block
from shapegen.model.scope import Scope
from shapegen.primitives import library
from shapegen.primitives.registry import REGISTRY, primitive

RULES = Path(__file__).resolve().parents[2] / "rules"

# Parameters that make each built-in primitive valid in a 4 x 3 x 2 m scope.
PARAMETERS = {"cable": {"sag": 1.0, "lanes": 2}, "suspenders": {"sag": 1.0}}
PROPER_ONLY = {"box"}  # its corner order assumes a right-handed frame


def _scopes(mirrored: bool):
    rng = np.random.default_rng(7)
    for _ in range(3):
        rotation = Rotation.random(random_state=rng).as_matrix()
        if mirrored:
            rotation = rotation @ np.diag([1.0, 1.0, -1.0])
        yield Scope(rng.normal(size=3) * 40.0, rotation, np.array([4.0, 3.0, 2.0]))


def _polyhedron(block: Block) -> list[float]:
    """Volume (m^3) and centroid (m): the same polyhedron has the same ones."""
    return [block.volume, *block.centroid]


@pytest.mark.parametrize("mirrored", [False, True])
@pytest.mark.parametrize("name", [n for n in library.available() if n in REGISTRY])
def test_a_placed_block_is_the_block_made_in_place(name, mirrored):
    made = library.get(name)
    if not made.scope_relative or (mirrored and name in PROPER_ONLY):
        pytest.skip(f"{name} is not placed from a template in this frame")
    params = PARAMETERS.get(name, {})
    for scope in _scopes(mirrored):
        direct = made._checked(scope, made.resolve(params))
        placed = made(scope, **params)
        assert len(placed) == len(direct)
        for a, b in zip(direct, placed, strict=True):
            # Hull-built blocks may list their vertices in another order; the polyhedron is one.
            assert _polyhedron(a) == pytest.approx(_polyhedron(b), abs=1e-9)
            assert np.allclose(np.sort(a.vertices, axis=0), np.sort(b.vertices, axis=0), atol=1e-9)
            assert b.tags == a.tags


def test_prism_built_blocks_are_placed_bit_for_bit():
    wall = library.get("wall")
    for scope in _scopes(mirrored=True):
        direct = wall._checked(scope, wall.resolve({}))
        placed = wall(scope)
        assert all(
            np.array_equal(a.vertices, b.vertices) for a, b in zip(direct, placed, strict=True)
        )
        assert all(a.faces == b.faces for a, b in zip(direct, placed, strict=True))


def test_each_insert_gets_new_blocks():
    scope = next(_scopes(mirrored=False))
    first = library.insert("arch", scope)
    second = library.insert("arch", scope)
    assert all(a is not b for a, b in zip(first, second, strict=True))
    first[0].density = 1.0
    first[0].tags = ("changed",)
    first[0].vertices[0] += 1.0
    again = library.insert("arch", scope)
    assert again[0].density != 1.0 and "changed" not in again[0].tags
    assert np.array_equal(again[0].vertices, second[0].vertices)


def test_a_lowered_block_limit_holds_for_a_made_template():
    scope = Scope(np.zeros(3), np.eye(3), np.array([4.0, 3.0, 2.0]))
    blocks = library.insert("wall", scope)
    with work_limits(max_primitive_blocks=len(blocks) - 1):
        with pytest.raises(GeometryError, match="max_primitive_blocks"):
            library.insert("wall", scope)


def test_a_primitive_that_reads_its_place_is_made_in_place():
    calls = []

    @primitive("plinth_at_height_for_a_test")
    def plinth(scope, *, depth: float = 0.5):
        calls.append(scope.origin.copy())
        height = 1.0 + scope.origin[1]  # depends on where the scope is: not scope-relative
        corners = np.array([[x, y, z] for x in (0, 1) for y in (0, height) for z in (0, depth)])
        return [Block.from_hull(scope.to_world(corners))]

    try:
        made = library.get("plinth_at_height_for_a_test")
        assert not made.scope_relative
        low = made(Scope(np.zeros(3), np.eye(3), np.ones(3)))
        high = made(Scope(np.array([0.0, 2.0, 0.0]), np.eye(3), np.ones(3)))
        assert len(calls) == 2
        assert high[0].volume == pytest.approx(3 * low[0].volume)
    finally:
        REGISTRY.pop("plinth_at_height_for_a_test", None)


@pytest.mark.parametrize("rule", ["cluny", "barrel_vault", "arch_columns"])
def test_a_model_from_templates_is_the_model_made_in_place(rule, monkeypatch):
    grammar = load_grammar(RULES / f"{rule}.grammar")
    placed = grammar.build()
    for name, made in list(REGISTRY.items()):
        monkeypatch.setitem(REGISTRY, name, dataclasses.replace(made, scope_relative=False))
    direct = grammar.build()
    assert len(placed.blocks) == len(direct.blocks)
    for a, b in zip(direct.blocks, placed.blocks, strict=True):
        assert (a.id, a.tags, a.rule_path, a.density) == (b.id, b.tags, b.rule_path, b.density)
        assert _polyhedron(a) == pytest.approx(_polyhedron(b), abs=1e-9)


def test_carried_volumes_and_centroids_are_those_of_the_placed_vertices():
    for scope in _scopes(mirrored=True):
        for block in library.insert("groin_vault", scope):
            recomputed = Block(block.vertices, block.faces)
            assert _polyhedron(block) == pytest.approx(_polyhedron(recomputed), abs=1e-9)
