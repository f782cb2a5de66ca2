"""Reference assemblies with known stability limits: arches, harmonic stacks, leaning towers.

Used to compare the simulation with the statics (tests, docs/simulation_study.py). Units: metres.
"""

from __future__ import annotations

__all__ = ["FRICTION", "arch", "harmonic_stack", "leaning_tower"]

from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.primitives.arch import semicircular_arch

FRICTION = 0.895  # the seed paper's value


def arch(
    ratio: float, segments: int = 40, radius: float = 1.0, friction: float = FRICTION
) -> Model:
    """A semicircular arch of ``segments`` voussoirs, thickness ``ratio * radius``, on the ground.

    With friction high enough that no joint slides it stands when ``ratio`` exceeds about
    0.107 (Milankovitch; Heyman); ``friction`` is the Coulomb coefficient of every joint.
    """
    blocks = semicircular_arch(radius, ratio * radius, segments, depth=0.5 * radius)
    return Model(blocks, friction=friction)


def harmonic_stack(factor: float, count: int = 6, length: float = 1.0) -> Model:
    """``count`` blocks, each shifted over the one below by ``factor`` times the critical overhang.

    The block ``k`` places from the top overhangs the block below it by ``length / (2 k)`` at the
    limit (the harmonic stack): the blocks above every joint then have their centre of mass right
    above its edge. It stands for ``factor < 1`` and falls for ``factor > 1``.
    """
    height, depth = 0.2 * length, 0.5 * length
    offsets = [0.0]
    for below in range(count - 1, 0, -1):  # from the bottom joint up
        offsets.append(offsets[-1] + factor * length / (2.0 * below))
    blocks = [
        Block.box([x, k * height, 0.0], [x + length, (k + 1) * height, depth], id=f"s{k}")
        for k, x in enumerate(offsets)
    ]
    return Model(blocks, friction=FRICTION)


def leaning_tower(factor: float, count: int = 8, width: float = 0.4) -> Model:
    """``count`` equal blocks, each shifted by ``factor * width / count`` over the one below.

    The blocks above the first joint have their centre of mass ``shift * count / 2`` from the
    centre of the bottom block; the tower stands while that is at most ``width / 2``, i.e. for
    ``factor <= 1``.
    """
    height, depth = 0.3 * width, width
    shift = factor * width / count
    blocks = [
        Block.box([k * shift, k * height, 0.0], [k * shift + width, (k + 1) * height, depth])
        for k in range(count)
    ]
    return Model(blocks, friction=FRICTION)
