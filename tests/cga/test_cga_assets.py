"""Inserting assets and CityEngine's primitives: files found in the rule's project, fitted into
the scope as op_i says (zero sizes keep the asset's proportion), blocks for closed convex
solids and surfaces for the rest; a missing file is a warning, never a silent empty leaf."""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest
import trimesh
from fbx_files import write_block_fbx

import shapegen
from shapegen.engine.derivation.state import Derivation, root_state
from shapegen.engine.operations.cga import register_all
from shapegen.engine.operations.cga.assets import fitted, is_asset_name, primitive_mesh
from shapegen.engine.operations.registry import compiler_for
from shapegen.engine.shapes.shape import MASS, Shape
from shapegen.errors import GrammarError
from shapegen.geometry.mesh import Mesh
from shapegen.grammar import ast
from shapegen.model.scope import Scope

register_all()  # every operation registered, whether a rule named it yet or not


@pytest.fixture
def project(tmp_path):
    """An extracted rule package: rules/ and assets/ side by side."""
    (tmp_path / "rules").mkdir()
    (tmp_path / "assets" / "doors").mkdir(parents=True)
    # a closed box 1 x 2 x 0.1 m centred on the origin, and an open L-shaped plate
    trimesh.creation.box(extents=(1, 2, 0.1)).export(tmp_path / "assets" / "doors" / "door.obj")
    (tmp_path / "assets" / "plate.obj").write_text(
        "v 0 0 0\nv 2 0 0\nv 2 0 1\nv 1 0 1\nv 1 0 2\nv 0 0 2\nf 6 5 4 3 2 1\n"
    )
    return tmp_path


def _build(project, text, lot=(12, 8)):
    path = project / "rules" / "house.cga"
    path.write_text("@StartRule\n" + text)
    return shapegen.load_grammar(path).build(lot=lot)


def test_asset_is_found_in_the_project_and_fitted_to_the_scope(project):
    model = _build(project, 'Lot --> extrude(4) split(x) { 3 : Door | ~1 : NIL }\n'
                            'Door --> s(\'1, \'1, 0.2) i("doors/door.obj")')  # fmt: skip
    (door,) = model.blocks
    assert door.vertices.min(axis=0) == pytest.approx([0, 0, 0])
    assert door.vertices.max(axis=0) == pytest.approx([3, 4, 0.2])
    assert door.volume == pytest.approx(3 * 4 * 0.2)
    assert door.rule_path == ("Lot", "Door")


def test_open_asset_is_a_surface(project):
    model = _build(project, 'Lot --> i("assets/plate.obj")')
    assert not model.blocks
    (plate,) = model.surfaces
    assert plate.reason  # says why it is not a block
    # fitted to the 12 x 8 lot: the L keeps three quarters of its bounding box
    mesh = Mesh(plate.vertices, plate.faces)
    assert mesh.area() == pytest.approx(0.75 * 12 * 8)


def test_missing_asset_is_a_warning_naming_file_and_rule(project):
    rules = "Lot --> extrude(2) split(x) { 6 : Gone | ~1 : Kept }\n"
    rules += 'Gone --> i("assets/nothere.obj")\nKept --> i("builtin:cube")'
    model = _build(project, rules)
    # CityEngine's runtime puts a box filling the scope in place of a missing asset
    assert len(model.blocks) == 2 and not model.surfaces
    assert sorted(round(b.volume, 9) for b in model.blocks) == [6 * 2 * 8.0, 6 * 2 * 8.0]
    (warning,) = model.metadata["warnings"]
    assert "'assets/nothere.obj' not found" in warning and "Lot -> Gone" in warning


def test_a_format_shapegen_cannot_read_is_an_asset_not_found_in_cga_and_an_error_in_grammar(
    project,
):
    (project / "assets" / "tree.usd").write_bytes(b"PXR-USDC")
    text = 'Lot --> extrude(1) i("assets/tree.usd")'
    model = _build(project, text)
    # CityEngine reads USD; shapegen says so and inserts the box of an asset not found
    assert [b.volume for b in model.blocks] == pytest.approx([12 * 1 * 8])
    (warning,) = model.metadata["warnings"]
    assert ".usd assets are not read by shapegen" in warning and "a box fills" in warning
    path = project / "rules" / "house.grammar"
    path.write_text("@StartRule\n" + text)
    with pytest.raises(GrammarError, match=r"\.usd assets are not read by shapegen; it reads"):
        shapegen.load_grammar(path)


