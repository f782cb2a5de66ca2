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
