"""Hostile rule packages (.rpk, 7z) and lot files (GeoJSON, gzip, OSM XML), crafted or mutated
from real ones, for the quick reproducers (test_hostile_reproducers.py) and the slow fuzzers
(test_fuzz_hostile.py); and the two doors they are given to, each checking that nothing is
written outside where the door may write.

Every input comes from ``(seed, number)``, so a failure names an input that can be replayed:
``python tests/fuzz/test_fuzz_hostile.py package SEED NUMBER``.
"""

from __future__ import annotations

import functools
import gzip
import io
import json
import math
import os
import random
import stat
import struct
import tempfile
import zlib
from pathlib import Path

import py7zr

ROOT = Path(__file__).resolve().parents[2]
CORPUS_FOLDERS = ROOT / "tests" / "data" / "cga-corpus"
SHARED_PACKAGES = Path("/work/shared/cga-corpus/packages")  # when present: the packages whole


# ------------------------------------------------------------------------------ packages
def package_bytes(members: dict, *, copy: bool = False, encoded_header: bool = True) -> bytes:
    """A 7z archive of ``members``: name -> bytes or text (names unchecked, as a hostile
    archive may hold them); ``("symlink", target)`` makes a symbolic link. ``copy`` stores
    the data uncompressed (so that a changed byte is a checksum failure, not an LZMA one)."""
    buffer = io.BytesIO()
    filters = [{"id": py7zr.FILTER_COPY}] if copy else None
    with py7zr.SevenZipFile(buffer, "w", filters=filters) as archive:
        archive.set_encoded_header_mode(encoded_header)
        for name, content in members.items():
            link = isinstance(content, tuple) and content[0] == "symlink"
            data = content[1] if link else content
            archive._writestr(data.encode() if isinstance(data, str) else data, name)  # unchecked
            if link:  # the link's target as its data, its mode a link's (as 7-Zip stores one)
                mode = stat.S_IFLNK | 0o777
                archive.header.files_info.files[-1]["attributes"] = (
                    (mode << 16) | _UNIX_EXTENSION | 0x20
                )
    return buffer.getvalue()


_UNIX_EXTENSION = 0x8000  # FILE_ATTRIBUTE_UNIX_EXTENSION: the high 16 bits hold st_mode


RULE = "Lot --> extrude(3) comp(f) { top : Roof | all : NIL }\nRoof --> NIL\n"


def small_package(**extra) -> dict:
    """The members of a valid small package, with ``extra`` ones."""
    return {"rules/main.cga": RULE, "bin/main.cgb": "compiled", **extra}


@functools.lru_cache(maxsize=1)
def corpus_packages() -> tuple[bytes, ...]:
    """The real packages: the corpus's when present, else packages made of the test corpus's
    folders (their rules and assets)."""
    if SHARED_PACKAGES.is_dir():
        found = sorted(SHARED_PACKAGES.glob("*.rpk"))
        if found:
            return tuple(path.read_bytes() for path in found)
    made = []
    for folder in sorted(p for p in CORPUS_FOLDERS.iterdir() if p.is_dir()):
        members = {
            str(path.relative_to(folder)): path.read_bytes()
            for path in sorted(folder.rglob("*"))
            if path.is_file()
        }
        made.append(package_bytes(members))
    return tuple(made)


@functools.lru_cache(maxsize=1)
def bomb_package() -> bytes:
    """One member of 640 MiB of zeros (over the default 512 MiB a package may unpack to; about
    100 kB packed), declared as it is."""
    buffer = io.BytesIO()
    with tempfile.TemporaryDirectory() as scratch:
        zeros = Path(scratch) / "zeros.bin"
        with open(zeros, "wb") as handle:
            handle.truncate(640 * 2**20)  # sparse: nothing on the disk
        fast = [{"id": py7zr.FILTER_LZMA2, "preset": 1}]
        with py7zr.SevenZipFile(buffer, "w", filters=fast) as archive:
            archive.write(zeros, "assets/zeros.bin")
            archive.writestr(RULE.encode(), "rules/main.cga")
    return buffer.getvalue()


