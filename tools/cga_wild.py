"""Run shapegen over a corpus of CityEngine rule files found in public repositories.

The corpus (``tests/data/cga-wild/manifest.json`` lists it; the files themselves live outside
the repository, see ``tests/data/cga-wild/README.md``) holds ``.cga`` files as their
repositories have them: each in its project's folder layout, with the assets beside it, so that
``import`` lines and asset paths resolve as in CityEngine. For every distinct file of the
manifest (an entry with ``duplicate_of`` is skipped: its content is run under the first path
that has it), the tool loads the file and derives it on a 12 x 8 m lot (default attrs, seed 0),
in a subprocess of its own started in the file's folder, with a time limit (60 s) and a memory
limit (4 GiB), and records the outcome:

``derives``
    The model was built; its number of blocks, of leaves (``metadata["leaves"]``) and of
    warnings (``metadata["warnings"]``: assets not found, operations ignored...) are kept.
``error``
    A :class:`~shapegen.errors.ShapegenError`: its first line (the first problem, with file,
    line and column) is kept, and for a grammar error every problem it lists.
``crash``
    Any other exception, or a subprocess that died: the exception type, its message and the
    last line of the traceback (the place that raised; with the last place in shapegen when
    that is in a library). An exception that the parser library wrapped is reported as the one
    it wraps. When shapegen itself fails to import (a module half-saved in a tree being edited),
    the file is run once more before its crash is recorded.
``timeout``
    No outcome within the time limit.

The start rule. ``Grammar.build`` takes no rule name: the start is the grammar's ``start_rule``,
the ``@StartRule`` rule, else the first rule without parameters. A CityEngine file without
``@StartRule`` starts wherever the shape's start rule names (``Lot`` for a lot drawn in a scene),
so for such a file the tool picks the first rule of the file, in source order, that has no
parameters and that no other rule of the file names (its text read with comments and strings
left out): the root of the file's rule tree, which is where a user would start it. That rule is
made the start by setting the compiled program's ``start`` before building. When every
parameterless rule is named by another one, shapegen's own choice stands. ``start_choice`` in
the outcomes says which case applied (``annotation``, ``unreferenced``, ``default``).

The summary printed: per repository the files run, how many derive and the rate; the totals;
the derive rate of the rule files alone (``kind`` other than ``library``), of those outside
generated families, and of those at their repository's head (earlier revisions left out); and
the failures ranked by kind. A kind is a message with its variable parts taken out (file names,
line and column, quoted names, numbers) so that the same failure in different files counts
together; each is shown with the number of files whose first problem it is, the number of files
that have it among their problems, the quoted names it was met with, one example file and that
file's exact message. The outcomes are written to ``tests/data/cga-wild/outcomes.json`` (with
``--only`` the entries of the files run are replaced and the others kept); ``--report`` prints
the summary of that file again without deriving anything::

    .venv/bin/python tools/cga_wild.py
    .venv/bin/python tools/cga_wild.py --only Roman-City --jobs 1
    .venv/bin/python tools/cga_wild.py --corpus /data/cga-wild --markdown /tmp/wild.md

The corpus folder is ``--corpus DIR``, else ``$SHAPEGEN_CGA_WILD``, else ``/work/cga-wild``.

The holdout. ``tests/data/cga-wild/holdout.json`` names the repositories kept out of sight
(``holdout``: drawn from the corpus; ``new``: collected after the draw); the others are
``seen``. The summary gives the measure for each part apart, and for the ``unseen`` files: those
of the hidden parts whose content no seen repository holds and the project's own tests and rules
do not hold either. The hidden parts show their totals only (no repository row, no failure)
unless ``--reveal`` is given; ``--part seen|holdout|new|hidden`` runs or reports one part.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import re
import subprocess
import sys
import time
import traceback
from collections import Counter, defaultdict
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "cga-wild"
MANIFEST = DATA / "manifest.json"
OUTCOMES = DATA / "outcomes.json"
HOLDOUT = DATA / "holdout.json"
DEFAULT_CORPUS = Path("/work/cga-wild")
LOT = (12.0, 8.0)
TIMEOUT = 60.0
MEMORY_LIMIT = 4 << 30  # bytes of address space for one derivation
TOP = 40

OUTCOME_ORDER = ("derives", "error", "crash", "timeout")
_IMPORT_FAILURES = ("ImportError", "ModuleNotFoundError", "SyntaxError", "IndentationError")


# ---------------------------------------------------------------------------------- start rule
_COMMENT_OR_STRING = re.compile(
    r'/\*.*?\*/|//[^\n]*|#[^\n]*|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S
)
# A rule head at the start of a line: optional annotations, the name, optional parameters.
_RULE_HEAD = re.compile(
    r"^[ \t]*(?:@\w+(?:\([^)\n]*\))?[ \t]*)*(?:extension[ \t]+)?"
    r"(?P<name>[A-Za-z_][\w.]*)[ \t]*(?P<params>\([^)\n]*\))?[ \t]*-->",
    re.M,
)
_IDENTIFIER = re.compile(r"[A-Za-z_][\w.]*")


def _blank(match: re.Match) -> str:
    """The match with every character but newlines replaced by a space (keeps offsets)."""
    return re.sub(r"[^\n]", " ", match.group(0))


def rule_tree_root(text: str) -> str | None:
    """The first parameterless rule of ``text`` that no other rule of the text names, or None.

    Comments and string literals are blanked first, so that a rule named in a comment or in an
    asset path does not count as named.
    """
    code = _COMMENT_OR_STRING.sub(_blank, text)
    heads = list(_RULE_HEAD.finditer(code))
    bodies = []
    for k, head in enumerate(heads):
        end = heads[k + 1].start() if k + 1 < len(heads) else len(code)
        bodies.append(set(_IDENTIFIER.findall(code[head.end() : end])))
    for k, head in enumerate(heads):
        params = head.group("params")
        if params and params.strip("() \t"):
            continue
        name = head.group("name")
        if not any(name in body for j, body in enumerate(bodies) if j != k):
            return name
    return None


def choose_start(grammar, text: str) -> tuple[str | None, str]:
    """Make the start rule of a loaded grammar the one described in the module docstring;
    return ``(rule name, choice)``."""
    tree = grammar.ast
    if any(rule.start for rule in tree.rules):
        return tree.start_rule.name, "annotation"
    program = getattr(grammar, "program", None)
    name = rule_tree_root(text)
    if name is not None and program is not None and hasattr(program, "start"):
        for rule in tree.rules:
            if rule.name == name and not rule.params:
                program.start = rule
                return name, "unreferenced"
    start = getattr(program, "start", None) or tree.start_rule
    return (start.name if start is not None else None), "default"


# ---------------------------------------------------------------------------------- one file
def _one_line(text: str) -> str:
    lines = str(text).strip().splitlines()
    return lines[0] if lines else ""


def _in_shapegen(filename: str) -> bool:
    return f"{os.sep}shapegen{os.sep}" in filename and "site-packages" not in filename


def _frame(frame: traceback.FrameSummary) -> str:
    """``file:line in function``, the file shown from ``shapegen/`` when it is shapegen's."""
    shown = frame.filename
    if _in_shapegen(shown):
        shown = "shapegen" + os.sep + shown.split(f"{os.sep}shapegen{os.sep}", 1)[1]
    elif "site-packages" in shown:
        shown = shown.split("site-packages" + os.sep, 1)[1]
    return f"{shown}:{frame.lineno} in {frame.name}"


