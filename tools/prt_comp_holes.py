"""Measure CityEngine's component split of faces with holes with its runtime: writes
``tests/data/prt_comp_holes.json``.

As tools/prt_roofs.py does, the corpus's ``FacesHolesVerticesrule`` package has its start rule
(``Footprint``) rewritten: the case's operations (``extrude(10)``, or none), reports of the
shape's ``geometry.nVertices``, ``nFaces`` and ``nHoles``, then a component split
``comp(h|e|fe|v|fv|f [, noAlign]) { selector : ... | ... }`` (the selectors fields of
``com.esri.gc.Comp``; ``:`` or ``=``) whose branches report, per component, under
``b<branch>.<comp.index>.``, its ``geometry.nFaces``, ``nHoles``, ``nVertices``, ``area``, its
``scope.sx``, ``sy``, ``sz`` and, through ``convert(x|y|z, scope, world, pos, ...)``, the world
places of its scope's origin (``p0``) and of the ends of its unit x, y and z axes (``p1``,
``p2``, ``p3``): each component's scope (and pivot: op_comp aligns them) in CityEngine's index
order. The components stay as they are (a face's corners reach the encoder in their order): the
PyEncoder's ``points``, ``indices`` and ``encoder_faces`` are recorded too. Run with PyPRT's
Python (a development tool; shapegen never imports it)::

    PYTHONPATH=. /tmp/prt-venv/bin/python tools/prt_comp_holes.py tests/data/prt_comp_holes.json
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
from prt_roofs import PACKAGE, _lot  # noqa: E402

GEOMETRY = ("nVertices", "nFaces", "nHoles")

LOTS = {
    # tools/prt_roofs.py's: 12 x 8 m with a 4 x 2 m courtyard from (4, 3) to (8, 5)
    "courtyard": _lot([(0, 8), (12, 8), (12, 0), (0, 0)], [(4, 3), (8, 3), (8, 5), (4, 5)]),
    # 20 x 10 m with two courtyards, the second a triangle
    "two_holes": _lot(
        [(0, 10), (20, 10), (20, 0), (0, 0)],
        [(3, 3), (7, 3), (7, 7), (3, 7)],
        [(12, 4), (16, 4), (14, 7)],
    ),
    # PyPRT's own test shape (its pyGeometry_test): a 10 x 10 m square, a triangular hole
    # wound as the outline is
    "square_triangle": {
        "coordinates": [0, 0, 0, 0, 0, 10, 10, 0, 10, 10, 0, 0, 2, 0, 2, 8, 0, 8, 2, 0, 8],
        "indices": [0, 1, 2, 3, 4, 5, 6],
        "face_counts": [4, 3],
        "holes": [[0, 1]],
    },
    # no hole
    "square": _lot([(0, 10), (10, 10), (10, 0), (0, 0)]),
}
# (component, alignment, branches "selector:1" (':') or "selector:0" ('='))
SPLITS = [
    ("h", "", ["all:1"]),
    ("h", "", ["all:0"]),
    ("h", "noAlign", ["all:1"]),
    ("h", "", ["top:1", "bottom:1"]),
    ("h", "", ["border:1", "inside:1"]),
    ("e", "", ["all:1"]),
    ("e", "", ["border:1", "inside:1"]),
    ("e", "", ["eave:1", "hip:1", "valley:1", "ridge:1"]),
    ("fe", "", ["all:1"]),
    ("v", "", ["all:1"]),
    ("v", "", ["border:1", "inside:1"]),
    ("fv", "", ["all:1"]),
    ("f", "", ["all:1"]),
]
CASES = [(ops, *split) for ops in ("", "extrude(10)") for split in SPLITS]

# The rewriter: Default$Footprint's code becomes the case's operations (args: in, out,
# "op;op|component|alignment||sel:each|..."), reports of the shape's geometry, then a comp whose
# branches, each a new static method _$cb$<k>, report their shape's geometry, scope sizes and
# scope points under "b<k>.<comp.index>." and end as a leaf.
PATCHER = r"""
import org.objectweb.asm.*;
import java.nio.file.*;

