"""Compare shapegen with CityEngine's runtime on the CGA corpus.

For every corpus rule file (``tests/data/cga-corpus``, each in its package's folder so that
imports resolve), load it, derive it on the 12 x 8 m lot (default attrs, seed 0) and compare
with the reference that PyPRT made of the package (``tools/cga_reference/*.json``, written by
``tools/cga_reference.py``): does it load, does it derive, and for a package's main rule the
leaf count, volume, bounding box and ``report()`` sums. The volume is the reference's: the
divergence theorem over every face of every leaf (blocks and surfaces alike), in world
coordinates, so that open leaves count as CityEngine's merged mesh counts them. Prints a
table; ``--markdown FILE`` writes it as markdown (the table of ``docs/cga-compatibility.md``).
Exits non-zero only when shapegen crashes (an exception that is not a ShapegenError)::

    .venv/bin/python tools/cga_compare.py
    .venv/bin/python tools/cga_compare.py --markdown /tmp/table.md

Orientation: the references' lot is read from each JSON's ``lot``. When its first edge runs
along +x (``(0,0,8) (12,0,8) (12,0,0) (0,0,0)``, shapegen's convention) the bounding boxes are
compared axis by axis; otherwise (older references: first edge along +z, so CityEngine's scope x
runs along world z) only orientation-free figures are compared: the box's extents sorted, the
volume, the counts.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
CORPUS = ROOT / "tests" / "data" / "cga-corpus"
REFERENCES = ROOT / "tools" / "cga_reference"
LOT = (12.0, 8.0)

VOLUME_TOLERANCE = 0.01
"""Relative tolerance of the volume (1 %)."""
BOX_TOLERANCE = 0.01
"""Absolute tolerance of the bounding box, m."""

_RANDOM_HEIGHT = frozenset({"volume", "bbox", "report Building Height.0"})
RANDOM = {
    "extrusion_rule": _RANDOM_HEIGHT,
    "simple_rule2019": _RANDOM_HEIGHT,
    # Eave_Ht + rand(3, 6); the roof form is 40% hip, 50% gable, else gambrel (PyPRT: gambrel)
    "Building_From_FootprintSMALL": frozenset({"bbox", "volume", "leaves"}),
    # vertical greenery: split(y) { ~rand(1.5, 3) : Tile_y }*, 12.5% of the tiles NIL, each image
    # s(.., scope.sy * rand(1.4, 1.6), ..); seeds 0-11 here give 437-445 leaves, 161-262 m3 and
    # a top at 12.66-12.86 m, around PyPRT's 442, 226.5 and 12.81
    "envelope2002": frozenset(
        {"leaves", "volume", "bbox", "report Greenery Area", "report green area"}
    ),
}
"""Figures driven by rand() (``extrude(rand(min, max))``), by rule family: shapegen's draws are
not CityEngine's, so these are flagged ("random"), never failed."""

_MAIN_RULE = {"dynamic_imports": "ruleA.cga"}
"""A package's main rule where it is not its only file nor named as the package."""


@dataclass
class Row:
    """One corpus file's outcome."""

    name: str  # the corpus list's name: <rule>_<SHA-1 prefix>.cga
    path: Path
    package: str
    main: bool  # the package's start rule (the reference describes its model)
    loads: bool = False
    derives: bool = False
    error: str = ""
    crash: bool = False
    leaves: int = 0
    volume: float = 0.0  # the divergence theorem over every leaf's faces (as the reference)
    low: list = field(default_factory=list)
    high: list = field(default_factory=list)
    reports: dict = field(default_factory=dict)
    checks: dict = field(default_factory=dict)  # figure -> (ok, shapegen, reference)


def corpus_files(root: Path = CORPUS) -> list[tuple[str, Path]]:
    """``(corpus name, path)`` of each distinct corpus file: the first copy in PROVENANCE.md."""
    table = (root / "PROVENANCE.md").read_text(encoding="utf-8")
    seen: dict[str, Path] = {}
    for path, name in re.findall(r"^\| `([^`]+)` \| `([^`]+)` \|", table, re.MULTILINE):
        seen.setdefault(name, root / path)
    return sorted(seen.items())


def package_of(path: Path, root: Path = CORPUS) -> str:
    return path.relative_to(root).parts[0]


def is_main_rule(path: Path, root: Path = CORPUS) -> bool:
    """The file PyPRT runs for the package: its only rule file, or the one named after it."""
    package = package_of(path, root)
    rules = sorted((root / package / "rules").rglob("*.cga"))
    if len(rules) == 1:
        return rules[0] == path
    for key, name in _MAIN_RULE.items():
        if key in package:
            return path.name == name
    return package.split("__")[0].endswith(path.stem)


def reference(package: str) -> dict | None:
    file = REFERENCES / f"{package}.json"
    return json.loads(file.read_text(encoding="utf-8")) if file.exists() else None


