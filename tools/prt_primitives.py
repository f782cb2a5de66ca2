"""Measure CityEngine's primitives with its runtime: writes ``tests/data/prt_primitives.json``.

PyPRT runs compiled rules (``bin/*.cgb`` in a rule package, Java class files) and cannot compile
CGA, so this tool takes the corpus's ``extrusion_rule`` package and rewrites its compiled rule:
the call of ``extrude`` in ``BuildingCreation`` becomes the operations of one case (calls of the
runtime's builtins with constant arguments) followed by reports of ``scope.sx`` ... ``scope.tz``.
Each case is then generated on a 10 x 10 m lot with the PyEncoder; the JSON gives, per case, the
scope, the bounds and vertices of the geometry and the facing of a one-face result.

It runs with PyPRT's Python (a development tool: ``python3 -m venv /tmp/prt &&
/tmp/prt/bin/pip install pyprt``; shapegen never imports it) and needs ``javac``/``java``, the ASM
bytecode library (Debian's ``libasm-java``) and ``7z`` (``p7zip-full``)::

    /tmp/prt/bin/python tools/prt_primitives.py tests/data/prt_primitives.json
    /tmp/prt/bin/python tools/prt_primitives.py out.json --corpus /work/shared/cga-corpus

The operations a case may use are those of ``CASES``: builtins taking numbers, and ``s()``, whose
sizes are written as absolute values.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from contextlib import contextmanager
from pathlib import Path

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "cga-corpus"
PACKAGE = "packages/Esri+pyprt__tests_data_extrusion_rule__e4df6667.rpk"
ASM_JAR = "/usr/share/java/asm.jar"
LOT = [[0, 0, 10], [10, 0, 10], [10, 0, 0], [0, 0, 0]]
"""PyPRT's initial shape: the 10 x 10 m lot shapegen makes, first edge along +x."""
SCOPE = ("sx", "sy", "sz", "tx", "ty", "tz")
MAX_POINTS = 26  # vertices kept for the cases with at most this many

CASES = [
    "primitiveCube(20, 2, 20)",
    "primitiveCube(20, 2, 20) s(4, 1, 4)",
    "primitiveCube()",
    "primitiveCube() s(4, 1, 4)",
    "extrude(5) primitiveCube(10, 15, 20)",
    "s(0, 0, 0) primitiveCube()",
    "s(0, 5, 0) primitiveCube()",
    "primitiveQuad()",
    "primitiveQuad(4, 6)",
    "primitiveQuad(4, 6) s(4, 1, 4)",
    "extrude(5) primitiveQuad()",
    "extrude(5) primitiveQuad(4, 6)",
    "rotateScope(0, 0, 90) primitiveQuad()",
    "rotateScope(0, 0, 90) primitiveQuad(10, 20)",
    "extrude(5) s(0, 5, 10) primitiveQuad(2, 3)",
    "extrude(5) s(4, 5, 0) primitiveQuad(2, 3)",
    "s(0, 0, 0) primitiveQuad()",
    "s(0, 5, 0) primitiveQuad()",
    "s(4, 0, 0) primitiveQuad()",
    "primitiveDisk()",
    "primitiveDisk(8)",
    "primitiveDisk(3, 3)",
    "primitiveDisk(4, 3)",
    "primitiveDisk(5, 3)",
    "primitiveDisk(6, 3)",
    "primitiveDisk(8, 3)",
    "primitiveDisk(8, 3) s(4, 1, 4)",
    "rotateScope(-90, 0, 0) primitiveDisk()",
    "rotateScope(-90, 0, 0) primitiveDisk(8, 10)",
    "extrude(5) s(4, 5, 0) primitiveDisk(8, 1)",
    "s(0, 0, 0) primitiveDisk()",
    "primitiveCylinder()",
    "primitiveCylinder(6, 3, 5)",
    "primitiveCylinder(8, 3, 5) s(4, 1, 4)",
    "extrude(5) s(4, 5, 0) primitiveCylinder(8, 1, 2)",
    "s(0, 0, 0) primitiveCylinder()",
    "s(0, 5, 0) primitiveCylinder()",
    "primitiveCone()",
    "primitiveCone(6, 3, 5)",
    "primitiveSphere()",
    "primitiveSphere(6, 4, 3)",
    "primitiveSphere(8, 4, 2) s(4, 1, 4)",
    "s(0, 0, 0) primitiveSphere()",
    "rotateScope(0, 0, 90) primitiveCube(2, 3, 4)",
    "primitiveCylinder(3.5)",
    "primitiveCylinder(4.5)",
    "primitiveCylinder(7.4)",
    "primitiveCylinder(7.6)",
    "primitiveSphere(8, 2.5)",
    "primitiveSphere(8, 3.5)",
    "primitiveCylinder(2.5)",
]

