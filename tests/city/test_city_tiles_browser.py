"""The city's 3D Tiles in a real browser: the viewer page (python -m shapegen.city.viewer)
in headless Chromium driven by playwright loads every tile and draws every building.

Skipped, saying why, where no Chromium or no playwright is installed (.ci/run installs Debian's
``chromium``; playwright comes with the test extra and drives that browser, downloading nothing).
"""

from __future__ import annotations

import json
import sys
import threading
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[2] / "docs"
sys.path.insert(0, str(DOCS))
import editor_screenshots as page_steps  # noqa: E402

pytest.importorskip(
    "playwright.sync_api", reason="the browser tests need playwright (pip install playwright)"
)
pytest.importorskip("pyproj")
BROWSER = page_steps.find_browser()
pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(
        BROWSER is None,
        reason="no Chromium found: the browser tests need Debian's chromium package"
        " (apt-get install chromium; .ci/run installs it) or SHAPEGEN_CHROMIUM=/path/to/chrome",
    ),
]  # a browser and a server: 8-12 s

from test_city_tiles import district_scene  # noqa: E402

from shapegen.city import read_lots  # noqa: E402
from shapegen.city.tiles import write_tiles  # noqa: E402
from shapegen.city.viewer import make_server  # noqa: E402


def test_the_viewer_loads_every_tile_and_draws_every_building(tmp_path):
    city = read_lots(DOCS / "data" / "district_l93.geojson")
    tileset = write_tiles(tmp_path, city, scene=district_scene(city), lots_per_tile=6)
    contents = [
        line for line in tileset.path.read_text().splitlines() if '"uri"' in line
    ]  # fmt: skip
    assert len(contents) == tileset.tiles > 1
    server = make_server(tmp_path, port=0)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    problems: list[str] = []
    statuses: dict[str, int] = {}
    failed: list[tuple[str, str]] = []
    try:
        from playwright.sync_api import sync_playwright

        with sync_playwright() as playwright:
            browser = page_steps.launch(playwright, BROWSER)
            page = browser.new_page(viewport=page_steps.VIEWPORT)
            page.on("pageerror", lambda error: problems.append(str(error)))
            page.on("console", lambda m: m.type == "error" and problems.append(m.text))
            page.on("response", lambda r: statuses.__setitem__(r.url, r.status))
            page.on("requestfailed", lambda r: failed.append((r.url, r.failure)))
            page.goto(server.url)
            page.wait_for_function("window.shapegenTiles && window.shapegenTiles.done",
                                   timeout=60_000)  # fmt: skip
            state = page.evaluate("window.shapegenTiles")
            page.screenshot(path=str(tmp_path / "tiles.png"))
            pixels = page.evaluate(_DRAWN)
            browser.close()
    finally:
        server.shutdown()
        server.server_close()
    built = sorted(lot.id for lot in city.lots if lot.problem is None)
    # Chromium now and then reports a tile's request as aborted after its whole body came (200)
    # and was drawn: only a request that got no answer is a failure.
    problems += [f"{url}: {why}" for url, why in failed if statuses.get(url) != 200]
    assert state["errors"] == [] and problems == []
    tiles = {url: status for url, status in statuses.items() if url.endswith(".glb")}
    assert len(tiles) == tileset.tiles and set(tiles.values()) == {200}
    assert state["tilesLoaded"] == state["tilesTotal"] == tileset.tiles
    assert state["meshes"] == len(built) == tileset.buildings
    assert sorted(state["buildings"]) == built
    assert pixels > 0.02, f"the buildings cover {pixels:.1%} of the canvas"
    assert json.loads(tileset.path.read_text())["asset"]["version"] == "1.1"


# the fraction of the canvas that is not the background colour (the buildings drawn)
_DRAWN = """() => {
  const canvas = document.querySelector('#view canvas');
  const copy = document.createElement('canvas');
  copy.width = canvas.width; copy.height = canvas.height;
  const context = copy.getContext('2d');
  context.drawImage(canvas, 0, 0);
  const data = context.getImageData(0, 0, copy.width, copy.height).data;
  let drawn = 0;
  for (let i = 0; i < data.length; i += 4) {
    if (Math.abs(data[i] - 0xee) + Math.abs(data[i + 1] - 0xf1) + Math.abs(data[i + 2] - 0xf4) > 12)
      drawn += 1;
  }
  return drawn / (data.length / 4);
}"""
