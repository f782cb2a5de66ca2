"""The one pipeline every front end runs: load -> optimize -> build -> assess -> report -> write.

The command line, the demo and any script call these functions; the structure a grammar names
(block statics by default, the cable model, a plug-in) is used throughout, so a bridge takes the
same path as a cathedral. The model written is always the model reported: the final design is
built once, with every attr the report lists (the caller's, the fixed and the optimized ones),
and judged as it is written.

>>> from shapegen import pipeline
>>> outcome = pipeline.design(pipeline.load("arch_columns.grammar"), assess=True)  # doctest: +SKIP
>>> outcome.assessment.stands, outcome.report["attrs"]                             # doctest: +SKIP
"""

from __future__ import annotations

__all__ = [
    "Outcome",
    "completed",
    "design",
    "encode_outputs",
    "load",
    "report_bytes",
    "write_outputs",
]

import json
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from shapegen.errors import OptionError
from shapegen.json_values import json_ready
from shapegen.limits import work_clock
from shapegen.model import Model
from shapegen.model.lot import Lot
from shapegen.search.search_options import SearchOptions
from shapegen.statics.statics_options import StaticsOptions
from shapegen.structures import Assessment, Design, Structure, make_structure


@dataclass
class Outcome:
    """What :func:`design` made: the model, how it was judged and found, and the report."""

    grammar: object
    model: Model
    structure: Structure
    assessment: Assessment | None
    optimization: object | None
    report: dict


def load(source: str):
    """The grammar named by ``source``: a rule file, or the name of a bundled one."""
    from shapegen.engine.grammar_api import load_grammar

    return load_grammar(source)


def design(
    grammar,
    *,
    attrs: Mapping[str, object] | None = None,
    seed: int = 0,
    lot: Lot | None = None,
    statics: StaticsOptions | None = None,
    search: SearchOptions | None = None,
    assess: bool = False,
    place: Callable[[Model], Model] | None = None,
    progress: Callable | None = None,
    capacity: Sequence[float] | None = None,
    previous: Outcome | None = None,
    measure_follows: bool = False,
) -> Outcome:
    """Optimize (with ``search``), build and assess (with ``assess`` or ``search``) a design.

    Parameters
    ----------
    grammar
        A loaded grammar.
    attrs, seed, lot
        Attr overrides and derivation settings; ``lot`` a :class:`~shapegen.model.lot.Lot` or
        what ``Lot.of`` takes (checked here, once), None for the rule's ``@Lot``.
    statics
        Block-statics options; refused (:class:`~shapegen.errors.OptionError`) when the grammar's
        structure is not block statics.
    search
        Search the free attrs first (:class:`~shapegen.search.search_options.SearchOptions`); the
        final design is built once, with every attr override.
    assess
        Judge the final model with the grammar's structure.
    place
        Moves the built model (an OpenStreetMap placement); a moved model is judged where it
        stands.
    progress
        Called with each :class:`~shapegen.search.IterationRecord` of the search.
    capacity
        Also find the final design's lateral capacity, the largest tilt at which it stands
        (implies ``assess``): towards each azimuth given (degrees from +x towards +z), or, for
        an empty sequence, over a sweep of directions and the worst. Refused
        (:class:`~shapegen.errors.OptionError`) for a structure that has none (cables). The
        report's ``analysis`` gets a ``capacity``.
    previous
        The outcome of the design before this one, a small change away (the design page's
        last): the final model is judged with :meth:`Structure.reassess`, which may carry
        over what did not change; the answer is the same.
    measure_follows
        With ``previous``: the assessment may be a pending one, its verdict alone (proven),
        when the measure would take longer; :func:`completed` gives the rest.
    """
    started = time.perf_counter()
    structure = make_structure(grammar.structure, statics)
    if capacity is not None and not structure.has_capacity:
        raise OptionError(
            f"the lateral capacity is a rigid-block figure; this design is judged by the"
            f" {structure.name!r} structure ({structure.description})"
        )
    attrs = dict(attrs or {})
    lot = Lot.of(lot) if lot is not None else None
    optimization = None
    if search is not None:
        from shapegen.search import optimize

        optimization = optimize(
            grammar, search, structure=structure, attrs=attrs, seed=seed, lot=lot, progress=progress
        )
        attrs = dict(optimization.attrs)
        model = optimization.model
    else:
        model = grammar.build(attrs=attrs, seed=seed, lot=lot)
    if place is not None:
        model = place(model)
    assessment = found = None
    if assess or optimization is not None or capacity is not None:
        # the cut into convex blocks, the checks and the solver: all under judging's clock
        with work_clock("judging the model"):
            if optimization is not None and place is None and optimization.assessment is not None:
                assessment = optimization.assessment
            elif previous is not None and previous.structure.name == structure.name:
                assessment = structure.reassess(
                    Design.of_model(model), previous.assessment, measure_follows=measure_follows
                )
            else:
                assessment = structure.assess(Design.of_model(model))
            if capacity is not None:
                found = structure.lateral_capacity(Design.of_model(model), list(capacity))
    report = build_report(model)
    if optimization is not None:
        report["optimization"] = optimization.to_report()
    if assessment is not None:
        report["analysis"] = assessment.to_report()
    if found is not None:
        report["analysis"]["capacity"] = found.to_report()
    report["seconds"] = time.perf_counter() - started
    return Outcome(grammar, model, structure, assessment, optimization, report)


