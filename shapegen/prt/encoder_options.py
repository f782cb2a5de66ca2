"""The one rule of an encoder's option names: each encoder lists the options it takes, with what
it does of each, and refuses any other name in one line, as CityEngine's runtime documents its
encoders' options (Esri/cityengine-sdk, ``esri_prt_codecs.html``)."""

from __future__ import annotations

__all__ = ["checked_option_names"]

from collections.abc import Collection, Mapping

from shapegen.errors import OptionError


def checked_option_names(
    encoder: str,
    options: Mapping[str, object],
    known: Collection[str],
    refused_text: Collection[str],
    why_refused: str,
) -> None:
    """Refuse a text option of ``refused_text`` given a value (``why_refused`` says why: the
    file has no place for it, or shapegen writes its own), then any name neither ``known`` nor
    among those, listing the ``known`` ones."""
    for name in refused_text:
        if options.get(name):
            raise OptionError(f"{encoder}: {name!r}: {why_refused}")
    unknown = sorted(set(options) - set(known) - set(refused_text))
    if unknown:
        raise OptionError(f"{encoder} takes {', '.join(known)}; not {', '.join(unknown)}")
