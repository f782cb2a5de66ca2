"""Measure CityEngine's ``setback`` with its runtime: writes ``tests/data/prt_setback.json``.

As tools/prt_holes.py does, a corpus package's compiled rule is rewritten and generated through
PyPRT's PyEncoder on chosen initial shapes (with holes where a case says). Here the package is
``FacesHolesVerticesrule`` (one start rule, ``Footprint``, in the runtime's static form), whose
start rule becomes ``setback(distance) { selector : Branch0 | ... }``: the compiled split tree
(``_$createSplitRoot``, one ``_$createSplitNode`` per branch with the ``com.esri.gc.Setback``
selector and its ``:``/``=`` operator, each branch's operations a static method of the class
given by its Methodref's constant-pool index) and ``Builtins.setback``. Each branch's operations
report its shape's ``geometry.nFaces``, ``nHoles``, ``nVertices`` and ``area`` under
``b<branch>.``, so the report's ``_n`` counts the shapes a branch gets, ``_sum`` their totals.
A case may keep only some branches (a setback discards what no branch selects), so that the
encoder's vertices and faces are one branch's geometry. Run with PyPRT's Python (a development
tool; shapegen never imports it)::

    /tmp/prt-venv/bin/python tools/prt_setback.py tests/data/prt_setback.json
"""

from __future__ import annotations

import argparse
import os
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
GEOMETRY = ("nFaces", "nHoles", "nVertices", "area")
MAX_POINTS = 40  # the encoder's vertices are kept for results with at most this many
LOTS = {
    # 12 x 8 m, first edge along +x at z = 8 (tools/prt_geometry.py's lot)
    "12x8": {"coordinates": [0, 0, 8, 12, 0, 8, 12, 0, 0, 0, 0, 0]},
    # tools/prt_geometry.py's L-shaped lot
    "L": {"coordinates": [0, 0, 0, 0, 0, 12, 6, 0, 12, 6, 0, 5, 14, 0, 5, 14, 0, 0]},
    # tools/prt_holes.py's courtyard: 12 x 8 m with a 4 x 2 m hole from (4, 3) to (8, 5)
    "courtyard": {
        "coordinates": [0, 0, 8, 12, 0, 8, 12, 0, 0, 0, 0, 0, 4, 0, 3, 8, 0, 3, 8, 0, 5, 4, 0, 5],
        "indices": [0, 1, 2, 3, 4, 5, 6, 7],
        "face_counts": [4, 4],
        "holes": [[0, 1]],
    },
}
# (distance, branches): a branch is "selector:" (each polygon a shape) or "selector=" (one
# shape for all), the selector a field of com.esri.gc.Setback (street.front is street$front)
CASES = [
    (3, "all: | remainder:"),
    (3, "all:"),
    (3, "remainder:"),
    (3, "all="),
    (2, "front: | remainder:"),
    (2, "front:"),
    (2, "side: | remainder:"),
    (2, "side:"),
    (2, "side="),
    (2, "front: | side: | remainder:"),
    (2, "back: | left:"),
    (5, "all: | remainder:"),
    (5, "all:"),
    (1, "all: | remainder:"),
    (1, "all:"),
    (1, "remainder:"),
    (1, "front: | remainder:"),
    (1, "side: | remainder:"),
    (2, "remainder: | all:"),
    (2, "left: | back:"),
    (2, "right: | front:"),
    (2, "side: | front: | remainder:"),
    (2, "front: | left: | back: | right: | remainder:"),
    (2, "back: | remainder:"),
    (2, "back="),
    (2, "front: | back: | remainder:"),
    ((1, 3, 2, 0.5), "all: | remainder:"),
    ((1, 3, 2, 0.5), "front: | side: | remainder:"),
    ((1, 3, 2, 0.5), "left: | back: | right: | front: | remainder:"),
    ((3, 0, 1, 2), "all: | remainder:"),
    ((2, 1, 1, 3, 2, 1), "all: | remainder:"),
    ((2, 1, 1, 3, 2, 1), "back: | right: | remainder:"),
]

