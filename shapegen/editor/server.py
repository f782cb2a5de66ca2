"""The editor's HTTP server: the page, its scripts, and the JSON API (docs/editor.md).

The standard library's :class:`~http.server.ThreadingHTTPServer` serves it, on 127.0.0.1 only:
one designer, a handful of small JSON requests, and files from the package; a thread per request
lets the page read the state while a search runs. Every answer to a bad request is a 4xx with a
JSON body ``{"error": "..."}``; an unexpected failure is a 500 with the same shape, and the
server keeps running. A client that hangs up is no failure: nothing is printed for it.

Only the page itself may change the design. A web page on another site can make the browser send
a request to 127.0.0.1 (a form, or ``fetch`` with ``mode: "no-cors"``) although it cannot read the
answer; so every request other than GET and HEAD is refused (403) when its ``Origin`` is not this
server's own (``"null"`` included: files and sandboxed frames) or its ``Sec-Fetch-Site`` is not
``same-origin``, and (415) unless its ``Content-Type`` is ``application/json``, which no page can
send to another origin without the browser first asking (a CORS preflight this server refuses).

Connections are bounded: one that sends nothing for :data:`IDLE_SECONDS` is closed, and at most
:data:`MAX_CONNECTIONS` are served at once; one more is answered 503 at once and closed, without
a thread of its own. So a flood of idle connections costs no more than that many threads, the
page answers as soon as they close, and a browser's own handful of connections is far below it.
"""

from __future__ import annotations

__all__ = ["API", "IDLE_SECONDS", "MAX_BODY", "MAX_CONNECTIONS", "EditorServer", "make_server"]

import json
import math
import mimetypes
import sys
import threading
import traceback
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from importlib import resources
from urllib.parse import parse_qsl, unquote, urlsplit

from shapegen.editor.attrs import RequestError
from shapegen.editor.session import EditorSession
from shapegen.errors import ShapegenError
from shapegen.json_values import json_ready

MAX_BODY = 64 * 1024  # bytes: far more than any attr update needs
IDLE_SECONDS = 20.0  # a connection silent this long (s) is closed: a browser opens a new one
MAX_CONNECTIONS = 64  # connections served at once; a browser keeps about 6 to one server
HOST = "127.0.0.1"
HOST_NAMES = (HOST, "localhost")  # the names the page may be served under
JSON_TYPE = "application/json"
# Sec-Fetch-Site values of a request the page itself makes ("none": typed by the user); a
# "same-site" request comes from another port of this machine, another program's page
SAME_ORIGIN_SITES = ("same-origin", "none")

# path -> {method: what it does}; the docs list the same table.
API = {
    "/api/state": {"GET": "attrs, verdict, timings, stable intervals, search progress, error"},
    "/api/scene": {"GET": "per-block colours by label and tension, forces, legend"},
    "/api/model.glb": {"GET": "the current model as binary glTF"},
    "/api/blocks/ID": {"GET": "one block: labels, rule path, attrs, joints' forces, tension"},
    "/api/report.json": {"GET": "the current design's report (as shapegen build --report)"},
    "/api/attrs.json": {"GET": "the current attrs, and the shapegen build line that builds them"},
    "/api/attrs": {"POST": 'set attrs: {"name": value, ...}; returns the new state'},
    "/api/undo": {"POST": "take the designer's values back to before the last change"},
    "/api/redo": {"POST": "make the last undone change again"},
    "/api/reset": {"POST": 'rule defaults again: {"attrs": ["name", ...]}, or {} for all'},
    "/api/optimize": {"POST": 'search the free attrs: {"objective": "energy" | "closest"}'},
    "/api/settings": {"POST": 'search and derivation: {"free", "margin", "seed", "lot"}'},
    "/api/cancel": {"POST": "stop a running search after its current iteration"},
    "/api/reload": {"POST": "re-read the grammar file now (during a search: when it ends)"},
}
_PAGES = {"/": "index.html", "/index.html": "index.html"}
_TYPES = {".js": "text/javascript", ".css": "text/css", ".html": "text/html", ".txt": "text/plain"}


