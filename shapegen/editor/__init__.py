"""``shapegen edit``: the design page in the browser and its JSON API (docs/editor.md).

>>> from shapegen.editor import EditorSession, make_server              # doctest: +SKIP
>>> server = make_server(EditorSession("barrel_vault.grammar"), port=8765)  # doctest: +SKIP
>>> server.serve_forever()                                              # doctest: +SKIP
"""

from shapegen.editor.attrs import AttrSpec, RequestError
from shapegen.editor.server import API, EditorServer, make_server
from shapegen.editor.session import EditorSession

__all__ = ["API", "AttrSpec", "EditorServer", "EditorSession", "RequestError", "make_server"]