def derive_file(path: Path) -> dict:
    """Load and derive one rule file in this process; the outcome as a dict."""
    from shapegen import load_grammar
    from shapegen.errors import ShapegenError

    result: dict = {"start_rule": None, "start_choice": None}
    started = time.perf_counter()
    try:
        grammar = load_grammar(path)
        text = path.read_text(encoding="utf-8", errors="replace")
        result["start_rule"], result["start_choice"] = choose_start(grammar, text)
        model = grammar.build(lot=LOT)
        metadata = model.metadata or {}
        result.update(
            outcome="derives",
            blocks=len(model.blocks),
            surfaces=len(getattr(model, "surfaces", ()) or ()),
            leaves=metadata.get("leaves"),
            warnings=len(metadata.get("warnings", ())),
        )
    except ShapegenError as exc:
        problems = getattr(exc, "problems", None) or [(None, str(exc))]
        messages = []
        for location, message in problems[:50]:
            line = _one_line(message)
            messages.append(f"{location}: {line}" if location is not None else line)
        result.update(outcome="error", error_type=type(exc).__name__, message=messages[0])
        result["problems"] = messages
    except Exception as exc:  # noqa: BLE001 - every other exception is what the tool looks for
        # a parser library wraps what a transformer raised: report the original exception
        cause = getattr(exc, "orig_exc", None)
        raised = cause if isinstance(cause, BaseException) else exc
        frames = traceback.extract_tb(raised.__traceback__) or traceback.extract_tb(
            exc.__traceback__
        )
        result.update(
            outcome="crash",
            error_type=type(raised).__name__,
            message=f"{type(raised).__name__}: {_one_line(str(raised))}",
            where=_frame(frames[-1]) if frames else "",
        )
        own = [frame for frame in frames if _in_shapegen(frame.filename)]
        if own and own[-1] is not frames[-1]:
            result["where_in_shapegen"] = _frame(own[-1])
    result["seconds"] = round(time.perf_counter() - started, 3)
    return result