class EditorServer(ThreadingHTTPServer):
    """A threading HTTP server that holds one :class:`EditorSession`."""

    daemon_threads = True
    allow_reuse_address = True
    request_queue_size = 64  # the page opens several connections at once; 5 made some wait 1 s

    def __init__(self, port: int, session: EditorSession | None, *, quiet: bool = True):
        self.session = session
        self.quiet = quiet
        self._connections = 0  # served now, each on its own thread
        self._connections_lock = threading.Lock()
        super().__init__((HOST, port), _ApiHandler)

    def process_request(self, request, client_address) -> None:
        with self._connections_lock:
            full = self._connections >= MAX_CONNECTIONS
            if not full:
                self._connections += 1
        if full:
            _refuse_busy(request)
            self.shutdown_request(request)
            return
        try:
            super().process_request(request, client_address)  # starts the connection's thread
        except BaseException:
            self._connection_ended()
            raise

    def process_request_thread(self, request, client_address) -> None:
        try:
            super().process_request_thread(request, client_address)
        finally:
            self._connection_ended()

    def _connection_ended(self) -> None:
        with self._connections_lock:
            self._connections -= 1

    @property
    def connections(self) -> int:
        """The connections served now (each on its own thread)."""
        with self._connections_lock:
            return self._connections

    @property
    def url(self) -> str:
        return f"http://{HOST}:{self.server_address[1]}/"

    @property
    def origins(self) -> tuple[str, ...]:
        """The origins of the page as served: ``http://127.0.0.1:PORT``, ``http://localhost:PORT``."""
        return tuple(f"http://{name}:{self.server_address[1]}" for name in HOST_NAMES)

    def handle_error(self, request, client_address) -> None:
        # a client that hangs up (a closed tab, an abandoned fetch) is not an error of the server
        if isinstance(sys.exc_info()[1], ConnectionError | TimeoutError):
            return
        super().handle_error(request, client_address)


def _refuse_busy(connection) -> None:
    """Answer 503 on a connection over :data:`MAX_CONNECTIONS`, without reading its request:
    a few hundred bytes that a new socket's send buffer takes at once, never waited for."""
    error = f"the server is serving {MAX_CONNECTIONS} connections; try again shortly"
    content = json.dumps({"error": error}).encode("utf-8")
    head = (
        "HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/json\r\n"
        f"Content-Length: {len(content)}\r\nRetry-After: 1\r\nConnection: close\r\n\r\n"
    ).encode("ascii")
    try:
        connection.setblocking(False)
        connection.send(head + content)
    except OSError:  # gone already, or a full buffer: the client sees the connection close
        pass


def make_server(
    session: EditorSession | None, port: int = 0, *, quiet: bool = True
) -> EditorServer:
    """The server for ``session`` on 127.0.0.1:``port`` (0: any free port); call
    ``serve_forever()`` on it. The session may be given later (``server.session = ...``), so
    that a port in use is known before any work."""
    return EditorServer(port, session, quiet=quiet)


def parsed_body(raw: bytes) -> object:
    """A request body as JSON (None when empty), or a :class:`RequestError` (400) in one line.

    Strict JSON: UTF-8, no ``NaN`` or ``Infinity``, no number beyond a float's range (a
    400-digit integer, ``1e400``), and no deeper nesting than the parser's stack allows.
    """
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        where, byte = exc.start, raw[exc.start]
        raise RequestError(f"the body is not UTF-8 text (byte {where} is {byte:#04x})") from None
    if not text.strip():
        return None
    try:
        return json.loads(text, parse_constant=_no_constant, parse_int=_int, parse_float=_float)
    except RecursionError:
        raise RequestError("the body is not valid JSON: it nests too deeply") from None
    except ValueError as exc:
        raise RequestError(f"the body is not valid JSON: {exc}") from None


def _no_constant(name: str) -> object:
    raise ValueError(f"{name} is not a JSON number")


def _int(text: str) -> int:
    value = int(text)  # more than 4 300 digits: Python's own ValueError
    try:
        float(value)
    except OverflowError:
        raise ValueError(f"the number {_shown(text)} ({len(text)} digits) is too large") from None
    return value


def _float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(f"the number {_shown(text)} is too large")
    return value


def _shown(text: str) -> str:
    return repr(text) if len(text) <= 40 else repr(text[:37]) + "..."


_BLOCKS = "/api/blocks/"


def _route(path: str) -> str:
    """The entry of :data:`API` that answers ``path`` (``/api/blocks/b3``: ``/api/blocks/ID``)."""
    if path.startswith(_BLOCKS) and len(path) > len(_BLOCKS) and "/" not in path[len(_BLOCKS) :]:
        return _BLOCKS + "ID"
    return path


def _static_root():
    return resources.files("shapegen.editor").joinpath("static")


