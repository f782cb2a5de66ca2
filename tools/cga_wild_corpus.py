"""Rebuild the wild corpus folder from git snapshots of its repositories, and add repositories.

``tests/data/cga-wild/README.md`` describes the corpus folder; this tool writes it. It reads
each repository of the manifest from a folder of git snapshots (``--snapshots DIR``, holding
``<owner>+<name>/`` with a git directory somewhere below: ``repo/``, ``repo/.git`` or the folder
itself) and writes, for each, the tree at the listed commit into ``<corpus>/<owner>+<name>/``,
and each earlier revision's tree into ``<owner>+<name>@<12 hex digits>/``: every ``.cga``
file, the assets under a rule's project folder, and every ``.rpk`` unpacked into
``<package path>.d/`` (compiled ``.cgb`` left out). Then it checks every manifest entry's
SHA-1 and prints the entries that are missing or differ::

    .venv/bin/python tools/cga_wild_corpus.py --snapshots /data/snapshots --corpus /work/cga-wild

A listed commit that the snapshot does not hold: the snapshot's head is used instead and said.

``--add owner/name`` (repeatable) adds repositories that the manifest does not hold: their
head is written to the corpus folder and one manifest entry per ``.cga`` file (and per ``.cga``
inside a rule package) is appended, with the fields the README lists; the licence is read from
the repository's ``LICENSE`` file (``--licence owner/name=SPDX`` overrides it) and the kind is
found from the text (see :func:`file_kind`). ``--holdout-part`` marks the added repositories as
part of the holdout (``tests/data/cga-wild/holdout.json``).
"""

from __future__ import annotations

import argparse
import hashlib
import io
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path, PurePosixPath

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "cga-wild"
MANIFEST = DATA / "manifest.json"
DEFAULT_CORPUS = Path("/work/cga-wild")
ASSET_LIMIT = 4_000_000
ASSET_EXTENSIONS = frozenset(
    ".obj .mtl .fbx .dae .glb .gltf .3ds .ply .stl .jpg .jpeg .png .tif .tiff .bmp .tga .gif "
    ".dds .hdr .exr .svg .csv .txt .json .xml .shp .dbf .shx .prj".split()
)


# ------------------------------------------------------------------------------------- git
def git_dir(snapshots: Path, repository: str) -> Path | None:
    """The git directory of ``repository``'s snapshot, or None."""
    folder = snapshots / repository.replace("/", "+")
    for candidate in (folder / "repo" / ".git", folder / "repo", folder / ".git", folder):
        if (candidate / "HEAD").is_file() and (candidate / "objects").is_dir():
            return candidate
    return None


def git(directory: Path, *args: str, binary: bool = False):
    done = subprocess.run(
        ["git", "--git-dir", str(directory), *args], capture_output=True, check=False
    )
    if done.returncode:
        raise RuntimeError(done.stderr.decode(errors="replace").strip())
    return done.stdout if binary else done.stdout.decode(errors="replace")


def has_commit(directory: Path, commit: str) -> bool:
    try:
        git(directory, "cat-file", "-e", f"{commit}^{{commit}}")
    except RuntimeError:
        return False
    return True


def tree_files(directory: Path, commit: str) -> list[tuple[str, str, int]]:
    """``(path, blob, size)`` of every file of ``commit``'s tree (links and submodules left
    out)."""
    out = git(directory, "ls-tree", "-r", "-l", "-z", commit, binary=True)
    files = []
    for row in out.split(b"\0"):
        if not row:
            continue
        meta, path = row.split(b"\t", 1)
        mode, kind, blob, size = meta.split()
        if kind != b"blob" or mode == b"120000" or not size.isdigit():
            continue  # a link, a submodule, or a blob the snapshot lacks (4 MB and more)
        files.append((path.decode("utf-8", errors="replace"), blob.decode(), int(size)))
    return files