def derive(name: str, path: Path) -> Row:
    """Load and derive one corpus file; record its figures."""
    from shapegen import load_grammar
    from shapegen.errors import ShapegenError

    row = Row(name, path, package_of(path), is_main_rule(path))
    try:
        grammar = load_grammar(path)
        row.loads = True
        model = grammar.build(lot=LOT)
        row.derives = True
    except ShapegenError as exc:
        row.error = str(exc)
        return row
    except Exception as exc:  # noqa: BLE001 - a crash is what this tool reports
        row.error = f"crash: {type(exc).__name__}: {exc}"
        row.crash = True
        return row
    points = [b.vertices for b in model.blocks] + [s.vertices for s in model.surfaces]
    row.leaves = int(model.metadata["leaves"])  # leaf shapes, before any convex decomposition
    row.volume = sum(
        enclosed_volume(leaf.vertices, leaf.faces) for leaf in [*model.blocks, *model.surfaces]
    )
    if points:
        stacked = np.vstack(points)
        row.low, row.high = stacked.min(axis=0).tolist(), stacked.max(axis=0).tolist()
    for key, value in model.metadata.get("reports", {}).items():
        values = value if isinstance(value, list) else [value]
        numbers = [float(v) for v in values if isinstance(v, (int, float))]
        if numbers:  # PyPRT sums the numeric reports (name_sum)
            row.reports[key] = float(sum(numbers))
        elif values and isinstance(values[-1], str):
            row.reports[key] = values[-1]
    return row


def enclosed_volume(vertices: np.ndarray, faces) -> float:
    """Sum over the faces' fan triangles of ``p0 . (pk x pk+1) / 6`` (the formula of
    ``tools/cga_reference.py``): a closed leaf's volume, an open leaf's share of it."""
    vertices = np.asarray(vertices, dtype=float)
    total = 0.0
    for face in faces:
        p = vertices[list(face)]
        total += float(np.einsum("j,kj->", p[0], np.cross(p[1:-1], p[2:]))) / 6.0
    return total


def compare(row: Row, ref: dict | None) -> None:
    """Fill ``row.checks`` with the figures that can be compared with the reference."""
    if not (row.derives and row.main and ref and ref.get("generated")):
        return
    checks = row.checks
    random = RANDOM.get(row.name.rsplit("_", 1)[0], frozenset())
    if "leaves" in ref:
        checks["leaves"] = (row.leaves == ref["leaves"], row.leaves, ref["leaves"])
    if ref.get("volume") is not None:
        expected = float(ref["volume"])
        ok = math.isclose(row.volume, expected, rel_tol=VOLUME_TOLERANCE, abs_tol=1e-6)
        checks["volume"] = (ok, round(row.volume, 3), round(expected, 3))
    if row.low and "bbox_min" in ref:
        low, high = np.asarray(ref["bbox_min"]), np.asarray(ref["bbox_max"])
        ours = np.asarray(row.high) - np.asarray(row.low)
        theirs = high - low
        if first_edge_along_x(ref["lot"]):
            ok = np.allclose(row.low, low, atol=BOX_TOLERANCE) and np.allclose(
                row.high, high, atol=BOX_TOLERANCE
            )
        else:
            ours, theirs = np.sort(ours), np.sort(theirs)
            ok = np.allclose(ours, theirs, atol=BOX_TOLERANCE)
        checks["bbox"] = (bool(ok), np.round(ours, 3).tolist(), np.round(theirs, 3).tolist())
    for key, expected in ref.get("reports", {}).items():
        name = key.removesuffix("_sum")
        value = row.reports.get(name)
        if isinstance(expected, str) or isinstance(value, str):
            ok = value == expected
        else:
            ok = isinstance(value, float) and math.isclose(
                value, expected, rel_tol=1e-6, abs_tol=1e-9
            )
        checks[f"report {name}"] = (ok, value, expected)
    for key in random & set(checks):
        checks[key] = (None, *checks[key][1:])


def first_edge_along_x(lot: list) -> bool:
    points = np.asarray(lot, float).reshape(-1, 3)
    edge = points[1] - points[0]
    return abs(edge[0]) > abs(edge[2])


def run(root: Path = CORPUS) -> list[Row]:
    rows = []
    for name, path in corpus_files(root):
        row = derive(name, path)
        compare(row, reference(row.package))
        rows.append(row)
    return rows


def _outcome(row: Row) -> str:
    if row.derives:
        return "derives"
    return "CRASH" if row.crash else ("loads" if row.loads else "no")


def _checks(row: Row) -> str:
    if not row.derives:
        return row.error.splitlines()[0] if row.error else ""
    if not row.main:
        return "(imported by the package's main rule; no reference of its own)"
    parts = []
    for key, (ok, ours, theirs) in row.checks.items():
        mark = "random" if ok is None else ("ok" if ok else "DIFFERS")
        parts.append(f"{key} {mark}" + ("" if ok else f" ({ours} vs {theirs})"))
    return "; ".join(parts) or "no reference figures"


def table(rows: list[Row], markdown: bool) -> str:
    derived = sum(r.derives for r in rows)
    lines = []
    if markdown:
        lines += [
            "| file | package | outcome | leaves | comparison with PyPRT |",
            "|---|---|---|---|---|",
        ]
        for r in rows:
            check = _checks(r).replace("|", "\\|")
            lines.append(
                f"| `{r.name}` | {r.package} | {_outcome(r)} | {r.leaves if r.derives else ''} "
                f"| {check} |"
            )
    else:
        for r in rows:
            lines.append(f"{r.name:42s} {_outcome(r):8s} {r.leaves:6d}  {_checks(r)}")
    lines.append("")
    lines.append(
        f"{derived} of {len(rows)} corpus files load and derive ({derived / len(rows):.0%})."
    )
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--markdown", type=Path, help="also write the table as markdown here")
    args = parser.parse_args(argv)
    rows = run()
    print(table(rows, markdown=False), end="")
    if args.markdown:
        tmp = args.markdown.with_name(args.markdown.name + ".tmp")
        tmp.write_text(table(rows, markdown=True), encoding="utf-8")
        tmp.replace(args.markdown)
    return 1 if any(r.crash for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
