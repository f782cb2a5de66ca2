"""Custom primitives: registration with the decorator, validation done by the library, and
discovery from an installed package through the ``shapegen.primitives`` entry-point group."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

import shapegen
from shapegen import plugins
from shapegen.errors import GeometryError, PluginError
from shapegen.model.block import Block
from shapegen.model.scope import Scope
from shapegen.primitives import Choice, available, insert, primitive, registry

PLUGIN_DIR = Path(__file__).parent / "plugin_pkg"
SCOPE = Scope.axis_aligned((0.0, 0.0, 0.0), (3.0, 0.6, 0.5))


@pytest.fixture
def fresh_registry(monkeypatch):
    """A copy of the registry with the built-ins, restored after the test."""
    available()  # register the built-in primitives first
    monkeypatch.setattr(registry, "REGISTRY", dict(registry.REGISTRY))
    yield registry.REGISTRY
    sys.modules.pop("jack_arch_plugin", None)


@pytest.fixture
def plugin_on_path(fresh_registry, monkeypatch):
    """The plug-in package directory (module + dist-info with its entry point) on sys.path, as
    an installation would leave it, and a registry that has not yet looked for plug-ins."""
    monkeypatch.syspath_prepend(str(PLUGIN_DIR))
    monkeypatch.setattr(plugins, "LOADED_GROUPS", set())
    return fresh_registry


def jack_arch_volume(width: float, height: float, depth: float, skewback: float) -> float:
    """A trapezoid: top width ``width``; the end joints lean ``skewback`` from the vertical."""
    bottom = width - 2 * height * math.tan(math.radians(skewback))
    return (width + bottom) / 2 * height * depth


def test_entry_point_discovery_registers_the_plugin(plugin_on_path):
    assert "jack_arch" not in plugin_on_path
    names = available()
    assert "jack_arch" in names
    assert {"box", "barrel_vault", "dome"} <= set(names)  # the built-ins are still there
    blocks = insert("jack_arch", SCOPE, segments=7, skewback=25.0)
    assert len(blocks) == 7
    exact = jack_arch_volume(SCOPE.sx, SCOPE.sy, SCOPE.sz, 25.0)
    assert sum(b.volume for b in blocks) == pytest.approx(exact, rel=1e-12)


def test_plugin_blocks_share_their_joints(plugin_on_path):
    from shapegen.model.model import Model
    from shapegen.statics.contacts import find_interfaces

    blocks = insert("jack_arch", SCOPE, segments=6)
    interfaces = find_interfaces(Model(blocks, ground=None))
    assert len(interfaces) == 5
    # Every joint radiates from one point below the soffit: all joint planes meet there.
    slope = math.tan(math.radians(20.0))
    centre = np.array([SCOPE.sx / 2, -(SCOPE.sx / (2 * slope) - SCOPE.sy), 0.0])
    for interface in interfaces:
        offset = interface.normal @ interface.vertices[0]
        assert interface.normal @ centre == pytest.approx(offset, abs=1e-12)


def test_plugin_parameters_are_validated_by_the_library(plugin_on_path):
    with pytest.raises(GeometryError, match="'jack_arch'.*parameter 'segments' must be a whole"):
        insert("jack_arch", SCOPE, segments="many")
    with pytest.raises(GeometryError, match="'jack_arch' has no parameter 'skew'.*'skewback'"):
        insert("jack_arch", SCOPE, skew=10.0)
    with pytest.raises(GeometryError, match="'jack_arch': parameter 'skewback' .* got 80 degrees"):
        insert("jack_arch", SCOPE, skewback=80.0)


def test_plugin_used_from_a_grammar(plugin_on_path):
    source = '@StartRule\n@Lot(3, 0.5)\nLot --> extrude(0.6) i("jack_arch", segments=9)\n'
    model = shapegen.parse_grammar(source).build()
    assert len(model.blocks) == 9
    exact = jack_arch_volume(3.0, 0.6, 0.5, 20.0)
    assert sum(b.volume for b in model.blocks) == pytest.approx(exact, rel=1e-9)


def test_a_broken_plugin_entry_point_is_reported(fresh_registry, tmp_path, monkeypatch):
    dist = tmp_path / "broken_plugin-1.0.dist-info"
    dist.mkdir()
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: broken-plugin\nVersion: 1.0\n")
    (dist / "entry_points.txt").write_text("[shapegen.primitives]\nbroken = no_such_module_xyz\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setattr(plugins, "LOADED_GROUPS", set())
    with pytest.raises(PluginError, match="cannot load primitives from 'no_such_module_xyz'"):
        available()


def test_the_library_checks_the_blocks_of_a_custom_primitive(fresh_registry):
    @primitive("dented_slab")
    def dented_slab(scope: Scope, *, dent: float = 0.2) -> list[Block]:
        # A non-convex block: the top's middle is pushed down (faces stay those of a box).
        block = Block.box([0, 0, 0], scope.size)
        block.vertices[6, 1] -= dent * 3 * scope.sy
        return [block]

    with pytest.raises(GeometryError, match="primitive 'dented_slab', piece 0: .*not convex"):
        insert("dented_slab", Scope.axis_aligned((0, 0, 0), (1.0, 1.0, 1.0)))


def test_choice_parameters_list_their_values(fresh_registry):
    @primitive("plinth")
    def plinth(scope: Scope, *, finish: Choice("rough", "dressed") = "rough") -> list[Block]:
        return [Block.box([0, 0, 0], scope.size)]

    assert len(insert("plinth", SCOPE, finish="dressed")) == 1
    with pytest.raises(GeometryError, match="'finish' must be one of 'rough', 'dressed'"):
        insert("plinth", SCOPE, finish="polished")


def test_a_taken_name_is_refused_unless_replacing(fresh_registry):
    def my_arch(scope: Scope) -> list[Block]:
        return [Block.box([0, 0, 0], scope.size)]

    with pytest.raises(PluginError, match="primitive 'arch' is already registered by shapegen"):
        primitive("arch")(my_arch)
    assert fresh_registry["arch"].function is not my_arch  # the built-in is untouched
    primitive("arch", replace=True)(my_arch)
    assert len(insert("arch", SCOPE)) == 1


def test_registering_the_same_function_again_is_harmless(fresh_registry):
    def pad(scope: Scope) -> list[Block]:
        return [Block.box([0, 0, 0], scope.size)]

    primitive("pad")(pad)
    primitive("pad")(pad)  # a module imported twice (or reloaded) registers again
    assert fresh_registry["pad"].function is pad
