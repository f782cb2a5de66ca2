"""Run one rule over every lot of a city: dispatch, record each lot as it finishes, resume.

Each lot goes through the project's one pipeline (:func:`shapegen.pipeline.design`: derive,
judge, and with a search optimize) on a worker; its record is written atomically the moment it
comes back, so an interrupted run keeps every lot that finished, and a rerun into the same
folder skips them (a lot whose corners or properties changed is run again). A folder holding a
run of another rule or other settings is refused rather than mixed.
"""

from __future__ import annotations

__all__ = ["CityProgress", "CityRun", "run_city"]

import hashlib
import json
import time
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, field, is_dataclass
from pathlib import Path

from shapegen.city.executors import DaskCluster, LocalProcesses
from shapegen.city.lots import City
from shapegen.city.outputs import lot_key, read_record, write_json, write_tables
from shapegen.city.work import CitySettings, LotTask, lot_seed, new_record
from shapegen.errors import InputFormatError, OptionError
from shapegen.export.atomic import atomic_write
from shapegen.json_values import json_ready

RUN_FORMAT = "shapegen-city"
RUN_VERSION = 1


@dataclass(frozen=True)
class CityProgress:
    """Where a run is, after each lot: ``done`` of ``total`` (``resumed`` of them from an
    earlier run), ``failed`` (errors and timeouts), seconds since the start, and the lot's
    record (None for the first call, before any lot)."""

    done: int
    total: int
    failed: int
    resumed: int
    seconds: float
    record: dict | None = None

    @property
    def rate(self) -> float:
        """Lots finished per second in this run (resumed ones not counted)."""
        ran = self.done - self.resumed
        return ran / self.seconds if self.seconds > 0 else 0.0


@dataclass
class CityRun:
    """What :func:`run_city` did: every lot's record (input order; None for a lot not done when
    it was interrupted), the counts and the files written."""

    city: City
    records: list[dict | None]
    resumed: int
    seconds: float
    files: dict = field(default_factory=dict)
    executor: str = ""

    @property
    def failed(self) -> int:
        return sum(1 for r in self.records if r is not None and r["status"] != "ok")

    @property
    def built(self) -> int:
        return sum(1 for r in self.records if r is not None and r["status"] == "ok")

    @property
    def standing(self) -> int:
        return sum(1 for r in self.records if r is not None and r.get("stands"))