def with_header_fixed(data: bytes) -> bytes:
    """``data`` whose start header's checksums are made right again after its next header
    (the member list, sizes and names) was edited: the edit then reaches the decoder as a
    lying header would, instead of stopping at the checksum."""
    data = bytearray(data)
    offset, size = struct.unpack_from("<QQ", data, 12)
    start = 32 + offset
    if size <= 0 or start + size > len(data):
        return bytes(data)
    struct.pack_into("<I", data, 28, zlib.crc32(data[start : start + size]))
    struct.pack_into("<I", data, 8, zlib.crc32(data[12:32]))
    return bytes(data)


def _corrupted(rng: random.Random, data: bytes) -> bytes:
    data = bytearray(data)
    for _ in range(rng.randint(1, 8)):
        data[rng.randrange(len(data))] = rng.randrange(256)
    return bytes(data)


def hostile_package(seed: int, number: int) -> tuple[str, bytes]:
    """A hostile package: (what it is, its bytes)."""
    rng = random.Random(f"package {seed} {number}")
    kind = rng.choice(PACKAGE_KINDS)
    return kind, PACKAGE_MAKERS[kind](rng)


def _lying_header(rng: random.Random) -> bytes:
    members = small_package(**{f"assets/a{k}.txt": "x" * rng.randint(0, 3000) for k in range(3)})
    data = bytearray(package_bytes(members, encoded_header=False, copy=rng.random() < 0.5))
    offset, size = struct.unpack_from("<QQ", data, 12)
    for _ in range(rng.randint(1, 6)):
        position = 32 + offset + rng.randrange(max(int(size), 1))
        if position < len(data):
            data[position] = rng.choice([0, 0xFF, 0x7F, 0x80, rng.randrange(256)])
    return with_header_fixed(bytes(data))


PACKAGE_MAKERS = {
    "corrupted corpus package": lambda rng: _corrupted(rng, rng.choice(corpus_packages())),
    "truncated corpus package": lambda rng: (p := rng.choice(corpus_packages()))[
        : rng.randrange(len(p))
    ],
    "lying header": _lying_header,
    "path escape": lambda rng: package_bytes(
        small_package(
            **{rng.choice(["../", "../../", "rules/../../", "..\\", "./../"]) + "evil.cga": "x"}
        )
    ),
    "absolute path": lambda rng: package_bytes(
        small_package(**{rng.choice(["/tmp/evil.cga", "//evil", "C:/evil", "\\evil"]): "x"})
    ),
    "symlink": lambda rng: package_bytes(
        small_package(
            **{"rules/link.cga": ("symlink", rng.choice(["/etc/passwd", "../../..", "main.cga"]))}
        )
    ),
    "deep folders": lambda rng: package_bytes(
        small_package(**{"d/" * rng.choice([65, 300, 2000, 5000]) + "x.cga": "x"})
    ),
    "many members": lambda rng: package_bytes(
        small_package(**{f"assets/{k}": b"" for k in range(rng.choice([100, 20_001]))})
    ),
    "bomb": lambda rng: bomb_package(),
    "corrupted bomb": lambda rng: _corrupted(rng, bomb_package()),
    "damaged copy stream": lambda rng: _corrupted(
        rng, package_bytes(small_package(**{"assets/data.bin": bytes(4000)}), copy=True)
    ),
}
PACKAGE_KINDS = sorted(PACKAGE_MAKERS)


def run_package(data: bytes) -> None:
    """Load ``data`` as a rule package in a fresh folder; fail when anything appears outside
    the package cache's own folder for it."""
    import shapegen

    with tempfile.TemporaryDirectory() as scratch:
        root = Path(scratch)
        package = root / "in" / "p.rpk"
        package.parent.mkdir()
        package.write_bytes(data)
        os.environ["SHAPEGEN_CACHE"] = str(root / "cache")
        try:
            shapegen.load_grammar(package)
        finally:
            _assert_only_in(root, [package, root / "cache" / "packages"])


