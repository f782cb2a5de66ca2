"""Measure CityEngine's trim() on faces with holes with its runtime: writes
``tests/data/prt_trim_holes.json``.

The start rule of the corpus's FacesHolesVerticesrule package (tools/prt_roofs.py's) is rewritten
into builtin calls, a ``comp`` with the runtime's own split tree, and in each branch more calls
and reports of the branch shape's ``geometry.nVertices``, ``nFaces``, ``nHoles``, ``area`` and
``volume`` under ``b<k>.``: a case is ``calls|component|selector:merge:calls|...``, the calls
``;``-separated (numbers, ``true``/``false`` or ``@Class.FIELD``, a constant of the runtime's
enum ``com.esri.gc.Class``; ``translate(@Mode.rel,@CoordSystem.world,x,y,z)`` is CGA's
``t(x, y, z)`` in world axes). Here the top of a 5 m extrusion (comp(f) gives it its trim
planes) is extruded 2 m, moved out of its planes or not, and trimmed. Run with PyPRT's Python
(a development tool; shapegen never imports it)::

    /tmp/prt-venv/bin/python tools/prt_trim_holes.py tests/data/prt_trim_holes.json \
        --corpus /work/shared/cga-corpus
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
from prt_roofs import LOTS as ROOF_LOTS  # noqa: E402
from prt_roofs import PACKAGE  # noqa: E402

GEOMETRY = ("nVertices", "nFaces", "nHoles", "area", "volume")
LOTS = {name: ROOF_LOTS[name] for name in ("courtyard", "L_courtyard", "two_holes", "L")}
MOVE = "translate(@Mode.rel,@CoordSystem.world,{})"
CASES = [
    "extrude(5)|f|top:1:extrude(2)",
    "extrude(5)|f|top:1:extrude(2);trim()",
    "extrude(5)|f|top:1:extrude(2);" + MOVE.format("3,0,0"),
    "extrude(5)|f|top:1:extrude(2);" + MOVE.format("3,0,0") + ";trim()",
    "extrude(5)|f|top:1:" + MOVE.format("3,0,0") + ";trim()",
    "extrude(5)|f|top:1:" + MOVE.format("1,0,1") + ";trim()",
]

# The rewriter (args: in, out, the case): Default$Footprint's code becomes the case's calls and
# its comp, each branch a new static method _$cb$<k> with its calls, reports and a leaf.
PATCHER = r"""
import org.objectweb.asm.*;
import java.nio.file.*;

