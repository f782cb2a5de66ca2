"""The footprint cut of a right prism (prism_cut.py) gives the general 3D cut's pieces.

Each case is cut both ways: by :func:`prism_decomposition` and by the general path of
cut.py (``_general_decomposition``, the plane-by-plane 3D clip). The pieces must be convex, closed
and made clean, fill the prism without overlapping, and be the general path's pieces: the same
corners (within 1e-9 of the prism's size) and faces of the same areas, in the same order.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest
from polygon_cases import star_polygon
from rotations import about_y

from shapegen.errors import LotError
from shapegen.geometry.cut import _general_decomposition, placed_convex_decomposition
from shapegen.geometry.extrude import prism
from shapegen.geometry.mesh import Mesh
from shapegen.geometry.prism_cut import prism_decomposition
from shapegen.geometry.scope_frames import lot_polygon, polygon_face, rotation_keeping_x
from shapegen.model.lot import Lot
from shapegen.tolerances import DEFAULT

OSM = Path(__file__).parents[1] / "data" / "osm" / "neubrandenburg.geojson.gz"

L_LOT = [(0, 0), (4, 0), (4, -2), (2, -2), (2, -4), (0, -4)]
U_LOT = [(0, 0), (6, 0), (6, -4), (4, -4), (4, -1), (2, -1), (2, -4), (0, -4)]
COMB = (
    [(0, 0), (9, 0), (9, -4)]
    + [
        p
        for k in range(4, 0, -1)
        for p in ((2 * k, -4), (2 * k, -1), (2 * k - 1, -1), (2 * k - 1, -4))
    ]
    + [(0, -4)]
)
STAR = [
    (5 * np.cos(a) * r, -5 * np.sin(a) * r)
    for k, a in enumerate(np.linspace(0, 2 * np.pi, 10, endpoint=False))
    for r in [1.0 if k % 2 == 0 else 0.4]
]
# a staircase whose cut lines run through other corners and along other edges
STAIRS = [(0, 0), (6, 0), (6, -2), (4, -2), (4, -4), (2, -4), (2, -6), (0, -6)]
# corners on the straight parts of an L (collinear), and two corners a hair apart
COLLINEAR_L = [(0, 0), (2, 0), (4, 0), (4, -1), (4, -2), (3, -2), (2, -2), (2, -4), (0, -4),
               (0, -2)]  # fmt: skip
NEAR_TWINS = [(0, 0), (4, 0), (4, -2), (2, -2), (2 + 1e-7, -2 - 1e-7), (2, -4), (0, -4)]
HAND_MADE = {
    "L": L_LOT,
    "U": U_LOT,
    "comb": COMB,
    "star": STAR,
    "stairs": STAIRS,
    "collinear L": COLLINEAR_L,
    "near twins": NEAR_TWINS,
}


def _prism(lot, height=3.0) -> Mesh:
    # a lot merges corners closer than LOT_MERGE_M; the near twins are a face a derivation
    # can still make (a split's sliver), so they are taken as they are
    _, face = polygon_face(lot) if lot is NEAR_TWINS else lot_polygon(Lot.polygon(lot))
    return prism(face.vertices, (0, height, 0))


@lru_cache(maxsize=1)
def _osm_footprints() -> tuple:
    from shapegen.city import read_lots

    city = read_lots(OSM)
    # as the city run gives them: x east, z south
    return tuple(tuple(map(tuple, np.asarray(lot.ring) * [1.0, -1.0])) for lot in city.lots)


def _turned(mesh: Mesh, seed: int) -> Mesh:
    """``mesh`` in a scope turned every way (the extrusion along no axis)."""
    rng = np.random.default_rng(seed)
    rotation = rotation_keeping_x(rng.normal(size=3), rng.normal(size=3))
    return Mesh(mesh.vertices @ rotation.T + rng.normal(size=3) * 10, mesh.faces)


def _same_pieces(fast: list[Mesh], general: list[Mesh], size: float) -> str:
    """Why the two lists of pieces differ ('' when they do not)."""
    if len(fast) != len(general):
        return f"{len(fast)} pieces against {len(general)}"
    for k, (a, b) in enumerate(zip(fast, general, strict=True)):
        a, b = a.cleaned(), b.cleaned()
        if a.n_vertices != b.n_vertices or a.n_faces != b.n_faces:
            return f"piece {k}: {a.n_vertices} corners, {a.n_faces} faces against "
        gap = np.linalg.norm(a.vertices[:, None] - b.vertices[None], axis=2)
        if max(gap.min(axis=0).max(), gap.min(axis=1).max()) > 1e-9 * size:
            return f"piece {k}: other corners"
        areas = np.sort(a.face_areas()) - np.sort(b.face_areas())
        if np.abs(areas).max() > 1e-9 * size**2:
            return f"piece {k}: faces of other areas"
    return ""


def _check_pieces(mesh: Mesh, pieces: list[Mesh], samples: int = 400) -> None:
    """Convex closed clean pieces that fill ``mesh`` and do not overlap."""
    size = mesh.size()
    # convex within the blocks' check's tolerance
    assert all(p.is_closed and p.is_convex(DEFAULT.convex_rel * size) for p in pieces)
    assert all(p.cleaned() is p for p in pieces)  # made clean: placed pieces are not cleaned again
    assert sum(p.volume() for p in pieces) == pytest.approx(mesh.volume(), rel=1e-9)
    # a point well inside two pieces would be in their overlap
    rng = np.random.default_rng(0)
    low, high = mesh.bounds()
    points = low + rng.random((samples, 3)) * (high - low)
    inside = np.zeros(samples, dtype=int)
    for piece in pieces:
        normals, centres = piece.normals_and_centres
        heights = points @ normals.T - (centres * normals).sum(axis=1)
        inside += (heights < -1e-6 * size).all(axis=1)
    assert inside.max() <= 1


def _compare(mesh: Mesh) -> tuple[list[Mesh] | None, list[Mesh] | None]:
    fast = prism_decomposition(mesh)
    general = _general_decomposition(Mesh(mesh.vertices, mesh.faces), 64)
    return fast, general


@pytest.mark.parametrize("name", sorted(HAND_MADE))
@pytest.mark.parametrize("turn", [None, 1, 2])
def test_hand_made_footprints_give_the_general_pieces(name, turn):
    mesh = _prism(HAND_MADE[name])
    if turn is not None:
        mesh = _turned(mesh, turn)
    fast, general = _compare(mesh)
    if name == "near twins":  # a side face of no width: left to the general path
        assert fast is None
        return
    assert fast is not None, "the footprint cut took the prism"
    assert _same_pieces(fast, general, mesh.size()) == ""
    _check_pieces(mesh, fast)


def test_the_pieces_of_a_comb_and_a_star():
    fast = prism_decomposition(_prism(COMB))
    assert len(fast) >= 5  # its back and its four teeth, at least
    assert len(prism_decomposition(_prism(STAR))) >= 5  # a piece per point, at least


def test_a_footprint_given_clockwise_is_cut_the_same():
    # the prism of a clockwise ring extruded up is turned inside out (Mesh.reversed's layout)
    lot = np.array(U_LOT, float)
    _, face = lot_polygon(Lot.polygon(lot))
    clockwise = face.vertices[::-1]
    mesh = prism(clockwise, (0, 3.0, 0))
    fast, general = _compare(mesh)
    assert fast is not None
    assert _same_pieces(fast, general, mesh.size()) == ""


def test_a_convex_prism_is_its_own_piece():
    mesh = _prism([(0, 0), (5, 0), (6, -3), (0, -4)])
    assert prism_decomposition(mesh) == [mesh]


@pytest.mark.parametrize(
    "case",
    ["a side face split", "a flat top", "a crossing ring", "a sheared prism", "a pyramid"],
)
def test_what_is_not_a_clean_right_prism_is_left_to_the_general_path(case):
    if case == "a side face split":
        mesh = _prism(L_LOT)
        a, b, c, d = mesh.faces[2]
        mesh = Mesh(mesh.vertices, mesh.faces[:2] + ((a, b, c), (a, c, d)) + mesh.faces[3:])
    elif case == "a flat top":
        mesh = _prism(L_LOT)
        v = mesh.vertices.copy()
        v[6, 1] += 0.5  # one top corner raised
        mesh = Mesh(v, mesh.faces)
    elif case == "a crossing ring":
        bowtie = np.array([(0, 0, 0), (4, 0, -4), (4, 0, 0), (0, 0, -4)], float)
        mesh = Mesh(np.vstack([bowtie, bowtie + (0, 3, 0)]), prism(bowtie, (0, 3, 0)).faces)
    elif case == "a sheared prism":
        mesh = _prism(L_LOT)
        v = mesh.vertices.copy()
        v[6:] += (0.7, 0, 0)  # the top moved sideways: the caps are not normal to the sides
        mesh = Mesh(v, mesh.faces)
    else:
        mesh = Mesh(
            [(0, 0, 0), (1, 0, 0), (0, 0, -1), (0, 1, 0)],
            [(0, 2, 1), (0, 1, 3), (1, 2, 3), (2, 0, 3)],
        )
    assert prism_decomposition(mesh) is None


def _osm_cases(count: int, stride: int) -> list[int]:
    return list(range(0, count * stride, stride))


def _osm_prism(index: int) -> Mesh | None:
    try:
        mesh = _prism(_osm_footprints()[index], 8.0)
    except LotError:  # a footprint the lot check refuses
        return None
    return mesh


def _check_osm(indices: list[int], turn: bool) -> None:
    taken = tried = 0
    differences = []
    for k in indices:
        mesh = _osm_prism(k)
        if mesh is None:
            continue
        if turn:
            mesh = _turned(mesh, k)
        tried += 1
        fast, general = _compare(mesh)
        if fast is None:
            continue
        taken += 1
        if general is None:
            differences.append(f"footprint {k}: the general path gives no pieces")
            continue
        why = _same_pieces(fast, general, mesh.size())
        if why:
            differences.append(f"footprint {k}: {why}")
        _check_pieces(mesh, fast, samples=100)
    assert differences == []
    assert taken >= 0.95 * tried  # the footprint cut is the one taken


def test_real_footprints_give_the_general_pieces():
    _check_osm(_osm_cases(150, 61), turn=False)


def test_real_footprints_in_turned_scopes_give_the_general_pieces():
    _check_osm(_osm_cases(60, 157), turn=True)


@pytest.mark.slow
def test_many_real_footprints_give_the_general_pieces():
    _check_osm(list(range(0, 10_000, 3)), turn=False)
    _check_osm(list(range(1, 10_000, 17)), turn=True)


@pytest.mark.parametrize("seed", range(30))
def test_random_star_footprints_give_the_general_pieces(seed):
    import shapely

    rng = np.random.default_rng(seed)
    points = star_polygon(rng, 1, 5) * [1.0, -1.0]
    if not shapely.LinearRing(points).is_simple:
        pytest.skip("a ring that crosses itself")
    mesh = _prism(points.tolist(), 2.0)
    fast, general = _compare(mesh)
    assert fast is not None
    assert _same_pieces(fast, general, mesh.size()) == ""
    _check_pieces(mesh, fast)


def test_placed_pieces_of_a_prism_are_the_general_ones_moved():
    mesh = _prism(COMB)
    rotation = about_y(25.0)
    origin = np.array([3.0, 1.0, -2.0])
    placed = placed_convex_decomposition(mesh, rotation, origin)
    general = [
        p.cleaned().transformed(rotation, origin)
        for p in _general_decomposition(Mesh(mesh.vertices, mesh.faces), 64)
    ]
    assert _same_pieces(placed, general, mesh.size()) == ""
