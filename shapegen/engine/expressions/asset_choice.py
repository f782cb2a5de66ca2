"""Choosing assets and images by how they fit the scope: celib's ``assetBestSize``,
``assetApproxSize``, ``assetFitSize``, ``assetBestRatio``, ``assetApproxRatio``,
``imageBestRatio``, ``imageApproxRatio`` (a search query of the project's files) and the
functions they rest on, ``assetsSortSize``, ``assetsSortRatio`` and ``imagesSortRatio`` (a
string list ``"a;b;"`` or a string array).

The reference names the axes compared but not the measure of a fit. shapegen's, said in a
warning of the derivation at the first use of each function:

- size along axes A: the sum over A of ``|ln(asset size / scope size)|`` (how far the asset is
  scaled; an axis where either size is 0 is left out); ``maxScaleError`` e keeps the assets
  scaled by a factor in [1 - e, 1 + e] along every axis of A (0 keeps all);
- ratio of axes "ab": ``|ln((asset a / asset b) / (scope a / scope b))|``; "xyz" adds the
  "xy" and "yz" terms; an image's ratio is its width / height (pixels), against the ratio of
  the two scope axes named.

The best fit is the least measure; among equal ones (and for the approximate functions among
the n best, for ``assetFitSize`` among those kept) one is drawn with the shape's random
generator, as ``fileRandom`` draws. An asset that cannot be read is left out with a warning.
"""

from __future__ import annotations

__all__ = ["PARTIAL_FUNCTIONS", "asset_choosers"]

import math
from collections.abc import Callable

from shapegen.engine.derivation.state import format_chain
from shapegen.engine.expressions.arrays import Array
from shapegen.engine.project.asset_files import find_asset, load_asset
from shapegen.errors import GeometryError
from shapegen.tolerances import ROUNDOFF_REL, at_most

_AXES = {"x": (0,), "y": (1,), "z": (2,), "xy": (0, 1), "xz": (0, 2), "yz": (1, 2),
         "xyz": (0, 1, 2)}  # fmt: skip
_RATIOS = {"xy": ((0, 1),), "xz": ((0, 2),), "yz": ((1, 2),), "yx": ((1, 0),), "zx": ((2, 0),),
           "zy": ((2, 1),), "xyz": ((0, 1), (1, 2))}  # fmt: skip
_MEASURE_NOTE = (
    "the reference gives no measure of a fit: shapegen's is the log of the scale factors"
)
#: The choosers differ from the reference in this (tools/cga_coverage.py reads it).
PARTIAL_FUNCTIONS: dict[str, str] = dict.fromkeys(
    (
        "assetBestSize", "assetApproxSize", "assetFitSize", "assetBestRatio", "assetApproxRatio",
        "imageBestRatio", "imageApproxRatio", "assetsSortSize", "assetsSortRatio",
        "imagesSortRatio",
    ),
    _MEASURE_NOTE,
)  # fmt: skip
_MEASURES = {
    "size": "the sum over the axes of |ln(asset size / scope size)|",
    "ratio": "|ln(asset ratio / scope ratio)| of the axes named",
}


def _log_ratio(a: float, b: float) -> float | None:
    return abs(math.log(a / b)) if a > 0 and b > 0 else None


def size_error(asset: tuple, scope: tuple, axes: str) -> float:
    terms = [_log_ratio(asset[k], scope[k]) for k in _AXES[axes]]
    return sum(t for t in terms if t is not None)


def within_scale(asset: tuple, scope: tuple, axes: str, tolerance: float) -> bool:
    if tolerance <= 0:
        return True
    return all(
        abs(scope[k] / asset[k] - 1) <= tolerance
        for k in _AXES[axes]
        if asset[k] > 0 and scope[k] > 0
    )


def ratio_error(asset: tuple, scope: tuple, axes: str) -> float:
    total = 0.0
    for a, b in _RATIOS[axes]:
        if min(asset[a], asset[b], scope[a], scope[b]) > 0:
            total += abs(math.log((asset[a] / asset[b]) / (scope[a] / scope[b])))
    return total


def image_ratio_error(image: tuple, scope: tuple, axes: str) -> float:
    """An image's width / height against the ratio of the two scope axes named."""
    ((a, b),) = _RATIOS[axes]
    width, height = image[:2]
    if min(width, height, scope[a], scope[b]) <= 0:
        return 0.0
    return abs(math.log((width / height) / (scope[a] / scope[b])))


