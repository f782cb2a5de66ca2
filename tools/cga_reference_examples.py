"""The code examples of CityEngine's CGA reference, as test data.

A development tool: it reads the reference pages of a checkout of Esri/cityengine-sdk (branch
``gh-pages``, folder ``html/cgaref/``) and writes ``tests/data/cga_reference_examples.json``,
which ``tests/cga/test_reference_examples.py`` reads. shapegen never reads the reference itself.

An example is a ``<pre class="codecga">`` (or ``<pre class="code">``) block of a page: the
reference's own mark for CGA code. The other ``<pre>`` blocks are table cells (a function's
input beside its result, a signature, pseudo-code, a caption); they are counted, not taken.

Each example keeps its page, its index on the page (0-based, in page order), its text as the
page shows it, and a kind:

- ``program``: a rule file as it stands (rules, attrs, consts, functions, annotations, imports);
- ``rule fragment``: a rule body without its head (``primitiveCube() comp(f) {...}``), wrapped
  as the body of one rule, ``Example --> ...``;
- ``expression fragment``: expressions alone (``clamp(1.5, 0, 1)``), each wrapped as an attr,
  ``attr example_1 = ...``, and a rule ``Example --> NIL`` so that a derivation evaluates them.

``program`` is the text to load (the wrapped text for a fragment), ``wrapping`` says the context
added (``""`` for none) and ``derive`` says whether it has a rule to derive. A line that is only
``...`` (the reference eliding code) is left out, and so is a printed result on a line of its
own (``(6)[0, 1, 2, 3, 4, 5]``); ``results`` keeps the results the page states (``# result =
...`` comments and those lines), in order.

    python3 tools/cga_reference_examples.py /path/to/cityengine-sdk            # a work tree
    python3 tools/cga_reference_examples.py /path/to/cityengine-sdk --git gh-pages  # a git dir
"""

from __future__ import annotations

import argparse
import html
import json
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "tests" / "data" / "cga_reference_examples.json"
ENTRIES = ROOT / "tools" / "cga_reference_entries.json"
PAGES = "html/cgaref/cgareference"
EXAMPLE_CLASSES = ("codecga", "code")

_PRE = re.compile(r"<pre([^>]*)>(.*?)</pre>", re.S | re.I)
# Markup inside a code block: only real tags, so that `a <= b` and `x<y` stay code.
_TAG = re.compile(r"</?(?:span|a|b|i|em|strong|br|font|code|u|sub|sup|p|div|tt|img)\b[^>]*>", re.I)
_CLASS = re.compile(r"""class\s*=\s*["']?([\w-]+)""", re.I)
_ELISION = re.compile(r"^\s*(\.\.\.|…)\s*$")
_PRINTED = re.compile(r"^\s*\(\d+\)\[.*\]\s*$")  # CityEngine's print of an array
_RESULT = re.compile(r"^\s*#\s*results?\s*=?\s*(.*)$", re.I)
# A line that only a rule file holds: a rule head, a definition, an annotation, an import.
_PROGRAM_LINE = re.compile(
    r"""^\s*(
        @\w+                                        # an annotation
      | (attr|const|import|version|extension)\b     # a definition or a file statement
      | .*-->                                       # a rule head (start X, X with (...))
      | [A-Za-z_]\w*\s*(\([^()]*\))?\s*=(?!=)       # a function definition
    )""",
    re.X,
)
_CALL_HEAD = re.compile(r"^\s*([A-Za-z_]\w*)\s*(\(|\{|$|\s)")


def page_texts(checkout: Path, git_ref: str | None) -> dict[str, str]:
    """``page name -> HTML`` for the reference pages of ``checkout`` (a work tree, or a git
    directory read at ``git_ref``); the redirect pages of ``generated/`` are left out."""
    pages = {}
    if git_ref is None:
        for path in sorted((checkout / PAGES).rglob("*.html")):
            if "generated" not in path.parts:
                pages[path.relative_to(checkout / PAGES).as_posix()] = path.read_text("utf-8")
        return pages
    names = subprocess.run(
        ["git", "-C", str(checkout), "ls-tree", "-r", "--name-only", git_ref, PAGES],
        check=True, capture_output=True, text=True,
    ).stdout.split()  # fmt: skip
    for name in sorted(names):
        if name.endswith(".html") and "/generated/" not in name:
            text = subprocess.run(
                ["git", "-C", str(checkout), "show", f"{git_ref}:{name}"],
                check=True, capture_output=True, text=True,
            ).stdout  # fmt: skip
            pages[name[len(PAGES) + 1 :]] = text
    return pages


