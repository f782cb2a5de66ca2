"""The wild corpus tools: the folder rebuilt from git snapshots, the holdout reported apart.

tools/cga_wild_corpus.py writes the corpus folder from git snapshots; tools/cga_wild.py reports
the rate of the parts kept out of sight (tests/data/cga-wild/holdout.json) apart from the rest.
"""

from __future__ import annotations

import hashlib
import importlib.util
import io
import json
import subprocess
import sys
from pathlib import Path

import pytest

_TOOLS = Path(__file__).resolve().parents[2] / "tools"
_DATA = Path(__file__).resolve().parents[1] / "data" / "cga-wild"


def _load(name: str):
    spec = importlib.util.spec_from_file_location(name, _TOOLS / f"{name}.py")
    module = sys.modules[name] = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


wild = _load("cga_wild")
corpus_tool = _load("cga_wild_corpus")


def _git(folder: Path, *args: str) -> str:
    command = ["git", "-C", str(folder), "-c", "user.name=t", "-c", "user.email=t@t", *args]
    return subprocess.run(command, capture_output=True, text=True, check=True).stdout.strip()


def _package(files: dict[str, bytes]) -> bytes:
    py7zr = pytest.importorskip("py7zr")
    buffer = io.BytesIO()
    with py7zr.SevenZipFile(buffer, "w") as archive:
        for name, data in files.items():
            archive.writestr(data, name)
    return buffer.getvalue()


def test_the_manifest_is_written_back_as_it_is_kept(tmp_path):
    manifest = corpus_tool.load(_DATA / "manifest.json")
    out = tmp_path / "manifest.json"
    corpus_tool.write_manifest(manifest, out)
    assert out.read_bytes() == (_DATA / "manifest.json").read_bytes()


def test_the_holdout_is_whole_repositories_of_the_manifest():
    manifest = corpus_tool.load(_DATA / "manifest.json")
    names = {repo["repository"] for repo in manifest["repositories"]}
    holdout = json.loads((_DATA / "holdout.json").read_text(encoding="utf-8"))
    drawn, new = set(holdout["repositories"]), set(holdout["new_repositories"])
    assert drawn <= names and new <= names and not drawn & new
    assert len(drawn) == round(38 / 5)


def test_a_repository_is_rebuilt_and_added_from_its_snapshot(tmp_path):
    repo = tmp_path / "snapshots" / "someone+city"
    (repo / "project" / "rules").mkdir(parents=True)
    (repo / "project" / "assets").mkdir()
    rule = b'version "2019.0"\n@StartRule\nLot --> extrude(10) Mass\n'
    library = b'import L : "lib.cga"\nattr h = 3\nStep(n) --> X\n'
    (repo / "project" / "rules" / "city.cga").write_bytes(rule)
    (repo / "project" / "rules" / "lib.cga").write_bytes(library)
    (repo / "project" / "assets" / "wall.obj").write_bytes(b"v 0 0 0\n")
    (repo / "elsewhere.obj").write_bytes(b"v 1 1 1\n")  # outside every project folder
    packed = _package({"rules/packed.cga": rule, "bin/packed.cgb": b"\0compiled"})
    (repo / "project" / "rules" / "packed.rpk").write_bytes(packed)
    _git(repo, "init", "-q")
    _git(repo, "add", "-A")
    _git(repo, "commit", "-q", "-m", "rules")
    corpus = tmp_path / "corpus"
    manifest = {"corpus": "test", "repositories": [], "files": []}

    entries = corpus_tool.add_repository(
        manifest, tmp_path / "snapshots", corpus, "someone/city", None
    )

    head = _git(repo, "rev-parse", "HEAD")
    by_path = {(e["path"], e.get("member")): e for e in entries}
    assert set(by_path) == {
        ("project/rules/city.cga", None),
        ("project/rules/lib.cga", None),
        ("project/rules/packed.rpk", "rules/packed.cga"),
    }
    assert by_path["project/rules/city.cga", None]["kind"] == "rule"
    assert by_path["project/rules/lib.cga", None]["kind"] == "library"
    packed_entry = by_path["project/rules/packed.rpk", "rules/packed.cga"]
    assert packed_entry["duplicate_of"] == "someone+city/project/rules/city.cga"
    assert all(e["commit"] == head and e["licence"] == "none" for e in entries)
    assert (corpus / "someone+city/project/assets/wall.obj").is_file()
    assert not (corpus / "someone+city/elsewhere.obj").exists()
    assert not (corpus / "someone+city/project/rules/packed.rpk.d/bin/packed.cgb").exists()
    assert manifest["repositories"] == [
        {"repository": "someone/city", "commit": head, "licence": "none"}
    ]

    # the rebuild writes the same files at the listed commit, and checks their SHA-1
    rebuilt = tmp_path / "rebuilt"
    assert corpus_tool.rebuild(manifest, tmp_path / "snapshots", rebuilt, None) == 0
    for entry in entries:
        data = (rebuilt / entry["local"]).read_bytes()
        assert hashlib.sha1(data).hexdigest() == entry["sha1"]
    (rebuilt / entries[0]["local"]).write_bytes(b"changed")
    assert corpus_tool.verify(manifest, rebuilt, None) == 1


def _record(repository, outcome, sha1, kind="rule"):
    return {
        "repository": repository,
        "local": f"{repository}/{sha1}.cga",
        "path": "x.cga",
        "sha1": sha1,
        "kind": kind,
        "outcome": outcome,
    }


def test_the_hidden_parts_are_reported_apart_and_copies_of_seen_files_are_not_unseen(capsys):
    entries = [
        _record("a/seen", "derives", "1"),
        _record("a/seen", "error", "2"),
        _record("b/held", "derives", "1"),  # the same content as a seen file
        _record("b/held", "error", "3"),
        _record("c/new", "derives", "4", kind="generated"),
        _record("c/new", "derives", "5"),  # a content the project's own tests hold
    ]
    for entry in entries[1:4:2]:
        entry["message"] = "x.cga:1:1: unexpected 'case'; expected an expression"
    marked = wild.mark_parts(entries, {"b/held": "holdout", "c/new": "new"}, {"5"})
    assert [r["part"] for r in marked] == ["seen", "seen", "holdout", "holdout", "new", "new"]
    assert [r.get("unseen") for r in marked] == [None, None, False, True, True, False]
    lines = wild.part_lines(marked)
    assert "seen: the measure: 1 / 2 derive (50.0 %)" in lines
    assert "holdout: the measure: 1 / 2 derive (50.0 %)" in lines
    assert "new: the measure outside generated families: 1 / 1 derive (100.0 %)" in lines
    assert (
        "unseen files (holdout and new, content in no seen repository): 1 / 2 derive (50.0 %)"
        in lines
    )
    assert [r["local"] for r in wild.runnable(marked, None, "hidden")] == [
        r["local"] for r in marked[2:]
    ]

    wild.print_summary(marked, Path("/corpus"), top=10, reveal=False)
    shown = capsys.readouterr().out
    assert "b/held" not in shown and "c/new" not in shown  # no row, no failure example
    assert "1 files (with it: 1)" in shown  # the seen failure is listed
    wild.print_summary(marked, Path("/corpus"), top=10, reveal=True)
    assert "b/held" in capsys.readouterr().out
