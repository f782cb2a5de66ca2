"""A small software renderer for block models: a depth buffer in numpy, no screen, no GL.

The blocks' front faces are cut into triangles and rasterized into a depth buffer at a few
samples per pixel (supersampling, so edges are anti-aliased when the samples are averaged).
The nearest surface wins at every sample whatever order the blocks come in, so occlusion is
exact. Faces are shaded flat (Lambert + ambient); the joints between blocks and the creases
of each block are found on the buffer of visible faces, so a line is drawn only where it is
seen. Non-structural blocks (translucent colours) are laid over the opaque ones as one
see-through layer. The camera is orthographic, y up, and frames the model so that its
projected bounding box fills :data:`FRAME_FILL` of the picture's width or height.

Why a renderer of our own: VTK and moderngl install as wheels and render off-screen, but both
load the system's OpenGL (Mesa's libEGL and a driver) at run time, which a plain Python
machine need not have; this one needs numpy alone and gives the same pixels everywhere.
See docs/results.md ("How the pictures are made").
"""

from __future__ import annotations

__all__ = ["FRAME_FILL", "MAX_SAMPLES", "SUPERSAMPLE", "Rendering", "render_blocks", "view_axes"]

from dataclasses import dataclass

import numpy as np

from shapegen.model.model import Model
from shapegen.model.packed import pack_blocks
from shapegen.tolerances import (
    COINCIDENT_M,
    COSINE_SLACK,
    GROUND_FLOOR_M,
    HORIZON_SIN,
    PIXEL_AREA_FLOOR,
    PIXEL_EDGE_SLACK_REL,
    are_positive,
    is_positive,
)

FRAME_FILL = 0.88  # the model's projected box spans this share of the limiting side
SUPERSAMPLE = 3  # samples per pixel along each axis (9 per pixel)
GROUND_MARGIN = 0.08  # the ground patch reaches this share of the footprint beyond it
CREASE_DEGREES = 30.0  # a fold within one block sharper than this is drawn as an edge
AMBIENT = 0.55  # share of the light that reaches every face, whatever its direction
EDGE_SHADE = 0.3  # an edge pixel keeps this share of its colour (darker = stronger lines)
GROUND_RGB = np.array([236.0, 233.0, 224.0])
SURFACE_BIAS = 1e-4  # surfaces are drawn this share of the model's size nearer the eye
MAX_SAMPLES = 40_000_000  # depth-buffer samples at most (about 1 GB of buffers)
_CHUNK_ROWS = 1 << 17  # triangle rows per rasterizer pass: bounds the memory


@dataclass(frozen=True)
class Rendering:
    """A rendered picture.

    Attributes
    ----------
    rgb
        ``(height, width, 3)`` uint8 colours.
    coverage
        ``(height, width)`` share of each pixel's samples that show a block (0..1); the rest
        show the ground or the background.
    scale
        Pixels per metre of the picture.
    """

    rgb: np.ndarray
    coverage: np.ndarray
    scale: float