class _ApiHandler(BaseHTTPRequestHandler):
    server: EditorServer
    server_version = "shapegen-edit"
    protocol_version = "HTTP/1.1"
    timeout = IDLE_SECONDS  # on every read and write of the connection's socket

    # ------------------------------------------------------------------ dispatch
    def _dispatch(self, method: str) -> None:
        try:
            self._answer(method)
        except (ConnectionError, TimeoutError):  # the client hung up: no one to answer
            self.close_connection = True

    def _answer(self, method: str) -> None:
        try:
            self._check_host()
            if method not in ("GET", "HEAD"):
                self._check_origin()
            path = urlsplit(self.path).path
            route = _route(path)
            if route in API:
                allowed = API[route]
                if method not in allowed and not (method == "HEAD" and "GET" in allowed):
                    raise RequestError(f"{path} takes {', '.join(allowed)}, not {method}", 405)
                self._api(method, path if route == path else route)
            elif method in ("GET", "HEAD"):
                self._file(path, head=method == "HEAD")
            elif path in _PAGES or path.startswith("/static/"):
                raise RequestError(f"{path} takes GET, not {method}", 405)
            else:
                raise RequestError(f"no such address: {path}", 404)
        except RequestError as exc:
            self.close_connection = True  # a body may be left unread
            self._json({"error": str(exc)}, exc.status)
        except ShapegenError as exc:
            self.close_connection = True
            self._json({"error": str(exc).splitlines()[0]}, 422)
        except (ConnectionError, TimeoutError):
            raise
        except Exception as exc:  # the server keeps running; the page shows the message
            sys.stderr.write(traceback.format_exc())
            self.close_connection = True
            self._json({"error": f"internal error: {type(exc).__name__}: {exc}"}, 500)

    def _check_host(self) -> None:
        # Only pages served from this address may drive it (a web page elsewhere could reach
        # 127.0.0.1 through a rebound DNS name, but it cannot forge the Host header).
        host = (self.headers.get("Host") or "").rsplit(":", 1)[0]
        if host not in HOST_NAMES:
            raise RequestError(f"requests must be addressed to {HOST}", 403)

    def _check_origin(self) -> None:
        """Refuse a request that changes something unless the page itself sent it: a browser
        names the page in ``Origin`` (``null`` for a file or a sandboxed frame) and says in
        ``Sec-Fetch-Site`` whether it is this server's; a script that sends neither is let in."""
        for origin in self.headers.get_all("Origin") or ():
            if origin.strip().lower() not in self.server.origins:
                raise RequestError(
                    f"a request from {_shown(origin)} may not change the design: only the page "
                    f"at {self.server.url} may", 403
                )  # fmt: skip
        for site in self.headers.get_all("Sec-Fetch-Site") or ():
            if site.strip().lower() not in SAME_ORIGIN_SITES:
                raise RequestError(
                    f"a {_shown(site)} request may not change the design: only the page at "
                    f"{self.server.url} may", 403
                )  # fmt: skip

    # ------------------------------------------------------------------ the API
    def _api(self, method: str, path: str) -> None:
        session = self.server.session
        if method in ("GET", "HEAD"):
            self._drain()
            if path == "/api/model.glb":
                self._send(session.glb(), "model/gltf-binary", head=method == "HEAD")
            elif path == "/api/report.json":
                self._json(session.report(), head=method == "HEAD")
            elif path == "/api/attrs.json":
                self._json(session.attrs_export(), head=method == "HEAD")
            elif path == "/api/blocks/ID":
                block_id = unquote(urlsplit(self.path).path[len(_BLOCKS) :])
                self._json(session.block(block_id), head=method == "HEAD")
            elif path == "/api/scene":
                self._json(session.scene(), head=method == "HEAD")
            else:
                self._json(session.state(), head=method == "HEAD")
            return
        body = self._body()
        if path == "/api/attrs":
            self._json(session.set_attrs(body, gesture=self._query().get("gesture")))
        elif path == "/api/undo":
            self._empty(body, path)
            self._json(session.undo())
        elif path == "/api/redo":
            self._empty(body, path)
            self._json(session.redo())
        elif path == "/api/reset":
            self._json(session.reset(body))
        elif path == "/api/settings":
            self._json(session.settings(body))
        elif path == "/api/optimize":
            self._json(session.optimize(body))
        elif path == "/api/cancel":
            self._json(session.cancel())
        else:
            state = session.reload()  # during a search: at once, re-read when it ends
            self._json(state, HTTPStatus.ACCEPTED if state["reload_pending"] else HTTPStatus.OK)

    def _body(self) -> object:
        """The request's JSON body (None when empty); it must be sent as ``application/json``."""
        kind = self.headers.get("Content-Type")
        media, _, parameters = (kind or "").partition(";")
        charset = parameters.strip().lower().removeprefix("charset=").strip('"')
        if media.strip().lower() != JSON_TYPE or charset not in ("", "utf-8"):
            self.close_connection = True
            shown = "none" if kind is None else _shown(kind)
            raise RequestError(
                f"send the body as JSON with Content-Type: {JSON_TYPE} (this request's: {shown})",
                415,
            )
        text = self.headers.get("Content-Length")
        if self.headers.get("Transfer-Encoding", "").lower() == "chunked":
            self.close_connection = True
            raise RequestError("send the body with a Content-Length, not chunked", 411)
        try:
            length = int(text) if text is not None else 0
        except ValueError:
            self.close_connection = True
            raise RequestError(f"bad Content-Length {_shown(text)}") from None
        if length < 0:
            self.close_connection = True
            raise RequestError(f"bad Content-Length {_shown(text)}")
        if length > MAX_BODY:
            self.close_connection = True  # the body is not read: the connection cannot be reused
            raise RequestError(f"the body is {length} bytes; at most {MAX_BODY} are accepted", 413)
        raw = self.rfile.read(length) if length else b""
        if len(raw) < length:
            raise ConnectionResetError("the client hung up before sending the whole body")
        return parsed_body(raw)

    def _query(self) -> dict[str, str]:
        """The request's query parameters (the last of each name)."""
        return dict(parse_qsl(urlsplit(self.path).query))

    @staticmethod
    def _empty(body: object, path: str) -> None:
        if body not in (None, {}):
            raise RequestError(f"{path} takes no values: send {{}} or nothing")

    def _drain(self) -> None:
        length = self.headers.get("Content-Length")
        if length and length.isdigit() and 0 < int(length) <= MAX_BODY:
            self.rfile.read(int(length))
        elif length and length != "0":
            self.close_connection = True

    # ------------------------------------------------------------------ files
    def _file(self, path: str, *, head: bool) -> None:
        name = _PAGES.get(path)
        if name is None:
            if not path.startswith("/static/"):
                raise RequestError(f"no such address: {path}", 404)
            name = path[len("/static/") :]
        parts = name.split("/")
        if any(part in ("", ".", "..") or "\\" in part for part in parts):
            raise RequestError(f"no such file: {path}", 404)
        resource = _static_root().joinpath(*parts)
        if not resource.is_file():
            raise RequestError(f"no such file: {path}", 404)
        suffix = "." + parts[-1].rsplit(".", 1)[-1] if "." in parts[-1] else ""
        kind = (
            _TYPES.get(suffix) or mimetypes.guess_type(parts[-1])[0] or "application/octet-stream"
        )
        if kind.startswith("text/"):
            kind += "; charset=utf-8"
        self._send(resource.read_bytes(), kind, head=head, cache=True)

    # ------------------------------------------------------------------ answers
    def _json(self, value: object, status: int = 200, *, head: bool = False) -> None:
        content = json.dumps(json_ready(value), allow_nan=False).encode("utf-8")
        self._send(content, "application/json", status=status, head=head)

    def _send(
        self, content: bytes, kind: str, *, status: int = 200, head: bool = False, cache=False
    ) -> None:
        self.send_response(status)
        self.send_header("Content-Type", kind)
        self.send_header("Content-Length", str(len(content)))
        self.send_header("Cache-Control", "max-age=300" if cache else "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        if status == HTTPStatus.METHOD_NOT_ALLOWED:
            path = _route(urlsplit(self.path).path)
            self.send_header("Allow", ", ".join(API.get(path, {"GET": ""})))
        if self.close_connection:
            self.send_header("Connection", "close")
        self.end_headers()
        if not head:
            self.wfile.write(content)

    def send_error(self, code: int, message: str | None = None, explain: str | None = None):
        # malformed request lines and unknown methods: the same JSON shape as every error
        self.close_connection = True
        if code == HTTPStatus.NOT_IMPLEMENTED:  # a method no address takes
            code, message = HTTPStatus.METHOD_NOT_ALLOWED, f"no address takes {self.command}"
        try:
            self._json({"error": message or HTTPStatus(code).phrase}, code)
        except (ConnectionError, TimeoutError):
            pass

    def log_message(self, format: str, *args) -> None:  # noqa: A002 (the standard library's name)
        if not self.server.quiet:
            sys.stderr.write(f"shapegen edit: {self.address_string()} {format % args}\n")


# BaseHTTPRequestHandler answers METHOD with its do_METHOD: each method a client may send goes to
# the one dispatch, which says 405 for a route that does not take it (any other method gets 501)
for _method in ("GET", "HEAD", "POST", "PUT", "DELETE", "PATCH", "OPTIONS"):
    setattr(_ApiHandler, f"do_{_method}", lambda self, method=_method: self._dispatch(method))
