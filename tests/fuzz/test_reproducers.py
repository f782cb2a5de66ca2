"""Every reported input that ran without bound or ended in a traceback now answers with one line
naming the problem (and, from the command, exit status 2 and no output file), or works where it
is valid and small.

The library cases run in a forked child capped at 10 s of CPU and 2 GiB
(tests/fuzz/fuzz_sandbox.py), so a regression fails here instead of hanging the suite. How fast
each one answers is a measured figure (docs/journal/performance.md, "Bounded work"), not asserted
here: a timed assert would fail on a loaded machine and pass a slow regression on a fast one.
"""

from __future__ import annotations

import json
import os
import random
import re
import subprocess
import sys

import pytest
from fuzz_sandbox import run_limited

import shapegen
from shapegen.readers.models import read_model

# the recursion reads the shape, so each call is made (a function of its arguments alone keeps
# its values, engine/expressions' _remembered: PURE_DOUBLING answers at once)
DOUBLING = "f(n) = case n > 0 : f(n - 1) + f(n - 1) else : scope.sx / 10\n"
PURE_DOUBLING = "f(n) = case n > 0 : f(n - 1) + f(n - 1) else : 1\n"
STRINGS = 'd(x) = x + x\ns(n) = case n > 0 : d(s(n - 1)) else : "x"\n'


def _rule(body: str, head: str = "") -> str:
    return f"{head}@StartRule @Lot(10, 1)\nLot --> extrude(5) {body}\n"


def _build(text: str, **kwargs) -> None:
    shapegen.parse_grammar(text).build(**kwargs)


