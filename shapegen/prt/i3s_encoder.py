"""``com.esri.prt.codecs.I3SEncoder``: the generated models as a Scene Layer Package (.slpk).

The options are those CityEngine's runtime documents for this encoder (Esri/cityengine-sdk,
``esri_prt_codecs.html``) and those PyPRT's scripts pass (``layerTexture*``, ``layerEnabled``);
each is honoured or refused with one line, in :data:`I3S_OPTIONS`. The per-layer options
(``layer...``) are lists, one item per layer; the models make one layer, so a list holds one
item (or none: the default). The layer itself is written by :mod:`shapegen.export.i3s`.

Coordinates: CGA's x, y (up), z become the scene's x (east), z (up) and -y (north), as
CityEngine's encoder writes them. A ``Local`` scene keeps them in the coordinate system
``sceneWkid`` names; a ``Global`` scene reads them as Web Mercator metres (EPSG:3857) and
writes longitude and latitude (WGS84, wkid 4326) whatever ``sceneWkid`` says, as PyPRT 1.12's
encoder does (measured: 38 m east of the origin becomes 0.000341360 degrees).
"""

from __future__ import annotations

__all__ = ["I3S_OPTIONS", "i3s_writer"]

from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np

from shapegen.errors import OptionError
from shapegen.export.surfaces import face_triangles
from shapegen.prt.encoder_options import checked_option_names

NAME = "com.esri.prt.codecs.I3SEncoder"
GRANULARITY = {"0": "shape", "FEATURE_PER_SHAPE": "shape",
               "1": "leaf", "FEATURE_PER_LEAF_SHAPE": "leaf"}  # fmt: skip
TEXTURE_OPTIONS = (
    "layerTextureEncoding",
    "layerTextureQuality",
    "layerTextureCompression",
    "layerTextureScaling",
    "layerTextureMaxDimension",
)
I3S_OPTIONS = {
    "outputPath": "the folder the package is written to",
    "baseName": "the package's name: <baseName>.slpk (default base_name)",
    "sceneType": "Local (the coordinates as they are) or Global (Web Mercator metres to WGS84)",
    "sceneWkid": "the coordinate system of a Local scene (default 32631)",
    "sceneAuth": "EPSG only",
    "layerName": "the layer's name (default baseName)",
    "layerUID": "the layer's store id",
    "layerEnabled": "[True] only: the one layer is written",
    "layerFeatureGranularity": "a feature per initial shape (0, default) or per leaf (1)",
    "featureGranularity": "as layerFeatureGranularity",
    "layerBackfaceCulling": "the material culls back faces",
    "backfaceCulling": "as layerBackfaceCulling",
    "emitReports": "each feature carries its shape's reports as attributes (default True)",
    "compression": "gzip each resource (default True)",
    "existingFiles": "OVERWRITE (default) or SKIP an existing package",
    "maxDepth": "at least 2: the tree is a root and one node",
    "ignoreLayers": "True only: one layer",
    "writePackage": "True only",
    "errorFallback": "False only: a shape that fails is left out",
    "writeLog": "False only",
    "shapeNameDelimiter": "accepted; features are numbered, not named",
    **{
        name: "accepted: the layer has no textures, so nothing to encode"
        for name in TEXTURE_OPTIONS
    },
}
"""Every option the encoder takes, with what it does; any other is refused."""
REFUSED_TEXT = ("author", "applicationName", "applicationVersion", "applicationString",
                "applicationVendor")  # fmt: skip