public class Patch {
    static final String B = "com/esri/gc/Builtins";
    static final String NODE = "Lcom/esri/gc/SplitNode;";
    static final String[] GEOMETRY = {"nVertices", "nFaces", "nHoles"};
    static final String[] BRANCH = {"geometry$nFaces", "geometry$nHoles", "geometry$nVertices",
                                    "geometry$area", "scope$sx", "scope$sy", "scope$sz"};
    static void report(MethodVisitor mv, String name, String builtin) {
        mv.visitLdcInsn(name);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, builtin, "()D", false);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "report", "(Ljava/lang/String;D)V", false);
    }
    static void key(MethodVisitor mv, String prefix, String name) {
        mv.visitLdcInsn(prefix);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "comp$index", "()D", false);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$add",
                           "(Ljava/lang/String;D)Ljava/lang/String;", false);
        mv.visitLdcInsn("." + name);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$add",
                           "(Ljava/lang/String;Ljava/lang/String;)Ljava/lang/String;", false);
    }
    static void call(MethodVisitor mv, String call) {
        String fn = call.substring(0, call.indexOf('('));
        String text = call.substring(call.indexOf('(') + 1, call.lastIndexOf(')'));
        StringBuilder descriptor = new StringBuilder("(");
        if (!text.isEmpty()) for (String v : text.split(",")) {
            if (v.equals("true") || v.equals("false")) {
                mv.visitInsn(v.equals("true") ? Opcodes.ICONST_1 : Opcodes.ICONST_0);
                descriptor.append("Z");
            } else if (v.startsWith("@")) {  // @Class.FIELD: a constant of com.esri.gc.Class
                String cls = "com/esri/gc/" + v.substring(1, v.indexOf('.'));
                String type = "L" + cls + ";";
                mv.visitFieldInsn(Opcodes.GETSTATIC, cls, v.substring(v.indexOf('.') + 1), type);
                descriptor.append(type);
            } else {
                mv.visitLdcInsn(Double.valueOf(v));
                descriptor.append("D");
            }
        }
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, fn, descriptor.append(")V").toString(),
                           false);
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
                if (!parts[0].isEmpty()) for (String c : parts[0].split(";")) call(mv, c);
                for (String what : GEOMETRY) report(mv, "geometry." + what, "geometry$" + what);
                mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/CompSelector", parts[1],
                                  "Lcom/esri/gc/CompSelector;");
                if (!parts[2].isEmpty()) {
                    mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/ScopeAlignment", parts[2],
                                      "Lcom/esri/gc/ScopeAlignment;");
                }
                mv.visitLdcInsn(Integer.valueOf(parts.length - 4));
                mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createSplitRoot", "(I)" + NODE,
                                   false);
                for (int k = 4; k < parts.length; k++) {
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
                    int ref = writer.newMethod(owner, "_$cb$" + (k - 4), "()V", false);
                    mv.visitIntInsn(Opcodes.SIPUSH, ref);
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$addOpSeq", "(" + NODE + "I)V",
                                       false);
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$addSplitNode",
                                       "(" + NODE + NODE + ")V", false);
                }
                String align = parts[2].isEmpty() ? "" : "Lcom/esri/gc/ScopeAlignment;";
                mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "comp",
                                   "(Lcom/esri/gc/CompSelector;" + align + NODE + ")V", false);
                mv.visitInsn(Opcodes.RETURN);
                mv.visitMaxs(0, 0);
                mv.visitEnd();
            }
            public void visitEnd() {
                for (int k = 4; k < parts.length; k++) {
                    MethodVisitor mv = super.visitMethod(
                        Opcodes.ACC_PUBLIC | Opcodes.ACC_STATIC, "_$cb$" + (k - 4), "()V",
                        null, null);
                    mv.visitCode();
                    String prefix = "b" + (k - 4) + ".";
                    for (String what : BRANCH) {
                        key(mv, prefix, what.substring(what.indexOf('$') + 1));
                        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, what, "()D", false);
                        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "report",
                                           "(Ljava/lang/String;D)V", false);
                    }
                    for (int p = 0; p < 4; p++) {  // the scope's origin and axis ends, world
                        for (String c : new String[] {"x", "y", "z"}) {
                            key(mv, prefix, "p" + p + c);
                            String coord = "Lcom/esri/gc/CoordSelector;";
                            String system = "Lcom/esri/gc/CoordSystem;";
                            String type = "Lcom/esri/gc/TypeSelector;";
                            mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/CoordSelector", c,
                                              coord);
                            mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/CoordSystem",
                                              "scope", system);
                            mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/CoordSystem",
                                              "world", system);
                            mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/TypeSelector",
                                              "pos", type);
                            for (int axis = 1; axis < 4; axis++) {
                                mv.visitInsn(p == axis ? Opcodes.DCONST_1 : Opcodes.DCONST_0);
                            }
                            mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "convert",
                                               "(" + coord + system + system + type + "DDD)D",
                                               false);
                            mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "report",
                                               "(Ljava/lang/String;D)V", false);
                        }
                    }
                    int leaf = writer.newMethod(owner, "Default$Leaf" + (k - 4) + "$", "()V",
                                                false);
                    mv.visitIntInsn(Opcodes.SIPUSH, leaf);
                    mv.visitInsn(Opcodes.ICONST_2);
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createShape", "(II)V", false);
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


