"""A two-block stack whose stability is known in closed form, for the editor tests.

The upper unit cube sits on the lower one shifted by ``offset`` along x; with compression-only
joints it stands exactly when its centroid lies over the contact, ``offset <= 0.5`` m.
"""

STACK = """\
@Free
@Description("Shift of the upper block along x (m)")
@Range(0, 0.9)
attr offset = 0.2

@Description("Colour of the stones")
attr stone = "limestone"

attr mortar = false

attr courses = 2

@StartRule @Lot(1, 1)
Lot --> extrude(2) split(y) { 1 : Lower | 1 : Upper }
Lower --> label("lower") i("box")
Upper --> t(offset, 0, 0) label("upper") i("box")
"""
STACK_BOUNDARY = 0.5  # m: the largest offset that stands
STACK_WEIGHT = 2 * 2400.0 * 9.81  # N: two unit cubes of the default stone


# The stack of editor_stack.py with an attr of every kind the Inspector knows.
ANNOTATED = """\
const widest = 0.9

@Free
@Description("Shift of the upper block along x (m)")
@Range(0, widest)
attr offset = 0.2

@Range(min=0, max=45, stepsize=15)
attr angle = 30

@Range(min=0, max=45, stepsize=15, restricted=false)
attr loose = 30

@Enum("limestone", "granite", "marble")
attr stone = "limestone"

@Range("low", "high")
attr detail = "low"

@Enum(1, 2, 4, restricted=false)
attr lanes = 2

@Enum(valuesAttr=sizes)
attr size = 2

@Hidden
attr sizes = [1, 2, 3]

@Group("Look", 2) @Color @Description("Colour of the upper block")
attr tint = "#aa8844"

@File("obj")
attr asset = "plate.obj"

@Directory
attr textures = "tex"

@Group("Structure", 1) @Order(2)
attr mortar = false

@Order(1)
attr courses = 2

@Group("Structure", "Deep")
attr depth = 1

@Group
attr loose_end = 0

@StartRule @Lot(1, 1)
Lot --> extrude(2) split(y) { 1 : Lower | 1 : Upper }
Lower --> label("lower") i("box")
Upper --> t(offset, 0, 0) color(tint) label("upper") i("box")
"""


def annotated_project(folder):
    """A CityEngine-like project in ``folder`` with :data:`ANNOTATED` as
    ``rules/stack.grammar``, asset files next to it and in its ``assets`` folder; its path."""
    project = folder / "project"
    (project / "rules").mkdir(parents=True)
    (project / "assets" / "doors").mkdir(parents=True)
    for name in ("plate.obj", "doors/door.obj", "doors/door.png", ".hidden.obj"):
        (project / "assets" / name).write_text("", encoding="utf-8")
    (project / "rules" / "near.obj").write_text("", encoding="utf-8")
    path = project / "rules" / "stack.grammar"
    path.write_text(ANNOTATED, encoding="utf-8")
    return path


# A CityEngine project: a .cga start rule that imports another and names an asset it lacks (a
# warning, not an error, in a .cga file).
CGA_BUILDING = """\
version "2023.0"
import lib : "lib.cga"

@Free @Group("Mass", 1) @Range(min=0.5, max=3)
attr floor_height = 1

@StartRule
Lot --> extrude(lib.height) Mass
Mass --> split(y) { floor_height : Floor }*
Floor --> i("missing.obj") Stone.
"""
CGA_LIB = """\
@Range(min=2, max=12)
attr height = 6
"""
CGA_WARNING = "asset 'missing.obj' not found"


def cga_project(folder):
    """A CityEngine project in ``folder``: ``rules/building.cga`` importing ``rules/lib.cga``;
    the start rule's path."""
    rules = folder / "project" / "rules"
    rules.mkdir(parents=True)
    (folder / "project" / "assets").mkdir()
    (rules / "lib.cga").write_text(CGA_LIB, encoding="utf-8")
    path = rules / "building.cga"
    path.write_text(CGA_BUILDING, encoding="utf-8")
    return path


def cga_package(folder, building=CGA_BUILDING):
    """The project of :func:`cga_project` as a CityEngine rule package (a 7z archive), with
    ``building`` as its start rule."""
    import py7zr

    path = folder / "building.rpk"
    with py7zr.SevenZipFile(path, "w") as archive:
        archive.writestr(building.encode(), "rules/building.cga")
        archive.writestr(CGA_LIB.encode(), "rules/lib.cga")
        archive.writestr(b"compiled", "bin/building.cgb")
        archive.writestr(b"compiled import", "bin/building$lib.cgb")
    return path


# A bound on waits for a state (a scan done, a page shown): the tests wait for the state, never
# for a time; the bound only ends a wait that would otherwise never end, so it is generous
# (the quick lane runs two workers per core on machines doing other work).
WAIT_BOUND_S = 600.0


def scanned(name: str):
    """A condition on the editor's state: the stable-range scan of attr ``name`` is done."""
    return lambda state: state["stability"].get(name, {}).get("status") == "done"
