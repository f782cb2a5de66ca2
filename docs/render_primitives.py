"""Render every built-in primitive to a PNG for docs/primitives.md.

Run from the repository root::

    .venv/bin/python docs/render_primitives.py [OUTPUT_DIR]

Pictures go to ``docs/images/primitives/NAME.png`` (600 x 450 pixels, drawn by the numpy
depth-buffer renderer of :mod:`shapegen.export.render`, no screen needed). The joints between
blocks are drawn as dark lines, so they show the stereotomy.
"""

from __future__ import annotations

__all__ = ["GALLERY", "render_gallery"]

import sys
from pathlib import Path

from shapegen.export.picture import render_model
from shapegen.model.model import Model
from shapegen.model.scope import Scope
from shapegen.primitives import available, insert

# file stem -> (primitive, scope size (sx, sy, sz) in m, parameters, view (elevation, azimuth))
GALLERY: dict[str, tuple[str, tuple[float, float, float], dict, tuple[float, float]]] = {
    "box": ("box", (2.0, 1.0, 1.0), {}, (25.0, -60.0)),
    "wall": ("wall", (4.0, 2.0, 0.4), {"block_length": 0.5, "block_height": 0.25}, (20.0, -70.0)),
    "column": ("column", (0.6, 3.0, 0.6), {"courses": 6}, (20.0, -60.0)),
    "column_round": (
        "column",
        (0.6, 3.0, 0.6),
        {"shape": "round", "sides": 16, "courses": 6},
        (20.0, -60.0),
    ),
    "arch": ("arch", (4.0, 2.0, 0.5), {"thickness": 0.4, "segments": 13}, (15.0, -75.0)),
    "arch_gothic": (
        "arch",
        (4.0, 3.0, 0.5),
        {"style": "gothic", "thickness": 0.4, "segments": 14, "pointedness": 1.0},
        (15.0, -75.0),
    ),
    "bezier_arch": (
        "bezier_arch",
        (4.0, 3.0, 0.5),
        {"thickness": 0.35, "segments": 16, "c1x": 0.0, "c1y": 1.0, "c2x": 1.0, "c2y": 1.0},
        (15.0, -75.0),
    ),
    "capped_arch": (
        "capped_arch",
        (4.0, 2.6, 0.5),
        {"thickness": 0.4, "segments": 12},
        (15.0, -75.0),
    ),
    "flying_buttress": (
        "flying_buttress",
        (4.0, 6.0, 0.8),
        {"angle": 60.0, "thickness": 0.4, "segments": 9, "pier_width": 0.9, "pier_courses": 5},
        (15.0, -70.0),
    ),
    "barrel_vault": (
        "barrel_vault",
        (4.0, 2.0, 4.0),
        {"thickness": 0.35, "segments": 13, "courses": 5, "running_bond": True},
        (25.0, -55.0),
    ),
    "groin_vault": (
        "groin_vault",
        (4.0, 2.0, 4.0),
        {"thickness": 0.35, "segments": 12},
        (30.0, -50.0),
    ),
    "dome": (
        "dome",
        (4.0, 2.0, 4.0),
        {"thickness": 0.3, "rings": 8, "meridians": 20},
        (25.0, -60.0),
    ),
    "dome_oculus": (
        "dome",
        (4.0, 2.0, 4.0),
        {"thickness": 0.3, "rings": 7, "meridians": 20, "oculus": 20.0},
        (35.0, -60.0),
    ),
}


def render_gallery(directory: Path) -> list[Path]:
    """Write one picture per :data:`GALLERY` entry into ``directory``; return their paths."""
    directory.mkdir(parents=True, exist_ok=True)
    missing = sorted({name for name, *_ in GALLERY.values()} - set(available()))
    if missing:
        raise SystemExit(f"primitives not registered: {', '.join(missing)}")
    written = []
    for stem, (name, size, params, (elevation, azimuth)) in GALLERY.items():
        blocks = insert(name, Scope.axis_aligned((0.0, 0.0, 0.0), size), **params)
        path = directory / f"{stem}.png"
        render_model(
            Model(blocks),
            path,
            title=f"{name} ({len(blocks)} blocks)",
            elevation=elevation,
            azimuth=azimuth,
            size_px=(600, 450),
        )
        written.append(path)
    return written


if __name__ == "__main__":
    default = Path(__file__).resolve().parent / "images" / "primitives"
    for path in render_gallery(Path(sys.argv[1]) if len(sys.argv) > 1 else default):
        print(path)