def asset_choosers(rule_file: str | None, matching: Callable[[str], list[str]]) -> dict:
    """The choosing functions for a rule written in ``rule_file``: ``name -> f(state, ...)``;
    ``matching(query)`` lists the project's files a search query names (func_fileSearch)."""

    def sizes(state, name: str, files: list[str], images: bool) -> list[tuple[str, tuple]]:
        found = []
        for path in files:
            size = _image_size(path, rule_file) if images else _asset_size(path, rule_file)
            if isinstance(size, str):
                _warn(state, f"{name}(): {path!r} {size}; it is left out")
            else:
                found.append((path, size))
        return found

    def ranked(state, name, files, axes, kind, images=False, tolerance=0.0):
        table = _RATIOS if kind == "ratio" else _AXES
        choices = [k for k in table if not images or len(k) == 2]
        if axes not in choices:
            raise ValueError(f"the axes are one of {', '.join(choices)}; got {axes!r}")
        _warn_measure(state, name, kind)
        scope = tuple(float(s) for s in state.shape.scope.size)
        measure = image_ratio_error if images else ratio_error if kind == "ratio" else size_error
        rows = []
        for path, size in sizes(state, name, files, images):
            if kind == "size" and not within_scale(size, scope, axes, tolerance):
                continue
            rows.append((measure(size, scope, axes), path))
        rows.sort(key=lambda row: row[0])
        return rows

    def draw(state, rows, count: int) -> str:
        if not rows:
            return ""
        best = rows[0][0]
        pool = (
            [p for e, p in rows if at_most(e, best, ROUNDOFF_REL)]
            if count == 1
            else [p for _, p in rows]
        )
        pool = pool[: max(count, 1)] if count > 1 else pool
        return pool[min(int(state.random() * len(pool)), len(pool) - 1)]

    def query_files(query) -> list[str]:
        if type(query) is not str:
            raise ValueError("needs a file search query (a string)")
        return matching(query)

    def listed(value) -> tuple[list[str], bool]:
        if isinstance(value, Array):
            return [str(v) for v in value.values], True
        if type(value) is not str:
            raise ValueError("needs a list of files (a string list or a string array)")
        return [item for item in value.split(";") if item], False

    def answer(paths: list[str], as_array: bool):
        if as_array:
            return Array(tuple(paths), 1 if paths else 0, len(paths), str)
        return "".join(f"{p};" for p in paths)

    def best_size(state, query, axes):
        return draw(state, ranked(state, "assetBestSize", query_files(query), axes, "size"), 1)

    def approx_size(state, query, axes, n):
        rows = ranked(state, "assetApproxSize", query_files(query), axes, "size")
        return draw(state, rows, _count(n))

    def fit_size(state, query, axes, tolerance):
        rows = ranked(state, "assetFitSize", query_files(query), axes, "size",
                      tolerance=float(tolerance))  # fmt: skip
        return draw(state, rows, len(rows))

    def best_ratio(state, query, axes):
        return draw(state, ranked(state, "assetBestRatio", query_files(query), axes, "ratio"), 1)

    def approx_ratio(state, query, axes, n):
        rows = ranked(state, "assetApproxRatio", query_files(query), axes, "ratio")
        return draw(state, rows, _count(n))

    def image_best(state, query, axes):
        rows = ranked(state, "imageBestRatio", query_files(query), axes, "ratio", images=True)
        return draw(state, rows, 1)

    def image_approx(state, query, axes, n):
        rows = ranked(state, "imageApproxRatio", query_files(query), axes, "ratio", images=True)
        return draw(state, rows, _count(n))

    def sort_size(state, files, axes, tolerance):
        paths, as_array = listed(files)
        rows = ranked(state, "assetsSortSize", paths, axes, "size", tolerance=float(tolerance))
        return answer([p for _, p in rows], as_array)

    def sort_ratio(state, files, axes):
        paths, as_array = listed(files)
        return answer([p for _, p in ranked(state, "assetsSortRatio", paths, axes, "ratio")],
                      as_array)  # fmt: skip

    def sort_images(state, files, axes):
        paths, as_array = listed(files)
        rows = ranked(state, "imagesSortRatio", paths, axes, "ratio", images=True)
        return answer([p for _, p in rows], as_array)

    return {
        "assetBestSize": best_size,
        "assetApproxSize": approx_size,
        "assetFitSize": fit_size,
        "assetBestRatio": best_ratio,
        "assetApproxRatio": approx_ratio,
        "imageBestRatio": image_best,
        "imageApproxRatio": image_approx,
        "assetsSortSize": sort_size,
        "assetsSortRatio": sort_ratio,
        "imagesSortRatio": sort_images,
    }


def _count(n) -> int:
    if type(n) is not float or n != int(n) or n < 1:
        raise ValueError(f"n is a whole number >= 1, got {n!r}")
    return int(n)


def _asset_size(path: str, rule_file: str | None) -> tuple | str:
    if path in ("builtin:cube", "builtin:cube:notex"):
        return (1.0, 1.0, 1.0)
    found = find_asset(path, rule_file)
    if found is None:
        return "is not found"
    try:
        low, high = load_asset(found).bounds()
    except (OSError, GeometryError, ValueError) as exc:
        return f"cannot be read ({exc})"
    return tuple(float(h - lo) for lo, h in zip(low, high, strict=True))


def _image_size(path: str, rule_file: str | None) -> tuple | str:
    found = find_asset(path, rule_file)
    if found is None:
        return "is not found"
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(found) as image:
            width, height = image.size
    except (OSError, UnidentifiedImageError, ValueError) as exc:
        return f"cannot be read ({exc})"
    return (float(width), float(height), 0.0)


def _warn(state, text: str) -> None:
    state.run.warn(f"{text} (rules: {format_chain(state.rule_path)})")


def _warn_measure(state, name: str, kind: str) -> None:
    state.run.warn(
        f"{name}(): the reference does not give its measure of a fit; shapegen's is "
        f"{_MEASURES[kind]}"
    )