def read_blobs(directory: Path, blobs: list[str]) -> dict[str, bytes]:
    """The content of each blob, through one ``git cat-file --batch``."""
    if not blobs:
        return {}
    request = "".join(f"{blob}\n" for blob in blobs).encode()
    done = subprocess.run(
        ["git", "--git-dir", str(directory), "cat-file", "--batch"],
        input=request,
        capture_output=True,
        check=True,
    )
    stream, contents = io.BytesIO(done.stdout), {}
    for blob in blobs:
        header = stream.readline().split()
        if len(header) < 3 or header[1] == b"missing":
            continue
        size = int(header[2])
        contents[blob] = stream.read(size)
        stream.read(1)
    return contents


# ---------------------------------------------------------------------------------- layout
def project_folder(path: str) -> PurePosixPath:
    """The folder that holds the rule's ``rules/`` folder (the nearest one), else the rule's
    own folder."""
    parts = PurePosixPath(path).parts[:-1]
    for k in range(len(parts) - 1, -1, -1):
        if parts[k].lower() == "rules":
            return PurePosixPath(*parts[:k])
    return PurePosixPath(*parts)


def within(path: str, folder: PurePosixPath) -> bool:
    return folder == PurePosixPath() or PurePosixPath(path).is_relative_to(folder)


def chosen_files(files: list[tuple[str, str, int]]) -> list[tuple[str, str, int]]:
    """The rule files, the packages and the assets under a rule's project folder."""
    rules = [f for f in files if f[0].lower().endswith((".cga", ".rpk"))]
    projects = {project_folder(path) for path, _, _ in rules}
    assets = [
        f
        for f in files
        if PurePosixPath(f[0]).suffix.lower() in ASSET_EXTENSIONS
        and f[2] <= ASSET_LIMIT
        and any(within(f[0], folder) for folder in projects)
    ]
    return rules + assets


def unpack_package(data: bytes, target: Path) -> list[str]:
    """Unpack a rule package (7z) into ``target``; the members written (``.cgb`` left out)."""
    import py7zr

    written = []
    try:
        with py7zr.SevenZipFile(io.BytesIO(data)) as archive:
            names = [n for n in archive.getnames() if not n.lower().endswith(".cgb")]
            archive.extract(path=target, targets=names)
    except Exception as exc:  # noqa: BLE001 - a broken package is reported and skipped
        print(f"    cannot unpack a package into {target}: {exc}", file=sys.stderr)
        return written
    for out in sorted(target.rglob("*")):
        if out.is_file():
            written.append(out.relative_to(target).as_posix())
    return written


def write_tree(directory: Path, commit: str, target: Path) -> dict[str, list[str]]:
    """Write the chosen files of ``commit`` into ``target``; ``{package path: members}``."""
    files = chosen_files(tree_files(directory, commit))
    contents = read_blobs(directory, sorted({blob for _, blob, _ in files}))
    packages = {}
    for path, blob, _ in files:
        if blob not in contents:
            continue
        out = target / path
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_bytes(contents[blob])
        if path.lower().endswith(".rpk"):
            packages[path] = unpack_package(contents[blob], target / f"{path}.d")
    return packages


# -------------------------------------------------------------------------------- rebuild
def load(path: Path) -> dict:
    return json.loads(path.read_text(encoding="utf-8"))


def rebuild(manifest: dict, snapshots: Path, corpus: Path, only: str | None) -> int:
    """Write the corpus folder for the manifest's repositories; the number of problems."""
    problems = 0
    for repo in manifest["repositories"]:
        name = repo["repository"]
        if only and only not in name:
            continue
        directory = git_dir(snapshots, name)
        if directory is None:
            print(f"{name}: no snapshot in {snapshots}", file=sys.stderr)
            problems += 1
            continue
        entries = [f for f in manifest["files"] if f["repository"] == name]
        trees = {repo["commit"]: name.replace("/", "+")}
        for entry in entries:
            if entry.get("revision") == "history":
                trees[entry["commit"]] = f"{name.replace('/', '+')}@{entry['commit'][:12]}"
        for commit, folder in trees.items():
            used = commit
            if not has_commit(directory, commit):
                used = git(directory, "rev-parse", "HEAD").strip()
                print(f"{name}: commit {commit[:12]} not in the snapshot: its head {used[:12]}")
            target = corpus / folder
            if target.exists():
                shutil.rmtree(target)
            write_tree(directory, used, target)
        print(f"{name}: {len(trees)} tree(s) written", file=sys.stderr)
    return problems + verify(manifest, corpus, only)