def _limit_memory() -> None:
    try:
        import resource

        resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
    except (ImportError, ValueError, OSError):
        pass


def _worker(path: str) -> int:
    """``--worker PATH``: derive one file, print its outcome as JSON on stdout.

    Whatever the derivation prints (CGA ``print()``) goes to stderr, so that stdout carries the
    outcome only.
    """
    _limit_memory()
    out = sys.stdout
    sys.stdout = sys.stderr
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10_000))
    result = derive_file(Path(path).resolve())
    out.write(json.dumps(result) + "\n")
    out.flush()
    return 0


def run_in_subprocess(path: Path, timeout: float) -> dict:
    """Derive ``path`` in a fresh interpreter started in the file's folder."""
    command = [sys.executable, str(Path(__file__).resolve()), "--worker", str(path)]
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    started = time.perf_counter()
    try:
        done = subprocess.run(
            command,
            cwd=path.parent,
            env=env,
            capture_output=True,
            text=True,
            timeout=timeout,
        )
    except subprocess.TimeoutExpired:
        return {"outcome": "timeout", "message": f"no outcome within {timeout:g} s"}
    lines = [line for line in done.stdout.splitlines() if line.startswith("{")]
    if done.returncode == 0 and lines:
        return json.loads(lines[-1])
    tail = [line for line in done.stderr.strip().splitlines() if line.strip()]
    last = tail[-1].strip() if tail else ""
    code = done.returncode
    reason = f"signal {-code}" if code < 0 else f"exit status {code}"
    if "MemoryError" in last:
        kind = "MemoryError"
    else:
        kind = "ProcessDied"
    return {
        "outcome": "crash",
        "error_type": kind,
        "message": f"{kind}: the subprocess ended with {reason}" + (f" ({last})" if last else ""),
        "where": "",
        "seconds": round(time.perf_counter() - started, 3),
    }


# ------------------------------------------------------------------------------------ kinds
_EXTENSIONS = (
    r"cga|rpk|cgb|obj|mtl|fbx|dae|glb|gltf|jpe?g|png|tiff?|bmp|tga|gif|csv|txt|json|xml|3ds|dds|"
    r"exr|hdr|svg|py"
)
# "file.cga:12:26: " or "file.cga: " at the start (a file name may hold spaces).
_LOCATION = re.compile(r"^.*?\.(?:cga|rpk)(?::\d+:\d+)?:\s+", re.I)
_FILE_NAME = re.compile(rf"(?:[\w.~$%+@-]*[/\\])*[\w.~$%+@-]*\.(?:{_EXTENSIONS})\b", re.I)
_FILE_LIST = re.compile(r"<file>(?:, <file>)+")
_QUOTED = re.compile(r"'''|(?<![\w)])'[^'\n]*'|\"[^\"\n]*\"|`[^`\n]*`")
_TRIED = re.compile(r"\(tried [^;)]*")
_NUMBER = re.compile(r"(?<![\w.])[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?(?![\w])", re.I)


def failure_kind(message: str, folders: tuple[str, ...] = ()) -> str:
    """The message with its variable parts taken out: the same failure, whatever the file.

    ``folders`` are folders whose paths are replaced whole (a path there may hold spaces): the
    corpus folder, the project's own.
    """
    text = _one_line(message)
    text = _LOCATION.sub("", text)
    for folder in folders:
        within = rf"{re.escape(folder.rstrip('/'))}/[^,;()'\"\n]*?\.(?:{_EXTENSIONS})\b"
        text = re.sub(within, "<file>", text, flags=re.I)
    text = _TRIED.sub("(tried …", text)
    text = _QUOTED.sub("'…'", text)
    text = _FILE_NAME.sub("<file>", text)
    text = _FILE_LIST.sub("<file>, …", text)
    text = _NUMBER.sub("N", text)
    return re.sub(r"\s+", " ", text).strip()


