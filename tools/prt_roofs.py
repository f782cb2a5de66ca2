"""Measure CityEngine's roofs on faces with holes with its runtime: writes
``tests/data/prt_roofs.json``.

As tools/prt_setback.py does, the corpus's ``FacesHolesVerticesrule`` package has its start rule
(``Footprint``) rewritten, here into one roof operation (``roofHip(30)``,
``roofRidge(@RoofValueType.byAngle, 30)``: numbers, ``true``/``false``, or ``@Class.FIELD`` for
a constant of the runtime's enum ``com.esri.gc.Class``) followed by reports of the roof's
``geometry.nVertices``, ``nFaces``, ``nHoles``, ``area``, ``volume`` and ``scope.sx`` ...
``scope.tz``, and optionally by a component split ``comp(f|e|h) { selector : Leaf | ... }``
(the selectors fields of ``com.esri.gc.Comp``) whose branches report their shapes'
``geometry.nFaces`` ... ``area`` under ``b<branch>.``: a branch's ``_n`` is the number of shapes
it gets. Without a split, the roof is the model, and its vertices and faces (the PyEncoder's
``points``, ``indices`` and ``encoder_faces``, a hole's ring after its face) are recorded. Run
with PyPRT's Python (a development tool; shapegen never imports it)::

    /tmp/prt-venv/bin/python tools/prt_roofs.py tests/data/prt_roofs.json
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from prt_primitives import (  # noqa: E402
    ASM_JAR,
    CORPUS,
    measured_cases,
    rewritable_package,
    write_fixture,
)

PACKAGE = "packages/Esri+pyprt__tests_data_FacesHolesVerticesrule__987e9f4b.rpk"
GEOMETRY = ("nVertices", "nFaces", "nHoles", "area", "volume")
BRANCH_GEOMETRY = ("nFaces", "nHoles", "nVertices", "area")
SCOPE = ("sx", "sy", "sz", "tx", "ty", "tz")


def _ring(points):
    return [c for p in points for c in (p[0], 0, p[1])]


def _lot(outline, *holes) -> dict:
    """An initial shape in PyPRT's form from (x, z) rings: the outline, then each hole."""
    coordinates = _ring(outline)
    counts = [len(outline)]
    for hole in holes:
        coordinates += _ring(hole)
        counts.append(len(hole))
    lot = {"coordinates": coordinates, "indices": list(range(sum(counts))), "face_counts": counts}
    if holes:
        lot["holes"] = [[0, *range(1, len(counts))]]
    return lot