def completed(outcome: Outcome) -> Outcome:
    """``outcome`` with its pending assessment (``design(measure_follows=True)``) completed:
    the measure and the forces; an outcome without one as it is."""
    assessment = outcome.assessment
    if assessment is None or not assessment.pending:
        return outcome
    started = time.perf_counter()
    with work_clock("judging the model"):
        assessment = outcome.structure.complete(assessment)
    report = {**outcome.report, "analysis": assessment.to_report()}
    report["seconds"] = outcome.report.get("seconds", 0.0) + time.perf_counter() - started
    return Outcome(outcome.grammar, outcome.model, outcome.structure, assessment,
                   outcome.optimization, report)  # fmt: skip


def build_report(model: Model) -> dict:
    """The build part of a report, from what the model records of its derivation.

    ``solids`` counts the closed leaves that are not convex, kept as derived (the statics cut
    them into convex parts when they judge); ``left_out`` counts the leaves drawn but left out
    of the statics (the model's other surfaces) by reason; ``warnings`` are the derivation's
    (an asset file not found...), one line each; ``cga_errors`` counts the operations a
    ``.cga`` derivation skipped past, as CityEngine's runtime does (each is among the warnings,
    once per place and message).
    """
    from shapegen.export.surfaces import left_out_summary, solids, solids_volume

    metadata = model.metadata or {}
    lot = metadata.get("lot")
    structure = metadata.get("structure") or {}
    return {
        "grammar": metadata.get("grammar"),
        "seed": metadata.get("seed"),
        "lot": list(lot) if lot is not None else None,
        "structure": structure.get("name"),
        "blocks": len(model.blocks),
        "solids": solids(model),
        "left_out": left_out_summary(model),
        "warnings": [str(w) for w in metadata.get("warnings", [])],
        "cga_errors": int(metadata.get("cga_errors", 0)),
        "volume": model.volume + solids_volume(model),  # the solids kept as derived too
        "attrs": dict(metadata.get("attrs", {})),
        "free_parameters": {
            name: {key: spec.get(key) for key in ("value", "min", "max")}
            for name, spec in (metadata.get("free_parameters") or {}).items()
        },
        "reports": dict(metadata.get("reports", {})),
    }


def report_bytes(report: dict) -> bytes:
    """A report as JSON text (non-finite numbers as null)."""
    text = json.dumps(json_ready(report), indent=1, allow_nan=False)
    return (text + "\n").encode("utf-8")


def encode_outputs(
    model: Model,
    assessment: Assessment | None,
    report: dict,
    *,
    model_path: str | Path | None = None,
    report_path: str | Path | None = None,
) -> list[tuple[Path, bytes]]:
    """Every requested output file's content, made in memory before anything is written."""
    from shapegen.export.model_io import encode_model

    outputs = []
    if model_path:
        analysis = assessment.block_analysis if assessment else None
        with work_clock("encoding the model"):
            outputs.append((Path(model_path), encode_model(model, model_path, analysis)))
    if report_path:
        outputs.append((Path(report_path), report_bytes(report)))
    return outputs


def write_outputs(outputs: list[tuple[Path, bytes]]) -> None:
    """Write every file atomically and together: all are written to temporary files first, and
    renamed into place only when every one was written, so a failure or an interrupt leaves the
    previous files (if any) as they were and no temporary file behind."""
    import contextlib

    from shapegen.export.atomic import atomic_write

    with contextlib.ExitStack() as stack:
        handles = [stack.enter_context(atomic_write(path, "wb")) for path, _ in outputs]
        for handle, (_, content) in zip(handles, outputs, strict=True):
            handle.write(content)
