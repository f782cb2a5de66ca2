"""WGS84 positions projected onto a local tangent plane, in metres.

Geodetic latitude/longitude (height 0) -> earth-centred coordinates -> east, north, up about the
origin; the up component (the earth's curvature, ``d^2 / 2R``, about 0.6 m at 2.7 km) is
dropped. Over a few kilometres distances in this plane differ from geodesic ones by less than
``(d / R)^2 / 6`` relative (2.7 km: 3e-8). shapegen is y-up and right-handed: east -> +x,
up -> +y, north -> -z.
"""

from __future__ import annotations

__all__ = ["WGS84_A", "WGS84_F", "east_north"]

import math

import numpy as np

WGS84_A = 6_378_137.0
"""WGS84 semi-major axis, m."""
WGS84_F = 1.0 / 298.257223563
"""WGS84 flattening (dimensionless)."""
_E2 = WGS84_F * (2.0 - WGS84_F)  # first eccentricity squared


def east_north(lat, lon, origin_lat: float, origin_lon: float) -> np.ndarray:
    """Project WGS84 positions onto the local tangent plane at an origin.

    Parameters
    ----------
    lat, lon
        Geodetic latitude and longitude, degrees (scalars or arrays of one shape).
    origin_lat, origin_lon
        The tangent point, degrees.

    Returns
    -------
    numpy.ndarray
        ``(..., 2)``: east and north of each position, m, about the origin (heights 0 on the
        ellipsoid; the up component is dropped).
    """
    lat, lon = np.broadcast_arrays(np.radians(lat), np.radians(lon))
    phi0, lambda0 = math.radians(origin_lat), math.radians(origin_lon)
    # Earth-centred offsets from the origin; differences of 6e6 m coordinates keep some 1e-9 m.
    delta = _earth_centred(lat, lon) - _earth_centred(np.array(phi0), np.array(lambda0))
    dx, dy, dz = np.moveaxis(delta, -1, 0)
    east = -math.sin(lambda0) * dx + math.cos(lambda0) * dy
    north = (
        -math.sin(phi0) * math.cos(lambda0) * dx
        - math.sin(phi0) * math.sin(lambda0) * dy
        + math.cos(phi0) * dz
    )
    return np.stack([east, north], axis=-1)


def _earth_centred(phi: np.ndarray, lam: np.ndarray) -> np.ndarray:
    """Earth-centred, earth-fixed coordinates of points on the ellipsoid, m."""
    prime_vertical = WGS84_A / np.sqrt(1.0 - _E2 * np.sin(phi) ** 2)
    return np.stack(
        [
            prime_vertical * np.cos(phi) * np.cos(lam),
            prime_vertical * np.cos(phi) * np.sin(lam),
            prime_vertical * (1.0 - _E2) * np.sin(phi),
        ],
        axis=-1,
    )
