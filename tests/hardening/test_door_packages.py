"""Hostile rule packages found by hand: what a package's rules read stays inside the package,
and imports that nest or multiply without end stop at a named limit, in one line."""

from __future__ import annotations

import io
import time

import py7zr
import pytest

from shapegen.cli import main
from shapegen.limits import work_limits

SECRET = "a line outside the package"


pytestmark = pytest.mark.usefixtures("package_cache")


def _package(tmp_path, members: dict, name: str = "p.rpk"):
    buffer = io.BytesIO()
    with py7zr.SevenZipFile(buffer, "w") as archive:
        for member, text in members.items():
            archive.writestr(text.encode(), member)
    path = tmp_path / name
    path.write_bytes(buffer.getvalue())
    return path


def _outside(tmp_path):
    """A file beside the cache, reached from a package's rules by ``../`` (5 levels up from
    ``cache/packages/p-.../rules/``)."""
    (tmp_path / "secret.txt").write_text(SECRET + "\n", encoding="utf-8")
    (tmp_path / "secret.cga").write_text("Lot --> extrude(1)\n", encoding="utf-8")
    (tmp_path / "secret.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", encoding="utf-8")
    return "../../../../"


@pytest.mark.parametrize(
    "body, warned",
    [
        ('const t = readTextFile("{up}secret.txt")\nLot --> print(t) extrude(3)\n',
         "readTextFile('{up}secret.txt'): the file not found"),
        ('Lot --> case fileExists("{up}secret.txt"): print("{secret}") extrude(3)\n'
         "    else: extrude(3)\n", None),
        ('Lot --> extrude(3) i("{up}secret.obj")\n', "asset '{up}secret.obj' not found"),
        ('const t = readStringTable("{up}secret.txt")\nLot --> print(t) extrude(3)\n',
         "readStringTable('{up}secret.txt'): the file not found"),
    ],
)  # fmt: skip
def test_a_package_reads_nothing_outside_itself(tmp_path, capsys, body, warned):
    up = _outside(tmp_path)
    rule = body.format(up=up, secret=SECRET)
    package = _package(tmp_path, {"rules/main.cga": rule, "bin/main.cgb": "compiled"})
    assert main(["build", str(package), "--lot", "12,8"]) == 0
    out = capsys.readouterr().out
    assert SECRET not in out
    if warned:
        assert warned.format(up=up) in out


def test_the_same_rule_outside_a_package_reads_beside_it(tmp_path, capsys):
    # the confinement is the package's: a rule file of a project still reads where it says
    _outside(tmp_path)
    rules = tmp_path / "project" / "rules"
    rules.mkdir(parents=True)
    (rules / "main.cga").write_text(
        'const t = readTextFile("../../secret.txt")\nLot --> print(t) extrude(3)\n',
        encoding="utf-8",
    )
    assert main(["build", str(rules / "main.cga"), "--lot", "12,8"]) == 0
    assert SECRET in capsys.readouterr().out


def test_a_package_imports_nothing_outside_itself(tmp_path, capsys):
    up = _outside(tmp_path)
    rule = f'import s:"{up}secret.cga"\nLot --> s.Lot\n'
    package = _package(tmp_path, {"rules/main.cga": rule, "bin/main.cgb": "compiled"})
    assert main(["build", str(package), "--lot", "12,8"]) == 2
    err = capsys.readouterr().err
    assert 'import of "../../../../secret.cga": it lies outside the rule package' in err


def test_a_package_imports_from_the_rules_path(tmp_path, capsys):
    library = tmp_path / "library" / "rules"
    library.mkdir(parents=True)
    (library / "base.cga").write_text("Mass --> extrude(2)\n", encoding="utf-8")
    rule = 'import b:"/library/rules/base.cga"\nLot --> b.Mass\n'
    package = _package(tmp_path, {"rules/main.cga": rule, "bin/main.cgb": "compiled"})
    argv = ["build", str(package), "--lot", "12,8", "--rules-path", str(tmp_path)]
    assert main(argv) == 0, capsys.readouterr().err
    assert "volume   192 m^3" in capsys.readouterr().out


def test_imports_that_double_at_every_level_stop_at_max_definitions(tmp_path, capsys):
    # each file imports the next twice under two prefixes: 2^30 definitions if nothing stopped
    members = {
        f"rules/l{d}.cga": f'import a:"l{d + 1}.cga"\nimport b:"l{d + 1}.cga"\nX --> NIL\n'
        for d in range(30)
    }
    members["rules/l30.cga"] = "X --> NIL\n"
    members["rules/main.cga"] = 'import a:"l0.cga"\nLot --> extrude(3)\n'
    members["bin/main.cgb"] = "compiled"
    package = _package(tmp_path, members)
    began = time.process_time()
    with work_limits(max_definitions=2000):
        assert main(["build", str(package), "--lot", "12,8"]) == 2
    assert time.process_time() - began < 30  # a guard against a hang, not a measure
    err = capsys.readouterr().err
    assert "the imports make more than 2000 definitions" in err
    assert "max_definitions" in err


def test_a_chain_of_imports_stops_at_max_import_depth(tmp_path, capsys):
    members = {f"rules/r{k}.cga": f'import n:"r{k + 1}.cga"\nLot --> n.Lot\n' for k in range(12)}
    members["rules/r12.cga"] = "Lot --> extrude(3)\n"
    members["bin/r0.cgb"] = "compiled"
    package = _package(tmp_path, members)
    with work_limits(max_import_depth=8):
        assert main(["build", str(package), "--lot", "12,8"]) == 2
    err = capsys.readouterr().err
    assert "the imports nest more than 8 files deep" in err and "max_import_depth" in err
    assert main(["build", str(package), "--lot", "12,8"]) == 0  # 13 files: within the default
