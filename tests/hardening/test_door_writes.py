"""Killed writes leave nothing behind for good: a rule package's unpacking killed outright
(SIGKILL) leaves its staging folder, which the next unpacking into that cache removes."""

from __future__ import annotations

import io
import os
import subprocess
import sys

import py7zr

import shapegen
from shapegen.export.atomic import writer_name


def _package(path):
    buffer = io.BytesIO()
    with py7zr.SevenZipFile(buffer, "w") as archive:
        archive.writestr(b"Lot --> extrude(3)\n", "rules/main.cga")
        archive.writestr(b"compiled", "bin/main.cgb")
    path.write_bytes(buffer.getvalue())
    return path


def test_a_killed_unpackings_staging_folder_is_removed_by_the_next(tmp_path, package_cache):
    packages = package_cache / "packages"
    packages.mkdir(parents=True)
    ended = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                           capture_output=True, text=True, check=True)  # fmt: skip
    gone_pid = int(ended.stdout)
    host = writer_name().split("-")[0]
    killed = packages / f".unpacking-{host}-{gone_pid}-abcdefgh"
    (killed / "rules").mkdir(parents=True)
    (killed / "rules" / "half.cga").write_text("Lot --> extr")
    running = packages / f".unpacking-{host}-{os.getppid()}-abcdefgh"  # a live process's
    running.mkdir()
    grammar = shapegen.load_grammar(_package(tmp_path / "p.rpk"))
    assert grammar.build(lot=(12, 8)).volume > 0
    assert not killed.exists()
    assert running.exists()
    unpacked = [p.name for p in packages.iterdir() if p.name != running.name]
    assert len(unpacked) == 1 and unpacked[0].startswith("p-")