def run_city(
    city: City,
    grammar,
    outdir: str | Path,
    *,
    attrs: Mapping[str, object] | None = None,
    seed: int = 0,
    search=None,
    statics=None,
    timeout: float | None = None,
    limits=None,
    workers: int | None = None,
    scheduler=None,
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
        The output folder (created); see :mod:`shapegen.city.outputs`.
    attrs
        Attrs for every lot; a lot's properties of the same names override them.
    seed
        The run's seed; each lot's is drawn from it and the lot's id.
    search, statics
        :class:`~shapegen.search.options.SearchOptions` (optimize each lot) and
        :class:`~shapegen.statics.StaticsOptions`, as for ``shapegen build``.
    timeout
        Seconds one lot may take; a lot past it is a row with status ``timeout``.
    limits
        :class:`~shapegen.limits.WorkLimits` for each lot (default: the current ones).
    workers
        Local worker processes (default: one per core); refused with ``scheduler``.
    scheduler
        A Dask scheduler address (``tcp://host:8786``) or a ``distributed.Client``.
    scene
        Write ``city.glb`` besides the tables.
    progress
        Called before the first lot and after each one with a :class:`CityProgress`.

    Raises
    ------
    InputFormatError
        The folder cannot be written or holds a run with other settings.
    OptionError
        A bad timeout or worker count, or ``workers`` with ``scheduler``.
    """
    if timeout is not None and not (isinstance(timeout, int | float) and timeout > 0):
        raise OptionError(f"timeout must be a positive number of seconds, got {timeout!r}")
    if workers is not None and scheduler is not None:
        raise OptionError("--workers applies to local processes; a Dask cluster has its own")
    if workers is not None and (not isinstance(workers, int) or workers < 1):
        raise OptionError(f"workers must be a whole number >= 1, got {workers!r}")
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
    )
    folder = prepare_folder(Path(outdir), _identity(settings), city)
    executor = DaskCluster(scheduler) if scheduler is not None else LocalProcesses(workers)
    started = time.perf_counter()
    records: list[dict | None] = [None] * len(city.lots)
    where = {lot.id: k for k, lot in enumerate(city.lots)}
    tasks = []
    resumed = 0
    for k, lot in enumerate(city.lots):
        fingerprint = _fingerprint(lot)
        old = read_record(folder / "lots" / f"{lot_key(lot.id)}.json")
        if old is not None and old.get("input") == fingerprint:
            records[k] = old
            resumed += 1
        elif lot.problem is not None:
            record = new_record(lot.id, lot_seed(lot.id, settings.seed))
            record.update(error=lot.problem, seconds=0.0, input=fingerprint)
            _save(folder, record)
            records[k] = record
        else:
            ring = tuple((float(e), float(n)) for e, n in lot.ring)
            tasks.append(LotTask(lot.id, ring, dict(lot.properties)))
    run = CityRun(city, records, resumed, 0.0, executor=executor.describe())
    total = len(city.lots)

    def report(record):
        if progress is not None:
            done = sum(1 for r in records if r is not None)
            progress(
                CityProgress(
                    done, total, run.failed, resumed, time.perf_counter() - started, record
                )
            )

    report(None)
    try:
        for record in executor.run(settings, tasks):
            k = where[record["id"]]
            record["input"] = _fingerprint(city.lots[k])
            _save(folder, record)
            records[k] = {key: value for key, value in record.items() if key != "model"}
            report(records[k])
    finally:
        run.seconds = time.perf_counter() - started
        run.files = write_tables(folder, city, records, scene=scene)
    return run


def prepare_folder(folder: Path, identity: dict, city: City) -> Path:
    """Create the output folder (and ``lots/``), check it is writable and that an earlier run
    in it had the same settings; record them in ``run.json``."""
    from shapegen.export.atomic import check_writable

    if folder.exists() and not folder.is_dir():
        raise InputFormatError(f"{folder}: exists and is not a folder")
    try:
        (folder / "lots").mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputFormatError(f"{folder}: cannot create it ({exc.strerror or exc})") from None
    check_writable(folder / "lots" / ".shapegen")
    manifest = folder / "run.json"
    if manifest.exists():
        try:
            earlier = json.loads(manifest.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            earlier = None
        if not isinstance(earlier, dict) or earlier.get("format") != RUN_FORMAT:
            raise InputFormatError(f"{manifest}: not a shapegen city run; choose another folder")
        changed = [k for k in identity if json_ready(identity[k]) != earlier.get("run", {}).get(k)]
        if changed:
            raise InputFormatError(
                f"{folder} holds a run with another {', '.join(changed)}; rerun with the same"
                " settings to resume it, or choose another folder"
            )
    write_json(
        manifest,
        {"format": RUN_FORMAT, "version": RUN_VERSION, "run": identity, "frame": city.frame()},
    )
    return folder


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
        }
    )


def _fingerprint(lot) -> str:
    """A hash of what a lot is built from: its corners and properties."""
    text = json.dumps(
        {"ring": [[round(float(v), 6) for v in p] for p in lot.ring], "properties": lot.properties},
        sort_keys=True,
        default=str,
    )
    return hashlib.blake2b(text.encode(), digest_size=8).hexdigest()


def _save(folder: Path, record: dict) -> None:
    """The lot's building (if any) and then its record, each atomically: a record on disk means
    the lot is done."""
    key = lot_key(record["id"])
    model = record.get("model")
    if model is not None:
        with atomic_write(folder / "lots" / f"{key}.blocks.json", "wb") as handle:
            handle.write(model)
    write_json(folder / "lots" / f"{key}.json", {k: v for k, v in record.items() if k != "model"})
