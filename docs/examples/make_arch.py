"""Write docs/examples/arch.json: a semicircular arch of voussoirs standing on the ground.

The arch spans the x axis in the plane z = 0..depth, springs from the ground y = 0 and has
radial joints. With the default thickness (t/R = 0.15, above the minimum 0.1075 of a
semicircular arch) it stands; try ``--thickness 0.18`` (t/R = 0.09) for one that does not.

    python docs/examples/make_arch.py [--voussoirs 24] [--radius 2] [--thickness 0.3] [OUT]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from shapegen import Block, Model
from shapegen.export.blocks_json import write_blocks_json


def semicircular_arch(voussoirs: int, radius: float, thickness: float, depth: float) -> Model:
    """``voussoirs`` blocks between radial joints; centreline ``radius``, all lengths in metres."""
    angles = np.linspace(0.0, np.pi, voussoirs + 1)
    cos, sin = np.cos(angles), np.sin(angles)
    sin[[0, -1]] = 0.0  # exact zeros, so the springing joints lie on the ground plane
    inner, outer = radius - thickness / 2, radius + thickness / 2
    blocks = []
    for k in range(voussoirs):
        corners = [
            [r * cos[j], r * sin[j], z]
            for j in (k, k + 1)
            for r in (inner, outer)
            for z in (0, depth)
        ]
        blocks.append(Block.from_hull(np.array(corners), id=f"v{k}", tags=("voussoir",)))
    return Model(blocks, ground=0.0, friction=0.7)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default=Path(__file__).with_name("arch.json"))
    parser.add_argument("--voussoirs", type=int, default=24)
    parser.add_argument("--radius", type=float, default=2.0, help="centreline radius, m")
    parser.add_argument("--thickness", type=float, default=0.3, help="radial thickness, m")
    parser.add_argument("--depth", type=float, default=0.5, help="depth along z, m")
    args = parser.parse_args()
    model = semicircular_arch(args.voussoirs, args.radius, args.thickness, args.depth)
    write_blocks_json(model, args.out)
    print(f"{args.out}: {len(model.blocks)} voussoirs, {model.total_weight:.0f} N")


if __name__ == "__main__":
    main()