def view_axes(elevation: float, azimuth: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(right, up, toward_viewer)`` unit vectors in model axes for a view from ``elevation``
    degrees above the horizon and ``azimuth`` degrees about the vertical y axis (azimuth -90
    looks along -z, towards the model's front; -60 adds a quarter turn's third for a 3/4 view)."""
    elev, azim = np.radians(elevation), np.radians(azimuth)
    eye = np.array([np.cos(elev) * np.cos(azim), np.sin(elev), -np.cos(elev) * np.sin(azim)])
    right = np.cross([0.0, 1.0, 0.0], eye)
    norm = np.linalg.norm(right)
    looking_down = not is_positive(norm, COSINE_SLACK)
    right = np.array([1.0, 0.0, 0.0]) if looking_down else right / norm
    return right, np.cross(eye, right), eye


def render_blocks(
    model: Model,
    colors: np.ndarray,
    *,
    size_px: tuple[int, int] = (800, 600),
    elevation: float = 25.0,
    azimuth: float = -60.0,
    bounds: np.ndarray | None = None,
    ground: bool = True,
    background: tuple[int, int, int] = (255, 255, 255),
    supersample: int = SUPERSAMPLE,
    surface_colors: np.ndarray | None = None,
) -> Rendering:
    """Render ``model`` with one colour per block, and its surfaces (seen from both sides).

    Parameters
    ----------
    colors
        ``(n, 4)`` RGBA in 0..255, one row per block; alpha below 255 draws the block as a
        see-through layer over the opaque ones.
    size_px
        Width and height of the picture, pixels.
    elevation, azimuth
        The view, degrees (see :func:`view_axes`).
    bounds
        ``(2, 3)`` corners (m) of the box to frame instead of the blocks' own: a fixed box keeps
        the view still across the frames of an animation.
    ground
        Draw the ground plane ``y = model.ground`` (when the model has one) around the model.
    supersample
        Samples a pixel along each axis (anti-aliasing); lowered for pictures so large that
        the samples would exceed :data:`MAX_SAMPLES`.
    surface_colors
        ``(m, 4)`` RGBA, one row per surface of ``model.surfaces``; default a light grey.
    """
    width, height = (int(v) for v in size_px)
    if width < 1 or height < 1 or width * height > MAX_SAMPLES:
        raise ValueError(
            f"a picture of {width} x {height} pixels: at least 1 x 1 and at most"
            f" {MAX_SAMPLES / 1e6:g} million pixels"
        )
    # Fewer samples a pixel for a large picture, so the buffers stay within MAX_SAMPLES.
    s = max(1, min(int(supersample), int(np.sqrt(MAX_SAMPLES / (width * height)))))
    colors = np.asarray(colors, dtype=float).reshape(-1, 4)
    if len(colors) != len(model.blocks):
        raise ValueError(f"{len(colors)} colours for {len(model.blocks)} blocks")
    right, up, eye = view_axes(elevation, azimuth)
    w, h = width * s, height * s
    sheets, sheet_owner = _surface_triangles(model)
    if not model.blocks and not len(sheets):
        rgb = np.broadcast_to(np.array(background, np.uint8), (height, width, 3)).copy()
        return Rendering(rgb, np.zeros((height, width)), 1.0)
    pack = pack_blocks(model.blocks)
    everything = np.vstack([pack.vertices, sheets.reshape(-1, 3)])
    framed = everything if bounds is None else _box_corners(np.asarray(bounds, float))
    project, scale = _camera(framed, right, up, eye, w, h)

    # Front faces only: every block is a closed convex solid, so a face turned away is hidden.
    front = are_positive(pack.face_normal @ eye, COSINE_SLACK)
    triangles, triangle_face = _fan_triangles(pack.corners, pack.corner_start, front)
    xy, depth = project(pack.vertices)
    tri_xy, tri_depth = xy[triangles], depth[triangles]
    # Surfaces are seen from both sides: each triangle is a face of its own, turned to the eye,
    # and owned by a "block" numbered after the real ones (so joints between them are drawn).
    face_block, face_normal = pack.face_block, pack.face_normal
    if len(sheets):
        normal = np.cross(sheets[:, 1] - sheets[:, 0], sheets[:, 2] - sheets[:, 0])
        length = np.linalg.norm(normal, axis=1)
        keep = length > 0
        sheets, sheet_owner = sheets[keep], sheet_owner[keep]
        normal = normal[keep] / length[keep, None]
        normal *= np.where(normal @ eye < 0, -1.0, 1.0)[:, None]
        paint = _surface_paint(surface_colors, len(model.surfaces))
        colors = np.vstack([colors, paint])
        sheet_xy, sheet_depth = project(sheets.reshape(-1, 3))
        # A surface lying on a block's face (a roof plane, a comp face kept as a leaf) is
        # drawn over it rather than fighting it sample by sample.
        sheet_depth = sheet_depth - SURFACE_BIAS * float(np.ptp(everything, axis=0).max())
        tri_xy = np.concatenate([tri_xy, sheet_xy.reshape(-1, 3, 2)])
        tri_depth = np.concatenate([tri_depth, sheet_depth.reshape(-1, 3)])
        triangle_face = np.concatenate([triangle_face, len(face_block) + np.arange(len(sheets))])
        face_block = np.concatenate([face_block, len(model.blocks) + sheet_owner])
        face_normal = np.vstack([face_normal, normal])
    face_rgb = colors[face_block, :3] * _shade(face_normal, right, up, eye)[:, None]
    alpha = colors[face_block, 3] / 255.0
    opaque = alpha[triangle_face] >= 1.0
    nf = len(face_block)
    ground_id = nf  # face number of the ground patch, after the blocks' faces
    if ground and model.ground is not None and is_positive(eye[1], HORIZON_SIN):
        patch_xy, patch_depth = project(_ground_patch(everything, float(model.ground)))
        patch = np.array([[0, 1, 2], [0, 2, 3]])
        tri_xy = np.concatenate([tri_xy, patch_xy[patch]])
        tri_depth = np.concatenate([tri_depth, patch_depth[patch]])
        triangle_face = np.concatenate([triangle_face, [ground_id, ground_id]])
        opaque = np.concatenate([opaque, [True, True]])
    ground_shade = _shade(np.array([[0.0, 1.0, 0.0]]), right, up, eye)[0]
    face_rgb = np.vstack([face_rgb, GROUND_RGB * ground_shade, np.array(background, float)])
    face_rgb = face_rgb.astype(np.float32)
    background_id = nf + 1

    solid_depth, solid_face = _rasterize(tri_xy[opaque], tri_depth[opaque], w, h)
    solid_face = np.where(solid_face >= 0, triangle_face[opaque][solid_face], background_id)
    image = np.take(face_rgb, solid_face, axis=0)
    visible = solid_face
    if not opaque.all():  # one see-through layer: the nearest translucent face over the rest
        glass_depth, glass_face = _rasterize(tri_xy[~opaque], tri_depth[~opaque], w, h)
        glass_face = np.where(glass_face >= 0, triangle_face[~opaque][glass_face], -1)
        over = (glass_face >= 0) & (glass_depth < solid_depth)
        a = alpha[glass_face[over]][:, None]
        image[over] = a * face_rgb[glass_face[over]] + (1 - a) * image[over]
        visible = np.where(over, glass_face, solid_face)
    edges = _edges(visible, face_block, face_normal, ground_id, background_id)
    image *= np.where(edges, np.float32(EDGE_SHADE), np.float32(1.0))[:, :, None]
    rgb = _downsample(image, s)
    block_samples = _downsample((visible < nf).astype(np.float32), s)
    return Rendering(np.clip(np.round(rgb), 0, 255).astype(np.uint8), block_samples, scale / s)


def _surface_triangles(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """``(t, 3, 3)`` corner positions of every surface triangle, and its surface's number."""
    from shapegen.export.surfaces import face_triangles

    corners, owner = [], []
    for k, surface in enumerate(getattr(model, "surfaces", None) or []):
        triangles = face_triangles(surface.vertices, surface.faces)
        corners.append(surface.vertices[triangles].reshape(-1, 3, 3))
        owner.append(np.full(len(triangles), k))
    if not corners:
        return np.empty((0, 3, 3)), np.empty(0, dtype=np.int64)
    return np.concatenate(corners), np.concatenate(owner)


def _surface_paint(colors: np.ndarray | None, count: int) -> np.ndarray:
    if colors is None:
        from shapegen.export.colors import SURFACE

        return np.tile(SURFACE.astype(float), (count, 1))
    colors = np.asarray(colors, dtype=float).reshape(-1, 4)
    if len(colors) != count:
        raise ValueError(f"{len(colors)} colours for {count} surfaces")
    return colors


def _camera(framed: np.ndarray, right, up, eye, w: int, h: int):
    """A projection to sample coordinates (x right, y down) and depth (metres, larger = farther)
    that centres ``framed`` and scales its projected box to :data:`FRAME_FILL` of the frame."""
    u, v = framed @ right, framed @ up
    du, dv = float(np.ptp(u)), float(np.ptp(v))
    extent = max(du, dv, COINCIDENT_M)
    scale = FRAME_FILL * min(w / max(du, 1e-3 * extent), h / max(dv, 1e-3 * extent))
    uc, vc = (u.min() + u.max()) / 2, (v.min() + v.max()) / 2

    def project(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        x = w / 2 + scale * (points @ right - uc)
        y = h / 2 - scale * (points @ up - vc)
        return np.stack([x, y], axis=-1), -(points @ eye)

    return project, scale


def _box_corners(bounds: np.ndarray) -> np.ndarray:
    lo, hi = bounds.reshape(2, 3)
    pick = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    return np.where(pick == 0, lo, hi)


def _ground_patch(vertices: np.ndarray, level: float) -> np.ndarray:
    """The four corners of a ground rectangle around the blocks' footprint, counter-clockwise
    seen from above."""
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    margin = GROUND_MARGIN * max(hi[0] - lo[0], hi[2] - lo[2], GROUND_FLOOR_M)
    x0, x1, z0, z1 = lo[0] - margin, hi[0] + margin, lo[2] - margin, hi[2] + margin
    return np.array([[x0, level, z1], [x1, level, z1], [x1, level, z0], [x0, level, z0]])


def _shade(normals: np.ndarray, right, up, eye) -> np.ndarray:
    """Flat Lambert shading with ambient light; the light comes from above, over the viewer's
    left shoulder, so the two visible sides of a box get different shades."""
    light = 0.55 * np.array([0.0, 1.0, 0.0]) + 0.45 * eye - 0.35 * right
    light /= np.linalg.norm(light)
    return AMBIENT + (1 - AMBIENT) * np.clip(normals @ light, 0.0, 1.0)


def _fan_triangles(
    corners: np.ndarray, corner_start: np.ndarray, chosen: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Triangles ``(t, 3)`` (vertex numbers) fanning each chosen convex face from its first
    corner, and the face of each triangle."""
    faces = np.flatnonzero(chosen)
    count = np.diff(corner_start)[faces] - 2
    face = np.repeat(faces, count)
    step = np.arange(len(face)) - np.repeat(np.cumsum(count) - count, count)
    first = corner_start[face]
    return (
        np.stack([corners[first], corners[first + step + 1], corners[first + step + 2]], axis=1),
        face,
    )


def _rasterize(xy: np.ndarray, depth: np.ndarray, w: int, h: int) -> tuple[np.ndarray, np.ndarray]:
    """Depth-buffer the triangles ``xy (t, 3, 2)`` (sample units), depths ``(t, 3)``.

    Returns the nearest depth and the triangle seen at each sample (``(h, w)``; inf and -1
    where none). A sample is covered when its centre lies inside or on a triangle's edge.
    Each triangle is cut into rows of samples, and each row's span is solved from the three
    edges, so only covered samples are ever generated.
    """
    zbuf = np.full(w * h, np.inf)
    seen = np.full(w * h, -1, dtype=np.int64)
    a, b, c = xy[:, 0], xy[:, 1], xy[:, 2]
    za, zb, zc = depth[:, 0], depth[:, 1], depth[:, 2]
    area = _cross(b - a, c - a)
    flip = area < 0  # make every triangle counter-clockwise in sample coordinates
    b, c = np.where(flip[:, None], c, b), np.where(flip[:, None], b, c)
    zb, zc = np.where(flip, zc, zb), np.where(flip, zb, zc)
    area = np.abs(area)
    top = np.maximum(np.ceil(np.minimum(np.minimum(a, b), c)[:, 1] - 0.5), 0).astype(np.int64)
    bottom = np.minimum(np.floor(np.maximum(np.maximum(a, b), c)[:, 1] - 0.5), h - 1)
    rows = np.maximum(bottom.astype(np.int64) - top + 1, 0)
    keep = np.flatnonzero(are_positive(area, PIXEL_AREA_FLOOR) & (rows > 0))
    if not len(keep):
        return zbuf.reshape(h, w), seen.reshape(h, w)
    # Edge functions e(x, y) = A x + B y + C, non-negative inside; the depth is their blend.
    edges = np.stack(
        [np.stack([p[:, 1] - q[:, 1], q[:, 0] - p[:, 0], _cross(p, q)], axis=1)
         for p, q in ((b, c), (c, a), (a, b))],  # the edge facing a, then b, then c
        axis=1,
    )[keep]  # fmt: skip
    z = np.stack([za, zb, zc], axis=1)[keep]
    plane = np.einsum("tk,tki->ti", z, edges) / area[keep, None]  # depth = plane . (x, y, 1)
    # A sample on an edge shared by two triangles is covered by both, never by neither.
    slack = PIXEL_EDGE_SLACK_REL * np.abs(edges[:, :, :2]).sum(axis=(1, 2))
    top, rows = top[keep], rows[keep]
    ends = np.cumsum(rows)
    start = 0
    while start < len(keep):  # a few hundred thousand rows at a time bound the memory
        stop = max(int(np.searchsorted(ends, ends[start] - rows[start] + _CHUNK_ROWS)), start + 1)
        pick = slice(start, stop)
        _rasterize_rows(edges[pick], plane[pick], slack[pick], top[pick], rows[pick],
                        keep[pick], zbuf, seen, w)  # fmt: skip
        start = stop
    return zbuf.reshape(h, w), seen.reshape(h, w)


def _rasterize_rows(edges, plane, slack, top, rows, ids, zbuf, seen, w: int) -> None:
    row_tri = np.repeat(np.arange(len(rows)), rows)
    py = np.repeat(top, rows) + np.arange(len(row_tri)) - np.repeat(np.cumsum(rows) - rows, rows)
    y = py + 0.5
    e = edges[row_tri]  # (r, 3 edges, A B C)
    bound = (-slack[row_tri, None] - e[:, :, 1] * y[:, None] - e[:, :, 2]) / np.where(
        e[:, :, 0] != 0, e[:, :, 0], 1.0
    )  # A x + B y + C >= -slack
    flat = e[:, :, 0] == 0
    lower = np.where(e[:, :, 0] > 0, bound, -np.inf).max(axis=1)
    upper = np.where(e[:, :, 0] < 0, bound, np.inf).min(axis=1)
    blocked = (flat & (e[:, :, 1] * y[:, None] + e[:, :, 2] < -slack[row_tri, None])).any(axis=1)
    first = np.maximum(np.ceil(lower - 0.5), 0)
    last = np.minimum(np.floor(upper - 0.5), w - 1)
    count = np.where(blocked, 0, np.maximum(last - first + 1, 0)).astype(np.int64)
    first = first.astype(np.int64, copy=False)
    p = plane[row_tri]
    z_first = p[:, 0] * (first + 0.5) + p[:, 1] * y + p[:, 2]
    offset = np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count, count)
    sample = np.repeat(py * w + first, count) + offset
    depth = np.repeat(z_first, count) + np.repeat(p[:, 0], count) * offset
    np.minimum.at(zbuf, sample, depth)
    nearest = depth <= zbuf[sample]
    seen[sample[nearest]] = ids[np.repeat(row_tri, count)[nearest]]


def _edges(
    face: np.ndarray, face_block: np.ndarray, normal: np.ndarray, ground_id: int, background_id: int
) -> np.ndarray:
    """Samples on a visible edge: where neighbouring samples show faces of two different blocks,
    a block against the ground or the background, or a fold sharper than
    :data:`CREASE_DEGREES` within one block. Both sides are marked, so lines are two samples
    wide."""
    nf = len(face_block)
    block = np.concatenate([face_block, [-1, -2]])  # the ground and the background: no block
    unit = np.vstack([normal, np.zeros((2, 3))])
    crease = np.cos(np.radians(CREASE_DEGREES))
    mark = np.zeros(face.shape, dtype=bool)
    for p, q, mp, mq in (
        (face[:, :-1], face[:, 1:], mark[:, :-1], mark[:, 1:]),
        (face[:-1, :], face[1:, :], mark[:-1, :], mark[1:, :]),
    ):
        differ = p != q
        pd, qd = p[differ], q[differ]
        some_block = (pd < nf) | (qd < nf)
        folded = (block[pd] != block[qd]) | (np.einsum("ij,ij->i", unit[pd], unit[qd]) < crease)
        line = np.zeros(p.shape, dtype=bool)
        line[differ] = some_block & folded
        mp |= line
        mq |= line
    return mark


def _downsample(samples: np.ndarray, s: int) -> np.ndarray:
    """The mean of each ``s`` x ``s`` block of samples (one output pixel)."""
    height, width = samples.shape[0] // s, samples.shape[1] // s
    grid = samples.reshape(height, s, width, s, *samples.shape[2:])
    return sum(grid[:, i, :, j] for i in range(s) for j in range(s)) / (s * s)


def _cross(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    return p[..., 0] * q[..., 1] - p[..., 1] * q[..., 0]
