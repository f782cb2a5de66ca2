"""What the tools that measure CityEngine's runtime (``tools/prt_*.py``) share.

PyPRT runs compiled rules (``bin/*.cgb`` in a rule package, Java class files) and cannot compile
CGA, so each tool takes a package of the shared corpus, rewrites its compiled rule with an ASM
``Patch`` class per case (``rewritable_package``, ``generated_model``), generates the case on an
initial shape through PyPRT's PyEncoder and keeps figures of the model (``encoder_figures``,
``branch_figures``, ``cga_errors``) as a JSON fixture a row a line (``write_fixture``).
``patch_class`` makes a rewriter's Java source, ``footprint_patcher`` that of the tools whose
start rule (``Footprint`` of the corpus's ``FacesHolesVerticesrule`` package) becomes one
operation with its compiled split tree.

The tools run with PyPRT's Python (a development tool; shapegen never imports it) and need
``javac``/``java``, the ASM bytecode library (Debian's ``libasm-java``) and ``7z``
(``p7zip-full``).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from contextlib import contextmanager
from importlib.metadata import version as installed
from pathlib import Path
from typing import Any, NamedTuple

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "cga-corpus"
ASM_JAR = "/usr/share/java/asm.jar"
# the package of the Footprint tools: one start rule, Footprint, in the runtime's static form
FOOTPRINT_PACKAGE = "packages/Esri+pyprt__tests_data_FacesHolesVerticesrule__987e9f4b.rpk"


class Rewriter(NamedTuple):
    """PyPRT's module and what ``rewritable_package`` made in its temporary ``work`` folder:
    the package unpacked (``source``) and the compiled ``Patch`` class's folder (``patcher``)."""

    pyprt: Any
    work: Path
    source: Path
    patcher: Path


@contextmanager
def rewritable_package(corpus: Path, tool: str, package: str, patcher: str):
    """The corpus's ``package`` unpacked and the ASM ``patcher`` (the source of a Java class
    ``Patch``) compiled, in a temporary folder, as a ``Rewriter``. What is missing (java, javac,
    7z, the ASM jar, the package) ends the tool with one line, status 2."""
    source_code = patcher
    package = corpus / package
    missing = [name for name in ("java", "javac", "7z") if shutil.which(name) is None]
    if missing or not Path(ASM_JAR).exists() or not package.exists():
        what = missing + [p for p in (ASM_JAR, str(package)) if not Path(p).exists()]
        print(f"{tool}: missing {', '.join(what)}", file=sys.stderr)
        raise SystemExit(2)
    import pyprt  # PyPRT's environment only

    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        source = work / "source"
        subprocess.run(["7z", "x", f"-o{source}", str(package)], check=True,
                       stdout=subprocess.DEVNULL)  # fmt: skip
        patcher = work / "patcher"
        patcher.mkdir()
        (patcher / "Patch.java").write_text(source_code)
        subprocess.run(["javac", "-cp", ASM_JAR, "Patch.java"], cwd=patcher, check=True)
        yield Rewriter(pyprt, work, source, patcher)


def lot_from_rings(outline, *holes) -> dict:
    """An initial shape in PyPRT's form from (x, z) rings in the ground plane, (x, 0, z): the
    outline, then each hole (its own face, named a hole of the first)."""
    rings = [outline, *holes]
    lot = {
        "coordinates": [c for ring in rings for x, z in ring for c in (x, 0, z)],
        "indices": list(range(sum(len(ring) for ring in rings))),
        "face_counts": [len(ring) for ring in rings],
    }
    if holes:
        lot["holes"] = [[0, *range(1, len(rings))]]
    return lot


def corpus_package(corpus: Path, tool: str, package: str) -> Path:
    """The corpus's ``package`` as it is (not rewritten); a missing one ends the tool with one
    line, status 2."""
    path = corpus / package
    if not path.exists():
        print(f"{tool}: missing {path}", file=sys.stderr)
        raise SystemExit(2)
    return path


def initial_shape(pyprt, lot: dict):
    """PyPRT's initial shape of ``lot``: its ``coordinates`` (x, y, z flat), and where it has
    ``holes`` its ``indices``, ``face_counts`` and ``holes`` too."""
    if "holes" in lot:
        return pyprt.InitialShape(
            lot["coordinates"], lot["indices"], lot["face_counts"], lot["holes"]
        )
    return pyprt.InitialShape(lot["coordinates"])