def comp_text(kind: str, align: str, branches: list[str]) -> str:
    """The split as CGA writes it: ``comp(e) { border : | inside : }``."""
    written = [f"{b.split(':')[0]} {':' if b.endswith(':1') else '='}" for b in branches]
    alignment = f", {align}" if align else ""
    return f"comp({kind}{alignment}) {{ {' | '.join(written)} }}"


def measure(pyprt, work: Path, source: Path, patcher: Path, lot: dict, case) -> dict:
    operations, kind, align, branches = case
    folder = Path(tempfile.mkdtemp(dir=work))
    package = folder / "package"
    shutil.copytree(source, package)
    (cgb,) = package.glob("bin/*.cgb")
    calls = operations.replace(" ", "")
    spec = "|".join([calls, kind, align, "", *branches])
    java = ["java", "-cp", f"{ASM_JAR}{os.pathsep}{patcher}", "Patch", str(cgb), str(cgb)]
    subprocess.run([*java, spec], check=True)
    rpk = folder / "case.rpk"
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
    row: dict = {"rule": operations, "comp": comp_text(kind, align, branches)}
    for key in GEOMETRY:
        value = report.get(f"geometry.{key}_avg")
        row[key] = None if value is None else round(value, 6) + 0.0
    for k, _ in enumerate(branches):
        found: dict = {}
        shapes = 0  # each shape reports its nFaces once: two of one comp.index count twice
        for name, value in report.items():
            parts = re.fullmatch(rf"b{k}\.(\d+)(?:\.0+)?\.(\w+)_(avg|n)", name)
            if parts and parts[3] == "avg":
                found.setdefault(int(parts[1]), {})[parts[2]] = round(value, 6) + 0.0
            elif parts and parts[2] == "nFaces":
                shapes += int(value)
        row[f"b{k}"] = {
            "shapes": shapes,
            "components": [{"index": i, **found[i]} for i in sorted(found)],
        }
    flat = list(model.get_vertices())
    row["encoder_faces"] = list(model.get_faces())
    row["points"] = [[round(c, 6) + 0.0 for c in flat[i : i + 3]] for i in range(0, len(flat), 3)]
    row["indices"] = list(model.get_indices())
    row["errors"] = [e for e in model.get_cga_errors() if "CGAC version" not in e]
    return row


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("output", type=Path, help="the JSON file to write")
    parser.add_argument("--corpus", type=Path, default=CORPUS, help="the shared CGA corpus")
    parser.add_argument("--lot", action="append", help="measure only these lots")
    args = parser.parse_args(argv)
    lots = {k: v for k, v in LOTS.items() if not args.lot or k in args.lot}
    with rewritable_package(args.corpus, "prt_comp_holes", PACKAGE, PATCHER) as context:
        pyprt, work, source, patcher = context
        rows = measured_cases(
            "prt_comp_holes",
            lots,
            CASES,
            lambda lot, case: measure(pyprt, work, source, patcher, lot, case),
        )
    from importlib.metadata import version as installed

    head = {
        "source": f"CityEngine's runtime, PyPRT {installed('pyprt')}, by "
        "tools/prt_comp_holes.py: each case's operations and component split run on the named "
        "initial shape (PyPRT's InitialShape with holes: (x, 0, z) coordinates) through PyPRT's "
        "PyEncoder; nVertices, nFaces, nHoles are geometry.* before the split; b<k> is the k-th "
        "branch: the shapes it gets and, per component by its comp.index, geometry.nFaces, "
        "nHoles, nVertices, area, scope.sx, sy, sz and the world places of its scope's origin "
        "(p0) and of the ends of its unit x, y, z axes (p1, p2, p3); points, indices and "
        "encoder_faces (vertex counts) are what the PyEncoder returns",
        "lots": LOTS,
    }
    write_fixture(args.output, head, "cases", rows)
    print(f"prt_comp_holes: {len(rows)} cases written to {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
