"""The editor's server in this process on a free port, and plain HTTP requests to it."""

import contextlib
import http.client
import json
import threading

from shapegen.editor import EditorSession, make_server


@contextlib.contextmanager
def serving(path, **options):
    """A server for a new session on the grammar file ``path`` (no stable-range scan)."""
    session = EditorSession(str(path), scan=False, **options)
    server = make_server(session, 0)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield server
    finally:
        server.shutdown()
        server.server_close()
        session.close()


@contextlib.contextmanager
def serving_stack(folder):
    """A server for a new session on the two-block stack of ``editor_stack``, written in
    ``folder``."""
    from editor_stack import STACK

    path = folder / "stack.grammar"
    path.write_text(STACK, encoding="utf-8")
    with serving(path) as server:
        yield server


def request(server, method, path, body=None, headers=None, *, answer_headers=False):
    """``(status, Content-Type, content)`` (and the answer's headers with ``answer_headers``).

    A request other than GET and HEAD is sent as JSON, as the page sends it, unless ``headers``
    say otherwise (a header given as None is left out)."""
    connection = http.client.HTTPConnection("127.0.0.1", server.server_address[1], timeout=60)
    try:
        data = body if isinstance(body, bytes) or body is None else json.dumps(body).encode()
        sent = {} if method in ("GET", "HEAD") else {"Content-Type": "application/json"}
        sent = {k: v for k, v in {**sent, **(headers or {})}.items() if v is not None}
        connection.request(method, path, body=data, headers=sent)
        response = connection.getresponse()
        content = response.read()
        result = (response.status, response.getheader("Content-Type"), content)
        return (*result, dict(response.getheaders())) if answer_headers else result
    finally:
        connection.close()


def state(server) -> dict:
    status, _, content = request(server, "GET", "/api/state")
    assert status == 200
    return json.loads(content)
