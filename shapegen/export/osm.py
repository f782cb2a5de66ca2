"""A model placed on an OpenStreetMap way (read by :mod:`shapegen.readers.osm`).

A bridge rule set runs along +x from x = 0 to x = ``length`` with its width across z. The bridge
is given the way's **straight** length, first node to last (a bridge is straight; the polyline
length, along every node, is reported beside it), then turned about +y so that +x points from
the first node to the last and moved so that its start (x = 0) sits on the first node, its width
(the model's extent in z) centred on the way, in the way's local frame (east +x, north -z).
"""

from __future__ import annotations

__all__ = ["place_on_way", "require_straight_length"]

import math

import numpy as np

from shapegen.errors import InputFormatError
from shapegen.model.model import Model, PointLoad
from shapegen.readers.osm import OsmWay

# A way whose ends are closer than this gives no direction to place a bridge along, m.
_MIN_STRAIGHT_LENGTH_M = 0.01


def require_straight_length(way: OsmWay) -> float:
    """The way's straight length (m); an error when its ends coincide (no direction)."""
    length = way.straight_length
    if length < _MIN_STRAIGHT_LENGTH_M:
        raise InputFormatError(
            f"{way.source}: the first and last nodes of way {way.id} coincide ({length:.3g} m"
            " apart); a bridge needs two distinct ends"
        )
    return length


def place_on_way(model: Model, way: OsmWay) -> Model:
    """The model turned and moved onto the way, in the way's local frame (m).

    The model's +x axis is turned about +y to point from the way's first node to its last, its
    x = 0 put on the first node (the frame's origin) and its extent in z centred on the way;
    heights are kept. ``metadata["osm"]`` records the way (:meth:`OsmWay.to_report`).
    """
    require_straight_length(way)
    theta = math.radians(way.heading)
    # Columns: where the model's x, y, z axes go. x -> (east sin, north cos) = (sin, 0, -cos).
    rotation = np.array(
        [
            [math.sin(theta), 0.0, math.cos(theta)],
            [0.0, 1.0, 0.0],
            [-math.cos(theta), 0.0, math.sin(theta)],
        ]
    )
    if model.blocks:
        lo = min(float(block.vertices[:, 2].min()) for block in model.blocks)
        hi = max(float(block.vertices[:, 2].max()) for block in model.blocks)
        middle = 0.5 * (lo + hi)
    else:
        middle = 0.0
    offset = -middle * rotation[:, 2]
    blocks = [block.transformed(rotation, offset) for block in model.blocks]
    loads = [
        PointLoad(load.block, rotation @ load.force, rotation @ load.point + offset)
        for load in model.loads
    ]
    metadata = {**model.metadata, "osm": way.to_report()}
    return Model(
        blocks,
        loads,
        gravity=model.gravity.copy(),
        ground=model.ground,
        friction=model.friction,
        metadata=metadata,
    )
