"""A city run's files: the per-lot records, the results table (CSV and GeoJSON), the city glTF
and its picture.

An output folder holds::

    run.json              the run's settings (rule, attrs, seed, search, statics) and frame
    lots/KEY.json         one record per finished lot (written atomically, as each finishes)
    lots/KEY.blocks.json  its building, placed in the city (shapegen-blocks), for built lots
    results.csv           one row per lot, in input order, assembled from the records
    results.geojson       the same rows as the properties of the lots' polygons
    results.parquet       the same rows as GeoParquet (with pyarrow: shapegen.city.parquet)
    city.glb              one node per building, named by the lot id, in the local metric frame

``KEY`` is the lot id made safe for a file name plus a short hash of the id, so two ids never
share a file.
"""

from __future__ import annotations

__all__ = [
    "city_scene",
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
_FAILED = np.array([220, 30, 30, 255], dtype=np.uint8)  # a building that does not stand


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
    writer = csv.DictWriter(buffer, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: "" if v is None else _csv_value(v) for k, v in row.items()})
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
    return (json.dumps(json_ready(document), allow_nan=False) + "\n").encode("utf-8")


def write_tables(folder: Path, city, records: list[dict], *, scene: bool = True) -> dict:
    """Write ``results.csv``, ``results.geojson`` and (with ``scene``) ``city.glb`` from the
    records (one per lot of ``city``, in its order; None for a lot not done); the paths."""
    done = [record for record in records if record is not None]
    columns, rows = table_rows(done)
    lots = [lot for lot, record in zip(city.lots, records, strict=True) if record is not None]
    written = {"csv": folder / "results.csv", "geojson": folder / "results.geojson"}
    outputs = [
        (written["csv"], encode_csv(columns, rows)),
        (written["geojson"], encode_geojson(_Subset(city, lots), rows)),
    ]
    from shapegen.city.parquet import encode_parquet, have_pyarrow

    if have_pyarrow():
        written["parquet"] = folder / "results.parquet"
        outputs.append(
            (written["parquet"], encode_parquet(_Subset(city, lots), columns, rows, done))
        )
    if scene:
        import trimesh

        written["glb"] = folder / "city.glb"
        buildings = [(record, _blocks_path(folder, record)) for record in done]
        outputs.append(
            (written["glb"], trimesh.exchange.gltf.export_glb(city_scene(city, buildings)))
        )
    for path, content in outputs:
        with atomic_write(path, "wb") as handle:
            handle.write(content)
    return written


class _Subset:
    def __init__(self, city, lots):
        self.lots, self.frame = lots, city.frame
        self.input_crs = getattr(city, "input_crs", None)


def _blocks_path(folder: Path, record: dict) -> Path:
    return folder / "lots" / f"{lot_key(record['id'])}.blocks.json"


def _building(path: Path):
    """The placed blocks of a lot (a Model of them), or None when it has none.

    The file was written by this run from a checked model, so its blocks are taken as they are
    (``model_from_dict`` would check every face's orientation again: 0.15 s per house).
    """
    from shapegen.model.block import Block
    from shapegen.model.model import Model

    try:
        document = json.loads(path.read_text(encoding="utf-8"))
        blocks = [
            Block(
                np.asarray(entry["vertices"], dtype=float),
                tuple(tuple(face) for face in entry["faces"]),
                id=str(entry["id"]),
                tags=tuple(entry.get("tags", ())),
                structural=bool(entry.get("structural", True)),
                fixed=bool(entry.get("fixed", False)),
            )
            for entry in document["blocks"]
        ]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    return Model(blocks)


def city_scene(city, buildings):
    """A trimesh scene of the city: one node per building (named by the lot id), its blocks in
    their label colours, red when the building does not stand; the frame in the scene's extras.
    ``buildings`` pairs each record with its blocks file."""
    import trimesh

    from shapegen.export.meshes import model_mesh

    scene = trimesh.Scene(metadata={"shapegen_city": city.frame()})
    for record, path in buildings:
        if record.get("status") != "ok":
            continue
        model = _building(path)
        if model is None or not model.blocks:
            continue
        mesh = model_mesh(model)
        mesh.visual.face_colors = _face_colors(model, stands=bool(record.get("stands")))
        extras = {key: record.get(key) for key in ("id", "stands", "measure", "blocks", "seed")}
        scene.add_geometry(
            mesh, node_name=record["id"], geom_name=record["id"], metadata=json_ready(extras)
        )
    return scene


def _block_colors(model, *, stands: bool) -> np.ndarray:
    from shapegen.export.colors import block_label_color, model_label_colors

    if not stands:
        return np.repeat(_FAILED[None], len(model.blocks), axis=0)
    by_label = model_label_colors(model.blocks)  # each label its own, as the design page has
    return np.array(
        [
            block_label_color(b.tags, fixed=b.fixed, structural=b.structural, colors=by_label)
            for b in model.blocks
        ],
        dtype=np.uint8,
    ).reshape(-1, 4)


def _face_colors(model, *, stands: bool) -> np.ndarray:
    from shapegen.export.meshes import block_triangles

    colors = _block_colors(model, stands=stands)
    counts = [len(block_triangles(block)) for block in model.blocks]
    return np.repeat(colors, counts, axis=0)


def encode_city_picture(folder: Path, records: list[dict], *, title: str = "", size_px=(1200, 800)):
    """PNG bytes of the built lots: label colours where a building stands, red where not."""
    from matplotlib.figure import Figure

    from shapegen.export.render import render_blocks
    from shapegen.model.model import Model

    blocks, colors = [], []
    for record in records:
        if record is None or record.get("status") != "ok":
            continue
        model = _building(_blocks_path(folder, record))
        if model is None:
            continue
        blocks.extend(model.blocks)
        colors.append(_block_colors(model, stands=bool(record.get("stands"))))
    if not blocks:
        raise ValueError("no building to draw")
    city = Model(_renamed(blocks))
    rendering = render_blocks(city, np.concatenate(colors), size_px=size_px, elevation=35.0)
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