# The rewriter: Default$Footprint's code becomes the setback of the case (args: in, out, then
# "distance|selector:merge|..." with merge 1 for ':' and 0 for '='), each branch a new static
# method _$sb$<k> reporting its shape's geometry.* under "b<k>.".
PATCHER = r"""
import org.objectweb.asm.*;
import java.nio.file.*;

public class Patch {
    static final String B = "com/esri/gc/Builtins";
    static final String NODE = "Lcom/esri/gc/SplitNode;";
    static final String[] GEOMETRY = {"nFaces", "nHoles", "nVertices", "area"};
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
                // its annotations (the start rule's) kept, its code replaced
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
                String[] distances = parts[0].split(",");
                String setback = "(D" + NODE + ")V";
                if (distances.length == 1) {
                    mv.visitLdcInsn(Double.valueOf(parts[0]));
                } else {  // an array of distances, one per edge
                    mv.visitLdcInsn(Integer.valueOf(distances.length));
                    mv.visitIntInsn(Opcodes.NEWARRAY, Opcodes.T_DOUBLE);
                    for (int i = 0; i < distances.length; i++) {
                        mv.visitInsn(Opcodes.DUP);
                        mv.visitLdcInsn(Integer.valueOf(i));
                        mv.visitLdcInsn(Double.valueOf(distances[i]));
                        mv.visitInsn(Opcodes.DASTORE);
                    }
                    mv.visitLdcInsn(Integer.valueOf(1));
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createArray",
                                       "([DI)Lcom/esri/gc/FloatArray;", false);
                    setback = "(Lcom/esri/gc/FloatArray;" + NODE + ")V";
                }
                mv.visitLdcInsn(Integer.valueOf(parts.length - 1));
                mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createSplitRoot",
                                   "(I)" + NODE, false);
                for (int k = 1; k < parts.length; k++) {
                    String[] branch = parts[k].split(":");
                    mv.visitInsn(Opcodes.DUP);
                    mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/Setback", branch[0],
                                      "Lcom/esri/gc/Setback;");
                    mv.visitInsn(Opcodes.DCONST_0);
                    mv.visitInsn(branch[1].equals("1") ? Opcodes.ICONST_1 : Opcodes.ICONST_0);
                    mv.visitInsn(Opcodes.ICONST_0);
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createSplitNode",
                                       "(Lcom/esri/gc/Setback;DZI)" + NODE, false);
                    mv.visitInsn(Opcodes.DUP);
                    int ref = writer.newMethod(owner, "_$sb$" + (k - 1), "()V", false);
                    mv.visitIntInsn(Opcodes.SIPUSH, ref);
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$addOpSeq",
                                       "(" + NODE + "I)V", false);
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$addSplitNode",
                                       "(" + NODE + NODE + ")V", false);
                }
                mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "setback", setback, false);
                mv.visitInsn(Opcodes.RETURN);
                mv.visitMaxs(0, 0);
                mv.visitEnd();
            }
            public void visitEnd() {
                for (int k = 1; k < parts.length; k++) {
                    MethodVisitor mv = super.visitMethod(
                        Opcodes.ACC_PUBLIC | Opcodes.ACC_STATIC, "_$sb$" + (k - 1), "()V",
                        null, null);
                    mv.visitCode();
                    for (String what : GEOMETRY) {
                        mv.visitLdcInsn("b" + (k - 1) + "." + what);
                        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "geometry$" + what, "()D",
                                           false);
                        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "report",
                                           "(Ljava/lang/String;D)V", false);
                    }
                    // the branch's shape becomes a terminal shape, "Leaf<k>."
                    int leaf = writer.newMethod(owner, "Default$Leaf" + (k - 1) + "$", "()V",
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


def branches(text: str) -> list[tuple[str, str]]:
    """``"all: | remainder="`` as ``[("all", ":"), ("remainder", "=")]``."""
    out = []
    for part in text.split("|"):
        part = part.strip()
        out.append((part[:-1].strip().replace(".", "$"), part[-1]))
    return out


def measure(pyprt, work: Path, source: Path, patcher: Path, lot: dict, distance, text) -> dict:
    case = Path(tempfile.mkdtemp(dir=work))
    package = case / "package"
    shutil.copytree(source, package)
    (cgb,) = package.glob("bin/*.cgb")
    values = distance if isinstance(distance, (list, tuple)) else (distance,)
    spec = "|".join([",".join(str(float(v)) for v in values)] + [
        f"{name}:{1 if op == ':' else 0}" for name, op in branches(text)
    ])  # fmt: skip
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
    written = (
        f"[{', '.join(f'{v:g}' for v in values)}]" if isinstance(distance, (list, tuple))
        else f"{distance:g}"
    )  # fmt: skip
    row: dict = {"rule": f"setback({written}) {{ {text} }}"}
    for k in range(len(branches(text))):
        shapes = report.get(f"b{k}.nFaces_n")
        sums = {what: report.get(f"b{k}.{what}_sum") for what in GEOMETRY}
        row[f"b{k}"] = {
            "shapes": 0 if shapes is None else int(shapes),
            **{w: None if v is None else round(v, 6) + 0.0 for w, v in sums.items()},
        }
    flat = list(model.get_vertices())
    row["encoder_vertices"] = len(flat) // 3
    row["encoder_faces"] = list(model.get_faces())
    if len(flat) // 3 <= MAX_POINTS:
        corners = range(0, len(flat), 3)
        row["points"] = [[round(c, 4) + 0.0 for c in flat[i : i + 3]] for i in corners]
        row["indices"] = list(model.get_indices())
    row["errors"] = [e for e in model.get_cga_errors() if "CGAC version" not in e]
    return row


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("output", type=Path, help="the JSON file to write")
    parser.add_argument("--corpus", type=Path, default=CORPUS, help="the shared CGA corpus")
    args = parser.parse_args(argv)
    with rewritable_package(args.corpus, "prt_setback", PACKAGE, PATCHER) as context:
        pyprt, work, source, patcher = context
        rows = measured_cases(
            "prt_setback",
            LOTS,
            CASES,
            lambda lot, case: measure(pyprt, work, source, patcher, lot, *case),
        )
    from importlib.metadata import version as installed

    head = {
        "source": f"CityEngine's runtime, PyPRT {installed('pyprt')}, by tools/prt_setback.py: "
        "each rule runs on the named initial shape through PyPRT's PyEncoder; b<k> is the "
        "k-th branch: the shapes it gets and the sums of their geometry.nFaces, nHoles, "
        "nVertices and area; encoder_vertices, encoder_faces (vertex counts, holes as their "
        "own rings after their face), points and indices what the PyEncoder returns",
        "lots": LOTS,
    }
    write_fixture(args.output, head, "cases", rows)
    print(f"prt_setback: {len(rows)} cases written to {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