def test_an_fbx_asset_without_ufbx_is_a_box_and_a_line_saying_what_to_install(project, monkeypatch):
    monkeypatch.setitem(sys.modules, "ufbx", None)  # as if it were not installed
    (project / "assets" / "tree.fbx").write_bytes(b"Kaydara FBX Binary  \x00")
    model = _build(project, 'Lot --> extrude(1) i("assets/tree.fbx")')
    assert [b.volume for b in model.blocks] == pytest.approx([12 * 1 * 8])
    (warning,) = model.metadata["warnings"]
    assert "reading FBX needs the ufbx package: pip install 'shapegen[fbx]'" in warning


def test_an_fbx_asset_is_read_with_its_faces_whole(project):
    pytest.importorskip("ufbx", reason="reading FBX needs the ufbx package")
    write_block_fbx(project / "assets" / "block.fbx")
    model = _build(project, 'Lot --> i("assets/block.fbx", yUp, keepSizeAndPosition) B.')
    faces = sorted(len(f) for leaf in [*model.blocks, *model.surfaces] for f in leaf.faces)
    assert faces == [4] * 6 + [5] and not model.metadata["warnings"]


@pytest.mark.parametrize(("up", "size"), [("Y_UP", (1, 2, 3)), ("Z_UP", (1, 3, 2)),
                                          ("X_UP", (2, 1, 3))])  # fmt: skip
def test_collada_assets_are_read_with_their_up_axis(project, up, size):
    box = trimesh.creation.box(extents=(1, 2, 3)).export(file_type="dae")
    text = box.decode() if isinstance(box, bytes) else box
    text = text.replace("<up_axis>Y_UP</up_axis>", f"<up_axis>{up}</up_axis>")
    (project / "assets" / "box.dae").write_text(text)
    model = _build(project, 'Lot --> i("assets/box.dae", yUp, keepSizeAndPosition) B.')
    (block,) = model.blocks
    extent = block.vertices.max(axis=0) - block.vertices.min(axis=0)
    assert np.allclose(extent, size) and not model.metadata["warnings"]


def test_a_built_in_asset_shapegen_lacks_is_an_asset_not_found(project):
    # CityEngine's compiler cannot know the strings i() is given: its runtime warns
    model = _build(project, 'Lot --> extrude(1) i("builtin:sphere")')
    assert [b.volume for b in model.blocks] == pytest.approx([12 * 1 * 8])
    (warning,) = model.metadata["warnings"]
    assert "'builtin:sphere' not found" in warning


def test_builtin_cube_fills_the_scope_and_template_primitives_still_work(project):
    model = _build(project, 'Lot --> extrude(3) split(x) { 4 : i("builtin:cube") C. | ~1 : '
                            'i("box") B. }')  # fmt: skip
    assert [b.volume for b in model.blocks] == pytest.approx([4 * 3 * 8, 8 * 3 * 8])


def test_asset_names():
    assert is_asset_name("assets/x.obj") and is_asset_name("builtin:cube")
    assert is_asset_name("door.glb") and not is_asset_name("box") and not is_asset_name("arch")


# ------------------------------------------------------------------------------ op_i fitting
ASSET = Mesh.box((2.0, 4.0, 1.0)).transformed(None, (10.0, 20.0, 30.0))  # bbox (10, 20, 30)+


def _scope(size):
    return Scope(np.zeros(3), np.eye(3), np.asarray(size, float))


def test_fit_all_sizes_scale_each_axis():
    scope, mesh = fitted(ASSET, _scope((6, 2, 3)))
    assert scope.size.tolist() == [6, 2, 3]
    assert mesh.bounds()[0].tolist() == [0, 0, 0] and mesh.bounds()[1].tolist() == [6, 2, 3]


def test_fit_zero_scope_keeps_the_asset_and_its_offset():
    scope, mesh = fitted(ASSET, _scope((0, 0, 0)))
    assert scope.size.tolist() == [2, 4, 1] and scope.origin.tolist() == [10, 20, 30]


def test_fit_two_zero_sizes_scale_uniformly():
    """op_i: only sy = 8 given (asset sy 4): scale 2 on every axis, the offsets scaled too."""
    scope, _ = fitted(ASSET, _scope((0, 8, 0)))
    assert scope.size.tolist() == [4, 8, 2]
    assert scope.origin.tolist() == [20, 0, 60]


