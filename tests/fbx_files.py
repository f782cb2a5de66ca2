"""A small FBX file written by hand, for the readers' tests."""

from pathlib import Path


def write_block_fbx(path: Path) -> None:
    """A 1 m cube of six quads and a level pentagon, written in centimetres (ASCII FBX 7.3)."""
    corners = [0, 0, 0, 100, 0, 0, 100, 100, 0, 0, 100, 0, 0, 0, 100, 100, 0, 100, 100, 100, 100,
               0, 100, 100, 300, 0, 0, 400, 0, 0, 450, 0, 80, 350, 0, 150, 250, 0, 80]  # fmt: skip
    faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7],
             [8, 12, 11, 10, 9]]  # fmt: skip
    index = [i for f in faces for i in [*f[:-1], -f[-1] - 1]]  # FBX ends a face with -(i + 1)
    settings = "".join(
        f'\t\tP: "{name}", "int", "Integer", "",{value}\n'
        for name, value in [("UpAxis", 1), ("UpAxisSign", 1), ("FrontAxis", 2),
                            ("FrontAxisSign", 1), ("CoordAxis", 0), ("CoordAxisSign", 1)]
    )  # fmt: skip
    path.write_text(
        "; FBX 7.3.0 project file\nFBXHeaderExtension:  {\n\tFBXVersion: 7300\n}\n"
        "GlobalSettings:  {\n\tVersion: 1000\n\tProperties70:  {\n" + settings
        + '\t\tP: "UnitScaleFactor", "double", "Number", "",1\n\t}\n}\n'
        'Objects:  {\n\tGeometry: 1000, "Geometry::block", "Mesh" {\n'
        f"\t\tVertices: *{len(corners)} {{\n\t\t\ta: {','.join(map(str, corners))}\n\t\t}}\n"
        f"\t\tPolygonVertexIndex: *{len(index)} {{\n\t\t\ta: {','.join(map(str, index))}\n\t\t}}\n"
        '\t}\n\tModel: 2000, "Model::block", "Mesh" {\n\t\tVersion: 232\n\t}\n}\n'
        'Connections:  {\n\tC: "OO",2000,0\n\tC: "OO",1000,2000\n}\n'
    )  # fmt: skip
