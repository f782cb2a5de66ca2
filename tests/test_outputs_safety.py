"""Outputs are checked before any work, written together or not at all, and an interrupt (Ctrl-C,
SIGTERM) at any point, imports included, ends in one line, exit 128 + signal, and no temporary
file nor damaged output left behind."""

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from shapegen.cli import main
from shapegen.export import atomic

REPO = Path(__file__).resolve().parents[1]
ARCH_JSON = REPO / "docs" / "examples" / "arch.json"


@pytest.fixture
def no_work(monkeypatch):
    """Fail the test if a command gets as far as building or judging anything."""
    import shapegen.pipeline

    def refuse(*args, **kwargs):
        raise AssertionError("the work started before the outputs were checked")

    monkeypatch.setattr(shapegen.pipeline, "design", refuse)
    monkeypatch.setattr(shapegen.pipeline, "load", refuse)


def _leftovers(folder: Path) -> list[Path]:
    return [p for p in folder.rglob("*") if p.is_file() and p.name not in ("old.json", "link.json")]


# (arguments, words every one of which the one error line holds); {tmp} is the test's folder.
MISTAKES = [
    (["build", "arch_columns.grammar", "-o", "{tmp}/x.json", "--report", "{tmp}/x.json"],
     ["-o {tmp}/x.json and --report {tmp}/x.json name the same file"]),
    (["build", "arch_columns.grammar", "-o", "{tmp}/x.json", "--report", "{tmp}/./x.json"],
     ["name the same file"]),
    (["build", "arch_columns.grammar", "-o", "{tmp}/link.json", "--report", "{tmp}/old.json"],
     ["-o {tmp}/link.json and --report {tmp}/old.json name the same file"]),
    (["build", "arch_columns.grammar", "--report", "{tmp}/p.png", "--picture", "{tmp}/p.png"],
     ["--report {tmp}/p.png and --picture {tmp}/p.png name the same file"]),
    (["build", "arch_columns.grammar", "-o", "{tmp}/folder"], ["-o {tmp}/folder: is a folder"]),
    (["build", "arch_columns.grammar", "--report", "{tmp}/folder"],
     ["--report {tmp}/folder: is a folder"]),
    (["build", "arch_columns.grammar", "-o", "{tmp}/missing/x.json"],
     ["-o {tmp}/missing/x.json: folder {tmp}/missing does not exist"]),
    (["build", "arch_columns.grammar", "--report", "{tmp}/old.json/r.json"],
     ["--report {tmp}/old.json/r.json: folder {tmp}/old.json is not a folder"]),
    (["build", "arch_columns.grammar", "-o", "{tmp}/x.step"], ["-o {tmp}/x.step: unknown output"]),
    (["analyze", "{arch}", "-o", "{tmp}/x.glb", "--report", "{tmp}/x.glb"],
     ["-o {tmp}/x.glb and --report {tmp}/x.glb name the same file"]),
    (["analyze", "{arch}", "--report", "{tmp}/folder"], ["--report {tmp}/folder: is a folder"]),
    (["landscape", "arch_columns.grammar", "arch_thickness", "column_width", "-o", "{tmp}/folder"],
     ["-o {tmp}/folder: is a folder"]),
    (["landscape", "arch_columns.grammar", "arch_thickness", "column_width", "-o", "{tmp}/l.jpg"],
     ["-o {tmp}/l.jpg: the landscape is written as .png"]),
]  # fmt: skip
if Path("/proc/self").is_dir():  # a folder no one can write in, root included
    MISTAKES.append(
        (["build", "arch_columns.grammar", "-o", "/proc/x.json"],
         ["-o /proc/x.json: cannot write in folder /proc"])
    )  # fmt: skip