def code_blocks(page: str) -> list[tuple[str, str]]:
    """``(class, text)`` of every ``<pre>`` block of ``page``, markup removed."""
    blocks = []
    for match in _PRE.finditer(page):
        found = _CLASS.search(match.group(1))
        text = html.unescape(_TAG.sub("", match.group(2)))
        blocks.append((found.group(1) if found else "", text.strip("\n").rstrip()))
    return blocks


def operation_names() -> set[str]:
    entries = json.loads(ENTRIES.read_text("utf-8"))
    names = {entry["name"] for entry in entries["operations"]}
    # the operations written without parentheses or with a body of their own
    return names | {"NIL", "primitiveCube", "primitiveQuad", "primitiveSphere", "case", "["}


def classify(text: str, operations: set[str]) -> dict:
    """The kind of an example's ``text`` and the least context that makes it a program."""
    kept, results = [], []
    for line in text.splitlines():
        result = _RESULT.match(line)
        if result:
            results.append(result.group(1).strip())
            continue
        if _PRINTED.match(line):
            results.append(line.strip())
            continue
        if _ELISION.match(line):
            continue
        kept.append(line)
    body = "\n".join(kept).strip("\n")
    lines = [line for line in body.splitlines() if line.strip() and not _comment(line)]
    example = {"results": results}
    if any(_PROGRAM_LINE.match(line) for line in lines):
        return {**example, "kind": "program", "wrapping": "", "program": body + "\n",
                "derive": any("-->" in line for line in lines)}  # fmt: skip
    head = _CALL_HEAD.match(lines[0]) if lines else None
    first = lines[0].lstrip()[:1] if lines else ""
    if head and head.group(1) in operations or first == "[":
        indented = "\n".join("    " + line for line in body.splitlines())
        return {**example, "kind": "rule fragment", "wrapping": "Example --> ...",
                "program": f"Example -->\n{indented}\n", "derive": True}  # fmt: skip
    expressions = _expressions(body)
    program = "".join(
        f"attr example_{k} =\n" + "\n".join("    " + line for line in e.splitlines()) + "\n"
        for k, e in enumerate(expressions, 1)
    )
    wrapping = "attr example_N = ... (one each), Example --> NIL"
    return {**example, "kind": "expression fragment", "wrapping": wrapping,
            "program": program + "\nExample --> NIL\n", "derive": True}  # fmt: skip


def _comment(line: str) -> bool:
    stripped = line.strip()
    return stripped.startswith(("//", "#", "/*", "*"))


def _expressions(body: str) -> list[str]:
    """The expressions of an expression fragment: one per group of lines between blank ones."""
    groups, current = [], []
    for line in body.splitlines():
        if not line.strip() or _comment(line):
            if current:
                groups.append("\n".join(current))
                current = []
            continue
        current.append(line)
    if current:
        groups.append("\n".join(current))
    return groups


def examples(pages: dict[str, str]) -> tuple[list[dict], dict[str, int]]:
    """Every example of ``pages`` classified, and the count of other ``<pre>`` cells by class."""
    operations = operation_names()
    found, others = [], {}
    for name, page in pages.items():
        index = 0
        for css, text in code_blocks(page):
            if css not in EXAMPLE_CLASSES:
                others[css or "plain"] = others.get(css or "plain", 0) + 1
                continue
            if not text.strip():
                continue
            entry = {"page": name, "index": index, "text": text}
            entry.update(classify(text, operations))
            found.append(entry)
            index += 1
    return found, others


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("checkout", type=Path, help="a checkout of Esri/cityengine-sdk")
    parser.add_argument("--git", metavar="REF", help="read the pages from this git ref")
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    pages = page_texts(args.checkout, args.git)
    if not pages:
        print(f"no reference pages under {args.checkout / PAGES}", file=sys.stderr)
        return 2
    found, others = examples(pages)
    kinds: dict[str, int] = {}
    for entry in found:
        kinds[entry["kind"]] = kinds.get(entry["kind"], 0) + 1
    data = {
        "about": "The code examples of CityEngine's CGA reference (Esri/cityengine-sdk, "
        "gh-pages, html/cgaref/), made by tools/cga_reference_examples.py",
        "pages": len(pages),
        "kinds": kinds,
        "table_cells_not_taken": others,
        "examples": found,
    }
    args.out.write_text(json.dumps(data, indent=1, ensure_ascii=False) + "\n", "utf-8")
    print(f"{len(found)} examples of {len(pages)} pages -> {args.out}: {kinds}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
