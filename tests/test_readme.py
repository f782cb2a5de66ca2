"""The README's commands, run as a newcomer runs them: from a clean copy of the repository's
files (what a fresh clone has: the tracked files, no ``out/``, no ``.venv``), each line of its
shell code blocks as written, and the figures the README states about a run checked against the
run (the figures and their places are listed in docs/make_figures.py, which remakes them).

Commands that take a second or less run in the quick lane, in process; the others, the
rule packages' searches, the servers and the Python examples in the slow lane, each in its own
process started in the copy (``python -m shapegen`` there imports the copy's package). Each run
adds ``--report FILE`` to a ``build``, ``analyze`` or ``simulate`` that has none, to read its
figures; a report changes nothing of the run. The servers (``shapegen edit``, the 3D Tiles
viewer) are asked for a page and stopped with Ctrl-C, on a free port (``--port 0``, since the
README's default port may be taken on a shared machine); ``make test`` is CI's own command and
``make demo`` runs its recipe's ``python -m shapegen.demo``.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import urllib.request
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "docs"))
import make_figures  # noqa: E402

README = ROOT / "README.md"

#: The README's commands that run in the quick lane (each a second or less).
QUICK = {
    "shapegen rules",
    "shapegen build arch_columns.grammar --analyze          # a thin arch on narrow columns: no",
    "shapegen build wall_windows.grammar --lot 12,8",
    'shapegen build wall_windows.grammar --lot "0,8 12,8 12,0 0,0"     # the same 12 x 8 m lot',
    "shapegen build wall_windows.grammar --lot docs/data/plot.obj",
    "shapegen build Building_From_FootprintSMALL.rpk --lot 12,8 -o building.glb",
}
#: Servers: started, asked for a page, stopped.
SERVERS = {
    "shapegen edit rules/barrel_vault.grammar": "api/state",
    "python -m shapegen.city.viewer out/l93": "",
}
#: Commands a server needs run before it, in the same copy.
BEFORE = {
    "python -m shapegen.city.viewer out/l93": [
        "shapegen city docs/data/district_l93.geojson docs/data/house.grammar -o out/l93 --tiles"
    ],
}
#: Command lines not run here, and why.
NOT_RUN = {"make test": "the quick lane itself, run by CI (.ci/run)"}
OUTPUT_OPTIONS = ("-o", "--report", "--picture")


def code_blocks(text: str) -> list[tuple[str, str]]:
    """``(language, body)`` of each fenced code block of a Markdown text."""
    return re.findall(r"^```([A-Za-z]*)\n(.*?)^```", text, flags=re.MULTILINE | re.DOTALL)


#: The programs a README command line starts with (a block of other lines, such as the
#: layout's tree, holds no commands).
PROGRAMS = ("shapegen", "make", "python")


def readme_commands() -> list[str]:
    """Each command line of the README's code blocks with no language."""
    lines = []
    for language, body in code_blocks(README.read_text(encoding="utf-8")):
        if not language:
            lines.extend(
                line for line in body.splitlines() if line.split()[:1] in ([p] for p in PROGRAMS)
            )
    return lines


def python_examples() -> list[str]:
    return [body for language, body in code_blocks(README.read_text(encoding="utf-8"))
            if language == "python"]  # fmt: skip


COMMANDS = readme_commands()


def measurement_of(command: str) -> make_figures.Measurement | None:
    for measurement in make_figures.MEASUREMENTS:
        if measurement.command is not None and (
            make_figures.shell_words(measurement.command) == make_figures.shell_words(command)
        ):
            return measurement
    return None


@pytest.fixture(scope="module")
def checkout(tmp_path_factory) -> Path:
    """A copy of the repository's tracked files as they are in the work tree."""
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("not a git checkout: the tracked files cannot be listed")
    listed = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True)
    copy = tmp_path_factory.mktemp("clone")
    for name in listed.stdout.decode().split("\0"):
        source = ROOT / name
        if not name or not (source.exists() or source.is_symlink()):
            continue  # deleted in the work tree, not yet committed
        target = copy / name
        target.parent.mkdir(parents=True, exist_ok=True)
        if source.is_symlink():
            target.symlink_to(os.readlink(source))
        else:
            shutil.copyfile(source, target)
    return copy