LOTS = {
    # 12 x 8 m (first edge along +x at z = 8) with a 4 x 2 m courtyard from (4, 3) to (8, 5)
    "courtyard": _lot([(0, 8), (12, 8), (12, 0), (0, 0)], [(4, 3), (8, 3), (8, 5), (4, 5)]),
    # an L (tools/prt_geometry.py's L-shaped lot) with an L-shaped courtyard in its corner
    "L_courtyard": _lot(
        [(0, 0), (0, 12), (6, 12), (6, 5), (14, 5), (14, 0)],
        [(2, 2), (11, 2), (11, 3), (3, 3), (3, 10), (2, 10)],
    ),
    # 20 x 10 m with two square courtyards
    "two_holes": _lot(
        [(0, 10), (20, 10), (20, 0), (0, 0)],
        [(3, 3), (7, 3), (7, 7), (3, 7)],
        [(12, 4), (16, 4), (16, 6), (12, 6)],
    ),  # fmt: skip
    # 16 x 12 m with a small off-centre hole that touches nothing: no edge of the outline, and
    # not roofRidge's ridge line (z = 6)
    "small_hole": _lot([(0, 12), (16, 12), (16, 0), (0, 0)], [(9, 3), (10, 3), (10, 4), (9, 4)]),
    # the same lot with the hole's edge on roofRidge's ridge line
    "hole_on_ridge": _lot([(0, 12), (16, 12), (16, 0), (0, 0)], [(9, 5), (10, 5), (10, 6), (9, 6)]),
    # tools/prt_geometry.py's L-shaped lot, without a hole: roofRidge's sides and roofPyramid's
    # angle on a face without holes
    "L": _lot([(0, 0), (0, 12), (6, 12), (6, 5), (14, 5), (14, 0)]),
    # an L whose arms' edges are not parallel: two ridges at different heights, which an even
    # roof levels each on its own
    "skew_L": _lot([(0, 0), (0, 12), (5, 12), (6, 5), (14, 4), (14, 0)]),
    # op_roofHip's even example: a trapezoid, whose hip roof's ridge slopes
    "trapezoid": _lot([(0, 0), (0, 8), (12, 6), (12, 2)]),
}
ROOFS = [
    "roofHip(15)",
    "roofHip(60)",
    "roofGable(15)",
    "roofGable(60)",
    "roofRidge(@RoofValueType.byAngle,15)",
    "roofRidge(@RoofValueType.byAngle,60)",
    "roofRidge(@RoofValueType.byHeight,2)",
    "roofPyramid(30)",
    "roofShed(30)",
]
SPLITS = [
    "",
    "f|top:|bottom:|side:",
    "f|horizontal:|aslant:|vertical:",
    "e|eave:|hip:|valley:|ridge:",
    "h|all:",
]
# overhangs, even ridges, an index, heights: the roof alone
OPTIONS = [
    "roofHip(30,1)",
    "roofHip(30,-0.5)",
    "roofHip(30,0,true)",
    "roofGable(30,1,1)",
    "roofGable(30,1,0.5)",
    "roofGable(30,0,0,true)",
    "roofGable(30,0,0,false,1)",
    "roofHip(@RoofValueType.byHeight,2)",
    "roofGable(@RoofValueType.byHeight,2)",
    "roofShed(30,1)",
]
CASES = [(roof, split) for roof in ROOFS for split in SPLITS] + [(roof, "") for roof in OPTIONS]

