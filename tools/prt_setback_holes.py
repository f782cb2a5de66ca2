"""Measure CityEngine's setbackToArea, shapeL, shapeU, shapeO and innerRectangle on faces with
holes with its runtime: writes ``tests/data/prt_setback_holes.json``.

As tools/prt_setback.py does for ``setback``, the start rule of the corpus's
FacesHolesVerticesrule package is rewritten into one operation with its compiled split tree
(``_$createSplitRoot``, one ``_$createSplitNode`` per branch with the operation's selector
enum: ``com.esri.gc.Setback`` for setbackToArea, ``ShapeLUO`` for shapeL/U/O,
``InnerRectangle`` for innerRectangle, as the corpus's compiled envelope2002 and
simpleRuleDataset rules call them) and the builtin (``Builtins.shapeL(DD...)``,
``innerRectangle(AlignmentMode, ...)``, ``setbackToArea(D...)``). Each branch reports its
shape's ``geometry.nFaces``, ``nHoles``, ``nVertices`` and ``area`` under ``b<branch>.``, and
the encoder's vertices and faces are kept. Run with PyPRT's Python (a development tool;
shapegen never imports it)::

    /tmp/prt-venv/bin/python tools/prt_setback_holes.py tests/data/prt_setback_holes.json \
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
from prt_setback import GEOMETRY, PACKAGE  # noqa: E402

MAX_POINTS = 64  # the encoder's vertices are kept for results with at most this many
LOTS = {
    # the 12 x 8 m lot without its courtyard, for what the same cases give without holes
    "12x8": {
        "coordinates": [0, 0, 8, 12, 0, 8, 12, 0, 0, 0, 0, 0],
        "indices": [0, 1, 2, 3],
        "face_counts": [4],
        "holes": [],
    },
    # tools/prt_holes.py's courtyard: 12 x 8 m with a 4 x 2 m hole from (4, 3) to (8, 5)
    "courtyard": {
        "coordinates": [0, 0, 8, 12, 0, 8, 12, 0, 0, 0, 0, 0, 4, 0, 3, 8, 0, 3, 8, 0, 5, 4, 0, 5],
        "indices": [0, 1, 2, 3, 4, 5, 6, 7],
        "face_counts": [4, 4],
        "holes": [[0, 1]],
    },
    # the courtyard with its first edge at the back (z = 0, along -x): which of two equal
    # rectangles innerRectangle takes
    "courtyard_back": {
        "coordinates": [12, 0, 0, 0, 0, 0, 0, 0, 8, 12, 0, 8, 4, 0, 3, 8, 0, 3, 8, 0, 5, 4, 0, 5],
        "indices": [0, 1, 2, 3, 4, 5, 6, 7],
        "face_counts": [4, 4],
        "holes": [[0, 1]],
    },
    # a perimeter block: 20 x 16 m, first edge along +x at z = 16, an 8 x 6 m courtyard from
    # (6, 5) to (14, 11)
    "block": {
        "coordinates": [0, 0, 16, 20, 0, 16, 20, 0, 0, 0, 0, 0]
        + [6, 0, 5, 14, 0, 5, 14, 0, 11, 6, 0, 11],
        "indices": [0, 1, 2, 3, 4, 5, 6, 7],
        "face_counts": [4, 4],
        "holes": [[0, 1]],
    },
    # a yard off the block's middle, from (6, 4) to (14, 10): one largest rectangle (20 x 6 m
    # at the front)
    "yard": {
        "coordinates": [0, 0, 16, 20, 0, 16, 20, 0, 0, 0, 0, 0]
        + [6, 0, 4, 14, 0, 4, 14, 0, 10, 6, 0, 10],
        "indices": [0, 1, 2, 3, 4, 5, 6, 7],
        "face_counts": [4, 4],
        "holes": [[0, 1]],
    },
    # a square yard turned 45 degrees (its diagonals 6 m) in the middle of the block
    "diamond": {
        "coordinates": [0, 0, 16, 20, 0, 16, 20, 0, 0, 0, 0, 0]
        + [10, 0, 5, 13, 0, 8, 10, 0, 11, 7, 0, 8],
        "indices": [0, 1, 2, 3, 4, 5, 6, 7],
        "face_counts": [4, 4],
        "holes": [[0, 1]],
    },
}
# (operation, arguments, branches): arguments are numbers, or an AlignmentMode's name
CASES = [
    ("shapeL", (2, 3), "shape: | remainder:"),
    ("shapeL", (2, 3), "shape="),
    ("shapeL", (4, 5), "shape: | remainder:"),
    ("shapeL", (4, 5), "remainder:"),
    ("shapeU", (2, 2, 2), "shape: | remainder:"),
    ("shapeU", (4, 5, 5), "shape: | remainder:"),
    ("shapeU", (4, 5, 5), "shape="),
    ("shapeO", (2, 2, 2, 2), "shape: | remainder:"),
    ("shapeO", (2, 2, 2, 2), "shape:"),
    ("shapeO", (4, 5, 4, 5), "shape: | remainder:"),
    ("shapeO", (4, 5, 4, 5), "remainder="),
    ("shapeO", (1, 2, 3, 4), "shape: | remainder:"),
    ("setbackToArea", (40,), "all: | remainder:"),
    ("setbackToArea", (40,), "remainder:"),
    ("setbackToArea", (60,), "front: | remainder:"),
    ("setbackToArea", (100,), "all= | remainder="),
    ("setbackToArea", (150,), "side: | remainder:"),
    ("setbackToArea", (500,), "front: | remainder:"),
    ("innerRectangle", ("scope",), "shape: | remainder:"),
    ("innerRectangle", ("edge",), "shape: | remainder:"),
    ("innerRectangle", ("scope",), "shape="),
]
ENUMS = {"shapeL": "ShapeLUO", "shapeU": "ShapeLUO", "shapeO": "ShapeLUO",
         "setbackToArea": "Setback", "innerRectangle": "InnerRectangle"}  # fmt: skip

# The rewriter: Default$Footprint's code becomes the operation of the case (args: in, out, then
# "operation|arguments|enum|selector:merge|..." with the arguments "d:NUMBER" or
# "e:AlignmentMode.NAME" separated by ",", merge 1 for ':' and 0 for '='), each branch a new
# static method _$sb$<k> reporting its shape's geometry.* under "b<k>.".
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
                StringBuilder desc = new StringBuilder("(");
                for (String argument : parts[1].split(",")) {
                    String value = argument.substring(2);
                    if (argument.startsWith("d:")) {
                        mv.visitLdcInsn(Double.valueOf(value));
                        desc.append("D");
                    } else {  // e:Class.FIELD, an enum constant of com.esri.gc
                        String[] field = value.split("\\.");
                        String type = "Lcom/esri/gc/" + field[0] + ";";
                        mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/" + field[0],
                                          field[1], type);
                        desc.append(type);
                    }
                }
                desc.append(NODE).append(")V");
                String enumType = "Lcom/esri/gc/" + parts[2] + ";";
                mv.visitLdcInsn(Integer.valueOf(parts.length - 3));
                mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createSplitRoot",
                                   "(I)" + NODE, false);
                for (int k = 3; k < parts.length; k++) {
                    String[] branch = parts[k].split(":");
                    mv.visitInsn(Opcodes.DUP);
                    mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/" + parts[2], branch[0],
                                      enumType);
                    mv.visitInsn(Opcodes.DCONST_0);
                    mv.visitInsn(branch[1].equals("1") ? Opcodes.ICONST_1 : Opcodes.ICONST_0);
                    mv.visitInsn(Opcodes.ICONST_0);
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createSplitNode",
                                       "(" + enumType + "DZI)" + NODE, false);
                    mv.visitInsn(Opcodes.DUP);
                    int ref = writer.newMethod(owner, "_$sb$" + (k - 3), "()V", false);
                    mv.visitIntInsn(Opcodes.SIPUSH, ref);
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$addOpSeq",
                                       "(" + NODE + "I)V", false);
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$addSplitNode",
                                       "(" + NODE + NODE + ")V", false);
                }
                mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, parts[0], desc.toString(), false);
                mv.visitInsn(Opcodes.RETURN);
                mv.visitMaxs(0, 0);
                mv.visitEnd();
            }
            public void visitEnd() {
                for (int k = 3; k < parts.length; k++) {
                    MethodVisitor mv = super.visitMethod(
                        Opcodes.ACC_PUBLIC | Opcodes.ACC_STATIC, "_$sb$" + (k - 3), "()V",
                        null, null);
                    mv.visitCode();
                    for (String what : GEOMETRY) {
                        mv.visitLdcInsn("b" + (k - 3) + "." + what);
                        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "geometry$" + what, "()D",
                                           false);
                        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "report",
                                           "(Ljava/lang/String;D)V", false);
                    }
                    int leaf = writer.newMethod(owner, "Default$Leaf" + (k - 3) + "$", "()V",
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
    """``"shape: | remainder="`` as ``[("shape", ":"), ("remainder", "=")]``."""
    out = []
    for part in text.split("|"):
        part = part.strip()
        out.append((part[:-1].strip().replace(".", "$"), part[-1]))
    return out


def rule_text(operation: str, arguments: tuple, text: str) -> str:
    """The case as CGA: ``shapeL(2, 3) { shape: | remainder: }``."""
    written = ", ".join(a if isinstance(a, str) else f"{a:g}" for a in arguments)
    return f"{operation}({written}) {{ {text} }}"


def measure(pyprt, work: Path, source: Path, patcher: Path, lot: dict, case) -> dict:
    operation, arguments, text = case
    package = Path(tempfile.mkdtemp(dir=work)) / "package"
    shutil.copytree(source, package)
    (cgb,) = package.glob("bin/*.cgb")
    pushed = ",".join(
        f"e:AlignmentMode.{a}" if isinstance(a, str) else f"d:{float(a)}" for a in arguments
    )
    spec = "|".join(
        [operation, pushed, ENUMS[operation]]
        + [f"{name}:{1 if op == ':' else 0}" for name, op in branches(text)]
    )
    java = ["java", "-cp", f"{ASM_JAR}{os.pathsep}{patcher}", "Patch", str(cgb), str(cgb)]
    subprocess.run([*java, spec], check=True)
    rpk = package.parent / "case.rpk"
    subprocess.run(
        ["7z", "a", "-t7z", "-m0=LZMA", "-ms=off", "-mhc=off", str(rpk), ".resolvemap.xml",
         "bin", "rules"],
        cwd=package, check=True, stdout=subprocess.DEVNULL,
    )  # fmt: skip
    shape = pyprt.InitialShape(lot["coordinates"], lot["indices"], lot["face_counts"], lot["holes"])
    options = {"emitReport": True, "emitGeometry": True}
    (model,) = pyprt.ModelGenerator([shape]).generate_model(
        [{}], str(rpk), "com.esri.pyprt.PyEncoder", options
    )
    report = model.get_report()
    row: dict = {"rule": rule_text(operation, arguments, text)}
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
    with rewritable_package(args.corpus, "prt_setback_holes", PACKAGE, PATCHER) as context:
        pyprt, work, source, patcher = context
        rows = measured_cases(
            "prt_setback_holes",
            LOTS,
            CASES,
            lambda lot, case: measure(pyprt, work, source, patcher, lot, case),
        )
    from importlib.metadata import version as installed

    head = {
        "source": f"CityEngine's runtime, PyPRT {installed('pyprt')}, by "
        "tools/prt_setback_holes.py: each rule runs on the named initial shape (with its holes) "
        "through PyPRT's PyEncoder; b<k> is the k-th branch: the shapes it gets and the sums "
        "of their geometry.nFaces, nHoles, nVertices and area; encoder_vertices, encoder_faces "
        "(vertex counts, holes as their own rings after their face), points and indices what "
        "the PyEncoder returns",
        "lots": LOTS,
    }
    write_fixture(args.output, head, "cases", rows)
    print(f"prt_setback_holes: {len(rows)} cases written to {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
