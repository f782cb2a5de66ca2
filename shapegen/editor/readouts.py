"""What the page reads of a session: its state, the report, the attrs as JSON with the command
line, one block's account, the model and its scene.

:class:`ReadoutsMixin` is mixed into :class:`~shapegen.editor.session.EditorSession`, which
provides the design (``_outcome``, ``grammar``, ``attrs``, ``seed``, ``lot``, ``path``), its
versions, the search's and the scans' state, ``_state_lock``, and ``_follower`` (the measure
that follows a pending verdict: what needs the forces waits for it).
"""

from __future__ import annotations

__all__ = ["ReadoutsMixin"]

from pathlib import Path

from shapegen.editor.annotations import attr_hints, inspector_sections
from shapegen.editor.attrs import RequestError, attr_specs, plain_value
from shapegen.editor.blocks import block_details
from shapegen.editor.exports import command_line
from shapegen.editor.scene import scene_data
from shapegen.json_values import finite_or_none, json_ready
from shapegen.statics.cables import CableSizing


class ReadoutsMixin:
    """The state, the report, the attrs export and a block's account."""

    def report(self) -> dict:
        """The current design's report, as ``shapegen build --analyze --report`` writes it."""
        self._settled()
        with self._state_lock:
            return json_ready(self._outcome.report)

    def glb(self) -> bytes:
        """The current model as binary glTF (blocks coloured by tension, resultant arrows)."""
        from shapegen.export.gltf import encode_glb

        self._settled()
        with self._state_lock:
            version, outcome = self.model_version, self._outcome
            if self._glb is not None and self._glb[0] == version:
                return self._glb[1]
        analysis = outcome.assessment.block_analysis if outcome.assessment is not None else None
        content = encode_glb(outcome.model, analysis)
        with self._state_lock:
            self._glb = (version, content)
        return content

    def scene(self) -> dict:
        """Colours, forces and legend of the current model (see :mod:`shapegen.editor.scene`)."""
        self._settled()
        with self._state_lock:
            version, outcome = self.model_version, self._outcome
            if self._scene is not None and self._scene[0] == version:
                return self._scene[1]
        data = json_ready(scene_data(outcome.model, outcome.assessment))
        data["model_version"] = version
        with self._state_lock:
            self._scene = (version, data)
        return data

    def _settled(self) -> None:
        """Wait until the design on screen is complete: a pending verdict's measure and forces
        followed (:mod:`shapegen.editor.completion`)."""
        with self._state_lock:
            outcome = self._outcome
        if self._follower is not None and outcome.assessment is not None:
            if outcome.assessment.pending:
                self._follower.wait(outcome)

    def attrs_export(self) -> dict:
        """The current design's attrs: every value (``attrs``), the designer's (``set``), and
        the ``shapegen build`` line that builds the design again (``command``: the designer's
        values; ``command_every_attr``: every value, for a file whose defaults may change)."""
        with self._state_lock:
            values = self._current_values()
            every = {k: plain_value(values[k]) for k in self.grammar.attrs if k in values}
            user = {k: every[k] for k in every if k in self.attrs}
            settable = {k: v for k, v in every.items() if not isinstance(v, list)}
            # a package is built from the .rpk itself, as it was opened
            path, seed, lot = self.package or self.path, self.seed, self.lot
            folders = self.rules_path
            return json_ready({
                "grammar": str(path) if path else None,
                "seed": seed,
                "lot": lot,
                "attrs": every,
                "set": user,
                "command": command_line(path, user, seed=seed, lot=lot, rules_path=folders),
                "command_every_attr": command_line(
                    path, settable, seed=seed, lot=lot, rules_path=folders
                ),
            })  # fmt: skip

    def block(self, block_id: str) -> dict:
        """One block of the current model: labels, rule path, the attrs its rules read, its
        joints' forces and the tension it needs (see :mod:`shapegen.editor.blocks`)."""
        self._settled()
        with self._state_lock:
            outcome, version = self._outcome, self.model_version
            values, user = self._current_values(), set(self.attrs)
        details = block_details(outcome, block_id, values, user)
        if details is None:
            raise RequestError(f"the current model has no block {block_id!r}", 404)
        details["model_version"] = version
        return json_ready(details)

    def _state(self) -> dict:
        outcome = self._outcome
        assessment = outcome.assessment
        values = self._current_values()
        section = assessment.section if assessment is not None else {}
        # the page's cable panel shows a bridge's sizing
        cable_sizing = isinstance(getattr(assessment, "detail", None), CableSizing)
        verdict = None
        if assessment is not None:
            verdict = {
                "stands": bool(assessment.stands),
                "measure": finite_or_none(assessment.measure),
                "measure_name": outcome.structure.measure_name,
                "fails_as": outcome.structure.fails_as,
                "judged": assessment.judged,  # False: the solver ended without an answer
                "status": assessment.status,
                # a proven verdict whose measure follows: measure and max_tension are null
                "max_tension": None if assessment.pending else section.get("max_tension"),
                "pending": bool(assessment.pending),
            }
        return {
            "version": self.version,
            "model_version": self.model_version,
            "grammar": {
                "name": Path(self.grammar.name).name,
                "path": str(self.path) if self.path else None,
                "package": str(self.package) if self.package else None,
                "structure": outcome.structure.name,
                "judges_blocks": outcome.structure.judges_blocks,
                "blocks": len(outcome.model.blocks),
                "dialect": self.grammar.dialect,
            },
            # what the load let through and the derivation warned about (a .cga file's)
            "warnings": [str(w) for w in (outcome.model.metadata or {}).get("warnings", [])],
            "attrs": [
                spec.to_json()
                for spec in attr_specs(self.grammar, values, user=self.attrs, free=self.free_attrs)
            ],
            "sections": inspector_sections(attr_hints(self.grammar)),
            "verdict": verdict,
            "cables": section if cable_sizing else None,
            "timings": dict(self._timings),
            "stability": dict(self._stability),
            "optimization": self._optimization,
            "reload_pending": self._reload_pending,
            "history": {"undo": len(self._undo), "redo": len(self._redo)},
            "settings": {
                "free": self.free_attrs,
                "free_from_file": self._free is None,
                "margin": self.margin,
                "seed": self.seed,
                "lot": self.lot,
                "file_lot": list(self.grammar.lot),
            },
            "error": self._error,
        }
