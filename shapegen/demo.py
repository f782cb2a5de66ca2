"""The main job (``make demo``): build the Cluny nave, optimize it until it stands, save it.

Writes ``out/<name>.glb`` (the optimized model, coloured by tension) and ``out/<name>.png``
(before and after, blocks that need tension in red) and prints a short summary.

    python -m shapegen.demo [RULE.grammar] [--out DIR]
"""

from __future__ import annotations

__all__ = ["main"]

import argparse
import sys
import time
from pathlib import Path

from shapegen.errors import ShapegenError


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m shapegen.demo",
        description="Build a bundled rule file, optimize its free parameters, save the result.",
    )
    parser.add_argument("rule", nargs="?", default="cluny.grammar", help="default cluny.grammar")
    parser.add_argument("--out", default="out", help="output folder (default out/)")
    args = parser.parse_args(argv)
    from shapegen.export.atomic import stop_on_signals

    try:
        with stop_on_signals():  # Ctrl-C or kill: no temporary file left, one line
            return _run(args.rule, Path(args.out))
    except ShapegenError as exc:
        sys.stderr.write(f"shapegen demo: error: {exc}\n")
        return 2
    except OSError as exc:
        where = f"{exc.filename}: " if exc.filename else ""
        sys.stderr.write(f"shapegen demo: error: {where}{exc.strerror or exc}\n")
        return 2
    except KeyboardInterrupt as exc:
        sys.stderr.write("shapegen demo: interrupted\n")
        return getattr(exc, "exit_status", 130)


def _run(rule: str, out: Path) -> int:
    from rich.table import Table

    from shapegen import pipeline
    from shapegen.cli.display import console as display_console
    from shapegen.export.atomic import check_writable
    from shapegen.export.model_io import write_model
    from shapegen.export.picture import render_model
    from shapegen.search.search_options import SearchOptions

    console = display_console()
    if out.exists() and not out.is_dir():
        raise ShapegenError(f"--out {out}: exists and is not a folder")
    out.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    grammar = pipeline.load(rule)
    name = Path(grammar.name).stem
    glb = out / f"{name}.glb"
    picture = out / f"{name}.png"
    for path in (glb, picture):  # before the search, not after it
        check_writable(path)
    console.print(f"[bold]shapegen demo[/bold]: {grammar.name}")

    start = pipeline.design(grammar, assess=True)
    before_model, before = start.model, start.assessment
    console.print(
        f"  built {len(before_model.blocks)} blocks; stands: "
        + ("[green]yes[/green]" if before.stands else "[red]no[/red]")
        + f" ({start.structure.measure_name} = {before.measure:.3g})"
    )

    def progress(record) -> None:
        console.print(
            f"  iter {record.iteration:3d}  measure {record.infeasibility:10.3e}  "
            f"{record.evaluations} evaluations  {record.seconds:6.1f} s"
        )

    end = pipeline.design(grammar, search=SearchOptions(), progress=progress)
    result, after_model = end.optimization, end.model
    # pictures colour blocks by tension only: a bridge's pictures show no tension
    before_analysis, after = before.block_analysis, end.assessment.block_analysis

    write_model(after_model, glb, after)
    _before_after(before_model, before_analysis, after_model, after, picture, render_model)

    table = Table(title=f"{name}: optimized parameters", title_justify="left")
    for column in ("parameter", "initial", "final", "min", "max"):
        table.add_column(column, justify="left" if column == "parameter" else "right")
    for pname, spec in result.parameters.items():
        table.add_row(pname, *(f"{spec[k]:.4g}" for k in ("initial", "final", "min", "max")))
    console.print(table)
    verdict = "[green]stands[/green]" if result.feasible else "[red]still does not stand[/red]"
    console.print(
        f"  blocks {len(after_model.blocks)}; before: "
        + ("stands" if before.stands else "does not stand")
        + f"; after: {verdict} (search margin {result.margin:g}); {result.iterations} iterations,"
        f" {result.evaluations} evaluations, "
        f"{result.seconds:.1f} s optimizing, {time.perf_counter() - started:.1f} s in all"
    )
    console.print(f"  wrote {glb} and {picture}")
    return 0 if result.feasible else 1


def _before_after(before_model, before, after_model, after, path: Path, render_model) -> None:
    """One PNG with the model before and after optimization side by side."""
    import tempfile

    import matplotlib.image as mpimg
    import matplotlib.pyplot as plt

    from shapegen.export.atomic import atomic_write

    with tempfile.TemporaryDirectory() as folder:
        left, right = Path(folder, "before.png"), Path(folder, "after.png")
        render_model(before_model, left, before, title="before (red: needs tension)")
        render_model(after_model, right, after, title="after optimization")
        fig, axes = plt.subplots(1, 2, figsize=(16, 6), dpi=100)
        for ax, image in zip(axes, (left, right), strict=True):
            ax.imshow(mpimg.imread(image))
            ax.set_axis_off()
        fig.tight_layout()
        with atomic_write(path, "wb") as handle:
            fig.savefig(handle, format="png")
        plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