def quoted_name(message: str) -> str | None:
    """The first quoted name of a message (after its location), or None."""
    found = _QUOTED.search(_LOCATION.sub("", _one_line(message)))
    return found.group(0) if found else None


# ------------------------------------------------------------------------------------ corpus
def corpus_folder(option: str | None) -> Path:
    if option:
        return Path(option)
    return Path(os.environ.get("SHAPEGEN_CGA_WILD") or DEFAULT_CORPUS)


def load_manifest(path: Path) -> list[dict]:
    data = json.loads(path.read_text(encoding="utf-8"))
    return data["files"] if isinstance(data, dict) else data


PARTS = ("seen", "holdout", "new")


def load_holdout(path: Path) -> dict[str, str]:
    """``{repository: part}`` for the repositories kept out of sight (``holdout``: drawn from
    the corpus; ``new``: collected after the draw); every other repository is ``seen``."""
    if not path.is_file():
        return {}
    data = json.loads(path.read_text(encoding="utf-8"))
    parts = {name: "holdout" for name in data.get("repositories", ())}
    parts.update({name: "new" for name in data.get("new_repositories", ())})
    return parts


def project_contents(root: Path = ROOT) -> set[str]:
    """SHA-1s of the rule files the project itself holds (its tests' data, its rules): a
    file of the hidden parts with one of these contents has been seen all the same."""
    contents = set()
    for folder in (root / "tests", root / "rules"):
        for path in folder.rglob("*.cga") if folder.is_dir() else ():
            contents.add(hashlib.sha1(path.read_bytes()).hexdigest())
    return contents


def mark_parts(
    entries: list[dict], holdout: dict[str, str], known: frozenset[str] | set[str] = frozenset()
) -> list[dict]:
    """Each entry with its ``part`` and, for the parts kept out of sight, ``unseen``: whether
    its content is in no file of a seen repository and not among ``known`` contents (the
    project's own copies, :func:`project_contents`): a file copied from a seen one is not a
    file the parser's authors have not seen."""
    seen_content = {
        e["sha1"] for e in entries if holdout.get(e["repository"], "seen") == "seen" and "sha1" in e
    }
    seen_content |= set(known)
    marked = []
    for entry in entries:
        part = holdout.get(entry["repository"], "seen")
        extra = {"part": part}
        if part != "seen":
            extra["unseen"] = entry.get("sha1") not in seen_content
        marked.append({**entry, **extra})
    return marked


def runnable(entries: list[dict], only: str | None, part: str = "all") -> list[dict]:
    chosen = [e for e in entries if not e.get("duplicate_of")]
    if only:
        chosen = [e for e in chosen if only in e["local"] or only in e["repository"]]
    if part == "hidden":
        chosen = [e for e in chosen if e.get("part", "seen") != "seen"]
    elif part != "all":
        chosen = [e for e in chosen if e.get("part", "seen") == part]
    return chosen


def run_corpus(entries: list[dict], corpus: Path, jobs: int, timeout: float) -> list[dict]:
    """Outcomes of ``entries`` (manifest entries), in manifest order."""

    def one(entry: dict) -> dict:
        path = corpus / entry["local"]
        record = {
            "local": entry["local"],
            "repository": entry["repository"],
            "path": entry["path"],
            "kind": entry.get("kind", "rule"),
            "revision": entry.get("revision", "head"),
            "part": entry.get("part", "seen"),
        }
        if "unseen" in entry:
            record["unseen"] = entry["unseen"]
        if not path.is_file():
            record.update(outcome="missing", message=f"not in the corpus folder: {path}")
            return record
        outcome = run_in_subprocess(path, timeout)
        if outcome.get("error_type") in _IMPORT_FAILURES and "shapegen" in outcome.get("where", ""):
            # shapegen itself did not import (a half-saved module of a tree being edited):
            # once more, a moment later, before calling it the file's crash
            time.sleep(5)
            outcome = run_in_subprocess(path, timeout)
        record.update(outcome)
        return record

    results: list[dict] = [{} for _ in entries]
    done = 0
    started = time.perf_counter()
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        futures = {pool.submit(one, entry): k for k, entry in enumerate(entries)}
        for future in futures:
            k = futures[future]
            results[k] = future.result()
            done += 1
            if done % 25 == 0 or done == len(entries):
                elapsed = time.perf_counter() - started
                print(f"  {done}/{len(entries)} files, {elapsed:.0f} s", file=sys.stderr)
    for record in results:
        if record.get("message") and record["outcome"] != "derives":
            record["failure_kind"] = failure_kind(record["message"], (str(corpus), str(ROOT)))
    return results


