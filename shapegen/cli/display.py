"""What the commands print: summaries of reports and progress on stderr (rich)."""

from __future__ import annotations

__all__ = [
    "ProgressBar",
    "SearchProgress",
    "SimulationProgress",
    "capacity_line",
    "console",
    "directions_line",
    "fmt",
    "left_out_line",
    "print_analysis",
    "print_build",
    "print_simulation",
    "empty_model_line",
    "holdings_rows",
    "stand_ins_line",
    "too_small_line",
]


#: The width given to output that is not a terminal (a pipe, a file): wide enough that no
#: table row or path is wrapped or cut, since a script reads it line by line.
UNWRAPPED_WIDTH = 100_000


def console(stderr: bool = False):
    """A rich console for stdout (or stderr): a terminal's width on a terminal (a long path
    then folds onto the next line, never cut), no wrapping at all when piped or redirected
    (rich would otherwise wrap at 80 columns)."""
    from rich.console import Console

    shown = Console(stderr=stderr, highlight=False)
    if shown.is_terminal:
        return shown
    return Console(stderr=stderr, highlight=False, width=UNWRAPPED_WIDTH)


def fmt(value) -> str:
    """A number in 4 significant digits, yes/no for booleans, '-' for nothing."""
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, float)):
        return f"{value:.4g}"
    try:
        return f"{float(value):.4g}"
    except (TypeError, ValueError):
        return str(value)


class SearchProgress:
    """One line per search iteration (iteration, measure, parameters) under a spinner."""

    def __init__(self, quiet: bool, measure: str = "y/W^2"):
        self.quiet = quiet
        self.measure = measure
        self.console = None
        self.status = None

    def __enter__(self):
        if not self.quiet:
            self.console = console(stderr=True)
            self.status = self.console.status("optimizing: first evaluation...")
            self.status.__enter__()
        return self

    def __exit__(self, *exc) -> None:
        if self.status is not None:
            self.status.__exit__(*exc)

    def __call__(self, record) -> None:
        if self.console is None:
            return
        values = "  ".join(f"{k}={v:.4g}" for k, v in record.parameters.items())
        mark = "[green]stands[/green]" if record.feasible else ""
        self.console.print(
            f"iter {record.iteration:3d}  {self.measure} {record.infeasibility:10.3e}  {values}"
            f"  {mark}"
        )
        self.status.update(f"optimizing: {record.evaluations} evaluations, {record.seconds:.1f} s")


class ProgressBar:
    """A rich progress bar on stderr that goes when it is done; nothing when ``quiet``.

    A command's bar says what it shows in :meth:`columns` (rich's default ones if none) and
    moves it in ``__call__``.
    """

    def __init__(self, quiet: bool):
        self.quiet = quiet
        self.bar = None
        self.task = None

    def columns(self) -> tuple:
        return ()

    def started(self) -> None:
        """Called once the bar is shown."""

    def __enter__(self):
        if not self.quiet:
            from rich.console import Console
            from rich.progress import Progress

            self.bar = Progress(*self.columns(), console=Console(stderr=True), transient=True)
            self.bar.__enter__()
            self.started()
        return self

    def __exit__(self, *exc_info):
        if self.bar is not None:
            self.bar.__exit__(*exc_info)
        return False


class SimulationProgress(ProgressBar):
    """A progress bar over simulated seconds, on stderr."""

    def started(self) -> None:
        self.task = self.bar.add_task("simulating", total=1.0)

    def __call__(self, done: float, total: float) -> None:
        if self.bar is not None:
            self.bar.update(self.task, completed=done / total)


def _grid():
    from rich.table import Table

    table = Table.grid(padding=(0, 2))
    table.add_column(style="bold", no_wrap=True)
    table.add_column(overflow="fold")  # a long path folds onto the next line, never cut
    return table


