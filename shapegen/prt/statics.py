"""The statics through PyPRT's API: a generated model judged as ``shapegen build --analyze``
(and ``--capacity``) judges it, as the report's ``analysis`` object."""

from __future__ import annotations

__all__ = ["judge"]

from collections.abc import Sequence

from shapegen.model.model import Model


def judge(model: Model, *, capacity: Sequence[float] | None = None, **options) -> dict:
    """The ``analysis`` object of ``shapegen build --analyze`` for ``model``: ``stands``,
    ``measure`` (y/W²), ``status``, ``margin`` and the structure's section; with ``capacity``
    (azimuths in degrees, or ``[]`` for the worst direction of a sweep) also ``capacity``, as
    ``--capacity``. ``options`` are :class:`~shapegen.statics.statics_options.StaticsOptions` fields
    (``friction``, ``margin``, ``pyramid``...); an unknown one is refused with one line."""
    from shapegen.errors import OptionError
    from shapegen.statics.statics_options import StaticsOptions
    from shapegen.structures import Design, make_structure

    try:
        settings = StaticsOptions(**options) if options else None
    except TypeError:
        known = ", ".join(StaticsOptions.__dataclass_fields__)
        raise OptionError(f"statics options are {known}; not {', '.join(options)}") from None
    structure = make_structure("blocks", settings)
    design = Design.of_model(model)
    analysis = structure.assess(design).to_report()
    if capacity is not None:
        analysis["capacity"] = structure.lateral_capacity(design, list(capacity)).to_report()
    return analysis
