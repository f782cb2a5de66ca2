"""Pictures of a simulation: PNG frames or an animated GIF, rendered offline (no screen, no GL).

Every frame is the model with each block moved by its recorded rigid motion, drawn by
:func:`shapegen.export.picture.render_model` inside one fixed box, so the view stays still while
the blocks move.
"""

from __future__ import annotations

__all__ = ["frame_bounds", "write_frames", "encode_gif", "write_gif", "write_picture"]

import io
import tempfile
from pathlib import Path

import numpy as np

from shapegen.errors import InputFormatError
from shapegen.export.atomic import atomic_write
from shapegen.export.picture import render_model
from shapegen.simulation.run import SimulationFrame, SimulationResult, moved_model

# How far beyond the model's starting box the view reaches on each side, as a share of the
# box's largest side: room for falling blocks without shrinking the building to a dot.
_VIEW_MARGIN = 0.25


def frame_bounds(result: SimulationResult) -> np.ndarray:
    """``(2, 3)`` box (metres) that frames every recorded frame of ``result``.

    The union of the blocks' positions over all frames, limited to the starting box grown by a
    quarter of its largest side in every direction (and never below the ground).
    """
    start = np.array(
        [np.min([b.vertices.min(axis=0) for b in result.model.blocks], axis=0),
         np.max([b.vertices.max(axis=0) for b in result.model.blocks], axis=0)]
    )  # fmt: skip
    reach = _VIEW_MARGIN * float((start[1] - start[0]).max())
    lo, hi = start[0].copy(), start[1].copy()
    for frame in result.frames:
        for block, rotation, translation in zip(
            result.model.blocks, frame.rotations, frame.translations, strict=True
        ):
            points = block.vertices @ rotation.T + translation
            lo = np.minimum(lo, points.min(axis=0))
            hi = np.maximum(hi, points.max(axis=0))
    lo = np.maximum(lo, start[0] - reach)
    hi = np.minimum(hi, start[1] + reach)
    if result.model.ground is not None:
        lo[1] = max(lo[1], float(result.model.ground))
    return np.array([lo, hi])


def _render_frame(
    result: SimulationResult, frame: SimulationFrame, path: Path, bounds: np.ndarray, **view
) -> None:
    title = f"t = {frame.time:.2f} s"
    if result.settings.shake > 0:
        title += f"  (ground shake {result.settings.shake:g} m/s)"
    render_model(moved_model(result.model, frame), path, title=title, bounds=bounds, **view)


def write_frames(result: SimulationResult, folder: str | Path, **view) -> list[Path]:
    """Write one PNG per recorded frame into ``folder`` (``frame_0000.png``...).

    ``view`` passes ``elevation``, ``azimuth`` (degrees) and ``size_px`` on to
    :func:`~shapegen.export.picture.render_model`. Returns the paths written.
    """
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise InputFormatError(f"--frames {folder}: exists and is not a folder")
    folder.mkdir(parents=True, exist_ok=True)
    bounds = frame_bounds(result)
    paths = []
    for k, frame in enumerate(result.frames):
        path = folder / f"frame_{k:04d}.png"
        _render_frame(result, frame, path, bounds, **view)
        paths.append(path)
    return paths


def write_picture(result: SimulationResult, path: str | Path, which: str = "final", **view) -> None:
    """Write one PNG of the ``"start"``, ``"settled"`` or ``"final"`` state."""
    frame = {"start": result.frames[0], "settled": result.settled, "final": result.frames[-1]}[
        which
    ]
    _render_frame(result, frame, Path(path), frame_bounds(result), **view)


def encode_gif(result: SimulationResult, frame_seconds: float | None = None, **view) -> bytes:
    """An animated GIF (bytes) of every recorded frame, looping.

    ``frame_seconds`` is the display time of each frame (default: the recorded interval, so the
    animation plays in real time).
    """
    from PIL import Image

    if frame_seconds is None:
        times = [f.time for f in result.frames]
        frame_seconds = float(np.median(np.diff(times))) if len(times) > 1 else 1.0
    bounds = frame_bounds(result)
    images = []
    with tempfile.TemporaryDirectory(prefix="shapegen-frames-") as folder:
        for k, frame in enumerate(result.frames):
            path = Path(folder) / f"frame_{k:04d}.png"
            _render_frame(result, frame, path, bounds, **view)
            with Image.open(path) as image:
                images.append(image.convert("RGB").quantize(colors=128))
    buffer = io.BytesIO()
    images[0].save(
        buffer,
        format="GIF",
        save_all=True,
        append_images=images[1:],
        duration=max(20, round(1000 * frame_seconds)),
        loop=0,
    )
    return buffer.getvalue()


def write_gif(result: SimulationResult, path: str | Path, **options) -> None:
    """Write :func:`encode_gif` to ``path`` atomically."""
    content = encode_gif(result, **options)
    with atomic_write(path, "wb") as handle:
        handle.write(content)