def analysis_table(title: str, analysis: dict):
    """The verdict of any structure, and its own figures."""
    from rich.text import Text

    from shapegen.structures import UNJUDGED_STATUSES, structure_class

    table = _grid()
    table.add_row("model", Text(title))
    stands = bool(analysis.get("stands"))
    status = analysis.get("status")
    if analysis.get("free_bodies") == 0:  # an empty structure stands, which says nothing
        table.add_row("stands", Text(NOTHING_TO_JUDGE, style="yellow"))
    elif status in UNJUDGED_STATUSES:  # no verdict: taken not to stand, and said so
        table.add_row("stands", Text(unjudged_line(analysis), style="bold yellow"))
    else:
        verdict = Text("yes" if stands else "no", style="green" if stands else "bold red")
        table.add_row("stands", verdict)
    table.add_row("judged by", Text(str(analysis.get("structure"))))
    structure = structure_class(analysis.get("structure"))
    if not structure.judges_blocks:  # a bridge's cables, a plug-in: the structure's own figures
        for label, text in structure.summary(analysis):
            table.add_row(label, text)
        return table
    table.add_row("blocks", judged_blocks_line(analysis))
    bodies = analysis.get("bodies")
    if bodies:
        table.add_row("bodies", bodies_line(bodies))
    stand_ins = analysis.get("stand_ins")
    too_small = too_small_line(stand_ins)
    if stand_ins and (stand_ins["leaves"] or not too_small):
        table.add_row(Text("stand-ins", style="yellow"), Text(stand_ins_line(stand_ins), "yellow"))
    if too_small:
        table.add_row(Text("too small", style="yellow"), Text(too_small, "yellow"))
    table.add_row("interfaces", str(analysis.get("interfaces")))
    table.add_row(
        "infeasibility",
        f"{fmt(analysis.get('infeasibility'))} N^2"
        f" (normalised {fmt(analysis.get('infeasibility_normalized'))})",
    )
    table.add_row("max tension", f"{fmt(analysis.get('max_tension'))} N")
    table.add_row("total weight", f"{fmt(analysis.get('total_weight'))} N")
    tilt = analysis.get("tilt")
    if tilt:
        towards = " (the worst direction)" if tilt.get("azimuth") == "worst" else ""
        table.add_row(
            "tilt",
            f"{fmt(tilt['tilt_deg'])} deg towards azimuth {fmt(tilt['azimuth_deg'])} deg"
            f"{towards}: horizontal load {fmt(tilt['load_multiplier'])} x the weight",
        )
    capacity = analysis.get("capacity")
    if capacity:
        judged = analysis.get("free_bodies") != 0
        table.add_row("lateral capacity", Text(capacity_line(capacity, judged)))
        if judged:
            table.add_row("by direction", Text(directions_line(capacity)))
    table.add_row("seconds", f"{fmt(analysis.get('seconds'))}")
    return table


def judged_blocks_line(analysis: dict) -> str:
    """The blocks in the statics: the model's own, and with stand-ins, theirs too, so that the
    count agrees with the stand-ins line (``571: the model's 69 and 502 standing in for 126
    leaves``; the bodies line says which ride as load)."""
    blocks = analysis.get("blocks") or 0
    stand_ins = analysis.get("stand_ins") or {}
    extra = stand_ins.get("blocks") or 0
    if not extra:
        return str(blocks)
    leaves = stand_ins.get("leaves", 0)
    return (
        f"{blocks + extra}: the model's {blocks} and {extra} standing in for {leaves}"
        f" {'leaf' if leaves == 1 else 'leaves'}"
    )


def unjudged_line(analysis: dict) -> str:
    """``unknown: the solver ended with numerical_error (solver reduced); taken not to stand``."""
    solver = analysis.get("solver")
    by = f" (solver {solver})" if solver else ""
    return f"unknown: the solver ended with {analysis.get('status')}{by}; taken not to stand"


