"""A city run's files: the results table (CSV, GeoJSON and GeoParquet), the city glTF and its
picture, assembled at the end from the batches' records and buildings.

An output folder (or URL: :mod:`shapegen.city.store`) holds::

    run.json              the run's settings (rule, attrs, seed, search, statics) and frame
    lots/B-KEY.json       the records of one batch of lots, written by the worker that ran it
    lots/B-KEY.blocks     their buildings, placed in the city (:mod:`shapegen.city.batches`)
    results.csv           one row per lot, in input order, assembled from the records
    results.geojson       the same rows as the properties of the lots' polygons
    results.parquet       the same rows as GeoParquet (with pyarrow: shapegen.city.parquet)
    city.glb              one node per building, named by the lot id, in the local metric frame
"""

from __future__ import annotations

__all__ = [
    "encode_city_picture",
    "lot_key",
    "read_record",
    "table_rows",
    "write_tables",
]

import csv
import hashlib
import io
import json
import re
from pathlib import Path

import numpy as np

from shapegen.city.batches import block_colors as _block_colors  # noqa: F401 - the scene's
from shapegen.export.atomic import atomic_write
from shapegen.json_values import json_ready

_KEY_CHARS = 40
COLUMNS = [
    "id",
    "status",
    "stands",
    "measure",
    "structure",
    "blocks",
    "solids",
    "left_out",
    "seconds",
    "iterations",
    "peak_rss_mib",
    "seed",
    "footprint",
    "lot_width",
    "lot_depth",
    "from_properties",
    "warnings",
    "error",
]


def lot_key(lot_id: str) -> str:
    """The file name stem of a lot's record."""
    safe = re.sub(r"[^A-Za-z0-9_.-]+", "_", lot_id).strip("._")[:_KEY_CHARS] or "lot"
    return f"{safe}-{hashlib.blake2b(lot_id.encode(), digest_size=4).hexdigest()}"


def write_json(path: Path, document, *, indent: int | None = 1) -> None:
    with atomic_write(path) as handle:
        json.dump(json_ready(document), handle, indent=indent, allow_nan=False)
        handle.write("\n")


def read_record(path: Path) -> dict | None:
    """A lot's record, or None when the file is not one (then the lot is run again)."""
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return record if isinstance(record, dict) and "status" in record else None


def table_rows(records: list[dict]) -> tuple[list[str], list[dict]]:
    """The columns and the rows (flat: one ``attr.NAME`` column per attr) of ``records``."""
    attrs: list[str] = []
    for record in records:
        attrs.extend(name for name in record.get("attrs") or {} if name not in attrs)
    rows = []
    for record in records:
        lot = record.get("lot") or [None, None]
        row = {column: record.get(column) for column in COLUMNS}
        row.update(
            lot_width=lot[0],
            lot_depth=lot[1],
            from_properties=";".join(record.get("from_properties") or []),
            warnings="; ".join(record.get("warnings") or []),
        )
        row.update({f"attr.{name}": (record.get("attrs") or {}).get(name) for name in attrs})
        rows.append(row)
    return COLUMNS + [f"attr.{name}" for name in attrs], rows


def encode_csv(columns: list[str], rows: list[dict]) -> bytes:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    for row in rows:
        writer.writerow(["" if (v := row.get(k)) is None else _csv_value(v) for k in columns])
    return buffer.getvalue().encode("utf-8")


def _csv_value(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)  # every digit, so the CSV reads back the same numbers
    return value


def encode_geojson(city, rows: list[dict]) -> bytes:
    features = []
    for lot, row in zip(city.lots, rows, strict=True):
        geometry = lot.geometry if isinstance(lot.geometry, dict) else None
        features.append({"type": "Feature", "id": lot.id, "geometry": geometry, "properties": row})
    document = {"type": "FeatureCollection", "shapegen": city.frame(), "features": features}
    urn = city.input_crs.urn() if getattr(city, "input_crs", None) is not None else None
    if urn is not None:  # the input's coordinates are kept: say their system (old-style member)
        document = {"type": "FeatureCollection", "crs": {"type": "name", "properties": {
            "name": urn}}, **document}  # fmt: skip
    try:  # the input's geometries and the rows (records read back from JSON) are plain JSON
        # already: not walked through value by value
        text = json.dumps(document, allow_nan=False)
    except (TypeError, ValueError):
        text = json.dumps(json_ready(document), allow_nan=False)
    return (text + "\n").encode("utf-8")