# The rewriter: Default$Footprint's code becomes the case's roof, reports of its geometry and
# scope, then (args: in, out, "roof|component|sel:merge|...") a comp whose branches, each a new
# static method _$cb$<k>, report their shape's geometry under "b<k>." and end as a leaf.
PATCHER = r"""
import org.objectweb.asm.*;
import java.nio.file.*;

public class Patch {
    static final String B = "com/esri/gc/Builtins";
    static final String NODE = "Lcom/esri/gc/SplitNode;";
    static final String[] GEOMETRY = {"nVertices", "nFaces", "nHoles", "area", "volume"};
    static final String[] BRANCH = {"nFaces", "nHoles", "nVertices", "area"};
    static final String[] SCOPE = {"sx", "sy", "sz", "tx", "ty", "tz"};
    static void report(MethodVisitor mv, String name, String builtin) {
        mv.visitLdcInsn(name);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, builtin, "()D", false);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "report", "(Ljava/lang/String;D)V", false);
    }
    public static void main(String[] a) throws Exception {
        ClassReader reader = new ClassReader(Files.readAllBytes(Paths.get(a[0])));
        final ClassWriter writer = new ClassWriter(reader, ClassWriter.COMPUTE_MAXS);
        final String owner = reader.getClassName();
        final String[] parts = a[2].split("\\|");
        reader.accept(new ClassVisitor(Opcodes.ASM9, writer) {
            public MethodVisitor visitMethod(int acc, String name, String desc, String sig,
                                             String[] ex) {
                final MethodVisitor target = super.visitMethod(acc, name, desc, sig, ex);
                if (!name.equals("Default$Footprint")) return target;
                return new MethodVisitor(Opcodes.ASM9) {
                    public AnnotationVisitor visitAnnotation(String d, boolean visible) {
                        return target.visitAnnotation(d, visible);
                    }
                    public void visitAttribute(Attribute attribute) {
                        target.visitAttribute(attribute);
                    }
                    public void visitEnd() {
                        footprint(target);
                    }
                };
            }
            void footprint(MethodVisitor mv) {
                mv.visitCode();
                String call = parts[0];
                String fn = call.substring(0, call.indexOf('('));
                String text = call.substring(call.indexOf('(') + 1, call.lastIndexOf(')'));
                StringBuilder descriptor = new StringBuilder("(");
                if (!text.isEmpty()) for (String v : text.split(",")) {
                    if (v.equals("true") || v.equals("false")) {
                        mv.visitInsn(v.equals("true") ? Opcodes.ICONST_1 : Opcodes.ICONST_0);
                        descriptor.append("Z");
                    } else if (v.startsWith("@")) {
                        String cls = "com/esri/gc/" + v.substring(1, v.indexOf('.'));
                        String type = "L" + cls + ";";
                        mv.visitFieldInsn(Opcodes.GETSTATIC, cls, v.substring(v.indexOf('.') + 1),
                                          type);
                        descriptor.append(type);
                    } else {
                        mv.visitLdcInsn(Double.valueOf(v));
                        descriptor.append("D");
                    }
                }
                mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, fn,
                                   descriptor.append(")V").toString(), false);
                for (String what : GEOMETRY) report(mv, "geometry." + what, "geometry$" + what);
                for (String what : SCOPE) report(mv, "scope." + what, "scope$" + what);
                if (parts.length > 2) {
                    mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/CompSelector", parts[1],
                                      "Lcom/esri/gc/CompSelector;");
                    mv.visitLdcInsn(Integer.valueOf(parts.length - 2));
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createSplitRoot",
                                       "(I)" + NODE, false);
                    for (int k = 2; k < parts.length; k++) {
                        String[] branch = parts[k].split(":");
                        mv.visitInsn(Opcodes.DUP);
                        mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/Comp", branch[0],
                                          "Lcom/esri/gc/Comp;");
                        mv.visitInsn(Opcodes.DCONST_0);
                        mv.visitInsn(branch[1].equals("1") ? Opcodes.ICONST_1 : Opcodes.ICONST_0);
                        mv.visitInsn(Opcodes.ICONST_0);
                        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createSplitNode",
                                           "(Lcom/esri/gc/Comp;DZI)" + NODE, false);
                        mv.visitInsn(Opcodes.DUP);
                        int ref = writer.newMethod(owner, "_$cb$" + (k - 2), "()V", false);
                        mv.visitIntInsn(Opcodes.SIPUSH, ref);
                        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$addOpSeq",
                                           "(" + NODE + "I)V", false);
                        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$addSplitNode",
                                           "(" + NODE + NODE + ")V", false);
                    }
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "comp",
                                       "(Lcom/esri/gc/CompSelector;" + NODE + ")V", false);
                }
                mv.visitInsn(Opcodes.RETURN);
                mv.visitMaxs(0, 0);
                mv.visitEnd();
            }
            public void visitEnd() {
                for (int k = 2; k < parts.length; k++) {
                    MethodVisitor mv = super.visitMethod(
                        Opcodes.ACC_PUBLIC | Opcodes.ACC_STATIC, "_$cb$" + (k - 2), "()V",
                        null, null);
                    mv.visitCode();
                    for (String what : BRANCH) {
                        report(mv, "b" + (k - 2) + "." + what, "geometry$" + what);
                    }
                    int leaf = writer.newMethod(owner, "Default$Leaf" + (k - 2) + "$", "()V",
                                                false);
                    mv.visitIntInsn(Opcodes.SIPUSH, leaf);
                    mv.visitInsn(Opcodes.ICONST_2);
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createShape", "(II)V",
                                       false);
                    mv.visitInsn(Opcodes.RETURN);
                    mv.visitMaxs(0, 0);
                    mv.visitEnd();
                }
                super.visitEnd();
            }
        }, 0);
        Files.write(Paths.get(a[1]), writer.toByteArray());
    }
}
"""


def written(roof: str) -> str:
    """The roof call as CGA writes it: ``roofRidge(byAngle, 15)``."""
    return re.sub(r"@\w+\.", "", roof).replace(",", ", ")