# ----------------------------------------------------------------------------------- summary
def _rate(part: int, whole: int) -> str:
    return f"{100.0 * part / whole:.1f} %" if whole else "-"


def repository_rows(results: list[dict]) -> list[tuple]:
    by_repo: dict[str, Counter] = defaultdict(Counter)
    for record in results:
        by_repo[record["repository"]][record["outcome"]] += 1
    rows = []
    for repo in sorted(by_repo, key=str.lower):
        counts = by_repo[repo]
        files = sum(counts.values())
        rows.append(
            (
                repo,
                files,
                counts["derives"],
                counts["error"],
                counts["crash"],
                counts["timeout"] + counts["missing"],
                _rate(counts["derives"], files),
            )
        )
    return rows


def _counted(results: list[dict]) -> list[dict]:
    """The measure's files: rule files, without libraries and files whose imports their own
    project lacks."""
    rules = [r for r in results if r.get("kind") != "library"]
    return [r for r in rules if not lacks_imports(r) and not is_library(r)]


def _line(label: str, chosen: list[dict]) -> str:
    derives = sum(r["outcome"] == "derives" for r in chosen)
    return f"{label}: {derives} / {len(chosen)} derive ({_rate(derives, len(chosen))})"


def rate_lines(results: list[dict]) -> list[str]:
    rules = [r for r in results if r.get("kind") != "library"]
    plain = [r for r in rules if r.get("kind") != "generated"]
    heads = [r for r in plain if r.get("revision", "head") == "head"]
    counted = _counted(results)
    counted_plain = [r for r in counted if r.get("kind") != "generated"]
    outcomes = Counter(r["outcome"] for r in results)
    return [
        _line("all distinct files", results),
        _line("rule files (library files left out)", rules),
        _line("rule files outside generated families", plain),
        _line("the same, at the repositories' HEAD only (earlier revisions left out)", heads),
        _line(
            "the measure: rule files, without libraries and files whose imports their own "
            "project lacks",
            counted,
        ),
        _line("the measure outside generated families", counted_plain),
        "outcomes: " + ", ".join(f"{k} {outcomes[k]}" for k in (*OUTCOME_ORDER, "missing")),
    ]


def part_lines(results: list[dict]) -> list[str]:
    """The measure for each part apart (``seen``, ``holdout``, ``new``), and for the files of
    the hidden parts whose content no seen repository holds: totals only, no failure."""
    lines = []
    for part in PARTS:
        chosen = [r for r in results if r.get("part", "seen") == part]
        if not chosen:
            continue
        counted = _counted(chosen)
        lines.append(_line(f"{part}: the measure", counted))
        plain = [r for r in counted if r.get("kind") != "generated"]
        lines.append(_line(f"{part}: the measure outside generated families", plain))
    hidden = [r for r in results if r.get("part", "seen") != "seen" and r.get("unseen")]
    if hidden:
        counted = _counted(hidden)
        lines.append(
            _line("unseen files (holdout and new, content in no seen repository)", counted)
        )
        plain = [r for r in counted if r.get("kind") != "generated"]
        lines.append(_line("unseen files outside generated families", plain))
    return lines


def lacks_imports(record: dict) -> bool:
    """True for a file that stopped because a file it imports is not in its own project (and
    not on the rules path): CityEngine's ESRI.lib, a folder the repository never had."""
    return (
        record["outcome"] == "error"
        and _IMPORT_MISSING.search(record.get("message", "")) is not None
    )


def is_library(record: dict) -> bool:
    """True for a file shapegen found to define no rule a lot can start (only attrs and
    functions, or only rules that take parameters): it is meant to be imported."""
    message = record.get("message", "") if record["outcome"] == "error" else ""
    return _LIBRARY.search(message) is not None