def test_fit_one_zero_size_takes_the_mean_scale():
    """op_i: sz = (sx/asset.sx + sy/asset.sy) * 0.5 * asset.sz = (3/2 + 2/4) / 2 * 1 = 1."""
    scope, _ = fitted(ASSET, _scope((3, 2, 0)))
    assert scope.size.tolist() == [3, 2, 1.0] and scope.origin.tolist() == [0, 0, 0]


# ------------------------------------------------------------------------------ primitives
@pytest.fixture(scope="module")
def program():
    return shapegen.parse_grammar("@StartRule\nLot --> extrude(1) A").program.operations


def _primitive(program, name, *numbers, size=(2.0, 3.0, 2.0)):
    node = ast.Operation(name, tuple(ast.OperationArgument("plain", ast.Number(float(v)))
                                     for v in numbers))  # fmt: skip
    state = root_state(Derivation(program, seed=0), Shape(_scope(size), MASS), {}, ())
    assert compiler_for(name)(program, node, {})(state, (), []) is True
    return state.shape


def _polygon_area(n: int, radius: float) -> float:
    return 0.5 * n * radius * radius * math.sin(2 * math.pi / n)


# an unsized 16-gon fitted to a 2 m scope: its flats span the scope (CityEngine's ring has an
# edge across each axis), so its vertices are at 1 / cos(pi / 16) m from the axis
_FITTED_16 = 1 / math.cos(math.pi / 16)


@pytest.mark.parametrize(
    "name, numbers, volume",
    [
        ("primitiveCube", (), 2 * 3 * 2),
        ("primitiveCube", (1, 2, 3), 6),
        ("primitiveCylinder", (), _polygon_area(16, _FITTED_16) * 3),
        ("primitiveCylinder", (8, 0.5, 2), _polygon_area(8, 0.5) * 2),
        ("primitiveCone", (), _polygon_area(16, _FITTED_16) * 3 / 3),
        ("primitiveCone", (6, 1, 1.5), _polygon_area(6, 1.0) * 1.5 / 3),
    ],
)
def test_solid_primitives_have_their_closed_form_volume(program, name, numbers, volume):
    shape = _primitive(program, name, *numbers)
    mesh = shape.mesh()
    assert mesh.is_closed and mesh.is_convex(1e-9)
    assert mesh.volume() == pytest.approx(volume, rel=1e-9)


def test_primitive_with_dimensions_sits_in_the_xz_centre_on_y0(program):
    # the scope becomes the octagon's box, 2 * 0.5 * cos(22.5 degrees) across its flats,
    # centred in the 2 x 3 x 2 scope on its y = 0; the mesh fills it
    shape = _primitive(program, "primitiveCylinder", 8, 0.5, 2)
    width = math.cos(math.pi / 8)
    assert shape.scope.size.tolist() == pytest.approx([width, 2, width])
    assert shape.scope.origin.tolist() == pytest.approx([1 - width / 2, 0, 1 - width / 2])
    lo, hi = shape.mesh().bounds()
    assert lo.tolist() == pytest.approx([0, 0, 0]) and hi.tolist() == pytest.approx(
        [width, 2, width]
    )


def test_sphere_is_a_closed_convex_solid_inside_its_sphere(program):
    mesh = _primitive(program, "primitiveSphere", size=(2, 2, 2)).mesh()
    assert mesh.is_closed and mesh.is_convex(1e-9)
    # inside the spheroid through its vertices: radius 1 / cos(pi / 16) in x-z, 1 in y
    assert 0.95 * 4 / 3 * math.pi < mesh.volume() < 4 / 3 * math.pi * _FITTED_16**2
    assert _primitive(program, "primitiveSphere", 8, 4).mesh().n_vertices == 8 * 3 + 2


@pytest.mark.parametrize(
    "name, area", [("primitiveQuad", 4.0), ("primitiveDisk", _polygon_area(16, _FITTED_16))]
)
def test_flat_primitives_lie_in_the_non_zero_plane(program, name, area):
    lying = _primitive(program, name, size=(2, 0, 2))
    standing = _primitive(program, name, size=(2, 2, 0))
    assert lying.mesh().area() == pytest.approx(area) and lying.normal_axis == 1
    assert standing.mesh().area() == pytest.approx(area) and standing.normal_axis == 2
    assert np.ptp(standing.mesh().vertices[:, 2]) == 0  # flat in the scope's x-y plane
    assert standing.mesh().face_normal(0) == pytest.approx([0, 0, 1])