def bodies_line(bodies: dict) -> str:
    """How many bodies the blocks make, and what rides on them."""
    text = f"{bodies['bodies']} ({bodies['several_parts']} of several parts"
    if bodies.get("glued"):
        text += f", {bodies['glued']} glued from overlapping blocks"
    text += ")"
    if bodies.get("ignored"):
        text += (
            f"; {bodies['ignored']} ornaments ride as load ({bodies['riding']} on the structure,"
            f" {bodies['riding_on_supports']} on the ground or supports)"
        )
    return text


def stand_ins_line(stand_ins: dict) -> str:
    """What the statics judged in place of leaves the model keeps as drawn (a warning: the
    verdict is that of solids the rule did not model)."""
    count = stand_ins["leaves"]
    reasons = ", ".join(f"{n} {reason}" for reason, n in stand_ins.get("by_reason", {}).items())
    return (
        f"{count} {'leaf' if count == 1 else 'leaves'} judged as solids the rule did not model"
        f" ({reasons}; {stand_ins['blocks']} blocks); the model itself is as derived"
    )


def too_small_line(stand_ins: dict | None) -> str:
    """``2 blocks within the model's volume tolerance (5.6e-07 m^3), not judged: 1 merged
    into its leaf's body, 1 carried as load by the block it touches``, or ``""``."""
    too_small = (stand_ins or {}).get("too_small") or {}
    count = too_small.get("blocks", 0)
    if not count:
        return ""
    reasons = ", ".join(f"{n} {reason}" for reason, n in too_small.get("by_reason", {}).items())
    return (
        f"{count} {'block' if count == 1 else 'blocks'} within the model's volume tolerance"
        f" ({fmt(too_small.get('volume_floor_m3'))} m^3), not judged: {reasons}"
    )


NOTHING_TO_JUDGE = (
    "nothing to judge: no solid block outside the supports (a rule of faces or open surfaces"
    " models no solids)"
)
"""The verdict's line for a model without a free block (its leaves left out are listed)."""


def capacity_line(capacity: dict, judged: bool = True) -> str:
    """``15.84 deg (load multiplier 0.2838) towards azimuth 0 deg, the worst of 17 directions``;
    ``none: nothing to judge`` when not ``judged`` (no free block)."""
    if not judged:
        return "none: nothing to judge"
    if not capacity.get("stands_upright"):
        return "none: the design does not stand upright"
    tilt = capacity.get("tilt_deg")
    if tilt is None:
        return "not found (the solver failed)"
    count = len(capacity.get("directions", []))
    where = ""
    if capacity.get("sweep"):
        where = f", the worst of {count} directions"
    elif count > 1:
        where = f", the least of the {count} directions asked for"
    multiplier = capacity.get("load_multiplier")
    multiplier = "unbounded" if multiplier is None else fmt(multiplier)
    return (
        f"{tilt:.2f} deg (load multiplier {multiplier}) towards azimuth"
        f" {fmt(capacity.get('azimuth_deg'))} deg{where}"
    )


def directions_line(capacity: dict) -> str:
    """``azimuth: tilt`` for every direction, in degrees."""

    def shown(entry: dict) -> str:
        tilt = entry.get("tilt_deg")
        return "-" if tilt is None else f"{tilt:.2f}"

    return ", ".join(
        f"{fmt(entry['azimuth_deg'])}: {shown(entry)}" for entry in capacity.get("directions", [])
    )


def print_analysis(title: str, analysis: dict) -> None:
    console().print(analysis_table(title, analysis))


def optimization_table(optimization: dict):
    from rich.table import Table

    table = Table(title="optimization", title_justify="left")
    for column in ("parameter", "initial", "final", "min", "max"):
        table.add_column(column, justify="left" if column == "parameter" else "right")
    for name, spec in optimization["parameters"].items():
        table.add_row(name, *(fmt(spec[k]) for k in ("initial", "final", "min", "max")))
    for name, value in (optimization.get("fixed") or {}).items():
        table.add_row(f"{name} (fixed)", fmt(value), fmt(value), "-", "-")
    return table