@pytest.mark.parametrize(("arguments", "words"), MISTAKES)
def test_output_mistakes_are_one_line_before_any_work(tmp_path, capsys, no_work, arguments, words):
    (tmp_path / "folder").mkdir()
    old = tmp_path / "old.json"
    old.write_text("{}")
    (tmp_path / "link.json").symlink_to(old)
    fill = {"{tmp}": str(tmp_path), "{arch}": str(ARCH_JSON)}

    def filled(text: str) -> str:
        for key, value in fill.items():
            text = text.replace(key, value)
        return text

    assert main([filled(a) for a in arguments]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("shapegen: error: "), err
    assert "Traceback" not in err
    for word in words:
        assert filled(word) in err, err
    assert old.read_text() == "{}"
    assert _leftovers(tmp_path) == []


def test_simulate_checks_its_outputs_before_any_work(tmp_path, capsys, no_work):
    pytest.importorskip("pybullet", reason="the simulator is the optional extra shapegen[sim]")
    (tmp_path / "file").write_text("")
    cases = [
        (["-o", f"{tmp_path}/s.png", "--report", f"{tmp_path}/s.png"], "name the same file"),
        (["--frames", f"{tmp_path}/file"], f"--frames {tmp_path}/file: exists and is not a folder"),
        (["--frames", f"{tmp_path}/file/frames"], f"--frames {tmp_path}/file/frames:"),
        (["-o", f"{tmp_path}/s.mp4"], f"-o {tmp_path}/s.mp4: the simulation"),
    ]
    for extra, words in cases:
        assert main(["simulate", "arch_columns.grammar", *extra]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and words in err and "Traceback" not in err, err
    assert [p.name for p in tmp_path.iterdir()] == ["file"]


# ------------------------------------------------------------------------------ all or nothing
def test_outputs_are_written_together_or_not_at_all(tmp_path, monkeypatch):
    from shapegen import pipeline

    first, second = tmp_path / "m.json", tmp_path / "r.json"
    first.write_text("old model")
    second.write_text("old report")

    with pytest.raises(TypeError):  # writing the second fails after the first was written
        pipeline.write_outputs([(first, b"new model"), (second, object())])
    assert first.read_text() == "old model" and second.read_text() == "old report"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.json", "r.json"]
    pipeline.write_outputs([(first, b"new model"), (second, b"new report")])
    assert first.read_text() == "new model" and second.read_text() == "new report"
    assert not atomic._TEMPORARIES


def test_an_interrupted_write_leaves_no_temporary_file(tmp_path):
    target = tmp_path / "model.json"
    target.write_text("old")
    with pytest.raises(KeyboardInterrupt):
        with atomic.atomic_write(target) as handle:
            handle.write("half")
            assert len(atomic._TEMPORARIES) == 1
            raise KeyboardInterrupt
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["model.json"]
    assert not atomic._TEMPORARIES


# ------------------------------------------------------------------------------ signals
# A child runs the command with a writer that announces the write and then stalls in it, so the
# signal arrives while a temporary file is open.
SLOW_WRITER = textwrap.dedent(
    """
    import os, sys, time
    from shapegen.export import atomic

    real_fdopen = os.fdopen

    class Stalling:
        def __init__(self, handle):
            self.handle = handle
        def __enter__(self):
            return self
        def __exit__(self, *exc):
            return self.handle.__exit__(*exc)
        def write(self, data):
            self.handle.write(data[: len(data) // 2])
            self.handle.flush()
            print("writing", flush=True)
            time.sleep(60)

    atomic.os.fdopen = lambda fd, *a, **k: Stalling(real_fdopen(fd, *a, **k))
    from shapegen.cli import main
    sys.exit(main(sys.argv[1:]))
    """
)


@pytest.mark.parametrize(("signum", "status"), [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_a_signal_during_the_write_removes_the_temporary_file(tmp_path, signum, status):
    model = tmp_path / "wall.json"
    model.write_text("the old model")
    child = subprocess.Popen(
        [sys.executable, "-c", SLOW_WRITER, "build", "wall_windows.grammar", "-q", "-o",
         str(model), "--report", str(tmp_path / "r.json")],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path,
    )  # fmt: skip
    try:
        assert child.stdout.readline() == "writing\n"
        assert len(list(tmp_path.glob(".*.tmp"))) >= 1  # the write is under way
        child.send_signal(signum)
        _, err = child.communicate(timeout=60)
    finally:
        child.kill()
    assert child.returncode == status
    assert err == "shapegen: interrupted\n"
    assert model.read_text() == "the old model"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["wall.json"]


# The import of this module sends the process a Ctrl-C, as a user pressing it at that moment.
TRIP = textwrap.dedent(
    """
    import os, signal, sys

    class Trip:
        def find_spec(self, name, path=None, target=None):
            if name == {module!r}:
                os.kill(os.getpid(), signal.SIGINT)
            return None

    sys.meta_path.insert(0, Trip())
    """
)


def _interruptible() -> None:
    """In the child: Ctrl-C as a terminal delivers it. A job started in the background by a
    non-interactive shell inherits SIGINT ignored, and Python then installs no KeyboardInterrupt
    handler, so before shapegen's own handler is in place an interrupt would go unseen."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


CONSOLE_SCRIPT = "from shapegen.cli import main\nsys.exit(main())\n"  # what pip's wrapper runs


@pytest.mark.parametrize(
    ("entry", "module"),
    [
        ("-m", "shapegen.cli"),  # python -m shapegen: shapegen/__main__.py guards this import
        ("console", "shapegen.export.atomic"),  # the first import main() makes
        ("console", "shapegen.cli.common_options"),
        ("console", "shapegen.cli.build"),
        ("console", "numpy"),
        ("-m", "lark"),  # while the grammar loads
    ],
)
def test_ctrl_c_at_any_import_is_one_line_and_130(tmp_path, entry, module):
    # (The console script's own `from shapegen.cli import main` runs no code of shapegen's but
    # `import sys`: only Python's import machinery can be interrupted there, which no package
    # can guard.)
    trip = TRIP.format(module=module)
    if entry == "console":
        command = [sys.executable, "-c", trip + CONSOLE_SCRIPT]
    else:
        command = [sys.executable, "-c", trip + "import runpy\nrunpy.run_module('shapegen',"
                   " run_name='__main__', alter_sys=True)\n"]  # fmt: skip
    command += ["build", "wall_windows.grammar", "--analyze", "-o", str(tmp_path / "w.json")]
    done = subprocess.run(
        command,
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
        preexec_fn=_interruptible,
    )
    assert (done.returncode, done.stderr) == (130, "shapegen: interrupted\n")
    assert list(tmp_path.iterdir()) == []


def test_interrupted_in_process_returns_130_and_keeps_handlers(monkeypatch, capsys):
    import shapegen.cli.rules as rules

    def interrupted(args):
        raise KeyboardInterrupt

    before = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    monkeypatch.setattr(rules, "run", interrupted)
    assert main(["rules"]) == 130
    assert capsys.readouterr().err == "shapegen: interrupted\n"
    assert {s: signal.getsignal(s) for s in before} == before


def test_sigterm_in_process_is_143(monkeypatch, capsys):
    import shapegen.cli.rules as rules

    def terminated(args):
        os.kill(os.getpid(), signal.SIGTERM)
        raise AssertionError("the handler should have stopped the run")

    monkeypatch.setattr(rules, "run", terminated)
    assert main(["rules"]) == 143
    assert capsys.readouterr().err == "shapegen: interrupted\n"


def test_the_demo_checks_its_folder_before_any_work(tmp_path, capsys, no_work):
    from shapegen.demo import main as demo

    (tmp_path / "file").write_text("")
    assert demo(["arch_columns.grammar", "--out", str(tmp_path / "file")]) == 2
    err = capsys.readouterr().err
    assert err == f"shapegen demo: error: --out {tmp_path / 'file'}: exists and is not a folder\n"


def test_remove_temporaries_removes_only_this_process_writes(tmp_path):
    mine, parents = tmp_path / ".a.json.1.tmp", tmp_path / ".b.json.2.tmp"
    mine.write_text("")
    parents.write_text("")
    atomic._TEMPORARIES.update({(os.getpid(), str(mine)), (os.getpid() + 1, str(parents))})
    try:
        assert atomic.remove_temporaries() == [str(mine)]
        assert not mine.exists() and parents.exists()  # a forked child spares its parent's file
    finally:
        atomic._TEMPORARIES.clear()


# ------------------------------------------------------------------------------ killed writes
def test_a_write_killed_outright_is_cleaned_by_the_next_run(tmp_path):
    model = tmp_path / "wall.glb"
    model.write_bytes(b"the old model")
    child = subprocess.Popen(
        [sys.executable, "-c", SLOW_WRITER, "build", "wall_windows.grammar", "-q", "-o",
         str(model)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path,
    )  # fmt: skip
    try:
        assert child.stdout.readline() == "writing\n"
        child.send_signal(signal.SIGKILL)  # no handler runs: the temporary file stays
        child.communicate(timeout=60)
    finally:
        child.kill()
    (left,) = tmp_path.glob(".*.tmp")
    assert left.name.startswith(f".wall.glb.{atomic._HOST}-{child.pid}.")
    assert model.read_bytes() == b"the old model"
    # another output in the same folder is the next write there: it sweeps the folder
    done = subprocess.run(
        [sys.executable, "-m", "shapegen", "build", "wall_windows.grammar", "-q", "-o",
         str(tmp_path / "other.json")],
        capture_output=True, text=True, cwd=tmp_path,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["other.json", "wall.glb"]


def test_only_abandoned_temporary_files_are_removed(tmp_path, monkeypatch):
    host = atomic._HOST
    alive = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    names = {
        "running": f".a.json.{host}-{alive.pid}.abc123_x.tmp",  # a write under way
        "mine": f".a.json.{host}-{os.getpid()}.abc123_x.tmp",
        "dead": f".a.json.{host}-{dead.pid}.abc123_x.tmp",
        "elsewhere": f".a.json.0a0b0c-{dead.pid}.abc123_x.tmp",  # another machine's writer
        "old elsewhere": f".b.json.0a0b0c-{dead.pid}.abc123_x.tmp",
        "not ours": f".a.json.{dead.pid}.tmp",
    }
    try:
        for name in names.values():
            (tmp_path / name).write_text("")
        old = time.time() - atomic.ABANDONED_SECONDS - 60
        os.utime(tmp_path / names["old elsewhere"], (old, old))
        removed = atomic.remove_abandoned(tmp_path)
    finally:
        alive.kill()
        alive.wait()
    assert sorted(removed) == sorted(str(tmp_path / names[k]) for k in ("dead", "old elsewhere"))
    kept = {p.name for p in tmp_path.iterdir()}
    assert kept == {names[k] for k in ("running", "mine", "elsewhere", "not ours")}