@pytest.fixture
def cache(tmp_path, monkeypatch) -> Path:
    monkeypatch.setenv("SHAPEGEN_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


def with_report(words: list[str], folder: Path) -> tuple[list[str], Path | None]:
    """The command's words with ``--report`` added to a command that writes one, and the path
    of the report (None for a command that has none)."""
    if len(words) < 2 or words[1] not in ("build", "analyze", "simulate"):
        return words, None
    if "--report" in words:
        return words, None  # its own report: read it where it says, in the copy
    report = folder / "report.json"
    return [*words, "--report", str(report)], report


def outputs_of(words: list[str]) -> list[str]:
    return [words[k + 1] for k, word in enumerate(words[:-1]) if word in OUTPUT_OPTIONS]


def run_line(line: str, copy: Path, folder: Path, in_process: bool, capsys=None) -> dict:
    """Run the README's command ``line`` in ``copy``; ``status``, ``output`` and ``report``."""
    words, report = with_report(make_figures.shell_words(line), folder)
    if in_process:
        from shapegen.cli import main

        previous = Path.cwd()
        os.chdir(copy)
        try:
            status = main(words[1:])
        finally:
            os.chdir(previous)
        captured = capsys.readouterr()
        output = captured.out + captured.err
    else:
        command = [sys.executable, *words[1:]] if words[0] == "python" else [
            sys.executable, "-m", "shapegen", *words[1:]]  # fmt: skip
        done = subprocess.run(command, cwd=copy, capture_output=True, text=True, timeout=3600)
        status, output = done.returncode, done.stdout + done.stderr
    if report is None and "--report" in words:
        report = copy / words[words.index("--report") + 1]
    found = json.loads(report.read_text()) if report is not None and report.is_file() else {}
    return {"status": status, "output": output, "report": found}


def check_run(line: str, result: dict, copy: Path) -> None:
    words = make_figures.shell_words(line)
    assert result["status"] == 0, f"{line}\n{result['output'][-3000:]}"
    for output in outputs_of(words):
        path = copy / output
        assert path.exists(), f"{line}: wrote no {output}"
        assert path.is_dir() or path.stat().st_size > 0, f"{line}: {output} is empty"
    measurement = measurement_of(line)
    if measurement is not None:
        for figure in measurement.figures:
            assert figure.value(result) == figure.stated(), (
                f"{line}: the README states {figure.name} {figure.stated()},"
                f" the run gives {figure.value(result)} (python docs/make_figures.py"
                f" --only {measurement.name} rewrites it)"
            )
    if words[1:2] == ["rules"]:
        # every rule the README's commands name by its bare name is one `shapegen rules` lists
        bare = {w for c in COMMANDS for w in make_figures.shell_words(c)
                if re.fullmatch(r"[\w.-]+\.(grammar|rpk)", w)}  # fmt: skip
        assert bare and all(name in result["output"] for name in bare), bare


def lane(line: str):
    slow = line not in QUICK
    marks = [pytest.mark.slow] if slow else []
    return pytest.param(line, marks=marks, id=line[:90])


RUN = [line for line in COMMANDS if line not in NOT_RUN and line not in SERVERS]


@pytest.mark.parametrize("line", [lane(line) for line in RUN])
def test_a_readme_command_runs_as_written_and_prints_what_the_readme_says(
    line, checkout, cache, tmp_path, capsys
):
    if line == "make demo":
        # the target's recipe, with the interpreter running these tests (the target itself
        # makes .venv first)
        recipe = subprocess.run([sys.executable, "-m", "shapegen.demo"], cwd=checkout,
                                capture_output=True, text=True, timeout=3600)  # fmt: skip
        assert recipe.returncode == 0, recipe.stdout + recipe.stderr
        for written in ("out/cluny.glb", "out/cluny.png"):  # the README says it writes them
            assert (checkout / written).stat().st_size > 0
        return
    for before in BEFORE.get(line, ()):
        assert run_line(before, checkout, tmp_path, in_process=False)["status"] == 0
    result = run_line(line, checkout, tmp_path, in_process=line in QUICK, capsys=capsys)
    check_run(line, result, checkout)


@pytest.mark.slow
@pytest.mark.parametrize("line", list(SERVERS))
def test_a_readme_server_serves_its_page_and_stops_on_ctrl_c(line, checkout, cache, tmp_path):
    for before in BEFORE.get(line, ()):
        assert run_line(before, checkout, tmp_path, in_process=False)["status"] == 0
    words = make_figures.shell_words(line)
    command = [sys.executable, *words[1:]] if words[0] == "python" else [
        sys.executable, "-m", "shapegen", *words[1:]]  # fmt: skip
    # nothing opens a browser here (Python's webbrowser runs $BROWSER)
    environment = {**os.environ, "BROWSER": "true"}
    process = subprocess.Popen(
        [*command, "--port", "0"],
        cwd=checkout,
        env=environment,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        first = process.stdout.readline()
        address = re.search(r"http://127\.0\.0\.1:\d+/", first)
        assert address, first + process.stderr.read() if process.poll() is not None else first
        with urllib.request.urlopen(address[0] + SERVERS[line], timeout=120) as answer:
            assert answer.status == 200 and answer.read()
    finally:
        process.send_signal(signal.SIGINT)
        try:
            process.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            process.kill()
            process.communicate()
    assert process.returncode in (0, 130), process.returncode


@pytest.mark.slow
@pytest.mark.parametrize("index", range(len(python_examples())))
def test_a_readme_python_example_runs_from_the_checkout(index, checkout, cache):
    done = subprocess.run([sys.executable, "-c", python_examples()[index]], cwd=checkout,
                          capture_output=True, text=True, timeout=1200)  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.strip()  # each example prints what it found


def test_the_readme_rule_example_builds_its_four_stones():
    import shapegen

    (body,) = [b for language, b in code_blocks(README.read_text()) if language == "grammar"]
    assert "A wall of four stones" in README.read_text()
    assert len(shapegen.parse_grammar(body).build().blocks) == 4


def test_the_readme_lot_forms_give_the_same_lot(checkout, cache, tmp_path, capsys):
    # the README says the polygon is "the same 12 x 8 m lot"; the OBJ file holds it too
    prefix = "shapegen build wall_windows.grammar --lot"
    lines = [line for line in COMMANDS if line.startswith(prefix) and "geojson" not in line]
    assert len(lines) == 3
    volumes = []
    for k, line in enumerate(lines):
        folder = tmp_path / str(k)
        folder.mkdir()
        volumes.append(
            run_line(line, checkout, folder, in_process=True, capsys=capsys)["report"]["volume"]
        )
    assert volumes[0] > 0 and volumes == pytest.approx([volumes[0]] * 3)


def test_every_command_the_test_names_is_still_in_the_readme():
    named = set(QUICK) | set(SERVERS) | set(NOT_RUN) | {c for cs in BEFORE.values() for c in cs}
    assert named <= set(COMMANDS), named - set(COMMANDS)
    # the parthenon's lines are the runs of their figures: a line edited in one place only
    # would leave its figures checked on a run the README no longer shows
    parthenon = [line for line in COMMANDS if "parthenon.rpk" in line]
    assert len(parthenon) == 2 and all(measurement_of(line) for line in parthenon), parthenon


@pytest.mark.parametrize("measurement", [
    pytest.param(m, marks=[pytest.mark.slow] if m.slow else [], id=m.name)
    for m in make_figures.MEASUREMENTS if m.command is None or not any(
        make_figures.shell_words(m.command) == make_figures.shell_words(c) for c in COMMANDS)
])  # fmt: skip
def test_a_figure_the_docs_state_holds(measurement, cache, tmp_path):
    """The figures whose run is no README command line (another lot, another option, the
    design page): measured as docs/make_figures.py measures them."""
    result = make_figures.measure(measurement, tmp_path)
    assert result.get("status", 0) == 0, result.get("output", "")[-3000:]
    stale = make_figures.stale(measurement, result)
    assert not stale, [(f.document, f.name, stated, measured) for f, stated, measured in stale]


def test_every_figure_is_found_once_in_its_document():
    for measurement in make_figures.MEASUREMENTS:
        for figure in measurement.figures:
            assert figure.stated()  # raises LookupError unless found exactly once
