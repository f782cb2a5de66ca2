"""Run one rule over every lot of a city: schedule batches, let the workers write, merge, resume.

Each lot goes through the project's one pipeline (:func:`shapegen.pipeline.design`: derive,
judge, and with a search optimize) on a worker. The parent process only schedules: it hands the
lots out in batches (:class:`~shapegen.city.executors.Batcher`), and the worker that runs a
batch writes the batch's records and buildings itself, atomically, into the output folder or URL
(:mod:`shapegen.city.batches`, :mod:`shapegen.city.store`). At the end the parent reads the
records back and writes the tables and the city's glTF from them. An interrupted run keeps every
batch written, and a rerun into the same output skips their lots (a lot whose corners or
properties changed is run again). An output holding a run of another rule or other settings is
refused rather than mixed.
"""

from __future__ import annotations

__all__ = ["CityProgress", "CityRun", "run_city"]

import contextlib
import gc
import hashlib
import json
import time
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, field, is_dataclass
from pathlib import Path

import numpy as np

from shapegen.city.batches import read_records
from shapegen.city.city_lots import City
from shapegen.city.executors import Batcher, DaskCluster, InProcess, LocalProcesses
from shapegen.city.outputs import write_tables
from shapegen.city.store import CityStore, open_store
from shapegen.city.work import CitySettings, LotTask
from shapegen.errors import InputFormatError, OptionError
from shapegen.json_values import json_ready

RUN_FORMAT = "shapegen-city"
RUN_VERSION = 2  # 2: batch files (lots/B-KEY.json and .blocks)


@dataclass(frozen=True)
class CityProgress:
    """Where a run is, after each batch: ``done`` of ``total`` lots (``resumed`` of them from an
    earlier run), ``failed`` (errors and timeouts), seconds since the start, and the batch's
    records (empty for the first call, before any batch)."""

    done: int
    total: int
    failed: int
    resumed: int
    seconds: float
    records: tuple = ()

    @property
    def record(self) -> dict | None:
        """The last record of the batch (None before any)."""
        return self.records[-1] if self.records else None

    @property
    def rate(self) -> float:
        """Lots finished per second in this run (resumed ones not counted)."""
        ran = self.done - self.resumed
        return ran / self.seconds if self.seconds > 0 else 0.0


@dataclass
class CityRun:
    """What :func:`run_city` did: every lot's record (input order; None for a lot not done when
    it was interrupted), the counts, the files written and where (``store``)."""

    city: City
    records: list[dict | None]
    resumed: int
    seconds: float
    files: dict = field(default_factory=dict)
    executor: str = ""
    store: CityStore | None = None

    @property
    def failed(self) -> int:
        return sum(1 for r in self.records if r is not None and r["status"] != "ok")

    @property
    def built(self) -> int:
        return sum(1 for r in self.records if r is not None and r["status"] == "ok")

    @property
    def derivation(self) -> dict:
        """How this run derived its lots: ``{"batch": lots derived together, "shape": lots
        derived one at a time, "reasons": {why a lot was not in a batch: lots}}`` (lots of an
        earlier run and of runs that judge or search, which derive one at a time, not
        counted as such)."""
        counts = {"batch": 0, "shape": 0, "reasons": {}}
        for record in self.records:
            how = None if record is None else record.get("derived")
            if how in ("batch", "shape"):
                counts[how] += 1
                why = record.get("batch_fallback")
                if how == "shape" and why:
                    counts["reasons"][why] = counts["reasons"].get(why, 0) + 1
        return counts

    @property
    def standing(self) -> int:
        return sum(1 for r in self.records if r is not None and r.get("stands"))