@pytest.mark.parametrize(
    "name, numbers, message",
    [
        ("primitiveCylinder", (2,), r"sides is a whole number 3\.\.4096, got 2"),
        ("primitiveSphere", (8, 1), r"divisions is a whole number 2\.\.4096, got 1"),
        ("primitiveCube", (1, 2), r"takes 0 or 3 arguments, got 2"),
        ("primitiveCube", (1, -2, 1), r"dimensions must be >= 0 m"),
    ],
)
def test_primitive_errors(program, name, numbers, message):
    with pytest.raises(GrammarError, match=message):
        _primitive(program, name, *numbers)


@pytest.mark.parametrize("sides", [3, 4, 5, 6, 8, 16])
def test_templates_are_cityengines(sides):
    # as its runtime makes them (PyPRT, tests/data/prt_primitives.json): the cube [0, 1]^3, the
    # quad [-0.5, 0.5]^2 in y = 0, round ones of radius 0.5 to their vertices about the y axis,
    # y in [0, 1], a ring's first edge straddling +z
    assert primitive_mesh("cube").bounds()[0].tolist() == [0, 0, 0]
    assert primitive_mesh("cube").bounds()[1].tolist() == [1, 1, 1]
    lo, hi = primitive_mesh("quad").bounds()
    assert lo.tolist() == [-0.5, 0, -0.5] and hi.tolist() == [0.5, 0, 0.5]
    for kind in ("disk", "cylinder", "cone", "sphere"):
        mesh = primitive_mesh(kind, sides, 4)
        v = mesh.vertices
        radii = np.hypot(v[:, 0], v[:, 2])
        assert radii.max() == pytest.approx(0.5) and v[:, 1].min() == 0
        assert v[:, 1].max() == (0 if kind == "disk" else 1)
        first, second = v[0], v[1]
        if kind == "sphere":  # its first ring follows the top
            first, second = v[1] / np.hypot(v[1, 0], v[1, 2]), v[2] / np.hypot(v[2, 0], v[2, 2])
        assert first[0] == pytest.approx(-second[0]) and first[2] == pytest.approx(second[2])
        assert first[2] > 0


def _slab(project):
    """A 1 x 2 x 3 m box asset (x, y, z) with its corner at (1, 0, 0)."""
    trimesh.creation.box(extents=(1, 2, 3)).apply_translation((1.5, 1, 1.5)).export(
        project / "assets" / "slab.obj"
    )


@pytest.mark.parametrize(
    "options, low, high",
    [
        # op_i: keepSizeAndPosition is s(0, 0, 0): the asset as it is, moved by its offset
        ("yUp, keepSizeAndPosition", (1, 0, 0), (2, 2, 3)),
        # zUp turns the asset by -90 degrees about x: its z (3 m) becomes y, its y points to -z
        ("zUp, keepSizeAndPosition", (1, 0, -2), (2, 3, 0)),
        # keepSizeAlignPosition: its own size, centred in the scope's x and z, bottom on y = 0
        ("yUp, keepSizeAlignPosition", (5.5, 0, 2.5), (6.5, 2, 5.5)),
        ("yUp, alignSizeAndPosition, noCleanup", (0, 0, 0), (12, 4, 8)),
    ],
)
def test_insert_options_up_axis_and_mode(project, options, low, high):
    _slab(project)
    model = _build(project, f'Lot --> extrude(4) i("slab.obj", {options})')
    (block,) = model.blocks
    assert block.vertices.min(axis=0) == pytest.approx(low)
    assert block.vertices.max(axis=0) == pytest.approx(high)


@pytest.mark.parametrize(
    "call, message",
    [
        ('i("slab.obj", xUp)', "argument 2 is one of yUp, zUp"),
        ('i("slab.obj", yUp, stretch)', "argument 3 is one of alignSizeAndPosition"),
        ('i("box", yUp)', "template primitive takes key=value parameters only"),
    ],
)
def test_bad_insert_options_are_load_errors(project, call, message):
    _slab(project)
    with pytest.raises(GrammarError, match=message):
        _build(project, f"Lot --> extrude(4) {call}")