def measure(pyprt, work: Path, source: Path, patcher: Path, lot: dict, roof, split) -> dict:
    case = Path(tempfile.mkdtemp(dir=work))
    package = case / "package"
    shutil.copytree(source, package)
    (cgb,) = package.glob("bin/*.cgb")
    spec = roof if not split else f"{roof}|{split.replace(':', ':1')}"
    java = ["java", "-cp", f"{ASM_JAR}{os.pathsep}{patcher}", "Patch", str(cgb), str(cgb)]
    subprocess.run([*java, spec], check=True)
    rpk = case / "case.rpk"
    subprocess.run(
        ["7z", "a", "-t7z", "-m0=LZMA", "-ms=off", "-mhc=off", str(rpk), ".resolvemap.xml",
         "bin", "rules"],
        cwd=package, check=True, stdout=subprocess.DEVNULL,
    )  # fmt: skip
    if "holes" in lot:
        shape = pyprt.InitialShape(
            lot["coordinates"], lot["indices"], lot["face_counts"], lot["holes"]
        )
    else:
        shape = pyprt.InitialShape(lot["coordinates"])
    options = {"emitReport": True, "emitGeometry": True}
    (model,) = pyprt.ModelGenerator([shape]).generate_model(
        [{}], str(rpk), "com.esri.pyprt.PyEncoder", options
    )
    report = model.get_report()
    row: dict = {"rule": written(roof)}
    for key in GEOMETRY:
        value = report.get(f"geometry.{key}_avg")
        row[key] = None if value is None else round(value, 6) + 0.0
    row["scope"] = [round(report.get(f"scope.{k}_avg", float("nan")), 4) + 0.0 for k in SCOPE]
    if split:
        component, *selectors = split.split("|")
        row["comp"] = f"comp({component}) {{ {' | '.join(selectors)} }}"
        for k, _ in enumerate(selectors):
            shapes = report.get(f"b{k}.nFaces_n")
            sums = {w: report.get(f"b{k}.{w}_sum") for w in BRANCH_GEOMETRY}
            row[f"b{k}"] = {
                "shapes": 0 if shapes is None else int(shapes),
                **{w: None if v is None else round(v, 6) + 0.0 for w, v in sums.items()},
            }
    else:
        flat = list(model.get_vertices())
        row["encoder_faces"] = list(model.get_faces())
        corners = range(0, len(flat), 3)
        row["points"] = [[round(c, 6) + 0.0 for c in flat[i : i + 3]] for i in corners]
        row["indices"] = list(model.get_indices())
    row["errors"] = [e for e in model.get_cga_errors() if "CGAC version" not in e]
    return row


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("output", type=Path, help="the JSON file to write")
    parser.add_argument("--corpus", type=Path, default=CORPUS, help="the shared CGA corpus")
    args = parser.parse_args(argv)
    with rewritable_package(args.corpus, "prt_roofs", PACKAGE, PATCHER) as context:
        pyprt, work, source, patcher = context
        rows = measured_cases(
            "prt_roofs",
            LOTS,
            CASES,
            lambda lot, case: measure(pyprt, work, source, patcher, lot, *case),
        )
    from importlib.metadata import version as installed

    head = {
        "source": f"CityEngine's runtime, PyPRT {installed('pyprt')}, by tools/prt_roofs.py: "
        "each roof runs on the named initial shape (PyPRT's InitialShape with holes: (x, 0, z) "
        "coordinates) through PyPRT's PyEncoder; nVertices ... volume are geometry.* of the "
        "roof, scope is scope.sx, sy, sz, tx, ty, tz; with comp, b<k> is the k-th branch: the "
        "shapes it gets and the sums of their geometry.nFaces, nHoles, nVertices and area; "
        "without, points, indices and encoder_faces (vertex counts, a hole's ring after its "
        "face) are what the PyEncoder returns",
        "lots": LOTS,
    }
    write_fixture(args.output, head, "cases", rows)
    print(f"prt_roofs: {len(rows)} cases written to {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
