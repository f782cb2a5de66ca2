"""PyPRT's ``get_rpk_attributes_info``: a rule package's attrs, their types and annotations.

The attrs and their annotations are the grammar's attribute catalogue's
(:mod:`shapegen.engine.attr_catalogue`): an ``@Group`` holds for the attrs that follow it in
its file until the next ``@Group`` (the Inspector's grouping), so each of them lists it after
its own annotations, as PRT does; ``@Hidden`` attrs are left out.

>>> import shapegen
>>> grammar = shapegen.parse_grammar('''
... @Group("Walls")
... attr height = 3
... attr depth = 1
... @StartRule
... Lot --> extrude(height) Stone
... ''')
>>> attributes_info_of(grammar.catalogue)["depth"]
{'type': 'float', 'annotations': [['@Group', ['#NULL#', 'Walls']]]}
"""

from __future__ import annotations

__all__ = ["NO_KEY", "attributes_info_of", "get_rpk_attributes_info"]

from collections.abc import Mapping

from shapegen.engine.attr_catalogue import AttrEntry
from shapegen.engine.expressions.arrays import Array
from shapegen.grammar.constant_folding import UNKNOWN, constant_value

NO_KEY = "#NULL#"
"""The key of an annotation argument given without a name (PyPRT's ``pyprt.NO_KEY``)."""


def get_rpk_attributes_info(rule_package_path: str) -> dict:
    """``name -> {"type", "annotations"}`` for every attr of the package's start rule file that
    is not ``@Hidden`` (imported attrs under their import's prefix). ``type`` is ``float``,
    ``string``, ``bool`` or those with ``[]`` for arrays; ``annotations`` lists each annotation
    as ``["@Name", [key, value], ...]``, the key of an unnamed argument being :data:`NO_KEY`."""
    from shapegen.engine.grammar_api import load_grammar

    return attributes_info_of(load_grammar(rule_package_path).catalogue)


def attributes_info_of(catalogue: Mapping[str, AttrEntry]) -> dict:
    """The attributes info of the attrs of a grammar's ``catalogue``."""
    out = {}
    for name, entry in catalogue.items():
        if entry.hidden:
            continue
        own = entry.node.annotations
        annotations = [_annotation(a) for a in own]
        if entry.group_annotation is not None and entry.group_annotation not in own:
            annotations.append(_annotation(entry.group_annotation))
        out[name] = {"type": _type_name(entry.default), "annotations": annotations}
    return out


def _type_name(value: object) -> str:
    if isinstance(value, Array):
        value = value.values  # an array attr's default: its items name the type
    if isinstance(value, list | tuple):
        kinds = {_type_name(item) for item in value} or {"float"}
        return f"{kinds.pop() if len(kinds) == 1 else 'string'}[]"
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, str):
        return "string"
    return "float"


def _annotation(annotation) -> list:
    arguments = [[NO_KEY, _value(arg)] for arg in annotation.args]
    arguments += [[kw.name, _value(kw.value)] for kw in annotation.keywords]
    return [f"@{annotation.name}", *arguments]


def _value(expression) -> object:
    value = constant_value(expression)
    return None if value is UNKNOWN else value
