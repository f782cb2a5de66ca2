"""PyPRT's API on shapegen: scripts written for CityEngine's Python runtime run after
``import shapegen.prt as pyprt``.

>>> import shapegen.prt as pyprt
>>> shape = pyprt.InitialShape([0, 0, 0, 0, 0, 10, 10, 0, 10, 10, 0, 0])
>>> model = pyprt.ModelGenerator([shape]).generate_model(
...     [{}], "extrusion.rpk", "com.esri.pyprt.PyEncoder", {})[0]  # doctest: +SKIP
>>> len(model.get_vertices()) // 3, model.get_faces()  # doctest: +SKIP
(8, [4, 4, 4, 4, 4, 4])

Names, arguments and return values follow PyPRT 1.12's reference: :class:`InitialShape`,
:class:`ModelGenerator`, :class:`GeneratedModel`, :func:`get_rpk_attributes_info`, and the
deprecated :func:`initialize_prt`, :func:`shutdown_prt`, :func:`is_prt_initialized`, which do
nothing as in PyPRT. Beyond PyPRT, :meth:`GeneratedModel.get_statics` tells whether the model
stands. What shapegen cannot do as PyPRT does is refused with one line
(:class:`~shapegen.errors.ShapegenError`), never done differently without a word.
"""

from __future__ import annotations

from shapegen.prt.generated_models import GeneratedModel
from shapegen.prt.initial_shapes import InitialShape
from shapegen.prt.model_generator import ModelGenerator
from shapegen.prt.rule_package_info import NO_KEY, get_rpk_attributes_info

__all__ = [
    "GeneratedModel",
    "InitialShape",
    "ModelGenerator",
    "NO_KEY",
    "get_api_version",
    "get_rpk_attributes_info",
    "initialize_prt",
    "is_prt_initialized",
    "shutdown_prt",
]

API_VERSION = [3, 3, 0]
"""The PRT API version whose behaviour this module follows (PyPRT 1.12 wraps PRT 3.3)."""


def get_api_version() -> list:
    """The PRT API version followed, ``[major, minor, build]``."""
    return list(API_VERSION)


def initialize_prt() -> None:
    """Deprecated in PyPRT, and nothing to do here."""


def shutdown_prt() -> None:
    """Deprecated in PyPRT, and nothing to do here."""


def is_prt_initialized() -> bool:
    """Always True, as in PyPRT."""
    return True
