"""PyPRT's ``GeneratedModel``: what the PyEncoder gives of one derived model.

The geometry is the derived leaves as one mesh, each leaf's vertices shared by its faces and
listed leaf after leaf: ``get_vertices()`` the ``x, y, z`` triples (metres, y up),
``get_indices()`` every face's vertex indices one after the other, ``get_faces()`` each face's
index count. ``get_report()`` aggregates every ``report()`` as PyPRT's encoder does: for a key
``K``, ``K_n`` (the number of reports, a float), and ``K_sum``, ``K_avg``, ``K_min``,
``K_max``; for text and booleans these four are the first value reported. ``get_attributes()``
gives the attrs the rule was evaluated with (hidden ones left out, imported ones under their
import's prefix), ``get_cga_prints()`` what ``print`` wrote, ``get_cga_errors()`` the CGA errors
and warnings of the derivation.

Beyond PyPRT, :meth:`GeneratedModel.get_statics` judges the model as ``shapegen build
--analyze --capacity`` does: whether it stands, y/W² and its lateral capacity.
"""

from __future__ import annotations

__all__ = ["GeneratedModel", "report_dictionary"]

from collections.abc import Mapping

import numpy as np

from shapegen.export.surfaces import face_triangles
from shapegen.model.model import Model


class GeneratedModel:
    """One model made by :meth:`ModelGenerator.generate_model` with the PyEncoder."""

    def __init__(
        self,
        model: Model,
        initial_shape_index: int,
        attributes: Mapping[str, object],
        prints: str,
        *,
        emit_geometry: bool = True,
        emit_report: bool = True,
        triangulate: bool = False,
        texture=None,
    ):
        self._model = model
        #: the initial shape's texturing (:class:`~shapegen.prt.initial_textures.InitialTexture`,
        #: or None), which the file encoders write
        self.initial_texture = texture
        self._index = initial_shape_index
        self._attributes = dict(attributes)
        self._prints = prints
        self._report = report_dictionary(model.metadata.get("reports", {})) if emit_report else {}
        self._errors = [str(w) for w in model.metadata.get("warnings", ())]
        if emit_geometry:
            self._vertices, self._indices, self._faces = _packed_geometry(model, triangulate)
        else:
            self._vertices, self._indices, self._faces = [], [], []

    def get_initial_shape_index(self) -> int:
        """The index of the initial shape, in the generator's list, this model was built on."""
        return self._index

    def get_vertices(self) -> list[float]:
        """The vertex coordinates, ``x, y, z`` per vertex (metres, y up); empty without
        geometry."""
        return self._vertices

    def get_indices(self) -> list[int]:
        """The vertex indices of all faces, face after face; empty without geometry."""
        return self._indices

    def get_faces(self) -> list[int]:
        """The number of vertex indices of each face; empty without geometry."""
        return self._faces

    def get_report(self) -> dict:
        """The aggregated ``report()`` values (``_n``, ``_sum``, ``_avg``, ``_min``, ``_max``
        per key); empty when reports were not asked for or the rule reports nothing."""
        return dict(self._report)

    def get_attributes(self) -> dict:
        """The rule's attrs and the values the model was generated with."""
        return dict(self._attributes)

    def get_cga_prints(self) -> str:
        """Everything the rule's ``print`` wrote, one line each."""
        return self._prints

    def get_cga_errors(self) -> list[str]:
        """The CGA errors and warnings of the derivation (assets not found, operations that
        could not be carried out...), one message each."""
        return list(self._errors)

    def get_statics(self, **options) -> dict:
        """Whether the model stands, as ``shapegen build --analyze --capacity`` judges it.

        Returns ``{"stands", "status", "y_over_w2", "capacity_deg", "blocks"}``; keyword
        options are those of :class:`shapegen.statics.statics_options.StaticsOptions`. A model with
        nothing to judge (faces only) gives ``stands`` None and the reason in ``status``.
        """
        from shapegen.prt.statics import judge

        return judge(self._model, **options)

    @property
    def model(self) -> Model:
        """The shapegen model behind this one (blocks, surfaces, metadata)."""
        return self._model


def report_dictionary(reports: Mapping[str, object]) -> dict:
    """PyPRT's report dictionary from shapegen's ``metadata["reports"]`` (a value per key, or
    a list of values for a key reported several times).

    >>> report_dictionary({"Area": [2.0, 4.0], "Name": "a"})["Area_avg"]
    3.0
    >>> sorted(report_dictionary({"Name": "a"}).items())[:2]
    [('Name_avg', 'a'), ('Name_max', 'a')]
    """
    out: dict = {}
    for key, value in reports.items():
        values = value if isinstance(value, list) else [value]
        if not values:
            continue
        out[f"{key}_n"] = float(len(values))
        numbers = all(
            isinstance(v, int | float | np.floating) and not isinstance(v, bool) for v in values
        )
        if numbers:
            floats = [float(v) for v in values]
            total = sum(floats)
            aggregates = (total, total / len(floats), min(floats), max(floats))
        else:
            aggregates = (values[0],) * 4
        for suffix, figure in zip(("_sum", "_avg", "_min", "_max"), aggregates, strict=True):
            out[key + suffix] = figure
    return out


def _packed_geometry(model: Model, triangulate: bool):
    vertices: list[np.ndarray] = []
    indices: list[int] = []
    faces: list[int] = []
    base = 0
    for leaf in [*model.blocks, *model.surfaces]:
        points = np.asarray(leaf.vertices, dtype=float)
        if triangulate:
            polygons = face_triangles(points, leaf.faces).tolist()
        else:  # a leaf with holes: its faces and their holes, as PyPRT's encoder writes them
            polygons = getattr(leaf, "polygons", None) or leaf.faces
        for polygon in polygons:
            indices.extend(base + int(i) for i in polygon)
            faces.append(len(polygon))
        vertices.append(points)
        base += len(points)
    if not vertices:
        return [], [], []
    return np.concatenate(vertices).ravel().tolist(), indices, faces