def _assert_only_in(root: Path, allowed: list[Path]) -> None:
    for path in root.rglob("*"):
        if path.is_symlink() and not any(path.is_relative_to(a) for a in allowed[1:]):
            raise AssertionError(f"a link was written: {path}")
        if not (path in allowed or any(path.is_relative_to(a) for a in allowed[1:])):
            if any(a.is_relative_to(path) for a in allowed):
                continue  # a folder on the way to an allowed place
            raise AssertionError(f"written outside the package's folder: {path}")
    packages = root / "cache" / "packages"
    for path in packages.iterdir() if packages.is_dir() else ():
        if not (path.is_dir() and path.name.startswith("p-")):  # the package's own folder
            raise AssertionError(f"written outside the package's folder: {path}")
    for path in packages.rglob("*") if packages.is_dir() else ():
        if path.is_symlink():
            raise AssertionError(f"a link was unpacked: {path}")


# ------------------------------------------------------------------------------ lot files
def feature_collection(rings, *, crs=None, ids=None) -> dict:
    features = [
        {
            "type": "Feature",
            "id": ids[k] if ids else f"lot{k}",
            "properties": {},
            "geometry": {"type": "Polygon", "coordinates": [ring]},
        }
        for k, ring in enumerate(rings)
    ]
    document = {"type": "FeatureCollection", "features": features}
    if crs is not None:
        document["crs"] = crs
    return document


def square(x0: float, y0: float = 0.0, size: float = 10.0) -> list:
    return [[x0, y0], [x0 + size, y0], [x0 + size, y0 + size], [x0, y0 + size], [x0, y0]]


def geojson_bytes(document) -> bytes:
    return json.dumps(document, allow_nan=True).encode()


@functools.lru_cache(maxsize=1)
def gzip_bomb() -> bytes:
    """A gzip of 256 MiB of spaces inside a FeatureCollection (about 250 kB; eight times the
    default max_file_bytes)."""
    buffer = io.BytesIO()
    with gzip.GzipFile(fileobj=buffer, mode="wb", compresslevel=9) as stream:
        stream.write(b'{"type": "FeatureCollection", "features": [')
        chunk = b" " * 2**24
        for _ in range(16):
            stream.write(chunk)
        stream.write(b"]}")
    return buffer.getvalue()


def _ring_with(rng: random.Random, value: float) -> list:
    ring = square(rng.uniform(-50, 50))
    corner = rng.randrange(len(ring))
    ring[corner] = [value, ring[corner][1]] if rng.random() < 0.5 else [ring[corner][0], value]
    return ring


def _huge_ring(rng: random.Random) -> list:
    count = rng.choice([10_000, 200_000])
    angles = [2 * math.pi * k / count for k in range(count)]
    ring = [[20 * math.cos(a), 20 * math.sin(a)] for a in angles]
    return [*ring, ring[0]]


def _deep(rng: random.Random) -> bytes:
    depth = rng.choice([257, 1000, 100_000, 1_000_000])
    opening, closing = rng.choice([("[", "]"), ('{"a":', "}")])
    return (b'{"type": "FeatureCollection", "features": ' + opening.encode() * depth
            + closing.encode() * depth + b"}")  # fmt: skip