def _unit_cube_json(x0: float) -> dict:
    vertices = [[x0 + x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    faces = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    block = {"id": "a", "vertices": vertices, "faces": faces}
    return {"format": "shapegen-blocks", "version": 1, "blocks": [block]}


def _json_with(coordinate: str) -> str:
    return (
        '{"format": "shapegen-blocks", "version": 1, "blocks": [{"id": "a", "vertices": '
        f"[[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, {coordinate}]]}}]}}"
    )


def _many_blocks(count: int) -> str:
    block = '{{"id": "b{k}", "vertices": [[{x}, 0, 0], [{x1}, 0, 0], [{x}, 1, 0], [{x}, 0, 1]]}}'
    blocks = ", ".join(block.format(k=k, x=2 * k, x1=2 * k + 1) for k in range(count))
    return f'{{"format": "shapegen-blocks", "version": 1, "blocks": [{blocks}]}}'


# (name, what comes before the start rule, its operations, pattern of the one line)
RULE_CASES = [
    ("doubling recursion", DOUBLING, "t(f(40), 0, 0) A", r"max_calls"),
    ("pure doubling recursion", PURE_DOUBLING, "t(f(40), 0, 0) A",
     r"reaches 1.1e\+12 m.*max_coordinate"),
    ("string growth", STRINGS, 'report("k", s(40))', r"max_string_length"),
    ("arch segments 1e7", "", 'i("arch", segments = 10000000)',
     r"'segments' is 1e\+07.*max_primitive_blocks"),
    ("dome 2000 x 2000", "", 'i("dome", rings = 2000, meridians = 2000)',
     r"4e\+06 blocks \(rings x meridians\).*max_primitive_blocks"),
    ("column courses 1e7", "", 'i("column", courses = 10000000)',
     r"'courses'.*max_primitive_blocks"),
    ("wall block_length 1e-9", "", 'i("wall", block_length = 1e-9)',
     r"primitive 'wall' would make .* blocks.*max_primitive_blocks"),
    ("arch segments 1e16", "", 'i("arch", segments = 1e16)', r"'segments' is 1e\+16"),
    ("barrel courses 1e308", "", 'i("barrel_vault", courses = 1e308)', r"'courses' is 1e\+308"),
    ("split 5e-324", "", "split(x) { 5e-324 : A }*", r"max_shapes"),
    ("floating split 5e-324", "", "split(x) { ~5e-324 : A }*", r"max_shapes"),
    ("fmod of infinity", "attr a = (0 - 1e308 * 10) % 2\n", "A", r"-inf % 2 is not defined"),
]  # fmt: skip

# (name, what to run, pattern of the one line; None: it must work)
LIBRARY_CASES = [
    (name, lambda head=head, body=body: _build(_rule(body, head)), pattern)
    for name, head, body, pattern in RULE_CASES
] + [
    ("5 MB expression", lambda: shapegen.parse_grammar("attr a = " + "1 + " * 1_250_000 + "1"),
     r"more than 100000 tokens.*max_definition_tokens"),
    ("12 MB source", lambda: shapegen.parse_grammar("// " + "x" * 12_000_000),
     r"12000003 characters.*max_source_chars"),
    ("lot 10**400", lambda: _build(_rule("A"), lot=(10**400, 1)),
     r"lot width and depth must be finite numbers > 0 m, got inf x 1"),
    ("density 10**400", lambda: _build(_rule("A"), attrs={"density": 10**400}),
     r"'density' must be a finite number, got an integer of 400 digits"),
    ("valid and small", lambda: _build(_rule('i("dome", rings = 4, meridians = 8)')), None),
]  # fmt: skip


@pytest.mark.parametrize(
    ("case", "pattern"),
    [(run, pattern) for _, run, pattern in LIBRARY_CASES],
    ids=[name for name, _, _ in LIBRARY_CASES],
)
def test_library_reproducer_answers_in_one_line(case, pattern):
    outcome = run_limited(lambda _: case(), None)
    assert outcome.kind == "clean", outcome.detail
    if pattern is None:
        assert outcome.detail == ""
    else:
        assert outcome.detail, "expected a ShapegenError"
        assert "\n" not in outcome.detail
        assert re.search(pattern, outcome.detail), outcome.detail


def _write(path, content) -> str:
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content)
    return str(path)


def _random_bytes(count: int) -> bytes:
    rng = random.Random(7)
    return bytes(rng.getrandbits(8) for _ in range(count))


FILE_CASES = [
    ("nested 100 000 deep", "deep.json", "[" * 100_000 + "]" * 100_000, r"nests too deeply"),
    ("coordinate 10**400", "huge.json", _json_with("1" + "0" * 400), r"must be a finite number"),
    ("5 000-digit integer", "digits.json", _json_with("7" * 5000), r"must be a finite number"),
    ("OBJ with a nan vertex", "nan.obj",
     "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 nan\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n",
     r"finite numbers"),
    ("random bytes as .obj", "random.obj", _random_bytes(5000), r"not \.obj text"),
    ("random bytes as .stl", "random.stl", _random_bytes(5000), r"neither a binary STL"),
    ("cube at x = 1e10", "far.json", json.dumps(_unit_cube_json(1e10)), None),
]  # fmt: skip


@pytest.mark.parametrize(
    ("name", "content", "pattern"),
    [(name, content, pattern) for _, name, content, pattern in FILE_CASES],
    ids=[case for case, _, _, _ in FILE_CASES],
)
def test_model_file_reproducer_answers_in_one_line(tmp_path, name, content, pattern):
    path = _write(tmp_path / name, content)
    outcome = run_limited(lambda _: read_model(path), None)
    assert outcome.kind == "clean", outcome.detail
    if pattern is None:
        assert outcome.detail == ""
    else:
        assert re.search(pattern, outcome.detail), outcome.detail


def test_a_model_of_215_000_blocks_is_refused_within_the_caps(tmp_path):
    path = _write(tmp_path / "many.json", _many_blocks(215_000))
    outcome = run_limited(lambda _: read_model(path), None)
    assert outcome.kind == "clean", outcome.detail
    assert "max_file_bytes" in outcome.detail or "max_blocks" in outcome.detail


def test_the_block_limit_of_a_model_file_names_itself(tmp_path):
    from shapegen.limits import work_limits

    path = _write(tmp_path / "some.json", _many_blocks(30))

    def read_under_a_small_limit(_):
        with work_limits(max_blocks=20):
            read_model(path)

    outcome = run_limited(read_under_a_small_limit, None)
    assert "the model has 30 blocks, more than 20" in outcome.detail
    assert "max_blocks" in outcome.detail


def _shapegen(*args: str, cwd) -> tuple[int, str, str]:
    done = subprocess.run(
        [sys.executable, "-m", "shapegen", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=120,
        env={**os.environ, "COLUMNS": "200"},
    )
    return done.returncode, done.stdout, done.stderr


def _special_file(tmp_path, kind: str) -> str:
    path = tmp_path / "model.json"
    if kind == "fifo":
        os.mkfifo(path)
    else:
        path.symlink_to("/dev/zero")
    return path.name


CLI_CASES = [
    ("--set arch_segments=1e16",
     lambda tmp: ["build", "wall_windows.grammar", "--set", "arch_segments=1e16"],
     r"'segments' is 1e\+16"),
    ("--set windows=1 and 400 zeros",
     lambda tmp: ["build", "wall_windows.grammar", "--set", "windows=1" + "0" * 400],
     r"expected a finite number"),
    ("a FIFO named .json", lambda tmp: ["analyze", _special_file(tmp, "fifo")],
     r"not a model file"),
    ("/dev/zero named .json", lambda tmp: ["analyze", _special_file(tmp, "zero")],
     r"not a model file"),
]  # fmt: skip


@pytest.mark.parametrize(
    ("arguments", "pattern"),
    [(arguments, pattern) for _, arguments, pattern in CLI_CASES],
    ids=[name for name, _, _ in CLI_CASES],
)
def test_command_reproducer_exits_2_with_one_line(tmp_path, arguments, pattern):
    out = tmp_path / "out.glb"
    code, stdout, stderr = _shapegen(*arguments(tmp_path), "-o", str(out), cwd=tmp_path)
    assert code == 2, stderr
    assert "Traceback" not in stderr
    errors = [line for line in stderr.splitlines() if line.startswith("shapegen: error:")]
    assert len(errors) == 1, stderr
    assert re.search(pattern, errors[0]), errors[0]
    assert not out.exists()