def run_city(
    city: City,
    grammar,
    outdir: str | Path,
    *,
    attrs: Mapping[str, object] | None = None,
    analyze: bool = True,
    seed: int = 0,
    search=None,
    statics=None,
    timeout: float | None = None,
    limits=None,
    workers: int | None = None,
    scheduler=None,
    batch_size: int | None = None,
    scene: bool = True,
    progress: Callable[[CityProgress], None] | None = None,
) -> CityRun:
    """Build, judge (and with ``search`` optimize) every lot of ``city`` with ``grammar``.

    Parameters
    ----------
    city
        From :func:`~shapegen.city.read_lots` or :func:`~shapegen.city.city_from_polygons`.
    grammar
        A loaded :class:`~shapegen.Grammar` read from a file (its text goes to the workers).
    outdir
        The output folder (created), or a URL that fsspec understands (``s3://bucket/city``,
        ``memory://city``); see :mod:`shapegen.city.outputs`. A Dask cluster's workers must
        all reach it.
    attrs
        Attrs for every lot; a lot's properties of the same names override them.
    analyze
        Judge every building (``stands``, ``measure``); False derives only (with ``search``
        the lots are judged anyway).
    seed
        The run's seed; each lot's is drawn from it and the lot's id.
    search, statics
        :class:`~shapegen.search.search_options.SearchOptions` (optimize each lot) and
        :class:`~shapegen.statics.StaticsOptions`, as for ``shapegen build``.
    timeout
        Seconds one lot may take; a lot past it is a row with status ``timeout``.
    limits
        :class:`~shapegen.limits.WorkLimits` for each lot (default: the current ones).
    workers
        Local worker processes (default: one per core); refused with ``scheduler``. A run
        into ``memory://`` derives in this process.
    scheduler
        A Dask scheduler address (``tcp://host:8786``) or a ``distributed.Client``.
    batch_size
        Lots per task (default: about half a second of a worker's time each, see
        :class:`~shapegen.city.executors.Batcher`).
    scene
        Write ``city.glb`` besides the tables.
    progress
        Called before the first batch and after each one with a :class:`CityProgress`.

    Raises
    ------
    InputFormatError
        The folder cannot be written or holds a run with other settings.
    OptionError
        A bad timeout, worker count or batch size, ``workers`` with ``scheduler``, or
        ``memory://`` with ``scheduler``.
    """
    if timeout is not None and not (isinstance(timeout, int | float) and timeout > 0):
        raise OptionError(f"timeout must be a positive number of seconds, got {timeout!r}")
    if workers is not None and scheduler is not None:
        raise OptionError("--workers applies to local processes; a Dask cluster has its own")
    if workers is not None and (not isinstance(workers, int) or workers < 1):
        raise OptionError(f"workers must be a whole number >= 1, got {workers!r}")
    if batch_size is not None and (not isinstance(batch_size, int) or batch_size < 1):
        raise OptionError(f"batch size must be a whole number >= 1, got {batch_size!r}")
    if getattr(grammar, "path", None) is None:
        raise OptionError("a city's rule must be read from a file (load_grammar)")
    from shapegen.grammar.source_files import read_rule_file

    text, _ = read_rule_file(Path(grammar.path))  # as load_grammar reads it: cp1252 files too
    settings = CitySettings(
        grammar_text=text,
        grammar_name=str(grammar.path),
        attrs=dict(attrs or {}),
        seed=int(seed),
        search=search,
        statics=statics,
        timeout=None if timeout is None else float(timeout),
        limits=limits,
        analyze=bool(analyze),
    )
    store = outdir if isinstance(outdir, CityStore) else open_store(outdir)
    if scheduler is not None and not store.shared_between_processes:
        raise OptionError(
            f"{store.location}: a Dask cluster's workers cannot write into this process's"
            " memory; give a folder or an object store URL"
        )
    prepare_folder(store, _identity(settings), city)
    if scheduler is not None:
        executor = DaskCluster(scheduler)
    elif not store.shared_between_processes:
        executor = InProcess()
    else:
        executor = LocalProcesses(workers)
    started = time.perf_counter()
    records: list[dict | None] = [None] * len(city.lots)
    where = {lot.id: k for k, lot in enumerate(city.lots)}
    earlier = read_records(store)
    tasks = []
    resumed = 0
    with np.errstate(over="ignore", invalid="ignore"):  # a refused lot's 1e308 corner
        fingerprints = [_fingerprint(lot) for lot in city.lots]
    for k, (lot, fingerprint) in enumerate(zip(city.lots, fingerprints, strict=True)):
        old = [r for r in earlier.get(lot.id, ()) if r.get("input") == fingerprint]
        if old:
            records[k] = old[-1]
            resumed += 1
        else:
            ring = np.asarray(lot.ring, dtype=float).tolist()
            holes = tuple(np.asarray(hole, dtype=float).tolist() for hole in lot.holes)
            tasks.append(
                LotTask(lot.id, ring, dict(lot.properties), fingerprint, lot.problem, holes,
                        lot.warnings)
            )  # fmt: skip
    run = CityRun(city, records, resumed, 0.0, executor=executor.describe(), store=store)
    total = len(city.lots)
    counts = {"done": resumed, "failed": sum(1 for r in records if r and r["status"] != "ok")}

    def report(batch):
        if progress is not None:
            seconds = time.perf_counter() - started
            progress(
                CityProgress(
                    counts["done"], total, counts["failed"], resumed, seconds, tuple(batch)
                )
            )

    report(())
    workers_count = getattr(executor, "workers", 1)
    batcher = Batcher(tasks, workers_count, batch_size)
    # The parent holds every lot's task and record: the cyclic collector's full passes over them
    # cost more than the scheduling (it makes no cycles to collect); lots derived in this
    # process do make them, so there it keeps running.
    paused = not isinstance(executor, InProcess)
    try:
        with _collector_paused(paused):
            for batch in executor.run(settings, store, batcher):
                for record in batch:
                    records[where[record["id"]]] = record
                counts["done"] += len(batch)
                counts["failed"] += sum(1 for r in batch if r["status"] != "ok")
                report(batch)
    finally:
        run.seconds = time.perf_counter() - started
        with _collector_paused(True):
            _merge(store, city, records)
            run.files = write_tables(store, city, records, scene=scene)
    return run


