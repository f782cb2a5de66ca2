"""A page that shows a city's 3D Tiles in a browser: ``python -m shapegen.city.viewer OUTDIR``.

It serves, on this machine only (127.0.0.1), the page and its three.js viewer
(``shapegen/city/static``), the three.js files the design page ships
(``shapegen/editor/static/vendor/three``) and ``OUTDIR/tiles`` (written by ``shapegen city
--tiles``). Nothing is fetched from anywhere else.

>>> server = make_server("city-out", port=0)            # doctest: +SKIP
>>> server.url                                          # doctest: +SKIP
'http://127.0.0.1:41235/'
"""

from __future__ import annotations

__all__ = ["make_server", "main"]

import argparse
import mimetypes
import sys
from functools import partial
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from urllib.parse import unquote, urlsplit

from shapegen.city.tiles import TILES_FOLDER
from shapegen.errors import InputFormatError

_PACKAGE = Path(__file__).resolve().parents[1]
_PAGE = {"/": "tiles.html", "/index.html": "tiles.html", "/tiles_viewer.js": "tiles_viewer.js"}
_STATIC = _PACKAGE / "city" / "static"
_THREE = _PACKAGE / "editor" / "static" / "vendor" / "three"
_TYPES = {".js": "text/javascript", ".json": "application/json", ".glb": "model/gltf-binary"}


class _TileHandler(BaseHTTPRequestHandler):
    def __init__(self, *args, tiles: Path, **kwargs):
        self.tiles = tiles
        super().__init__(*args, **kwargs)

    def do_GET(self):  # noqa: N802 - http.server's name
        path = unquote(urlsplit(self.path).path)
        if path in _PAGE:
            self._send(_STATIC / _PAGE[path])
        elif path.startswith("/vendor/three/"):
            self._send(_inside(_THREE, path.removeprefix("/vendor/three/")))
        elif path.startswith(f"/{TILES_FOLDER}/"):
            self._send(_inside(self.tiles, path.removeprefix(f"/{TILES_FOLDER}/")))
        else:
            self._send(None)

    def _send(self, file: Path | None) -> None:
        if file is None or not file.is_file():
            self.send_error(HTTPStatus.NOT_FOUND)
            return
        data = file.read_bytes()
        kind = _TYPES.get(file.suffix) or mimetypes.guess_type(file.name)[0]
        self.send_response(HTTPStatus.OK)
        self.send_header("Content-Type", kind or "application/octet-stream")
        self.send_header("Content-Length", str(len(data)))
        self.send_header("Cache-Control", "no-store")
        self.end_headers()
        self.wfile.write(data)

    def log_message(self, *args) -> None:  # quiet: the page's requests are not news
        pass


def _inside(folder: Path, relative: str) -> Path | None:
    """``folder / relative`` when it stays inside ``folder``, else None."""
    file = (folder / relative).resolve()
    return file if file.is_relative_to(folder.resolve()) else None


def make_server(outdir: str | Path, port: int = 8765, host: str = "127.0.0.1"):
    """An HTTP server (not yet serving) of the viewer and ``outdir/tiles``; its ``url``.

    Raises
    ------
    InputFormatError
        ``outdir`` holds no ``tiles/tileset.json``.
    """
    tiles = Path(outdir) / TILES_FOLDER
    if not (tiles / "tileset.json").is_file():
        raise InputFormatError(
            f"{outdir}: no {TILES_FOLDER}/tileset.json (write it with shapegen city ... --tiles)"
        )
    server = ThreadingHTTPServer((host, port), partial(_TileHandler, tiles=tiles))
    server.daemon_threads = True
    server.url = f"http://{host}:{server.server_address[1]}/"
    return server


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m shapegen.city.viewer",
        description="Show the 3D Tiles of a shapegen city run (OUTDIR/tiles) in a browser.",
    )
    parser.add_argument("outdir", metavar="OUTDIR", help="the output folder of shapegen city")
    parser.add_argument("--port", type=int, default=8765, help="the port (default 8765)")
    args = parser.parse_args(argv)
    try:
        server = make_server(args.outdir, args.port)
    except (InputFormatError, OSError) as exc:
        sys.stderr.write(f"shapegen: error: {exc}\n")
        return 2  # as shapegen's commands say a user's mistake
    print(f"the city's tiles: {server.url} (Ctrl-C stops)", flush=True)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        pass
    finally:
        server.server_close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