def generated_model(rewriter: Rewriter, spec: str, lot: dict, report: bool = True):
    """The model of one case: a copy of the package whose compiled rule ``Patch`` rewrote after
    ``spec`` (its third argument), packed as a rule package and generated on ``lot`` through
    PyPRT's PyEncoder, with the report unless ``report`` is false."""
    case = Path(tempfile.mkdtemp(dir=rewriter.work))
    package = case / "package"
    shutil.copytree(rewriter.source, package)
    (cgb,) = package.glob("bin/*.cgb")
    classpath = f"{ASM_JAR}{os.pathsep}{rewriter.patcher}"
    subprocess.run(["java", "-cp", classpath, "Patch", str(cgb), str(cgb), spec], check=True)
    rpk = case / "case.rpk"
    # LZMA, not solid, header not compressed: what CityEngine's runtime reads
    subprocess.run(
        ["7z", "a", "-t7z", "-m0=LZMA", "-ms=off", "-mhc=off", str(rpk), ".resolvemap.xml",
         "bin", "rules"],
        cwd=package, check=True, stdout=subprocess.DEVNULL,
    )  # fmt: skip
    shape = initial_shape(rewriter.pyprt, lot)
    options = {"emitReport": report, "emitGeometry": True}
    (model,) = rewriter.pyprt.ModelGenerator([shape]).generate_model(
        [{}], str(rpk), "com.esri.pyprt.PyEncoder", options
    )
    return model


def rounded_points(flat: list, digits: int) -> list[list[float]]:
    """PyPRT's flat vertex list as (x, y, z) points rounded to ``digits`` decimals (no -0.0)."""
    return [[round(c, digits) + 0.0 for c in flat[i : i + 3]] for i in range(0, len(flat), 3)]


def averages(report: dict, prefix: str, figures, digits: int = 6) -> dict:
    """The report's ``<prefix><figure>_avg`` of each of ``figures`` rounded (None where the
    report has none)."""
    values = {figure: report.get(f"{prefix}{figure}_avg") for figure in figures}
    return {k: None if v is None else round(v, digits) + 0.0 for k, v in values.items()}


def branch_figures(report: dict, branch: int, figures) -> dict:
    """What the ``branch``-th branch of a split reported under ``b<branch>.``: the number of
    shapes it got (the count of its ``nFaces`` reports, one a shape) and the sums of
    ``figures`` over them."""
    shapes = report.get(f"b{branch}.nFaces_n")
    sums = {figure: report.get(f"b{branch}.{figure}_sum") for figure in figures}
    return {
        "shapes": 0 if shapes is None else int(shapes),
        **{w: None if v is None else round(v, 6) + 0.0 for w, v in sums.items()},
    }


