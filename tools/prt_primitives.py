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

import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from prt_measure import (  # noqa: E402
    Rewriter,
    arguments,
    fixture_written,
    generated_model,
    patch_class,
    rewritable_package,
    rounded_points,
)

PACKAGE = "packages/Esri+pyprt__tests_data_extrusion_rule__e4df6667.rpk"
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
# case's calls (args: in, out, "call;call;..."); a call `report:NAME` reports the builtin NAME()D,
# another is a builtin's with its arguments (s() takes Scale.ABS, `@Scale.ABS`, before each size).
PATCHER = patch_class(r"""
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
                        for (String c : calls) {
                            if (c.startsWith("report:")) {
                                report(mv, c.substring(7), c.substring(7));
                            } else {
                                call(mv, c);
                            }
                        }
                    }
                };
            }
        }, 0);
        Files.write(Paths.get(a[1]), writer.toByteArray());
    }
""")


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


def measure(rewriter: Rewriter, operations: str) -> dict:
    flat_lot = {"coordinates": [c for p in LOT for c in p]}
    model = generated_model(rewriter, runtime_calls(operations), flat_lot)
    points = rounded_points(list(model.get_vertices()), 4)
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


def main(argv: list[str] | None = None) -> int:
    args = arguments(__doc__, argv)
    with rewritable_package(args.corpus, "prt_primitives", PACKAGE, PATCHER) as rewriter:
        rows = [measure(rewriter, case) for case in CASES]
    about = (
        "each rule's operations run on the lot below through PyPRT's PyEncoder; scope_size and "
        "scope_origin are scope.sx, sy, sz and scope.tx, ty, tz reported after the operations "
        "(the origin moved from PyPRT's pivot, the lot's first vertex, to the world), lo and hi "
        "the bounds of the vertices (m, world), points the vertices in PyPRT's order, normal the "
        "unit normal of a one-face result"
    )
    return fixture_written("prt_primitives", args.output, about, {"lot": LOT}, "cases", rows)


if __name__ == "__main__":
    sys.exit(main())