def write_tables(folder, city, records: list[dict], *, scene: bool = True) -> dict:
    """Write ``results.csv``, ``results.geojson`` and (with ``scene``) ``city.glb`` from the
    records (one per lot of ``city``, in its order; None for a lot not done) into ``folder`` (a
    path or a :class:`~shapegen.city.store.CityStore`); their paths (URLs for a URL store)."""
    from shapegen.city.batches import read_batch_buildings
    from shapegen.city.scene import encode_city_glb
    from shapegen.city.store import open_store

    store = folder if hasattr(folder, "write") else open_store(folder)
    done = [record for record in records if record is not None]
    columns, rows = table_rows(done)
    lots = [lot for lot, record in zip(city.lots, records, strict=True) if record is not None]
    written = {"csv": "results.csv", "geojson": "results.geojson"}
    outputs = [
        (written["csv"], encode_csv(columns, rows)),
        (written["geojson"], encode_geojson(_Subset(city, lots), rows)),
    ]
    from shapegen.city.parquet import encode_parquet, have_pyarrow

    if have_pyarrow():
        written["parquet"] = "results.parquet"
        outputs.append(
            (written["parquet"], encode_parquet(_Subset(city, lots), columns, rows, done))
        )
    if scene:
        written["glb"] = "city.glb"
        arrays_of = lambda key: read_batch_buildings(store, key)  # noqa: E731
        outputs.append((written["glb"], encode_city_glb(city.frame(), done, arrays_of)))
    for name, content in outputs:
        store.write(name, content)
    return {role: store.path_of(name) for role, name in written.items()}


class _Subset:
    def __init__(self, city, lots):
        self.lots, self.frame = lots, city.frame
        self.input_crs = getattr(city, "input_crs", None)


def encode_city_picture(folder, records: list[dict], *, title: str = "", size_px=(1200, 800)):
    """PNG bytes of the built lots: label colours where a building stands, red where not.
    ``folder`` is the run's output (a path or a :class:`~shapegen.city.store.CityStore`)."""
    from matplotlib.figure import Figure

    from shapegen.city.batches import read_building
    from shapegen.city.store import open_store
    from shapegen.export.render import render_blocks
    from shapegen.model.model import Model

    store = folder if hasattr(folder, "write") else open_store(folder)
    blocks, surfaces, colors, surface_colors, cache = [], [], [], [], {}
    for record in records:
        if record is None or record.get("status") != "ok":
            continue
        building = read_building(store, record, cache)
        if building is None:
            continue
        blocks.extend(building[0].blocks)
        surfaces.extend(building[0].surfaces)
        colors.append(building[1])
        surface_colors.append(building[2])
    if not blocks and not surfaces:
        raise ValueError("no building to draw")
    city = Model(_renamed(blocks), surfaces=surfaces)
    rendering = render_blocks(
        city,
        np.concatenate(colors),
        size_px=size_px,
        elevation=35.0,
        surface_colors=np.concatenate(surface_colors),
    )
    width, height = size_px
    figure = Figure(figsize=(width / 100, height / 100), dpi=100, facecolor="white")
    figure.figimage(rendering.rgb, xo=0, yo=0, origin="upper")
    if title:
        figure.text(0.5, 0.97, title, ha="center", va="top", fontsize=12)
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=100)
    return buffer.getvalue()


def _renamed(blocks):
    """Blocks of several buildings with ids unique across them."""
    from dataclasses import replace

    return [replace(block, id=f"c{k}") for k, block in enumerate(blocks)]