def _wrong_crs(rng: random.Random) -> dict:
    crs = rng.choice([
        {"type": "name", "properties": {"name": "EPSG:999999"}},
        {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::2154"}},
        {"type": "name", "properties": {"name": ["x"]}},
        {"type": "name", "properties": None}, "EPSG:4326", 7, [],
        {"type": "name", "properties": {"name": "+proj=longlat +datum=NAD27"}},
        {"type": "name", "properties": {"name": "x" * 10_000}},
    ])  # fmt: skip
    rings = [square(rng.choice([0, 1e6, 1e12, -1e300, 600000]), rng.choice([0, 6e6, 1e15]))]
    return feature_collection(rings, crs=crs)


def _mutated_json(rng: random.Random) -> bytes:
    rings = [square(10 * k) for k in range(rng.randint(1, 5))]
    text = bytearray(geojson_bytes(feature_collection(rings)))
    for _ in range(rng.randint(1, 10)):
        position = rng.randrange(len(text))
        choice = rng.random()
        if choice < 0.4:
            text[position] = rng.choice(b'[]{}",:0123456789-.eE NaInfity')
        elif choice < 0.7:
            del text[position]
        else:
            text[position:position] = rng.choice(
                [b"NaN", b"Infinity", b"-Infinity", b"1e999", b"[", b"]", b"null", b"9" * 400]
            )
    return bytes(text)


def _osm(rng: random.Random) -> bytes:
    nodes = "".join(
        f'<node id="{k}" lat="{rng.choice([0.0, 0.0001 * k, "nan", "inf", 91, -1e308])}" '
        f'lon="{0.0001 * (k % 2)}"/>'
        for k in range(1, 5)
    )
    way = '<way id="1">' + "".join(f'<nd ref="{k}"/>' for k in (1, 2, 3, 4, 1))
    way += '<tag k="building" v="yes"/></way>'
    if rng.random() < 0.3:  # entity expansion
        doctype = (
            '<!DOCTYPE osm [<!ENTITY a "aaaaaaaaaa">'
            + "".join(
                f'<!ENTITY {chr(98 + k)} "' + f"&{chr(97 + k)};" * 10 + '">' for k in range(8)
            )
            + "]>"
        )
        return f'<?xml version="1.0"?>{doctype}<osm version="0.6">&i;{nodes}{way}</osm>'.encode()
    return f'<?xml version="1.0"?><osm version="0.6">{nodes}{way}</osm>'.encode()


LOT_MAKERS = {
    "nan corner": lambda rng: geojson_bytes(
        feature_collection([square(0), _ring_with(rng, rng.choice([math.nan, math.inf]))])
    ),
    "nan closing corner": lambda rng: geojson_bytes(
        feature_collection([square(0), [[math.nan, 0], [30, 0], [30, 10], [math.nan, 0]]])
    ),
    "self-crossing": lambda rng: geojson_bytes(
        feature_collection([square(0), [[20, 0], [30, 10], [30, 0], [20, 10], [20, 0]]])
    ),
    "huge ring": lambda rng: geojson_bytes(feature_collection([_huge_ring(rng)])),
    "extreme numbers": lambda rng: geojson_bytes(
        feature_collection(
            [[[rng.choice([1e308, -1e308, 5e-324, 1e15, 0]) for _ in range(2)] for _ in range(5)]]
        )
    ),
    "deep nesting": _deep,
    "gzip bomb": lambda rng: gzip_bomb(),
    "truncated gzip": lambda rng: gzip.compress(geojson_bytes(feature_collection([square(0)])))[
        : rng.randint(2, 30)
    ],
    "wrong crs": lambda rng: geojson_bytes(_wrong_crs(rng)),
    "mutated json": _mutated_json,
    "duplicate ids": lambda rng: geojson_bytes(
        feature_collection([square(0), square(20)], ids=["a", "a"])
    ),
    "osm xml": _osm,
    "random bytes": lambda rng: bytes(rng.randrange(256) for _ in range(rng.randint(0, 2000))),
}
LOT_KINDS = sorted(LOT_MAKERS)


def hostile_lots(seed: int, number: int) -> tuple[str, bytes]:
    """A hostile lot file: (what it is, its bytes)."""
    rng = random.Random(f"lots {seed} {number}")
    kind = rng.choice(LOT_KINDS)
    return kind, LOT_MAKERS[kind](rng)


def run_lots(data: bytes) -> None:
    """Read ``data`` as a city's lots (``shapegen city``'s reader, any CRS option) and write
    the results tables of its lots as failed rows; then as ``--lot`` (the first polygon)."""
    from shapegen.city import read_lots
    from shapegen.city.outputs import write_tables
    from shapegen.city.work import new_record
    from shapegen.errors import ShapegenError
    from shapegen.readers.lot_sources import read_lot

    with tempfile.TemporaryDirectory() as scratch:
        root = Path(scratch)
        suffix = ".osm" if data.lstrip()[:1] == b"<" else ".geojson"
        path = root / f"lots{suffix}"
        path.write_bytes(data)
        crs = random.Random(data[:64]).choice([None, "metres", "lonlat", "EPSG:2154"])

        def as_city() -> None:
            city = read_lots(path, crs=crs)
            records = []
            for k, lot in enumerate(city.lots):
                record = new_record(lot.id, k)
                record.update(error=lot.problem or "not built", seconds=0.0)
                records.append(record)
            (root / "out").mkdir(exist_ok=True)
            write_tables(root / "out", city, records, scene=False)

        refusals = []
        for door in (as_city, lambda: read_lot(str(path))):
            try:
                door()
            except ShapegenError as exc:
                refusals.append(exc)
        if refusals:
            raise refusals[0]
