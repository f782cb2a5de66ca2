"""Where the loads go: each block's weight and point loads on the free body that carries it
(a body of several parts takes its torques about its own centroid, the common volume of two
overlapping parts counted once; an ornament riding as load goes to its host), and the scaled
load vector of a problem, turned for the tilting-table test."""

from __future__ import annotations

__all__ = ["Loading", "block_loading", "load_vector", "tilted", "wrench"]

from dataclasses import dataclass, replace

import numpy as np

from shapegen.model.block import compute_mass_properties


@dataclass(frozen=True)
class Loading:
    """Where each block's weight and point loads go: ``row`` (the free row group of the body
    that carries it, -1 for none), ``loaded`` (its weight counts), ``reference`` (the centroid
    of that body, m: torques are taken about it), with the blocks' ``masses`` (kg) and
    ``centroids`` (m)."""

    row: np.ndarray
    loaded: np.ndarray
    reference: np.ndarray
    masses: np.ndarray
    centroids: np.ndarray


def wrench(model, loading: Loading, nf, length, weight_scale, transform=None) -> np.ndarray:
    """``(6 nf,)`` scaled wrench of the weights and point loads on the free bodies, each force
    first mapped by the ``(3, 3)`` matrix ``transform`` (None: as they are) at its own point."""
    load = np.zeros(6 * nf)
    gravity = np.asarray(model.gravity, float)
    if transform is not None:
        gravity = transform @ gravity
    loaded = np.flatnonzero(loading.loaded)
    if nf and len(loaded):
        rows = loading.row[loaded]
        gravity_force = loading.masses[loaded, None] * gravity[None, :]
        np.add.at(load.reshape(nf, 6)[:, :3], rows, gravity_force / weight_scale)
        # a part off its body's centroid adds a torque; a body of one block has none
        lever = loading.centroids[loaded] - loading.reference[loaded]
        off = np.any(lever != 0.0, axis=1)
        if off.any():
            torque = np.cross(lever[off] / length, gravity_force[off]) / weight_scale
            np.add.at(load.reshape(nf, 6)[:, 3:], rows[off], torque)
    for point_load in model.loads:
        k = model.index_of(point_load.block)
        if loading.row[k] < 0:
            continue  # a load on a support goes straight into the ground
        force = np.asarray(point_load.force, float)
        if transform is not None:
            force = transform @ force
        row = 6 * loading.row[k]
        lever = (point_load.point - loading.reference[k]) / length
        load[row : row + 3] += force / weight_scale
        load[row + 3 : row + 6] += np.cross(lever, force) / weight_scale
    return load


def load_vector(model, problem, transform: np.ndarray | None = None) -> np.ndarray:
    """The scaled external wrench of ``model``'s loads in ``problem``'s rows, every force mapped
    by ``transform`` first: a rotation turns them (:func:`shapegen.statics.tilt.rotation`), the
    lateral map gives the horizontal load of a tilting table
    (:func:`shapegen.statics.tilt.lateral_map`). ``model`` is the model ``problem`` was
    assembled from."""
    loading = problem.loading
    if loading is None:
        loading = block_loading(model, problem.bodies, problem.n_free)[0]
    return wrench(model, loading, problem.n_free, problem.length, problem.weight, transform)


def tilted(problem, model, tilt: float, azimuth: float):
    """``problem`` with every load turned by ``tilt`` degrees towards ``azimuth`` (degrees in
    the ground plane from +x towards +z): the tilting-table test, :mod:`shapegen.statics.tilt`.
    The matrices and caches are shared; only the load changes. The scales (``W``, ``L``) stay
    those of the upright problem, so ``y / W^2`` keeps its meaning."""
    from shapegen.statics.tilt import rotation

    load = load_vector(model, problem, rotation(tilt, azimuth))
    return replace(problem, load=load, tilt=float(tilt), azimuth=float(azimuth))


def block_loading(model, bodies):
    """Per block of ``model``: where its weight goes (:class:`Loading`), its free row
    (``free_index``, with a last entry -1 for the ground), one block of each free body
    (``free_blocks``), whether it is a support (``support``, the ground last) or takes part in
    the statics (``usable``), and its body (None without ``bodies``: each block its own)."""
    blocks = model.blocks
    nb = len(blocks)
    structural = np.array([b.structural for b in blocks], dtype=bool)
    fixed = np.array([b.fixed for b in blocks], dtype=bool)
    compute_mass_properties(blocks)
    masses = np.array([b.mass for b in blocks]) if nb else np.zeros(0)
    centroids = np.array([b.centroid for b in blocks]).reshape(nb, 3)
    free_index = np.full(nb + 1, -1)  # the extra last entry stands for GROUND (-1)
    if bodies is None:
        free = structural & ~fixed
        free_blocks = np.flatnonzero(free)
        free_index[free_blocks] = np.arange(len(free_blocks))
        support = np.append(fixed, True)  # fixed blocks and the ground
        usable = np.append(structural | fixed, True)
        loading = Loading(free_index[:nb].copy(), free, centroids, masses, centroids)
        return loading, free_index, free_blocks, support, usable, None
    body = bodies.body
    inside = body >= 0
    free_bodies = np.flatnonzero(~bodies.fixed)
    body_row = np.full(bodies.count, -1)
    body_row[free_bodies] = np.arange(len(free_bodies))
    free_index[:nb][inside] = body_row[body[inside]]
    first_part = np.full(bodies.count, nb)
    np.minimum.at(first_part, body[inside], np.flatnonzero(inside))
    free_blocks = first_part[free_bodies]
    on_support = np.zeros(nb, dtype=bool)  # a part of a support (none when no body is left)
    on_support[inside] = bodies.fixed[body[inside]]
    support = np.append(on_support, True)
    usable = np.append(inside, True)
    # a body's centroid: the mass centroid of its parts, the common volume of two overlapping
    # parts counted once (a body of one block keeps its own centroid)
    parts = np.flatnonzero(inside)
    overlaps = bodies.overlaps
    if overlaps is not None and len(overlaps.body):
        masses = np.concatenate([masses, overlaps.mass])
        centroids = np.concatenate([centroids, overlaps.centroid])
        owner = np.concatenate([body[parts], overlaps.body])
        entries = np.concatenate([parts, nb + np.arange(len(overlaps.body))])
    else:
        owner, entries = body[parts], parts
    mass = np.bincount(owner, masses[entries], minlength=bodies.count)
    weighted = np.where(mass[owner] > 0, masses[entries], 1.0)  # massless: the volume's mean
    total = np.bincount(owner, weighted, minlength=bodies.count)
    moment = np.stack(
        [np.bincount(owner, weighted * centroids[entries, k], bodies.count) for k in range(3)],
        axis=1,
    )
    centre = moment / np.where(total != 0, total, 1.0)[:, None]
    count = np.bincount(owner, minlength=bodies.count)
    single = parts[count[body[parts]] == 1]
    centre[body[single]] = centroids[single]
    reference = centroids.copy()
    reference[entries] = centre[owner]
    row = np.full(len(masses), -1)
    row[:nb] = free_index[:nb]
    row[entries] = body_row[owner]
    loaded = row >= 0
    riders = bodies.riders
    if len(riders):
        host = bodies.host[riders]
        row[riders] = body_row[host]
        reference[riders] = centre[host]
        loaded[riders] = row[riders] >= 0
    loading = Loading(row, loaded, reference, masses, centroids)
    return loading, free_index, free_blocks, support, usable, body