def i3s_writer(options: Mapping[str, object]) -> Callable[[list, Path, str], None]:
    """Check ``options`` (all but ``outputPath``) and return the package's writer."""
    from shapegen.export.i3s import SceneLayer

    checked_option_names(
        NAME, options, I3S_OPTIONS, REFUSED_TEXT, "an I3S 1.7 layer has no field for it"
    )
    for name in TEXTURE_OPTIONS:
        _layer_value(options, name, None)
    scene = str(options.get("sceneType", "Global"))
    if scene not in ("Local", "Global"):
        raise OptionError(f"{NAME}: sceneType {scene!r} is not Local or Global")
    if str(options.get("sceneAuth", "EPSG")) != "EPSG":
        raise OptionError(f"{NAME}: sceneAuth {options['sceneAuth']!r}: only EPSG is known")
    try:
        wkid = int(str(options.get("sceneWkid", "32631")))
    except ValueError:
        raise OptionError(f"{NAME}: sceneWkid {options['sceneWkid']!r} is not a number") from None
    if scene == "Local" and wkid == 4326:
        raise OptionError(f"{NAME}: a Local scene in WGS84 degrees (sceneWkid 4326): use Global")
    for name, allowed in (("layerEnabled", True), ("ignoreLayers", True), ("writePackage", True),
                          ("errorFallback", False), ("writeLog", False)):  # fmt: skip
        value = (
            _layer_value(options, name, allowed)
            if name == "layerEnabled"
            else options.get(name, allowed)
        )
        if value is not allowed:
            raise OptionError(f"{NAME}: {name} {value!r}: only {allowed} is supported")
    depth = options.get("maxDepth", 2)
    if isinstance(depth, bool) or not isinstance(depth, int) or depth < 2:
        raise OptionError(f"{NAME}: maxDepth {depth!r}: the tree has 2 levels, give at least 2")
    existing = str(options.get("existingFiles", "OVERWRITE"))
    if existing not in ("OVERWRITE", "SKIP"):
        raise OptionError(f"{NAME}: existingFiles {existing!r} is not OVERWRITE or SKIP")
    granularity = _layer_value(options, "layerFeatureGranularity", None)
    if granularity is None:
        granularity = options.get("featureGranularity", "FEATURE_PER_SHAPE")
    if str(granularity) not in GRANULARITY:
        raise OptionError(
            f"{NAME}: feature granularity {granularity!r}: give {', '.join(GRANULARITY)}"
        )
    per_leaf = GRANULARITY[str(granularity)] == "leaf"
    culling = _layer_value(options, "layerBackfaceCulling", None)
    if culling is None:
        culling = options.get("backfaceCulling", False)
    flags = {n: options.get(n, True) for n in ("emitReports", "compression")} | {"culling": culling}
    for name, value in flags.items():
        if not isinstance(value, bool):
            raise OptionError(f"{NAME}: {name} is a boolean, got {value!r}")
    layer_name = _layer_value(options, "layerName", None)
    uid = _layer_value(options, "layerUID", "")

    def write(models: list, folder: Path, base: str) -> None:
        from shapegen.export.atomic import atomic_write
        from shapegen.export.i3s import encode_slpk

        target = folder / f"{base}.slpk"
        if existing == "SKIP" and target.exists():
            return
        layer = SceneLayer(
            name=str(layer_name or base),
            wkid=4326 if scene == "Global" else wkid,
            uid=str(uid),
            cull_back_faces=flags["culling"],
            gzip_resources=flags["compression"],
        )
        features = scene_features(models, per_leaf=per_leaf, reports=flags["emitReports"])
        payload = encode_slpk(features, layer)
        with atomic_write(target, "wb") as handle:
            handle.write(payload)

    return write


def scene_features(models: list, *, per_leaf: bool, reports: bool) -> list:
    """The features of ``models`` (:class:`GeneratedModel`): one per model or per leaf, in the
    scene's frame (x east, y north, z up), with the shape's reports as attributes."""
    from shapegen.export.i3s import Feature

    features = []
    for model in models:
        attributes = _report_attributes(model.model.metadata.get("reports", {})) if reports else {}
        leaves = [*model.model.blocks, *model.model.surfaces]
        meshes = [_leaf_mesh(leaf) for leaf in leaves]
        if per_leaf:
            features += [Feature(p, t, attributes, c) for p, t, c in meshes]
            continue
        positions, triangles, colors, base = [], [], [], 0
        for points, faces, rgba in meshes:
            positions.append(points)
            triangles.append(faces + base)
            colors.append(rgba)
            base += len(points)
        features.append(
            Feature(
                np.concatenate(positions) if positions else np.zeros((0, 3)),
                np.concatenate(triangles) if triangles else np.zeros((0, 3), dtype=int),
                attributes,
                np.concatenate(colors) if colors else None,
            )
        )
    return features


def _leaf_mesh(leaf) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A leaf's corners in the scene's frame, its triangles, and their colour: the leaf's
    ``color`` and opacity (CityEngine's default white where the rule set none)."""
    points = np.asarray(leaf.vertices, dtype=float).reshape(-1, 3)
    triangles = face_triangles(points, leaf.faces).reshape(-1, 3)
    # CGA y up, z south; the scene z up, y north (a proper rotation: the turn is kept)
    scene = np.column_stack([points[:, 0], -points[:, 2], points[:, 1]])
    look = leaf.appearance
    rgb = look.color if look is not None and look.color is not None else (1.0, 1.0, 1.0)
    alpha = look.opacity if look is not None else 1.0
    rgba = np.round(np.clip([*rgb, alpha], 0.0, 1.0) * 255).astype(np.uint8)
    return scene, triangles, np.tile(rgba, (len(triangles), 1))


def _report_attributes(reports: Mapping[str, object]) -> dict:
    """A report's value, or for a key reported several times the sum of its numbers (the
    first value of a text), as PyPRT's report dictionary aggregates them."""
    out = {}
    for key, value in reports.items():
        values = value if isinstance(value, list) else [value]
        if not values:
            continue
        numbers = [v for v in values if isinstance(v, int | float) and not isinstance(v, bool)]
        out[key] = float(sum(numbers)) if len(numbers) == len(values) else values[0]
    return out


def _layer_value(options: Mapping[str, object], name: str, default):
    """The one item of a per-layer option (a list of one), or ``default`` when not given."""
    if name not in options:
        return default
    value = options[name]
    if not isinstance(value, list | tuple):
        raise OptionError(f"{NAME}: {name} is a per-layer list (one item per layer), got {value!r}")
    if len(value) > 1:
        raise OptionError(f"{NAME}: {name} has {len(value)} items; the models make one layer")
    return value[0] if value else default
