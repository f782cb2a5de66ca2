"""Cases measured with PyPRT (CityEngine's runtime) and kept as fixtures, for the tests that run
them again on ``shapegen.prt``: a case's test id, its rule written as a package's rule file,
and the rings of an encoder's faces."""

from __future__ import annotations


def case_id(case: dict) -> str:
    return f"{case['lot']}:{case['rule']}"


def branch_rule(text: str, figures) -> str:
    """The case's rule (one operation with branches, ``op(...) { sel: | sel= }``) as a .cga
    file: the shape of branch ``k`` reports ``b<k>.<figure>`` for each of ``figures``."""
    body = text[text.index("{") + 1 : text.rindex("}")]
    branches = [part.strip() for part in body.split("|")]
    head = text[: text.index("{")].strip()
    written = [f"{b[:-1].strip()} {b[-1]} B{k}" for k, b in enumerate(branches)]
    lines = [f"Lot --> {head} {{ {' | '.join(written)} }}"]
    for k in range(len(branches)):
        reports = " ".join(f'report("b{k}.{f}", geometry.{f})' for f in figures)
        lines.append(f"B{k} --> {reports}")
    return 'version "2023.0"\n@StartRule\n' + "\n".join(lines) + "\n"


def encoder_rings(vertices, indices, counts) -> list[list[tuple]]:
    """Each face (or hole) of an encoder's flat arrays as its corners in order."""
    points = [tuple(vertices[i : i + 3]) for i in range(0, len(vertices), 3)]
    out, start = [], 0
    for n in counts:
        out.append([points[i] for i in indices[start : start + n]])
        start += n
    return out
