"""What the page reads of a session: its state, the attrs as JSON with the command line, one
block's account, the model and its scene.

The session takes a :class:`Shown` (what is on screen at one moment, copied under its lock) and
these functions read nothing else; :class:`ModelFiles` keeps the model's glTF and scene of the
latest model version, made once however often the page asks.
"""

from __future__ import annotations

__all__ = ["ModelFiles", "Shown", "attrs_export", "block_readout", "error_json", "state_json"]

import threading
from dataclasses import dataclass
from pathlib import Path

from shapegen.editor.annotations import inspector_sections
from shapegen.editor.attrs import RequestError, attr_specs, plain_value, range_warnings
from shapegen.editor.blocks import block_details
from shapegen.editor.exports import command_line
from shapegen.editor.scene import scene_data
from shapegen.errors import ShapegenError
from shapegen.json_values import finite_or_none, json_ready
from shapegen.model.lot import Lot


@dataclass(frozen=True)
class Shown:
    """What is on screen: the design and what the designer chose of it, with the state of the
    search, the scans and the history."""

    grammar: object  # the loaded Grammar
    outcome: object  # the pipeline's DesignOutcome of the design on screen
    attrs: dict  # the designer's values
    values: dict  # every attr's value the design was built with, the designer's included
    free: list  # the attrs the search varies
    free_from_file: bool  # they are the file's @Free ones
    margin: float
    seed: int
    lot: Lot | None
    path: Path | None  # the rule file read
    package: Path | None  # the .rpk opened, if one was
    rules_path: tuple
    version: int
    model_version: int
    timings: dict
    stability: dict
    optimization: dict | None
    reload_pending: bool
    history: dict  # {"undo": n, "redo": n}
    error: dict | None


def state_json(shown: Shown) -> dict:
    """The page's state (plain JSON): attrs, verdict, timings, stability, search, error."""
    outcome = shown.outcome
    assessment = outcome.assessment
    structure = outcome.structure
    verdict = None
    if assessment is not None:
        section = assessment.section
        verdict = {
            "stands": bool(assessment.stands),
            "measure": finite_or_none(assessment.measure),
            "measure_name": structure.measure_name,
            "fails_as": structure.fails_as,
            "judged": assessment.judged,  # False: the solver ended without an answer
            "status": assessment.status,
            # a proven verdict whose measure follows: measure and max_tension are null
            "max_tension": None if assessment.pending else section.get("max_tension"),
            "pending": bool(assessment.pending),
        }
    return json_ready({
        "version": shown.version,
        "model_version": shown.model_version,
        "grammar": {
            "name": Path(shown.grammar.name).name,
            "path": str(shown.path) if shown.path else None,
            "package": str(shown.package) if shown.package else None,
            "structure": structure.name,
            "judges_blocks": structure.judges_blocks,
            "blocks": len(outcome.model.blocks),
            "dialect": shown.grammar.dialect,
            "judged_by": structure.description,  # the page's words for what judges it
        },
        # the designer's values outside their @Range, taken as given as on the command line,
        # then what the load let through and the derivation warned about (a .cga file's)
        "warnings": [
            *range_warnings(shown.grammar, shown.attrs, shown.values, shown.free),
            *(str(w) for w in (outcome.model.metadata or {}).get("warnings", [])),
        ],
        "attrs": [
            spec.to_json()
            for spec in attr_specs(shown.grammar, shown.values, user=shown.attrs, free=shown.free)
        ],
        "sections": inspector_sections(shown.grammar.catalogue),
        "verdict": verdict,
        # the structure's own panel (a bridge's cable sizing), in the structure's words
        "panel": structure.panel(assessment.section) if assessment is not None else None,
        "timings": dict(shown.timings),
        "stability": dict(shown.stability),
        "optimization": shown.optimization,
        "reload_pending": shown.reload_pending,
        "history": dict(shown.history),
        "settings": {
            "free": shown.free,
            "free_from_file": shown.free_from_file,
            "margin": shown.margin,
            "seed": shown.seed,
            "lot": shown.lot.to_json() if shown.lot is not None else None,
            "file_lot": list(shown.grammar.lot),
        },
        "error": shown.error,
    })  # fmt: skip


def attrs_export(shown: Shown) -> dict:
    """The design's attrs: every value (``attrs``), the designer's (``set``), and the
    ``shapegen build`` line that builds the design again (``command``: the designer's values;
    ``command_every_attr``: every value, for a file whose defaults may change)."""
    values = shown.values
    every = {k: plain_value(values[k]) for k in shown.grammar.attrs if k in values}
    user = {k: every[k] for k in every if k in shown.attrs}
    settable = {k: v for k, v in every.items() if not isinstance(v, list)}
    # a package is built from the .rpk itself, as it was opened
    path, seed, lot, folders = shown.package or shown.path, shown.seed, shown.lot, shown.rules_path
    return json_ready({
        "grammar": str(path) if path else None,
        "seed": seed,
        "lot": lot.to_json() if lot is not None else None,
        "attrs": every,
        "set": user,
        "command": command_line(path, user, seed=seed, lot=lot, rules_path=folders),
        "command_every_attr": command_line(path, settable, seed=seed, lot=lot, rules_path=folders),
    })  # fmt: skip


def block_readout(shown: Shown, block_id: str) -> dict:
    """One block of the model on screen: labels, rule path, the attrs its rules read, its
    joints' forces and the tension it needs (see :mod:`shapegen.editor.blocks`)."""
    details = block_details(shown.outcome, block_id, shown.values, set(shown.attrs))
    if details is None:
        raise RequestError(f"the current model has no block {block_id!r}", 404)
    details["model_version"] = shown.model_version
    return json_ready(details)


class ModelFiles:
    """The glTF and the scene of the latest model version, each made once."""

    def __init__(self):
        self._lock = threading.Lock()
        self._glb: tuple[int, bytes] | None = None
        self._scene: tuple[int, dict] | None = None

    def glb(self, model_version: int, outcome) -> bytes:
        """The model as binary glTF (blocks coloured by tension, resultant arrows)."""
        from shapegen.export.gltf import encode_glb

        with self._lock:
            if self._glb is not None and self._glb[0] == model_version:
                return self._glb[1]
        assessment = outcome.assessment
        content = encode_glb(
            outcome.model, assessment.block_analysis if assessment is not None else None
        )
        with self._lock:
            self._glb = (model_version, content)
        return content

    def scene(self, model_version: int, outcome) -> dict:
        """Colours, forces and legend of the model (see :mod:`shapegen.editor.scene`)."""
        with self._lock:
            if self._scene is not None and self._scene[0] == model_version:
                return self._scene[1]
        data = json_ready(scene_data(outcome.model, outcome.assessment))
        data["model_version"] = model_version
        with self._lock:
            self._scene = (model_version, data)
        return data


def error_json(exc: ShapegenError) -> dict:
    """A grammar (or build) error for the page: the message, its place and the source excerpt."""
    location = getattr(exc, "location", None)
    return {
        "message": getattr(exc, "message", None) or str(exc).splitlines()[0],
        "text": str(exc),
        "file": location.file if location else None,
        "line": location.line if location else None,
        "column": location.column if location else None,
    }
