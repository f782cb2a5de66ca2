"""What the page shows of one block the designer clicks: where it came from and how it is held.

- its id, labels, the chain of rules that made it (``rule_path``), and the attrs those rules
  read (:func:`rule_attrs`: through consts, functions and the defaults of other attrs);
- its weight, and per joint (a contact with another block, a support or the ground): the other
  side, the force on this block split into compression along the joint's normal and shear in
  its plane, where it acts, and the tension the joint needs (N, the sum of the tensions at its
  corners); the block's tension is the largest of its joints', as the tension colours (the
  verdict's largest tension is the largest at one corner).

>>> block_details(outcome, "b3")["joints"][0]["compression"]     # doctest: +SKIP
"""

from __future__ import annotations

__all__ = ["block_details", "rule_attrs"]

import weakref

import numpy as np

from shapegen.grammar import ast
from shapegen.grammar.tree import walk
from shapegen.json_values import finite_or_none
from shapegen.statics.interface import GROUND
from shapegen.tolerances import FORCE_NOISE_REL

GRAVITY = 9.81  # m/s^2, as the statics' loads
_CACHE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def rule_attrs(grammar, rule_path) -> list[str]:
    """The attrs the rules of ``rule_path`` read, in file order: named in a rule's body (or
    its annotations) or, through them, in a const, a function or another attr's default. A
    rule's or function's parameter of the same name hides the attr."""
    cache = _CACHE.setdefault(grammar, {})
    key = tuple(rule_path)
    if key not in cache:
        cache[key] = _rule_attrs(grammar, key)
    return cache[key]


def _rule_attrs(grammar, rule_path: tuple[str, ...]) -> list[str]:
    tree = grammar.ast
    attrs = grammar.program.attr_nodes
    consts = {c.name: c for c in tree.consts}
    functions: dict[str, list[ast.Function]] = {}
    for function in tree.functions:
        functions.setdefault(function.name, []).append(function)
    found: set[str] = set()
    visited: set[int] = set()
    pending: list = [rule for name in dict.fromkeys(rule_path) if (rule := tree.rule(name))]
    while pending:
        definition = pending.pop()
        if id(definition) in visited:
            continue
        visited.add(id(definition))
        hidden = {p.name for p in getattr(definition, "params", ())}
        for item in walk(definition):
            if isinstance(item, ast.Name) and item.name not in hidden:
                name = item.name
                if name in attrs:
                    found.add(name)
                    pending.append(attrs[name])
                elif name in consts:
                    pending.append(consts[name])
            elif isinstance(item, ast.Call) and item.name in functions:
                pending.extend(functions[item.name])
    return [name for name in attrs if name in found]


def block_details(outcome, block_id: str, values: dict, user=()) -> dict | None:
    """The page's account of block ``block_id`` of ``outcome.model`` (None: no such block).

    ``values`` are the attrs' current values, ``user`` names the designer's. Forces are in N,
    points in m; a joint's ``force`` is the one on this block. ``joints`` is None when the
    design is not judged by block statics (a bridge's cables).
    """
    model = outcome.model
    index = next((k for k, b in enumerate(model.blocks) if b.id == block_id), None)
    if index is None:
        return None
    block = model.blocks[index]
    low, high = block.vertices.min(axis=0), block.vertices.max(axis=0)
    assessment = outcome.assessment
    analysis = assessment.block_analysis if assessment is not None else None
    tension = None
    joints = None
    if analysis is not None:
        joints = _joints(model, analysis, index)
        tension = max((j["tension"] or 0.0 for j in joints), default=0.0)
    return {
        "id": block.id,
        "index": index,
        "labels": list(block.tags),
        "rule_path": list(block.rule_path),
        "attrs": [
            {"name": name, "value": values.get(name), "user": name in user}
            for name in rule_attrs(outcome.grammar, block.rule_path)
        ],
        "structural": bool(block.structural),
        "fixed": bool(block.fixed),
        "volume": float(block.volume),
        "weight": float(block.mass) * GRAVITY,
        "centroid": [float(c) for c in block.centroid],
        "bounds": [low.tolist(), high.tolist()],
        "tension": tension,
        "joints": joints,
    }


def _joints(model, analysis, index: int) -> list[dict]:
    interfaces = analysis.interfaces
    if not interfaces:
        return []
    first = np.array([i.first for i in interfaces])
    second = np.array([i.second for i in interfaces])
    forces = np.asarray(analysis.resultant_forces, float).reshape(-1, 3)
    points = np.asarray(analysis.resultant_points, float).reshape(-1, 3)
    tensions = np.asarray(analysis.interface_tension, float).reshape(-1)
    # the solver's round-off (a shear of 1e-10 N under a 20 kN block) reads as zero
    noise = FORCE_NOISE_REL * float(analysis.total_weight or 0.0)

    def newtons(value: float) -> float | None:
        value = float(value)
        return 0.0 if abs(value) <= noise else finite_or_none(value)

    # the joints number the blocks judged: the model's, then any stand-ins (statics.standins)
    judged = analysis.model if getattr(analysis, "model", None) is not None else model
    rows = []
    for j in np.flatnonzero((first == index) | (second == index)):
        interface = interfaces[j]
        other = int(second[j] if first[j] == index else first[j])
        # the resultant acts on ``second`` from ``first``; a compression pushes ``second``
        # along the normal
        on_second = forces[j]
        compression = float(on_second @ interface.normal)
        shear = float(np.linalg.norm(on_second - compression * interface.normal))
        on_this = on_second if second[j] == index else -on_second
        ground = other == GROUND
        rows.append(
            {
                "other": "ground" if ground else judged.blocks[other].id,
                "support": ground or bool(judged.blocks[other].fixed),
                "area": float(interface.area),
                "compression": newtons(compression),
                "shear": newtons(shear),
                "force": [newtons(f) for f in on_this],
                "point": [finite_or_none(p) for p in points[j]],
                "tension": newtons(max(float(tensions[j]), 0.0)),
            }
        )
    return rows
