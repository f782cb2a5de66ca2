"""The results table as GeoParquet (1.1): one row per lot, its polygon as WKB in the input's
coordinate system, the ``geo`` file metadata saying so (the system as PROJJSON).

The columns are the CSV's (:func:`shapegen.city.outputs.table_rows`) with their own types:
``warnings`` and ``from_properties`` are lists of strings, ``seconds`` (a lot's time in its
worker), ``iterations`` (of a search) and ``peak_rss_mib`` (its worker's peak memory) numbers,
then ``geometry``. A column of ``attr.NAME`` whose lots hold values of different kinds (a number
here, a string there) is written as strings. pyarrow comes with ``shapegen[city]``; without it
the file is not written and :func:`encode_parquet` says why in one line.
"""

from __future__ import annotations

__all__ = ["GEOPARQUET_VERSION", "PARQUET_MISSING", "encode_parquet", "have_pyarrow"]

import json

import numpy as np

GEOPARQUET_VERSION = "1.1.0"
PARQUET_MISSING = (
    "results.parquet not written: it needs pyarrow (pip install 'shapegen[city]' or pyarrow)"
)
_LISTS = ("warnings", "from_properties")
_NUMBERS = {"measure": "float64", "seconds": "float64", "peak_rss_mib": "float64",
            "lot_width": "float64", "lot_depth": "float64", "blocks": "int64", "solids": "int64",
            "left_out": "int64", "seed": "int64", "iterations": "int64"}  # fmt: skip


def have_pyarrow() -> bool:
    """Whether pyarrow can be imported (GeoParquet is written only with it)."""
    try:
        import pyarrow  # noqa: F401
        import pyarrow.parquet  # noqa: F401
    except ImportError:
        return False
    return True


def encode_parquet(city, columns: list[str], rows: list[dict], records: list[dict]) -> bytes:
    """GeoParquet bytes of the results table.

    Parameters
    ----------
    city
        Its ``lots`` (one per row, in order: their ``geometry`` in input coordinates) and
        ``input_crs`` (:class:`~shapegen.readers.crs.InputCrs`, for the ``geo`` metadata).
    columns, rows
        From :func:`~shapegen.city.outputs.table_rows`.
    records
        The lots' records (one per row), for the columns kept as lists.
    """
    import pyarrow as pa
    import pyarrow.parquet as pq
    import shapely

    data = {}
    for name in columns:
        if name in _LISTS:
            values = [list(record.get(name) or []) for record in records]
            data[name] = pa.array(values, type=pa.list_(pa.string()))
        else:
            data[name] = _column(name, [row.get(name) for row in rows])
    shapes = _shapes([lot.geometry for lot in city.lots])
    # a list, not numpy's array of objects: given an array, pyarrow looks for a masked one,
    # which imports numpy.ma (~7 ms of every run); the column is the same
    data["geometry"] = pa.array(shapely.to_wkb(shapes).tolist(), type=pa.binary())
    table = pa.table(data)
    geo = _geo_metadata(city, shapes[~shapely.is_missing(shapes)])
    table = table.replace_schema_metadata({b"geo": json.dumps(geo).encode("utf-8")})
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink, compression="zstd")
    return sink.getvalue().to_pybytes()


def _column(name: str, values: list):
    import pyarrow as pa

    if name in _NUMBERS:
        kind = pa.int64() if _NUMBERS[name] == "int64" else pa.float64()
        if kind == pa.int64() and any(isinstance(v, float) and not v.is_integer() for v in values):
            kind = pa.float64()
        return pa.array(values, type=kind)
    if name == "stands":
        return pa.array(values, type=pa.bool_())
    try:
        return pa.array(values)
    except (pa.ArrowInvalid, pa.ArrowTypeError):
        # values of several kinds (an attr that is a number on one lot, text on another)
        return pa.array([None if v is None else str(v) for v in values], type=pa.string())


def _shapes(geometries: list) -> np.ndarray:
    """Each lot's geometry as a shapely geometry (None where :func:`_shape` gives none): the
    plain polygons (one ring of pairs of finite numbers, the common case) made together from one
    array of their corners, the others one by one."""
    import shapely

    from shapegen.city.lot_rings import plain_corners

    plain, corners, offsets = plain_corners([{"geometry": g} for g in geometries])
    out = np.empty(len(geometries), dtype=object)
    if len(offsets) > 1:
        index = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
        try:
            out[plain] = shapely.polygons(shapely.linearrings(corners, indices=index))
        except (ValueError, shapely.errors.ShapelyError):  # a ring of too few corners
            plain[:] = False
    for k in np.flatnonzero(~plain).tolist():
        out[k] = _shape(geometries[k])
    return out


def _shape(geometry):
    """The lot's geometry as a shapely Polygon/MultiPolygon, or None when it has none or none
    that WKB can hold (a non-finite corner: its row says why the lot was not built)."""
    import numpy as np
    import shapely
    import shapely.geometry

    if not isinstance(geometry, dict):
        return None
    try:
        shape = shapely.geometry.shape(geometry)
    except (
        ValueError,
        TypeError,
        AttributeError,
        IndexError,
        KeyError,
        shapely.errors.ShapelyError,
    ):
        return None
    if shape.is_empty or not np.all(np.isfinite(shapely.get_coordinates(shape))):
        return None
    return shape


def _geo_metadata(city, shapes) -> dict:
    """The ``geo`` key of the file metadata (GeoParquet 1.1): WKB, the geometry types, the
    bounding box, the coordinate system as PROJJSON (null when it is unknown: local metres)."""
    import numpy as np

    kinds = sorted({shape.geom_type for shape in shapes})
    column: dict = {"encoding": "WKB", "geometry_types": kinds}
    input_crs = getattr(city, "input_crs", None)
    if input_crs is not None:
        column["crs"] = input_crs.projjson()  # None (JSON null): the system is unknown
    if len(shapes):
        import shapely

        bounds = shapely.bounds(np.asarray(shapes, dtype=object))
        column["bbox"] = [
            float(bounds[:, 0].min()),
            float(bounds[:, 1].min()),
            float(bounds[:, 2].max()),
            float(bounds[:, 3].max()),
        ]
    return {"version": GEOPARQUET_VERSION, "primary_column": "geometry", "columns": {
        "geometry": column}}  # fmt: skip
