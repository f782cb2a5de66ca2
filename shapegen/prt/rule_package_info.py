"""PyPRT's ``get_rpk_attributes_info``: a rule package's attrs, their types and annotations.

An ``@Group`` holds for the attrs that follow it in its file until the next ``@Group`` (the
Inspector's grouping), so each of them lists it after its own annotations, as PRT does.

>>> info = attributes_info_of({"height": 3.0}, {})
>>> info["height"]
{'type': 'float', 'annotations': []}
"""

from __future__ import annotations

__all__ = ["NO_KEY", "attributes_info_of", "get_rpk_attributes_info"]

from collections.abc import Mapping

from shapegen.grammar.constant_folding import UNKNOWN, constant_value

NO_KEY = "#NULL#"
"""The key of an annotation argument given without a name (PyPRT's ``pyprt.NO_KEY``)."""


def get_rpk_attributes_info(rule_package_path: str) -> dict:
    """``name -> {"type", "annotations"}`` for every attr of the package's start rule file that
    is not ``@Hidden`` (imported attrs under their import's prefix). ``type`` is ``float``,
    ``string``, ``bool`` or those with ``[]`` for arrays; ``annotations`` lists each annotation
    as ``["@Name", [key, value], ...]``, the key of an unnamed argument being :data:`NO_KEY`."""
    from shapegen.engine.grammar_api import load_grammar

    grammar = load_grammar(rule_package_path)
    return attributes_info_of(grammar.attrs, grammar.program.attr_nodes)


def attributes_info_of(defaults: Mapping[str, object], nodes: Mapping[str, object]) -> dict:
    """The attributes info of attrs with these default values and definitions."""
    out = {}
    groups: dict[str, list] = {}  # the last @Group of each file (by import prefix)
    for name, value in defaults.items():
        annotations = [_annotation(a) for a in getattr(nodes.get(name), "annotations", ())]
        prefix = name.rpartition(".")[0]
        own = [a for a in annotations if a[0] == "@Group"]
        if own:
            groups[prefix] = own[-1]
        elif prefix in groups:
            annotations.append(groups[prefix])
        if any(a[0] == "@Hidden" for a in annotations):
            continue
        out[name] = {"type": _type_name(value), "annotations": annotations}
    return out


def _type_name(value: object) -> str:
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