# The rewriter: replaces `invokestatic Builtins.extrude(D)V` of Default$BuildingCreation by the
# case's calls. An argument `@Class.FIELD` pushes that enum constant of com/esri/gc (s() takes
# Scale.ABS before each size), a number a double; `report:NAME` reports the builtin NAME()D.
PATCHER = r"""
import org.objectweb.asm.*;
import java.nio.file.*;

public class Patch {
    static final String B = "com/esri/gc/Builtins";
    public static void main(String[] a) throws Exception {
        ClassReader reader = new ClassReader(Files.readAllBytes(Paths.get(a[0])));
        ClassWriter writer = new ClassWriter(reader, ClassWriter.COMPUTE_MAXS);
        String[] calls = a[2].split(";");
        reader.accept(new ClassVisitor(Opcodes.ASM9, writer) {
            public MethodVisitor visitMethod(int acc, String name, String desc, String sig,
                                             String[] ex) {
                MethodVisitor mv = super.visitMethod(acc, name, desc, sig, ex);
                if (!name.equals("Default$BuildingCreation")) return mv;
                return new MethodVisitor(Opcodes.ASM9, mv) {
                    public void visitMethodInsn(int op, String owner, String n, String d,
                                                boolean itf) {
                        if (!n.equals("extrude")) {
                            super.visitMethodInsn(op, owner, n, d, itf);
                            return;
                        }
                        super.visitInsn(Opcodes.POP2);
                        for (String call : calls) {
                            if (call.startsWith("report:")) {
                                String what = call.substring(7);
                                super.visitLdcInsn(what);
                                super.visitMethodInsn(Opcodes.INVOKESTATIC, B, what, "()D", false);
                                super.visitMethodInsn(Opcodes.INVOKESTATIC, B, "report",
                                                      "(Ljava/lang/String;D)V", false);
                                continue;
                            }
                            String fn = call.substring(0, call.indexOf('('));
                            String text = call.substring(call.indexOf('(') + 1,
                                                         call.lastIndexOf(')'));
                            StringBuilder descriptor = new StringBuilder("(");
                            if (!text.isEmpty()) for (String v : text.split(",")) {
                                if (v.startsWith("@")) {
                                    String cls = "com/esri/gc/" + v.substring(1, v.indexOf('.'));
                                    String type = "L" + cls + ";";
                                    super.visitFieldInsn(Opcodes.GETSTATIC, cls,
                                                         v.substring(v.indexOf('.') + 1), type);
                                    descriptor.append(type);
                                } else {
                                    super.visitLdcInsn(Double.valueOf(v));
                                    descriptor.append("D");
                                }
                            }
                            super.visitMethodInsn(Opcodes.INVOKESTATIC, B, fn,
                                                  descriptor.append(")V").toString(), false);
                        }
                    }
                };
            }
        }, 0);
        Files.write(Paths.get(a[1]), writer.toByteArray());
    }
}
"""


def runtime_calls(operations: str) -> str:
    """The case's operations as the rewriter's calls: ``s(4, 1, 4)`` is
    ``s(@Scale.ABS,4,@Scale.ABS,1,@Scale.ABS,4)``."""
    calls = []
    for call in re.findall(r"\w+\([^)]*\)", operations):
        name, args = (
            call[: call.index("(")],
            [a.strip() for a in call[call.index("(") + 1 : -1].split(",") if a.strip()],
        )
        if name == "s":
            args = [part for size in args for part in ("@Scale.ABS", size)]
        calls.append(f"{name}({','.join(args)})")
    calls += [f"report:scope${k}" for k in SCOPE]
    return ";".join(calls)


