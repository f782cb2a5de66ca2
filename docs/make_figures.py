"""The figures and pictures that README.md and the docs state, remade from the code.

Each figure the README (or a page of docs/) states about a run, such as the column diameter the
parthenon's search finds, is listed here with the run that measures it and the place in the
text where it stands (a regular expression whose group ``value`` is the figure). Run from the
repository root::

    .venv/bin/python docs/make_figures.py              # every figure and picture (long)
    .venv/bin/python docs/make_figures.py --quick      # the figures of quick runs only
    .venv/bin/python docs/make_figures.py --check      # change nothing; exit 1 on a stale one
    .venv/bin/python docs/make_figures.py --only parthenon-12x8-search --no-pictures

``make figures`` runs the first line. A figure that no longer holds is rewritten in its
document (and printed, old -> new); a measurement marked ``held`` (a known regression being
fixed elsewhere) is measured and printed but its figures are left as they are. The pictures of
the README (the landscape, the parthenon, the design page's screenshots) and of
docs/primitives.md are remade by their own commands and scripts, listed in :data:`PICTURES`.

``tests/test_readme.py`` checks the same figures against the same runs: the quick ones in the
quick lane, the long ones in the slow lane.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request
from collections.abc import Callable
from dataclasses import dataclass, field
from decimal import ROUND_HALF_UP, Decimal
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _decimals(places: int) -> Callable[[float], str]:
    return lambda x: f"{x:.{places}f}"


def _thousands(count: int) -> str:
    """3497 -> "3 497", as the README writes counts."""
    return f"{count:,}".replace(",", " ")


@dataclass(frozen=True)
class Figure:
    """One figure in one document: where it stands and how a measurement's result gives it."""

    name: str
    document: str  # relative to the repository root
    pattern: str  # a regular expression matching once; its group "value" is the figure
    value: Callable[[dict], str]  # the figure's text from the measurement's result

    def find(self, text: str) -> re.Match:
        # a space of the pattern matches any run of white space: a paragraph may be rewrapped
        matches = list(re.finditer(_spaced(self.pattern), text))
        if len(matches) != 1:
            raise LookupError(
                f"{self.document}: the figure {self.name!r} ({self.pattern!r}) is found"
                f" {len(matches)} times, not once"
            )
        return matches[0]

    def stated(self) -> str:
        """The figure as the document states it now."""
        return self.find((ROOT / self.document).read_text(encoding="utf-8"))["value"]


def _spaced(pattern: str) -> str:
    """``pattern`` with each plain space outside a character class made ``\\s+``."""
    out, in_class = [], False
    for k, char in enumerate(pattern):
        escaped = k > 0 and pattern[k - 1] == "\\"
        if char == "[" and not escaped:
            in_class = True
        elif char == "]" and not escaped:
            in_class = False
        out.append(r"\s+" if char == " " and not in_class else char)
    return "".join(out)


@dataclass(frozen=True)
class Measurement:
    """A run and the figures it gives. ``command`` is a ``shapegen`` command line (its
    arguments, as the README writes them); it runs with ``--report`` added, and its figures
    are read from the report (``result["report"]``). ``measure`` is instead a function of a
    working folder that returns the result itself."""

    name: str
    figures: tuple[Figure, ...]
    command: str | None = None
    measure: Callable[[Path], dict] | None = None
    slow: bool = True
    held: str = ""  # why the documents keep their figures for now (the run still checks them)
    pictures: dict[str, str] = field(default_factory=dict)  # file the run writes -> docs path


def shell_words(line: str) -> list[str]:
    """The words of a command line as the shell splits them: a ``#`` that starts a word starts
    a comment, one inside a word (``district.geojson#lot-01``) does not."""
    return shlex.split(re.sub(r"(^|\s)#.*$", "", line))


def shapegen_command(command: str) -> list[str]:
    """The argument list of a README command line (``shapegen ...``, a trailing ``# comment``
    dropped), as the shell splits it."""
    words = shell_words(command)
    if words and words[0] == "shapegen":
        words = words[1:]
    return words