_IMPORT_MISSING = re.compile(r'import of "[^"]*": no such file')
_LIBRARY = re.compile(r"the grammar has no rules|the start rule '[^']*' cannot take parameters")


def failure_ranking(results: list[dict], corpus: Path) -> list[dict]:
    first: dict[str, list[dict]] = defaultdict(list)
    anywhere: Counter = Counter()
    for record in results:
        if record["outcome"] == "derives":
            continue
        kind = f"{record['outcome']}: {record.get('failure_kind', '')}"
        if record["outcome"] == "crash" and record.get("where"):
            kind += f" [{record.get('where_in_shapegen') or record['where']}]"
        first[kind].append(record)
        kinds = {kind}
        for problem in record.get("problems", ())[1:]:
            kinds.add(f"error: {failure_kind(problem, (str(corpus), str(ROOT)))}")
        anywhere.update(kinds)
    ranking = []
    for kind, records in first.items():
        example = records[0]
        names = Counter(quoted_name(r.get("message", "")) for r in records)
        names.pop(None, None)
        ranking.append(
            {
                "kind": kind,
                "files": len(records),
                "files_with_it": anywhere[kind],
                "names": ", ".join(f"{name} {count}" for name, count in names.most_common(8)),
                "distinct_names": len(names),
                "example": str(corpus / example["local"]),
                "message": example.get("message", ""),
            }
        )
    ranking.sort(key=lambda item: (-item["files"], -item["files_with_it"], item["kind"]))
    return ranking


def print_summary(results: list[dict], corpus: Path, top: int, reveal: bool = True) -> None:
    """The summary; without ``reveal`` the hidden parts (holdout, new) show their totals
    only: no repository row, no failure."""
    shown = results if reveal else [r for r in results if r.get("part", "seen") == "seen"]
    rows = repository_rows(shown)
    width = max([len("repository")] + [len(row[0]) for row in rows])
    header = f"{'repository':<{width}}  files  derive  error  crash  other  rate"
    print(header)
    print("-" * len(header))
    for repo, files, derives, errors, crashes, other, rate in rows:
        print(
            f"{repo:<{width}}  {files:>5}  {derives:>6}  {errors:>5}  {crashes:>5}  {other:>5}"
            f"  {rate}"
        )
    print()
    print(f"{len(rows)} repositories, {len(shown)} distinct files")
    for line in rate_lines(shown):
        print(line)
    print()
    for line in part_lines(results):
        print(line)
    print()
    ranking = failure_ranking(shown, corpus)
    print(f"failure kinds ({len(ranking)}), the first {min(top, len(ranking))}:")
    for k, item in enumerate(ranking[:top], 1):
        print(
            f"{k:>3}. {item['files']:>4} files (with it: {item['files_with_it']})  {item['kind']}"
        )
        if item["distinct_names"] > 1:
            print(f"       names: {item['names']}")
        print(f"       e.g. {item['example']}")
        print(f"       {item['message']}")