def optimization_line(optimization: dict) -> str:
    """How the search ended, printed under its table as one line (as the table's caption it
    was wrapped to the table's width)."""
    return (
        f"{optimization['message']}; {optimization['method']}, {optimization['iterations']}"
        f" iterations, {optimization['evaluations']} evaluations, {fmt(optimization['seconds'])} s"
    )


def print_build(title: str, report: dict, lot_source: str | None = None) -> None:
    """The build's table: what the model holds, counted by kind (blocks, solids kept as
    derived, surfaces), its volume, and why nothing can be judged when it holds no solid.
    ``lot_source`` says where the lot came from (``"--lot"``, ``"@Lot"``, ``"default"``) for
    the hint under a model that holds nothing."""
    from rich.text import Text

    out = console()
    table = _grid()
    table.add_row("grammar", Text(title))
    for label, text in holdings_rows(report):
        table.add_row(label, Text(text))
    table.add_row("volume", f"{fmt(report['volume'])} m^3")
    table.add_row("seconds", fmt(report["seconds"]))
    for name, value in report.get("reports", {}).items():
        table.add_row(Text(f"report {name}"), Text(str(value)))
    out.print(table)
    empty = empty_model_line(report, lot_source)
    if empty and not (report.get("left_out") and "analysis" in report):  # its verdict says it
        out.print(Text(empty, style="yellow"), soft_wrap=True)
    # what the statics still leave out, once the leaves they can judge stand in (without an
    # analysis the surfaces row has said it)
    stand_ins = (report.get("analysis") or {}).get("stand_ins")
    left_out = left_out_line(stand_ins["left_out"]) if stand_ins else ""
    if left_out:  # one line, never wrapped
        out.print(Text(f"left out: {left_out}"), soft_wrap=True)
    for warning in report.get("warnings", []):
        out.print(Text(f"warning: {warning}", style="yellow"), soft_wrap=True)
    if report.get("cga_errors"):
        out.print(Text(cga_errors_line(report["cga_errors"]), style="yellow"), soft_wrap=True)
    if "optimization" in report:
        out.print(optimization_table(report["optimization"]))
        out.print(Text(optimization_line(report["optimization"])), soft_wrap=True)
    if "analysis" in report:
        out.print(analysis_table(title, report["analysis"]))


def holdings_rows(report: dict) -> list[tuple[str, str]]:
    """What a built model holds, one row per kind: ``blocks`` (convex, judged as they are),
    ``solids`` (solid leaves kept as derived: closed ones that are not convex, and inserts
    drawn open where trim planes cut them) and ``surfaces`` (leaves drawn but not solid: faces,
    open meshes), the last two only when there are some."""
    rows = [("blocks", str(report["blocks"]))]
    solids = report.get("solids") or 0
    if solids:
        rows.append(("solids", f"{solids} kept as derived: closed and not convex, or cut open"
                               " at trim planes (judged as solids)"))  # fmt: skip
    surfaces = report.get("left_out") or {}
    if surfaces.get("leaves"):
        reasons = ", ".join(f"{n} {why}" for why, n in surfaces.get("by_reason", {}).items())
        rows.append(("surfaces", f"{surfaces['leaves']} drawn, not solid: {reasons}"))
    return rows


def empty_model_line(report: dict, lot_source: str | None = None) -> str:
    """Why a model without a block or a solid has nothing to judge (a rule of faces), or
    what to try when the rule made nothing at all on its lot; ``""`` for a model with one."""
    if report["blocks"] or report.get("solids"):
        return ""
    surfaces = (report.get("left_out") or {}).get("leaves", 0)
    if surfaces:
        return (
            f"nothing to judge: the model holds {surfaces} surface{'s' * (surfaces != 1)} and no"
            " solid (a rule of faces or open surfaces models no volume; the statics judge"
            " blocks and closed solids)"
        )
    lot = report.get("lot")
    size = ""
    if isinstance(lot, list | tuple) and len(lot) == 2 and all(isinstance(v, float) for v in lot):
        size = f" of {fmt(lot[0])} x {fmt(lot[1])} m"
    where = {
        "--lot": f"the lot{size} given with --lot",
        "@Lot": f"the rule's @Lot{size}",
    }.get(lot_source or "", f"the default lot{size}")
    return (
        f"the rule made nothing on {where}: a rule may make nothing below a size or on another"
        " shape; try another lot with --lot WIDTH,DEPTH (or the rule's @Lot)"
    )