public class Patch {
    static final String B = "com/esri/gc/Builtins";
    static final String NODE = "Lcom/esri/gc/SplitNode;";
    static final String[] GEOMETRY = {"nVertices", "nFaces", "nHoles", "area", "volume"};
    static void report(MethodVisitor mv, String name, String builtin) {
        mv.visitLdcInsn(name);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, builtin, "()D", false);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "report", "(Ljava/lang/String;D)V", false);
    }
    static void calls(MethodVisitor mv, String text) {
        if (text.isEmpty()) return;
        for (String call : text.split(";")) {
            String fn = call.substring(0, call.indexOf('('));
            String args = call.substring(call.indexOf('(') + 1, call.lastIndexOf(')'));
            StringBuilder d = new StringBuilder("(");
            if (!args.isEmpty()) for (String v : args.split(",")) {
                if (v.equals("true") || v.equals("false")) {
                    mv.visitInsn(v.equals("true") ? Opcodes.ICONST_1 : Opcodes.ICONST_0);
                    d.append("Z");
                } else if (v.startsWith("@")) {
                    String cls = "com/esri/gc/" + v.substring(1, v.indexOf('.'));
                    String type = "L" + cls + ";";
                    mv.visitFieldInsn(Opcodes.GETSTATIC, cls, v.substring(v.indexOf('.') + 1),
                                      type);
                    d.append(type);
                } else {
                    mv.visitLdcInsn(Double.valueOf(v));
                    d.append("D");
                }
            }
            mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, fn, d.append(")V").toString(), false);
        }
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
                    public void visitEnd() { footprint(target); }
                };
            }
            void footprint(MethodVisitor mv) {
                mv.visitCode();
                calls(mv, parts[0]);
                mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/CompSelector", parts[1],
                                  "Lcom/esri/gc/CompSelector;");
                mv.visitLdcInsn(Integer.valueOf(parts.length - 2));
                mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createSplitRoot", "(I)" + NODE,
                                   false);
                for (int k = 2; k < parts.length; k++) {
                    String[] branch = parts[k].split(":", 3);
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
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$addOpSeq", "(" + NODE + "I)V",
                                       false);
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$addSplitNode",
                                       "(" + NODE + NODE + ")V", false);
                }
                mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "comp",
                                   "(Lcom/esri/gc/CompSelector;" + NODE + ")V", false);
                mv.visitInsn(Opcodes.RETURN);
                mv.visitMaxs(0, 0);
                mv.visitEnd();
            }
            public void visitEnd() {
                for (int k = 2; k < parts.length; k++) {
                    String[] branch = parts[k].split(":", 3);
                    MethodVisitor mv = super.visitMethod(Opcodes.ACC_PUBLIC | Opcodes.ACC_STATIC,
                                                         "_$cb$" + (k - 2), "()V", null, null);
                    mv.visitCode();
                    calls(mv, branch.length > 2 ? branch[2] : "");
                    for (String what : GEOMETRY)
                        report(mv, "b" + (k - 2) + "." + what, "geometry$" + what);
                    int leaf = writer.newMethod(owner, "Default$Leaf" + (k - 2) + "$", "()V",
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


def rule_text(case: str) -> str:
    """The case as CGA: ``extrude(5) comp(f) { top: extrude(2) t(3, 0, 0) trim() }``."""

    def written(calls: str) -> str:
        out = []
        for call in filter(None, calls.split(";")):
            call = call.replace("@Mode.", "").replace("@CoordSystem.", "")
            out.append(call.replace(",", ", "))
        return " ".join(out)

    before, component, *branches = case.split("|")
    parts = []
    for branch in branches:
        selector, merge, calls = branch.split(":", 2)
        parts.append(f"{selector} {':' if merge == '1' else '='} {written(calls)}".rstrip())
    return f"{written(before)} comp({component}) {{ {' | '.join(parts)} }}"


def measure(pyprt, work: Path, source: Path, patcher: Path, lot: dict, case: str) -> dict:
    folder = Path(tempfile.mkdtemp(dir=work))
    package = folder / "package"
    shutil.copytree(source, package)
    (cgb,) = package.glob("bin/*.cgb")
    java = ["java", "-cp", f"{ASM_JAR}{os.pathsep}{patcher}", "Patch", str(cgb), str(cgb)]
    subprocess.run([*java, case], check=True)
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
    row: dict = {"rule": rule_text(case)}
    for k in range(len(case.split("|")) - 2):
        shapes = report.get(f"b{k}.nFaces_n")
        sums = {what: report.get(f"b{k}.{what}_sum") for what in GEOMETRY}
        row[f"b{k}"] = {
            "shapes": 0 if shapes is None else int(shapes),
            **{w: None if v is None else round(v, 6) + 0.0 for w, v in sums.items()},
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
    args = parser.parse_args(argv)
    with rewritable_package(args.corpus, "prt_trim_holes", PACKAGE, PATCHER) as context:
        pyprt, work, source, patcher = context
        rows = measured_cases(
            "prt_trim_holes",
            LOTS,
            CASES,
            lambda lot, case: measure(pyprt, work, source, patcher, lot, case),
        )
    from importlib.metadata import version as installed

    head = {
        "source": f"CityEngine's runtime, PyPRT {installed('pyprt')}, by "
        "tools/prt_trim_holes.py: each rule runs on the named initial shape (PyPRT's "
        "InitialShape with holes: (x, 0, z) coordinates) through PyPRT's PyEncoder; b<k> is "
        "the k-th branch of the comp: the shapes it gets and the sums of their geometry.* after "
        "its calls; points, indices and encoder_faces (vertex counts, a hole's ring after its "
        "face) are what the PyEncoder returns",
        "lots": LOTS,
    }
    write_fixture(args.output, head, "cases", rows)
    print(f"prt_trim_holes: {len(rows)} cases written to {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
