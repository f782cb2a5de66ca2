"""Fuzzing the ``.cga`` door with real rule files made wrong: each input is a file of the corpus
(tests/data/cga-corpus) with a few mutations of its tokens (a token deleted, two swapped, one
doubled, random unicode put in, a number made extreme, a brace or a nesting repeated deep),
loaded from a copy of the file's package (so its imports resolve) and derived on a 12 x 8 m lot in a
forked child capped at 20 s of CPU and 4 GiB.

Every input must end cleanly: a model (the warnings CityEngine's runtime gives are fine) or one
ShapegenError; never a traceback, past the caps or hung. The campaign's seed is printed and
every input comes from its number and the seed:
``python tests/fuzz/test_fuzz_cga_mutations.py 2000 SEED`` runs a campaign,
``python tests/fuzz/test_fuzz_cga_mutations.py replay SEED NUMBER`` prints and runs one input.
The slow lane runs 300 inputs a run (a few minutes); the figure of a 2 000-input campaign is in
docs/cga-compatibility.md. ``SHAPEGEN_FUZZ_CGA_CORPUS=FOLDER`` mutates the rule files of another
folder (one folder a repository) instead.
"""

from __future__ import annotations

import functools
import itertools
import os
import random
import re
import shutil
import sys
import tempfile
from pathlib import Path

import pytest
from fuzz_sandbox import fuzz_seed, print_figures, run_campaign

CORPUS = Path(__file__).resolve().parents[1] / "data" / "cga-corpus"
# Another folder of rule files, one folder a repository (SHAPEGEN_FUZZ_CGA_CORPUS): files of
# repositories too large to copy for each input are derived from a copy of the file alone, with
# the file's folder and its repository on the rules path (where their imports and assets are).
OTHER_CORPUS = os.environ.get("SHAPEGEN_FUZZ_CGA_CORPUS")
COPIED_FILES, COPIED_BYTES = 2000, 100 * 2**20  # a repository of more is not copied
CPU_SECONDS = 20
DERIVATION_SECONDS = 8
MEMORY_BYTES = 4 * 2**30
SLOW_LANE_INPUTS = 300

TOKEN = re.compile(
    r"\s+|//[^\n]*|/\*.*?\*/|\"(?:\\.|[^\"\\])*\"|\d+(?:\.\d*)?(?:e[-+]?\d+)?|\w+|.", re.S
)
EXTREME = ["1e308", "-1e308", "(0/0)", "1e-320", "1e18", "-0", "4096", "99999999999"]
UNICODE = ["\u00e9", "\u200b", "\ufeff", "\U0001f600", "\u202e", "\x00", "\u2028", "\ud7ff"]
MUTATIONS = ("delete", "swap", "double", "unicode", "extreme", "deep")


def corpus() -> Path:
    return Path(OTHER_CORPUS).resolve() if OTHER_CORPUS else CORPUS


@functools.cache
def corpus_files() -> list[Path]:
    return sorted(corpus().rglob("*.cga"))


@functools.cache
def _copied(repository: Path) -> bool:
    """Whether a repository of the corpus is small enough to copy for each input."""
    files = list(itertools.islice(repository.rglob("*"), COPIED_FILES + 1))
    size = sum(f.stat().st_size for f in files if f.is_file() and not f.is_symlink())
    return len(files) <= COPIED_FILES and size <= COPIED_BYTES


def mutated(seed: int, number: int) -> tuple[Path, str]:
    """The corpus file input ``number`` of campaign ``seed`` mutates, and its mutated text."""
    draw = random.Random(f"{seed}/{number}")
    path = draw.choice(corpus_files())
    tokens = TOKEN.findall(path.read_text(encoding="utf-8", errors="replace"))
    for _ in range(draw.randint(1, 4)):
        _mutate(tokens, draw)
    return path, "".join(tokens)