def encoder_figures(model, digits: int, max_points: int | None = None, count: bool = False):
    """What the PyEncoder returned: ``encoder_vertices`` (the vertex count, if ``count``),
    ``encoder_faces`` (vertex counts), then ``points`` (rounded to ``digits``) and ``indices``
    unless there are more than ``max_points`` vertices."""
    flat = list(model.get_vertices())
    row: dict = {"encoder_vertices": len(flat) // 3} if count else {}
    row["encoder_faces"] = list(model.get_faces())
    if max_points is None or len(flat) // 3 <= max_points:
        row["points"] = rounded_points(flat, digits)
        row["indices"] = list(model.get_indices())
    return row


def cga_errors(model) -> list[str]:
    """The model's CGA errors but the warning every old compiled rule gets (its CGAC version)."""
    return [e for e in model.get_cga_errors() if "CGAC version" not in e]


def measured_cases(tool: str, lots: dict, cases, measure_case) -> list[dict]:
    """``measure_case(lot, case)`` for every lot of ``lots`` (name -> initial shape) and every
    case, each row led by its lot's name; a case the rewriter cannot make is said on stderr
    and left out, not fatal."""
    rows = []
    for name, lot in lots.items():
        for case in cases:
            try:
                row = measure_case(lot, case)
            except Exception as exc:  # noqa: BLE001 - recorded, the others still measured
                print(f"{tool}: {name} {case!r}: {exc}", file=sys.stderr)
                continue
            rows.append({"lot": name, **row})
    return rows


def write_fixture(path: Path, head: dict, key: str, rows: list) -> None:
    """The measured ``rows`` as a JSON fixture: ``head``'s entries, then ``key`` with a row a
    line, so that a new measurement's difference reads row by row."""
    lines = [
        "{",
        *(f" {json.dumps(k)}: {json.dumps(v)}," for k, v in head.items()),
        f" {json.dumps(key)}: [",
    ]
    lines += [f"  {json.dumps(row)}," for row in rows]
    lines[-1] = lines[-1].rstrip(",")
    path.write_text("\n".join([*lines, " ]", "}"]) + "\n")


def arguments(doc: str, argv: list[str] | None, lots: dict | None = None) -> argparse.Namespace:
    """A tool's command line: the JSON file to write and ``--corpus``; with ``lots``, also
    ``--lot`` (repeated) to measure only some of them, an unknown name refused."""
    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    parser.add_argument("output", type=Path, help="the JSON file to write")
    parser.add_argument("--corpus", type=Path, default=CORPUS, help="the shared CGA corpus")
    if lots is not None:
        parser.add_argument("--lot", action="append", help="measure only these lots")
    args = parser.parse_args(argv)
    unknown = [name for name in getattr(args, "lot", None) or [] if name not in lots]
    if unknown:
        parser.error(f"unknown lot {', '.join(unknown)}; the lots are {', '.join(lots)}")
    return args


def fixture_written(tool: str, output: Path, about: str, head: dict, key: str, rows: list) -> int:
    """``rows`` written to ``output`` under ``key``, after a ``source`` line (the runtime's
    version, the tool, then ``about``) and ``head``'s entries; one line says so. Status 0."""
    source = f"CityEngine's runtime, PyPRT {installed('pyprt')}, by tools/{tool}.py: {about}"
    write_fixture(output, {"source": source, **head}, key, rows)
    print(f"{tool}: {len(rows)} {key} written to {output}")
    return 0


def measuring_main(argv, doc: str, tool: str, rewriting, lots: dict, cases, measure, about: str):
    """The command of a tool that measures ``cases`` on each of ``lots``: the package and
    patcher ``rewriting`` (``(package, patcher)``) made ready, ``measure(rewriter, lot, case)``
    a row for each (or for the lots ``--lot`` names), written with the lots as ``cases``."""
    args = arguments(doc, argv, lots)
    chosen = {k: v for k, v in lots.items() if not args.lot or k in args.lot}
    with rewritable_package(args.corpus, tool, *rewriting) as rewriter:
        rows = measured_cases(tool, chosen, cases, lambda lot, c: measure(rewriter, lot, c))
    return fixture_written(tool, args.output, about, {"lots": lots}, "cases", rows)


# The Java of a rewriter: a class Patch whose main(in, out, case) rewrites the compiled rule
# ``in`` into ``out`` with the ASM library, and these helpers: push(mv, "a,b,...") pushes
# arguments (numbers, true/false, or @Class.FIELD, a constant of the runtime's enum
# com.esri.gc.Class) and returns their descriptor; call(mv, "fn(a,b)") calls a builtin with
# them, calls(mv, "fn();fn(a)") each of ";"-separated calls; report(mv, name, builtin) reports
# the value of a builtin of no arguments under name.
PATCH_CLASS = r"""
import org.objectweb.asm.*;
import java.nio.file.*;

public class Patch {
    static final String B = "com/esri/gc/Builtins";
    static String push(MethodVisitor mv, String args) {
        StringBuilder descriptor = new StringBuilder();
        if (!args.isEmpty()) for (String v : args.split(",")) {
            if (v.equals("true") || v.equals("false")) {
                mv.visitInsn(v.equals("true") ? Opcodes.ICONST_1 : Opcodes.ICONST_0);
                descriptor.append("Z");
            } else if (v.startsWith("@")) {
                String cls = "com/esri/gc/" + v.substring(1, v.indexOf('.'));
                String type = "L" + cls + ";";
                mv.visitFieldInsn(Opcodes.GETSTATIC, cls, v.substring(v.indexOf('.') + 1), type);
                descriptor.append(type);
            } else {
                mv.visitLdcInsn(Double.valueOf(v));
                descriptor.append("D");
            }
        }
        return descriptor.toString();
    }
    static void call(MethodVisitor mv, String call) {
        String fn = call.substring(0, call.indexOf('('));
        String args = call.substring(call.indexOf('(') + 1, call.lastIndexOf(')'));
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, fn, "(" + push(mv, args) + ")V", false);
    }
    static void calls(MethodVisitor mv, String text) {
        if (!text.isEmpty()) for (String c : text.split(";")) call(mv, c);
    }
    static void report(MethodVisitor mv, String name, String builtin) {
        mv.visitLdcInsn(name);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, builtin, "()D", false);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "report", "(Ljava/lang/String;D)V", false);
    }
@MEMBERS@
}
"""


def patch_class(members: str) -> str:
    """The Java source of a rewriter: ``PATCH_CLASS`` with a tool's ``members`` (its ``main``
    and what that needs)."""
    return PATCH_CLASS.replace("@MEMBERS@\n", members.strip("\n") + "\n")


# The members of the Footprint tools' rewriter (the case: "|"-separated parts): Default$Footprint's
# code becomes what the tool's static footprint(mv) writes, and each branch part from the tool's
# FIRST on (selector:merge[:calls], merge 1 for ':' and 0 for '=') a new static method _$cb$<k>
# with the part's calls, then what the tool's branch(mv, k, part split at ':') writes, ending as
# a leaf.
FOOTPRINT_MEMBERS = r"""
    static final String NODE = "Lcom/esri/gc/SplitNode;";
    static ClassWriter writer;
    static String owner;
    static String[] parts;
    // the split tree of the branch parts, their selectors fields of com.esri.gc's enum
    // selectorClass: _$createSplitRoot, then a _$createSplitNode per branch, whose operations
    // are the static method given by its Methodref's constant-pool index
    static void splitTree(MethodVisitor mv, String selectorClass) {
        String type = "Lcom/esri/gc/" + selectorClass + ";";
        mv.visitLdcInsn(Integer.valueOf(parts.length - FIRST));
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createSplitRoot", "(I)" + NODE, false);
        for (int k = FIRST; k < parts.length; k++) {
            String[] branch = parts[k].split(":", 3);
            mv.visitInsn(Opcodes.DUP);
            mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/" + selectorClass, branch[0], type);
            mv.visitInsn(Opcodes.DCONST_0);
            mv.visitInsn(branch[1].equals("1") ? Opcodes.ICONST_1 : Opcodes.ICONST_0);
            mv.visitInsn(Opcodes.ICONST_0);
            mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createSplitNode",
                               "(" + type + "DZI)" + NODE, false);
            mv.visitInsn(Opcodes.DUP);
            int ref = writer.newMethod(owner, "_$cb$" + (k - FIRST), "()V", false);
            mv.visitIntInsn(Opcodes.SIPUSH, ref);
            mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$addOpSeq", "(" + NODE + "I)V", false);
            mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$addSplitNode",
                               "(" + NODE + NODE + ")V", false);
        }
    }
    static void end(MethodVisitor mv) {
        mv.visitInsn(Opcodes.RETURN);
        mv.visitMaxs(0, 0);
        mv.visitEnd();
    }
    public static void main(String[] a) throws Exception {
        ClassReader reader = new ClassReader(Files.readAllBytes(Paths.get(a[0])));
        writer = new ClassWriter(reader, ClassWriter.COMPUTE_MAXS);
        owner = reader.getClassName();
        parts = a[2].split("\\|");
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
                        target.visitCode();
                        footprint(target);
                        end(target);
                    }
                };
            }
            public void visitEnd() {
                for (int k = FIRST; k < parts.length; k++) {
                    MethodVisitor mv = super.visitMethod(Opcodes.ACC_PUBLIC | Opcodes.ACC_STATIC,
                                                         "_$cb$" + (k - FIRST), "()V", null, null);
                    mv.visitCode();
                    String[] part = parts[k].split(":", 3);
                    if (part.length > 2) calls(mv, part[2]);
                    branch(mv, k - FIRST, part);
                    // the branch's shape becomes a terminal shape, "Leaf<k>."
                    int leaf = writer.newMethod(owner, "Default$Leaf" + (k - FIRST) + "$", "()V",
                                                false);
                    mv.visitIntInsn(Opcodes.SIPUSH, leaf);
                    mv.visitInsn(Opcodes.ICONST_2);
                    mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createShape", "(II)V", false);
                    end(mv);
                }
                super.visitEnd();
            }
        }, 0);
        Files.write(Paths.get(a[1]), writer.toByteArray());
    }
"""


def java_strings(name: str, values) -> str:
    """A Java member: the array of strings ``name`` holding ``values``, so that a rewriter and
    its tool read the same list."""
    strings = ", ".join(f'"{v}"' for v in values)
    return f"    static final String[] {name} = {{{strings}}};\n"


def footprint_patcher(first: int, members: str, branch_geometry=()) -> str:
    """The Java source of a Footprint tool's rewriter: ``FOOTPRINT_MEMBERS``, the index of the
    case's ``first`` branch part, and the tool's Java ``members``: ``static void
    footprint(MethodVisitor mv)`` and, unless each branch is to report its shape's
    ``branch_geometry`` (builtins ``geometry.*``) under ``b<k>.`` (``branch_figures`` reads
    them back), ``static void branch(MethodVisitor mv, int k, String[] branch)``."""
    if branch_geometry:
        members += java_strings("BRANCH_GEOMETRY", branch_geometry)
        members += r"""    static void branch(MethodVisitor mv, int k, String[] branch) {
        for (String what : BRANCH_GEOMETRY) report(mv, "b" + k + "." + what, "geometry$" + what);
    }
"""
    return patch_class(f"    static final int FIRST = {first};\n" + FOOTPRINT_MEMBERS + members)