def verify(manifest: dict, corpus: Path, only: str | None) -> int:
    bad = 0
    for entry in manifest["files"]:
        if only and only not in entry["repository"]:
            continue
        path = corpus / entry["local"]
        if not path.is_file():
            print(f"missing: {entry['local']}")
            bad += 1
        elif hashlib.sha1(path.read_bytes()).hexdigest() != entry["sha1"]:
            print(f"differs: {entry['local']}")
            bad += 1
    return bad


# ------------------------------------------------------------------------- new repositories
_COMMENTS = re.compile(r"/\*.*?\*/|//[^\n]*|#[^\n]*", re.S)
_RULE = re.compile(
    r"^[ \t]*(?:@\w+(?:\([^)\n]*\))?[ \t]*)*(?P<name>[A-Za-z_][\w.]*)[ \t]*"
    r"(?P<params>\([^)\n]*\))?[ \t]*-->",
    re.M,
)
_IMPORT = re.compile(r'^[ \t]*import[ \t]+\w+[ \t]*:[ \t]*"([^"]+)"', re.M)
_GENERATED = re.compile(r"automatically generated|generated by|facade wizard", re.I)


def file_kind(text: str, imported: bool) -> tuple[str, str | None]:
    """``(kind, family)`` of a rule file, as the README defines the kinds.

    ``generated``: its first line says a program wrote it. ``library``: no rule without
    parameters, or a file other files import that has no ``@StartRule``. Else ``rule``.
    """
    first = text.lstrip("\ufeff").splitlines()[0] if text.strip() else ""
    if _GENERATED.search(first):
        return "generated", "header: automatically generated"
    code = _COMMENTS.sub(" ", text)
    plain = [m for m in _RULE.finditer(code) if not (m.group("params") or "").strip("() \t")]
    if not plain:
        return "library", None
    if imported and "@StartRule" not in code:
        return "library", None
    return "rule", None


def licence_of(directory: Path, commit: str) -> str:
    """An SPDX identifier read from the repository's licence file, ``none`` without one."""
    files = [f for f in tree_files(directory, commit) if "/" not in f[0]]
    licences = [f for f in files if re.match(r"(?i)(licen[cs]e|copying)(\.\w+)?$", f[0])]
    if not licences:
        return "none"
    text = read_blobs(directory, [licences[0][1]])[licences[0][1]].decode(errors="replace")
    marks = [
        ("Apache License", "Apache-2.0"),
        ("MIT License", "MIT"),
        ("Permission is hereby granted, free of charge", "MIT"),
        ("GNU GENERAL PUBLIC LICENSE", "GPL-3.0" if "Version 3" in text else "GPL-2.0"),
        ("GNU LESSER GENERAL PUBLIC", "LGPL-3.0"),
        ("Mozilla Public License", "MPL-2.0"),
        ("Attribution-NonCommercial", "CC-BY-NC-4.0"),
        ("Creative Commons Attribution", "CC-BY-4.0"),
        ("BSD 3-Clause", "BSD-3-Clause"),
        ("Redistribution and use in source and binary forms", "BSD-3-Clause"),
        ("The Unlicense", "Unlicense"),
        ("This is free and unencumbered", "Unlicense"),
    ]
    for mark, spdx in marks:
        if mark.lower() in text.lower():
            return spdx
    return "other"