def run_shapegen(arguments: list[str], cwd: Path, timeout: float = 3600) -> dict:
    """Run ``shapegen`` with ``arguments`` in ``cwd`` (this repository's package), adding
    ``--report``; the result holds ``status``, ``output`` (stdout and stderr) and ``report``."""
    report = Path(tempfile.mkdtemp(prefix="figures-")) / "report.json"
    environment = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), *_pythonpath()])}
    done = subprocess.run(
        [sys.executable, "-m", "shapegen", *arguments, "--report", str(report)],
        cwd=cwd,
        env=environment,
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    result = {"status": done.returncode, "output": done.stdout + done.stderr, "report": {}}
    if report.is_file():
        result["report"] = json.loads(report.read_text(encoding="utf-8"))
    shutil.rmtree(report.parent, ignore_errors=True)
    return result


def _pythonpath() -> list[str]:
    return [part for part in os.environ.get("PYTHONPATH", "").split(os.pathsep) if part]


def measure(measurement: Measurement, cwd: Path) -> dict:
    """The result of ``measurement``, run in ``cwd``."""
    if measurement.measure is not None:
        return measurement.measure(cwd)
    return run_shapegen(shapegen_command(measurement.command), cwd)


def _report(*keys: str, then: Callable = str) -> Callable[[dict], str]:
    """The figure at ``report[k1][k2]...``, formatted by ``then``."""

    def value(result: dict) -> str:
        found = result["report"]
        for key in keys:
            found = found[key]
        return then(found)

    return value


def _tilt_towards(result: dict, azimuth: float) -> float:
    """The tilt (degrees) the capacity sweep found towards ``azimuth`` (degrees)."""
    directions = result["report"]["analysis"]["capacity"]["directions"]
    (found,) = [d["tilt_deg"] for d in directions if abs(d["azimuth_deg"] - azimuth) < 1e-6]
    return found


def _editor_stable_range(cwd: Path) -> dict:
    """The stable interval the design page shades on the barrel vault's ``angle`` slider at
    60 degrees, as docs/editor.md's picture shows it (the scan's samples include the current
    value, so its ends move within the resolution with it), asked of ``shapegen edit``'s JSON
    API as the page asks it."""
    sys.path.insert(0, str(ROOT / "docs"))
    from editor_screenshots import Editor

    with Editor("barrel_vault.grammar", "--set", "angle=60") as editor:
        deadline = time.monotonic() + 600
        while time.monotonic() < deadline:
            with urllib.request.urlopen(f"{editor.url}api/state", timeout=60) as answer:
                state = json.load(answer)
            stability = (state.get("stability") or {}).get("angle") or {}
            if stability.get("status") == "done":
                angle = next(a for a in state["attrs"] if a["name"] == "angle")
                return {"stability": stability, "default": angle["default"]}
            time.sleep(0.5)
    raise TimeoutError("the design page's scan of 'angle' did not end in 600 s")


def page_number(x: float) -> str:
    """A number as the design page prints it: JavaScript's ``Number(x.toPrecision(4))``, four
    significant digits of the exact binary value, a tie rounded up (85.625 -> 85.63, where
    Python's format would give 85.62), no trailing zeros."""
    exact = Decimal(x)
    if exact == 0:
        return "0"
    quantum = Decimal(1).scaleb(exact.adjusted() - 3)
    rounded = exact.quantize(quantum, rounding=ROUND_HALF_UP)
    return f"{float(rounded):g}"


def _interval(result: dict) -> str:
    lo, hi = result["stability"]["intervals"][0]
    return f"{page_number(lo)}–{page_number(hi)}"


README = "README.md"
EDITOR = "docs/editor.md"
STATICS = "docs/statics.md"

MEASUREMENTS: tuple[Measurement, ...] = (
    Measurement(
        "arch-columns-verdict",
        command="shapegen build arch_columns.grammar --analyze",
        slow=False,
        figures=(
            Figure(
                "the thin arch's verdict",
                README,
                r"arch_columns\.grammar --analyze\s+# a thin arch on narrow columns:"
                r" (?P<value>\w+)",
                _report("analysis", "stands", then=lambda s: "yes" if s else "no"),
            ),
        ),
    ),
    Measurement(
        "parthenon-12x8-search",
        command="shapegen build parthenon.rpk --lot 12,8 --set Column_Height=10.43 --free Diameter"
        " --optimize --tilt 10 --pyramid 4 --capacity --max-seconds 1800",
        figures=(
            Figure(
                "the diameter found",
                README,
                r"on the 12 x 8 m lot: (?P<value>[0-9.]+) m instead of 1\.92 m",
                _report("attrs", "Diameter", then=_decimals(2)),
            ),
            Figure(
                "its iterations",
                README,
                r"in (?P<value>\d+) SLSQP iterations?",
                _report("optimization", "iterations"),
            ),
            Figure(
                "its designs judged",
                README,
                r"SLSQP iterations? \((?P<value>\d+) designs judged\)",
                _report("optimization", "evaluations"),
            ),
            Figure(
                "the found design's tilt",
                README,
                r"the design then tilts (?P<value>[0-9.]+)° before it falls",
                _report("analysis", "capacity", "tilt_deg", then=_decimals(2)),
            ),
            Figure(
                "the diameter found (statics page)",
                STATICS,
                r"--tilt 10` finds a diameter of (?P<value>[0-9.]+) m that stands at 10°",
                _report("attrs", "Diameter", then=_decimals(2)),
            ),
            Figure(
                "the found design's tilt (statics page)",
                STATICS,
                r"machine\); that design tilts (?P<value>[0-9.]+)°\.",
                _report("analysis", "capacity", "tilt_deg", then=_decimals(2)),
            ),
        ),
    ),
    Measurement(
        "parthenon-12x8-pyramid",
        command="shapegen build parthenon.rpk --lot 12,8 --analyze --capacity --pyramid 4"
        " --max-seconds 1800",
        figures=(
            Figure(
                "the 12 x 8 m temple's tilt, pyramid (search)",
                README,
                r"instead of 1\.92 m \(which tilts (?P<value>[0-9.]+)°\)",
                _report("analysis", "capacity", "tilt_deg", then=_decimals(2)),
            ),
            Figure(
                "the 12 x 8 m temple's tilt, pyramid (cone's comparison)",
                README,
                r"where the pyramid gave (?P<value>[0-9.]+)°",
                _report("analysis", "capacity", "tilt_deg", then=_decimals(2)),
            ),
        ),
    ),
    Measurement(
        "parthenon-12x8-cone",
        command="shapegen build parthenon.rpk --lot 12,8 --analyze --capacity --max-seconds 1800",
        figures=(
            Figure(
                "the 12 x 8 m temple's tilt, cone",
                README,
                r"the 12 x 8 m temple tilts (?P<value>[0-9.]+)°",
                _report("analysis", "capacity", "tilt_deg", then=_decimals(2)),
            ),
        ),
    ),
    Measurement(
        "parthenon-30x70",
        command="shapegen build parthenon.rpk --lot 30,70 --analyze --capacity"
        " --picture parthenon.png --max-seconds 1800",
        pictures={"parthenon.png": "docs/images/parthenon.png"},
        figures=(
            Figure(
                "its leaves standing in",
                README,
                r"on a 30 x 70 m lot: (?P<value>[0-9][0-9 ]*[0-9]) leaves standing in as",
                _report("analysis", "stand_ins", "leaves", then=_thousands),
            ),
            Figure(
                "the blocks standing in for them",
                README,
                r"leaves standing in as (?P<value>[0-9][0-9 ]*[0-9]) blocks",
                _report("analysis", "stand_ins", "blocks", then=_thousands),
            ),
            Figure(
                "its bodies",
                README,
                r"open shells capped\), (?P<value>[0-9][0-9 ]*[0-9]) bodies",
                _report("analysis", "bodies", "bodies", then=_thousands),
            ),
            Figure(
                "its weight",
                README,
                r"bodies, W = (?P<value>[0-9.]+) MN",
                _report("analysis", "total_weight", then=lambda w: f"{w / 1e6:.1f}"),
            ),
            Figure(
                "its lateral capacity",
                README,
                r"its lateral capacity is \*\*(?P<value>[0-9.]+)°\*\*",
                _report("analysis", "capacity", "tilt_deg", then=_decimals(2)),
            ),
            Figure(
                "its lateral capacity along the temple",
                README,
                r"across the temple, (?P<value>[0-9.]+)° along it",
                lambda result: _decimals(2)(_tilt_towards(result, 90.0)),
            ),
            Figure(
                "its load multiplier",
                README,
                r"a horizontal load of (?P<value>[0-9.]+) times its weight",
                _report("analysis", "capacity", "load_multiplier", then=_decimals(3)),
            ),
        ),
    ),
    Measurement(
        "parthenon-30x70-search",
        command="shapegen build parthenon.rpk --lot 30,70 --set Column_Height=10.43 --free Diameter"
        " --optimize --tilt 10@0 --pyramid 4 --max-seconds 1800",
        figures=(
            Figure(
                "the diameter found on 30 x 70 m",
                README,
                r"search a sweep of directions per design\) gives (?P<value>[0-9.]+) m\.",
                _report("attrs", "Diameter", then=_decimals(2)),
            ),
            Figure(
                "the diameter found on 30 x 70 m (statics page)",
                STATICS,
                r"the same search finds (?P<value>[0-9.]+) m",
                _report("attrs", "Diameter", then=_decimals(2)),
            ),
        ),
    ),
    Measurement(
        "editor-barrel-vault-angle",
        measure=_editor_stable_range,
        figures=(
            Figure(
                "the angle's stable interval (caption)",
                EDITOR,
                r"where the design stands with every other attr held \(here"
                r" (?P<value>[0-9.]+–[0-9.]+) degrees\)",
                _interval,
            ),
            Figure(
                "the angle's stable interval (the page's words)",
                EDITOR,
                r"`stands for (?P<value>[0-9.]+–[0-9.]+) \(±[0-9.]+\)`",
                _interval,
            ),
            Figure(
                "the angle's resolution",
                EDITOR,
                r"`stands for [0-9.]+–[0-9.]+ \(±(?P<value>[0-9.]+)\)`",
                lambda result: page_number(result["stability"]["resolution"]),
            ),
        ),
    ),
)


@dataclass(frozen=True)
class Picture:
    """A picture of the docs and the command that remakes it (run from the repository root)."""

    name: str
    command: tuple[str, ...]
    slow: bool = True


PICTURES: tuple[Picture, ...] = (
    Picture(
        "docs/images/arch_columns_landscape.png",
        (
            "-m",
            "shapegen",
            "landscape",
            "arch_columns.grammar",
            "arch_thickness",
            "column_width",
            "-o",
            "docs/images/arch_columns_landscape.png",
        ),
    ),  # fmt: skip
    Picture("docs/images/primitives/*.png", ("docs/render_primitives.py",)),
    Picture("docs/images/editor_*.png (Chromium)", ("docs/editor_screenshots.py",)),
)


def stale(measurement: Measurement, result: dict) -> list[tuple[Figure, str, str]]:
    """``(figure, stated, measured)`` for each figure of ``measurement`` that ``result`` no
    longer gives."""
    found = []
    for figure in measurement.figures:
        measured = figure.value(result)
        stated = figure.stated()
        if stated != measured:
            found.append((figure, stated, measured))
    return found


def rewrite(figure: Figure, measured: str) -> None:
    path = ROOT / figure.document
    text = path.read_text(encoding="utf-8")
    match = figure.find(text)
    text = text[: match.start("value")] + measured + text[match.end("value") :]
    path.write_text(text, encoding="utf-8")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="change nothing; exit 1 if stale")
    parser.add_argument("--quick", action="store_true", help="only the quick runs")
    parser.add_argument("--only", nargs="+", metavar="NAME", help="these measurements only")
    parser.add_argument("--no-pictures", action="store_true", help="remake no picture")
    args = parser.parse_args(argv)
    chosen = [
        m
        for m in MEASUREMENTS
        if (not args.quick or not m.slow) and (not args.only or m.name in args.only)
    ]
    unknown = set(args.only or ()) - {m.name for m in MEASUREMENTS}
    if unknown:
        parser.error(f"no measurement {', '.join(sorted(unknown))}")
    failed = False
    for measurement in chosen:
        started = time.monotonic()
        with tempfile.TemporaryDirectory(prefix="figures-") as folder:
            try:
                result = measure(measurement, Path(folder))
            except Exception as exc:  # a run that breaks is reported, the others still run
                print(f"{measurement.name}: failed: {exc}")
                failed = True
                continue
            seconds = time.monotonic() - started
            if result.get("status", 0) != 0:
                tail = result["output"].strip().splitlines()[-1:] or [""]
                print(f"{measurement.name}: exit {result['status']} ({seconds:.0f} s): {tail[0]}")
                failed = failed or not measurement.held
                continue
            changes = stale(measurement, result)
            for figure, stated, measured in changes:
                print(
                    f"{measurement.name}: {figure.document}: {figure.name}: {stated} -> {measured}"
                )
            if not changes:
                print(
                    f"{measurement.name}: {len(measurement.figures)} figures hold ({seconds:.0f} s)"
                )
            if measurement.held:
                print(f"{measurement.name}: held, left as stated: {measurement.held}")
            elif changes and args.check:
                failed = True
            elif changes:
                for figure, _, measured in changes:
                    rewrite(figure, measured)
            if not args.check and not args.no_pictures and not measurement.held:
                for made, kept in measurement.pictures.items():
                    shutil.copyfile(Path(folder) / made, ROOT / kept)
                    print(f"{measurement.name}: wrote {kept}")
    if not args.check and not args.no_pictures and not args.only:
        for picture in PICTURES:
            if args.quick and picture.slow:
                continue
            environment = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), *_pythonpath()])}
            done = subprocess.run([sys.executable, *picture.command], cwd=ROOT, env=environment)
            print(f"{picture.name}: {'remade' if done.returncode == 0 else 'failed'}")
            failed = failed or done.returncode != 0
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
