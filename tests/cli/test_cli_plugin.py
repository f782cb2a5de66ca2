"""``--plugin``: a primitive of one's own, written as docs/primitives.md shows, used from the
command line without packaging it; and what an unknown primitive's error says."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import pytest

from shapegen import plugins
from shapegen.cli import main
from shapegen.primitives import available, registry

# A stepped pier of three boxes, each 0.1 sx narrower on every side than the one below.
PIERS_PY = '''
import numpy as np

from shapegen import Block, Scope
from shapegen.primitives import primitive


@primitive("stepped_pier", scope_relative=True)
def stepped_pier(scope: Scope, *, steps: int = 3) -> list[Block]:
    """A pier of ``steps`` boxes, each narrower than the one below."""
    blocks = []
    for k in range(steps):
        inset = 0.1 * k * scope.sx
        y0, y1 = k * scope.sy / steps, (k + 1) * scope.sy / steps
        corners = [(x, y, z) for x in (inset, scope.sx - inset) for y in (y0, y1)
                   for z in (inset, scope.sz - inset)]
        blocks.append(Block.from_hull(scope.to_world(np.array(corners, float))))
    return blocks
'''

PIERS_GRAMMAR = """\
@StartRule @Lot(2, 2)
Lot --> extrude(3) Pier
Pier --> i("stepped_pier", steps = 3)
"""


@pytest.fixture
def own_registry(monkeypatch):
    """The registry, the modules loaded and SHAPEGEN_PLUGINS as they were, after the test."""
    available()  # the built-ins and installed plug-ins first
    monkeypatch.setattr(registry, "REGISTRY", dict(registry.REGISTRY))
    monkeypatch.setattr(plugins, "_LOADED_MODULES", {})
    monkeypatch.setenv(plugins.PLUGINS_VARIABLE, "")


@pytest.fixture
def piers(tmp_path) -> tuple[Path, Path]:
    module = tmp_path / "piers.py"
    module.write_text(PIERS_PY, encoding="utf-8")
    rule = tmp_path / "piers.grammar"
    rule.write_text(PIERS_GRAMMAR, encoding="utf-8")
    return module, rule


def test_an_unknown_primitive_says_how_to_make_one_known(own_registry, piers, capsys):
    _, rule = piers
    assert main(["build", str(rule), "-q"]) == 2
    err = capsys.readouterr().err
    assert "3:10: unknown primitive 'stepped_pier'" in err
    assert "--plugin MODULE_OR_FILE.py" in err and "group 'shapegen.primitives'" in err


def test_a_py_file_given_with_plugin_builds_and_judges(own_registry, piers, tmp_path, capsys):
    module, rule = piers
    report = tmp_path / "piers.report.json"
    argv = ["build", str(rule), "--plugin", str(module), "--analyze", "--report", str(report)]
    assert main([*argv, "-q"]) == 0, capsys.readouterr().err
    result = json.loads(report.read_text(encoding="utf-8"))
    assert result["blocks"] == 3
    # 2 x 1 x 2 + 1.6 x 1 x 1.6 + 1.2 x 1 x 1.2 m^3 (steps inset by 0.1 of the 2 m lot)
    assert result["volume"] == pytest.approx(4 + 2.56 + 1.44)
    assert result["analysis"]["stands"] is True
    # named for the processes this one starts (a city's workers), as an absolute path
    assert os.environ[plugins.PLUGINS_VARIABLE] == str(module.resolve())


def test_a_module_name_given_with_plugin_is_imported(own_registry, piers, monkeypatch, capsys):
    module, rule = piers
    module.rename(module.with_name("own_piers_for_a_test.py"))
    monkeypatch.syspath_prepend(str(module.parent))
    try:
        argv = ["build", str(rule), "--plugin", "own_piers_for_a_test", "-q"]
        assert main(argv) == 0, capsys.readouterr().err
        assert "stepped_pier" in available()
    finally:
        sys.modules.pop("own_piers_for_a_test", None)


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ("{tmp}/missing.py", "plug-in {tmp}/missing.py: no such file"),
        ("no_such_plugin_module", "plug-in 'no_such_plugin_module': no module named"),
        ("{tmp}/broken.py", "plug-in {tmp}/broken.py: ZeroDivisionError: division by zero"),
    ],
)
def test_a_plugin_that_cannot_be_loaded_is_one_line(
    own_registry, piers, tmp_path, capsys, given, message
):
    (tmp_path / "broken.py").write_text("1 / 0\n", encoding="utf-8")
    _, rule = piers
    tmp = str(tmp_path.resolve())
    assert main(["build", str(rule), "--plugin", given.format(tmp=tmp), "-q"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message.format(tmp=tmp) in err[0], err