def cga_errors_line(count: int) -> str:
    """``CGA errors: 3 operations skipped ...``: the count of a .cga derivation's CGA errors."""
    what = "operation" if count == 1 else "operations"
    return (
        f"CGA errors: {count} {what} skipped, the derivation carried on as CityEngine's "
        "does (see the warnings)"
    )


def left_out_line(left_out: dict | None) -> str:
    """``3 leaves not judged by the statics: 2 a face (no volume), 1 not convex``, or ``""``
    when every leaf is a block."""
    if not left_out or not left_out.get("leaves"):
        return ""
    count = left_out["leaves"]
    reasons = ", ".join(f"{n} {reason}" for reason, n in left_out.get("by_reason", {}).items())
    return f"{count} {'leaf' if count == 1 else 'leaves'} not judged by the statics: {reasons}"


def print_simulation(title: str, result, args, build: dict) -> None:
    from rich.text import Text

    table = _grid()
    table.add_row("model", Text(title))
    table.add_row("blocks", str(len(result.model.blocks)))
    if "optimization" in build:
        optimization = build["optimization"]
        values = ", ".join(
            f"{name} {fmt(spec['final'])}" for name, spec in optimization["parameters"].items()
        )
        table.add_row("optimized", Text(f"{optimization['message']}: {values}"))
    if result.removed:
        table.add_row("removed", Text(", ".join(result.removed)))
    stands = result.stands
    verdict = Text(result.verdict, style="green" if stands else "bold red")
    table.add_row("verdict", verdict.append(f": {result.explanation()}", style=""))
    movers = result.largest_movers(3)
    table.add_row(
        "largest motion",
        Text(", ".join(f"{m.id} {_distance(m.relative_displacement * m.width)}"
                       f" ({_widths(m.relative_displacement)})" for m in movers)),
    )  # fmt: skip
    track = result.displacement_over_time()
    shown = sorted({round(k * (len(track["time"]) - 1) / 5) for k in range(1, 6)})
    table.add_row(
        "over time",
        ", ".join(f"{track['time'][k]:.3g} s {_distance(track['max_displacement'][k])}"
                  for k in shown),
    )  # fmt: skip
    table.add_row(
        "speed",
        f"peak {result.peak_speed:.3g} m/s, at the end {result.final_speed:.3g} m/s",
    )
    table.add_row(
        "moved blocks",
        f"{result.moved_blocks} ({result.fallen_blocks} fell, {result.moving_blocks} still moving)",
    )
    table.add_row(
        "settlement",
        f"{result.settlement * 1000:.4g} mm, then {result.max_displacement * 1000:.4g} mm",
    )
    if result.settings.shake > 0:
        table.add_row("shake", f"{result.settings.shake:g} m/s over 1/60 s")
    table.add_row(
        "seconds",
        f"{result.seconds:.4g} simulated, {result.wall_seconds:.4g} wall"
        f" ({result.speed:.3g} simulated s per wall s)",
    )
    for label, path in (("report", args.report), ("output", args.output), ("frames", args.frames)):
        if path:
            table.add_row(label, Text(str(path)))
    console().print(table)


def _distance(metres: float) -> str:
    return f"{metres:.3g} m" if metres >= 1.0 else f"{metres * 1000:.3g} mm"


def _widths(ratio: float) -> str:
    """A displacement over its block's smallest width, as a share or a count of widths."""
    return f"{ratio:.2%} of its width" if ratio < 1.0 else f"{ratio:.3g} widths"