def _mutate(tokens: list[str], draw: random.Random) -> None:
    if not tokens:
        return
    k = draw.randrange(len(tokens))
    kind = draw.choice(MUTATIONS)
    if kind == "delete":
        del tokens[k]
    elif kind == "swap":
        j = draw.randrange(len(tokens))
        tokens[k], tokens[j] = tokens[j], tokens[k]
    elif kind == "double":
        tokens.insert(k, tokens[k])
    elif kind == "unicode":
        tokens.insert(k, draw.choice(UNICODE))
    elif kind == "extreme":
        numbers = [i for i, t in enumerate(tokens) if t[:1].isdigit()]
        if numbers:
            tokens[draw.choice(numbers)] = draw.choice(EXTREME)
    else:  # a nesting repeated deep: a block, a bracket or a parenthesis opened many times
        opener = draw.choice(["{", "(", "[", "split(x) { 1 : "])
        tokens.insert(k, opener * draw.choice([50, 500, 5000]))


def derive(item: tuple[str, str]) -> None:
    """What a child does with one input: the file's package copied to a folder of its own (the
    corpus is never written to), the file replaced by its mutated text, loaded and derived."""
    import shapegen
    from shapegen.limits import work_limits

    original, text, copied = item
    relative = Path(original).relative_to(corpus())
    repository = corpus() / relative.parts[0]
    with tempfile.TemporaryDirectory() as folder:
        if copied:
            shutil.copytree(repository, Path(folder) / relative.parts[0], symlinks=True)
            path, rules_path = Path(folder) / relative, ()
        else:
            path, rules_path = Path(folder) / relative.name, (Path(original).parent, repository)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8", errors="surrogatepass")
        with work_limits(max_seconds=DERIVATION_SECONDS):
            shapegen.load_grammar(path, rules_path).build(lot=(12.0, 8.0))


def campaign(seed: int, count: int, *, progress: bool = False) -> dict:
    """Run ``count`` inputs of campaign ``seed``; the figures and the failures."""
    from fuzz_inputs import warm_up

    warm_up()

    def inputs():
        for number in range(count):
            path, text = mutated(seed, number)
            copied = _copied(corpus() / path.relative_to(corpus()).parts[0])
            yield f"seed {seed} input {number} ({path.name})", derive, (str(path), text, copied)

    return run_campaign(
        inputs(), cpu_seconds=CPU_SECONDS, memory_bytes=MEMORY_BYTES, progress=progress
    )


@pytest.mark.slow
def test_mutated_corpus_files_end_cleanly():
    seed = fuzz_seed()
    print(f"cga mutation fuzz seed {seed}")
    figures = campaign(seed, SLOW_LANE_INPUTS)
    print(figures)
    shown = "\n".join(figures["failures"][:10])
    assert not figures["failures"], f"{len(figures['failures'])} inputs failed:\n{shown}"
    assert figures["peak_mib"][0] <= MEMORY_BYTES / 2**20


def test_the_mutations_are_replayable_and_of_every_kind():
    texts = [mutated(3, n) for n in range(60)]
    assert texts == [mutated(3, n) for n in range(60)]
    originals = {path: path.read_text(encoding="utf-8", errors="replace") for path, _ in texts}
    assert sum(text != originals[path] for path, text in texts) >= 55  # mutated, not copied
    assert len({path for path, _ in texts}) > 10  # drawn from across the corpus


def _main(argv: list[str]) -> None:
    if argv and argv[0] == "replay":
        path, text = mutated(int(argv[1]), int(argv[2]))
        print(f"// mutated {path}\n{text}")
        derive((str(path), text, _copied(corpus() / path.relative_to(corpus()).parts[0])))
        return
    count = int(argv[0]) if argv else 2000
    seed = int(argv[1]) if len(argv) > 1 else random.randrange(10**6)
    print(f"cga mutation fuzz seed {seed}")
    print_figures(campaign(seed, count, progress=True), shown=20)


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).parent))
    _main(sys.argv[1:])