def add_repository(
    manifest: dict, snapshots: Path, corpus: Path, name: str, licence: str | None
) -> list[dict]:
    """Write ``name``'s head into the corpus and append its entries to the manifest."""
    if any(r["repository"] == name for r in manifest["repositories"]):
        raise SystemExit(f"{name} is in the manifest already")
    directory = git_dir(snapshots, name)
    if directory is None:
        raise SystemExit(f"{name}: no snapshot in {snapshots}")
    commit = git(directory, "rev-parse", "HEAD").strip()
    licence = licence or licence_of(directory, commit)
    folder = name.replace("/", "+")
    target = corpus / folder
    if target.exists():
        shutil.rmtree(target)
    packages = write_tree(directory, commit, target)
    rule_paths = sorted(
        p for p, _, _ in tree_files(directory, commit) if p.lower().endswith(".cga")
    )
    found: list[tuple[str, str | None, Path]] = [(p, None, target / p) for p in rule_paths]
    for package, members in sorted(packages.items()):
        for member in sorted(m for m in members if m.lower().endswith(".cga")):
            found.append((package, member, target / f"{package}.d" / member))
    texts = {local: local.read_text(encoding="utf-8", errors="replace") for *_, local in found}
    imported_names = {
        PurePosixPath(target_path).name.lower()
        for text in texts.values()
        for target_path in _IMPORT.findall(_COMMENTS.sub(" ", text))
    }
    if not found:
        shutil.rmtree(target)
        raise SystemExit(f"{name}: no rule file (.cga, or .cga inside a rule package) at its head")
    # a content the manifest holds already is listed as a duplicate of its first entry
    seen = {e["sha1"]: e["local"] for e in reversed(manifest["files"]) if not e.get("duplicate_of")}
    entries = []
    for path, member, local in found:
        data = local.read_bytes()
        sha1 = hashlib.sha1(data).hexdigest()
        kind, family = file_kind(texts[local], local.name.lower() in imported_names)
        relative = str(local.relative_to(corpus))
        entry = {
            "repository": name,
            "path": path,
            **({"member": member} if member else {}),
            "local": relative,
            "revision": "head",
            "commit": commit,
            "sha1": sha1,
            "size": len(data),
            "licence": licence,
            "kind": kind,
        }
        if family:
            entry["family"] = f"{relative} ({family})"
        if sha1 in seen:
            entry["duplicate_of"] = seen[sha1]
        else:
            seen[sha1] = relative
        entries.append(entry)
    manifest["repositories"].append({"repository": name, "commit": commit, "licence": licence})
    manifest["files"].extend(entries)
    return entries


def write_manifest(manifest: dict, path: Path) -> None:
    """The manifest as it is kept: one repository and one file a line."""
    lines = ["{"]
    for key, value in manifest.items():
        if key not in ("repositories", "files"):
            lines.append(f" {json.dumps(key)}: {json.dumps(value, ensure_ascii=False)},")
    for key in ("repositories", "files"):
        rows = [f"  {json.dumps(row, ensure_ascii=False)}" for row in manifest[key]]
        lines.append(f' "{key}": [')
        lines.append(",\n".join(rows))
        lines.append(" ]," if key == "repositories" else " ]")
    lines.append("}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--snapshots", required=True, help="folder of <owner>+<name>/ git dirs")
    parser.add_argument("--corpus", default=str(DEFAULT_CORPUS), help="the corpus folder")
    parser.add_argument("--manifest", default=str(MANIFEST), help="the manifest JSON")
    parser.add_argument("--only", help="the repositories whose name contains this")
    parser.add_argument("--add", action="append", default=[], help="add owner/name's head")
    parser.add_argument("--licence", action="append", default=[], help="owner/name=SPDX")
    args = parser.parse_args(argv)
    snapshots, corpus, manifest_path = Path(args.snapshots), Path(args.corpus), Path(args.manifest)
    manifest = load(manifest_path)
    corpus.mkdir(parents=True, exist_ok=True)
    if args.add:
        licences = dict(item.split("=", 1) for item in args.licence)
        for name in args.add:
            entries = add_repository(manifest, snapshots, corpus, name, licences.get(name))
            kinds = ", ".join(f"{e['kind']} {e['local']}" for e in entries)
            print(f"{name}: {len(entries)} file(s): {kinds}")
        write_manifest(manifest, manifest_path)
        return 0
    problems = rebuild(manifest, snapshots, corpus, args.only)
    print(f"{problems} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