@contextlib.contextmanager
def _collector_paused(pause: bool):
    """Python's cyclic garbage collector off within (when ``pause``), as it was after."""
    was = gc.isenabled()
    if pause:
        gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def _merge(store: CityStore, city: City, records: list) -> None:
    """Take every lot's record from the files the workers wrote (the authority: what a rerun
    reads), in place; a lot with none keeps what came back to the parent (or None)."""
    written = read_records(store)
    for k, lot in enumerate(city.lots):
        if records[k] is None:
            continue
        fingerprint = records[k].get("input")
        found = [r for r in written.get(lot.id, ()) if r.get("input") == fingerprint]
        if found:
            records[k] = found[-1]


def prepare_folder(store: CityStore, identity: dict, city: City) -> CityStore:
    """Create the output (and ``lots/``), check it is writable and that an earlier run in it had
    the same settings; record them in ``run.json``."""
    store.prepare("lots")
    data = store.read("run.json")
    if data is not None:
        try:
            earlier = json.loads(data)
        except ValueError:
            earlier = None
        manifest = store.name("run.json")
        if not isinstance(earlier, dict) or earlier.get("format") != RUN_FORMAT:
            raise InputFormatError(f"{manifest}: not a shapegen city run; choose another folder")
        changed = [k for k in identity if json_ready(identity[k]) != earlier.get("run", {}).get(k)]
        if changed:
            raise InputFormatError(
                f"{store.location} holds a run with another {', '.join(changed)}; rerun with the"
                " same settings to resume it, or choose another folder"
            )
    document = {
        "format": RUN_FORMAT,
        "version": RUN_VERSION,
        "run": identity,
        "frame": city.frame(),
    }
    text = json.dumps(json_ready(document), indent=1, allow_nan=False) + "\n"
    store.write("run.json", text.encode("utf-8"))
    return store


def _identity(settings: CitySettings) -> dict:
    """What makes two runs the same run (the timeout and the workers do not)."""

    def plain(value):
        return json_ready(asdict(value)) if is_dataclass(value) else value

    return json_ready(
        {
            "rule": Path(settings.grammar_name).name,
            "rule_sha256": hashlib.sha256(settings.grammar_text.encode()).hexdigest(),
            "attrs": settings.attrs,
            "seed": settings.seed,
            "search": plain(settings.search),
            "statics": plain(settings.statics),
            "limits": plain(settings.limits),
            "analyze": settings.analyze,
        }
    )


def _fingerprint(lot) -> str:
    """A hash of what a lot is built from: its corners and its holes' (to the micrometre) and
    properties.
    Called under ``np.errstate(over="ignore", invalid="ignore")``: a refused lot's corner may be
    1e308 (the state is entered once for all lots: it costs as much as the rest)."""
    corners = np.round(np.asarray(lot.ring, dtype=float), 6)
    digest = hashlib.blake2b(corners.tobytes(), digest_size=8)
    for hole in lot.holes:  # a lot without holes keeps the fingerprint it had before holes
        digest.update(b"hole")
        digest.update(np.round(np.asarray(hole, dtype=float), 6).tobytes())
    digest.update(_PROPERTIES.encode(lot.properties).encode())
    return digest.hexdigest()


# json.dumps(properties, sort_keys=True, default=str), made once rather than for every lot
_PROPERTIES = json.JSONEncoder(sort_keys=True, default=str)