def markdown(results: list[dict], corpus: Path, top: int) -> str:
    lines = [
        "| repository | files | derive | error | crash | other | rate |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for repo, files, derives, errors, crashes, other, rate in repository_rows(results):
        lines.append(f"| {repo} | {files} | {derives} | {errors} | {crashes} | {other} | {rate} |")
    lines += ["", *(f"- {line}" for line in rate_lines(results))]
    lines += [*(f"- {line}" for line in part_lines(results)), ""]
    lines += ["| # | files | with it | kind | example | message |", "|---:|---:|---:|---|---|---|"]
    for k, item in enumerate(failure_ranking(results, corpus)[:top], 1):
        cells = [item["kind"], item["example"], item["message"]]
        kind, example, message = (cell.replace("|", "\\|") for cell in cells)
        lines.append(
            f"| {k} | {item['files']} | {item['files_with_it']} | {kind} | `{example}` | "
            f"`{message}` |"
        )
    return "\n".join(lines) + "\n"


def shapegen_revision() -> str:
    try:
        head = subprocess.run(
            ["git", "-C", str(ROOT), "rev-parse", "HEAD"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return head


def write_outcomes(results: list[dict], path: Path, merge: bool) -> None:
    records = {r["local"]: r for r in results}
    if merge and path.is_file():
        previous = json.loads(path.read_text(encoding="utf-8")).get("files", [])
        kept = {r["local"]: r for r in previous if r["local"] not in records}
        records = {**kept, **records}
    data = {
        "lot": list(LOT),
        "seed": 0,
        "timeout_seconds": TIMEOUT,
        "shapegen_commit": shapegen_revision(),
        "files": [records[key] for key in sorted(records)],
    }
    # one file a line: a new run changes the lines of the files whose outcome changed
    head = {key: value for key, value in data.items() if key != "files"}
    lines = [json.dumps(head, ensure_ascii=False)[:-1] + ', "files": [']
    rows = [json.dumps(record, ensure_ascii=False) for record in data["files"]]
    lines.append(",\n".join(rows))
    lines.append("]}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def reported(path: Path, entries: list[dict], corpus: Path) -> list[dict]:
    """The outcomes recorded in ``path`` for ``entries``, with the manifest's kinds."""
    if not path.is_file():
        sys.exit(f"no outcomes file {path}: run the tool first")
    recorded = {r["local"]: r for r in json.loads(path.read_text(encoding="utf-8"))["files"]}
    results = []
    for entry in entries:
        record = recorded.get(entry["local"])
        if record is None:
            continue
        record = {**record, "kind": entry.get("kind", "rule")}
        record["revision"] = entry.get("revision", "head")
        record["part"] = entry.get("part", "seen")
        record.pop("unseen", None)
        if "unseen" in entry:
            record["unseen"] = entry["unseen"]
        if record.get("message") and record["outcome"] != "derives":
            record["failure_kind"] = failure_kind(record["message"], (str(corpus), str(ROOT)))
        results.append(record)
    return results


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--corpus", help="the corpus folder (default: $SHAPEGEN_CGA_WILD)")
    parser.add_argument("--manifest", default=str(MANIFEST), help="the manifest JSON")
    parser.add_argument("--outcomes", default=str(OUTCOMES), help="where to write the outcomes")
    parser.add_argument("--only", help="run the files whose path or repository contains this")
    parser.add_argument("--jobs", type=int, default=2, help="files derived at once (default 2)")
    parser.add_argument("--timeout", type=float, default=TIMEOUT, help="seconds per file")
    parser.add_argument("--top", type=int, default=TOP, help="failure kinds printed")
    parser.add_argument("--markdown", help="also write the tables as markdown to this file")
    parser.add_argument(
        "--report",
        action="store_true",
        help="derive nothing: print the summary of the outcomes file (kinds from the manifest)",
    )
    parser.add_argument("--holdout", default=str(HOLDOUT), help="the holdout JSON")
    parser.add_argument(
        "--part",
        choices=("all", "seen", "holdout", "new", "hidden"),
        default="all",
        help="run or report this part only (hidden: holdout and new)",
    )
    parser.add_argument(
        "--reveal",
        action="store_true",
        help="show the hidden parts' repositories and failures too (else their totals only)",
    )
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        return _worker(args.worker)

    corpus = corpus_folder(args.corpus)
    if not corpus.is_dir():
        parser.error(f"no corpus folder {corpus} (see tests/data/cga-wild/README.md)")
    holdout = load_holdout(Path(args.holdout))
    marked = mark_parts(load_manifest(Path(args.manifest)), holdout, project_contents())
    entries = runnable(marked, args.only, args.part)
    if args.report:
        results = reported(Path(args.outcomes), entries, corpus)
        print_summary(results, corpus, args.top, args.reveal)
        if args.markdown:
            shown = results if args.reveal else [r for r in results if r["part"] == "seen"]
            Path(args.markdown).write_text(markdown(shown, corpus, args.top), encoding="utf-8")
        return 0
    if not entries:
        parser.error("no manifest entry to run")
    print(f"deriving {len(entries)} files from {corpus} ...", file=sys.stderr)
    results = run_corpus(entries, corpus, args.jobs, args.timeout)
    write_outcomes(results, Path(args.outcomes), merge=bool(args.only) or args.part != "all")
    print_summary(results, corpus, args.top, args.reveal)
    if args.markdown:
        shown = results if args.reveal else [r for r in results if r["part"] == "seen"]
        Path(args.markdown).write_text(markdown(shown, corpus, args.top), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