def unit_normal(points: list) -> list:
    """The unit normal of one polygon through ``points`` in order (Newell's sum)."""
    n = [0.0, 0.0, 0.0]
    for (x0, y0, z0), (x1, y1, z1) in zip(points, points[1:] + points[:1], strict=True):
        n[0] += (y0 - y1) * (z0 + z1)
        n[1] += (z0 - z1) * (x0 + x1)
        n[2] += (x0 - x1) * (y0 + y1)
    length = sum(c * c for c in n) ** 0.5
    return [round(c / length, 6) + 0.0 for c in n]


def measure(pyprt, work: Path, source: Path, patcher: Path, operations: str) -> dict:
    case = Path(tempfile.mkdtemp(dir=work))
    package = case / "package"
    shutil.copytree(source, package)
    cgb = package / "bin" / "extrusion_rule.cgb"
    java = ["java", "-cp", f"{ASM_JAR}{os.pathsep}{patcher}", "Patch", str(cgb), str(cgb)]
    subprocess.run([*java, runtime_calls(operations)], check=True)
    rpk = case / "case.rpk"
    # LZMA, not solid, header not compressed: what CityEngine's runtime reads
    subprocess.run(
        ["7z", "a", "-t7z", "-m0=LZMA", "-ms=off", "-mhc=off", str(rpk), ".resolvemap.xml",
         "bin", "rules"],
        cwd=package, check=True, stdout=subprocess.DEVNULL,
    )  # fmt: skip
    generator = pyprt.ModelGenerator([pyprt.InitialShape([c for p in LOT for c in p])])
    options = {"emitReport": True, "emitGeometry": True}
    (model,) = generator.generate_model([{}], str(rpk), "com.esri.pyprt.PyEncoder", options)
    flat = list(model.get_vertices())
    points = [[round(c, 4) + 0.0 for c in flat[i : i + 3]] for i in range(0, len(flat), 3)]
    report = model.get_report()
    scope = [round(report[f"scope${k}_avg"], 4) + 0.0 for k in SCOPE]
    scope[5] = round(scope[5] + LOT[0][2], 4)  # scope.t is relative to the lot's first vertex
    row = {
        "rule": operations,
        "scope_size": scope[:3],
        "scope_origin": scope[3:],
        "lo": [min(p[k] for p in points) for k in range(3)],
        "hi": [max(p[k] for p in points) for k in range(3)],
        "vertices": len(points),
        "faces": len(model.get_faces()),
    }
    if len(points) <= MAX_POINTS:
        row["points"] = points
    if row["faces"] == 1:
        row["normal"] = unit_normal(points)
    return row


@contextmanager
def rewritable_package(corpus: Path, tool: str, package: str = PACKAGE, patcher: str = PATCHER):
    """The corpus's ``package`` (the extrusion_rule one unless named) unpacked and the ASM
    ``patcher`` (this tool's unless given; a Java class ``Patch``) compiled, in a temporary
    folder: ``(pyprt, work, source, patcher)`` for each tool's ``measure``. What is missing
    (java, javac, 7z, the ASM jar, the package) ends the tool with one line, status 2."""
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
        yield pyprt, work, source, patcher


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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("output", type=Path, help="the JSON file to write")
    parser.add_argument("--corpus", type=Path, default=CORPUS, help="the shared CGA corpus")
    args = parser.parse_args(argv)
    with rewritable_package(args.corpus, "prt_primitives") as (pyprt, work, source, patcher):
        rows = [measure(pyprt, work, source, patcher, case) for case in CASES]
    from importlib.metadata import version as installed

    version = installed("pyprt")
    head = {
        "source": f"CityEngine's runtime, PyPRT {version}, by tools/prt_primitives.py: each rule's "
        "operations run on the lot below through PyPRT's PyEncoder; scope_size and scope_origin "
        "are scope.sx, sy, sz and scope.tx, ty, tz reported after the operations (the origin "
        "moved from PyPRT's pivot, the lot's first vertex, to the world), lo and hi the bounds "
        "of the vertices (m, world), points the vertices in PyPRT's order, normal the unit "
        "normal of a one-face result",
        "lot": LOT,
    }
    write_fixture(args.output, head, "cases", rows)
    print(f"prt_primitives: {len(rows)} cases written to {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
