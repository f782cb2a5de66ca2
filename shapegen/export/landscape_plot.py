"""A picture of an energy landscape with the feasible region and an optimizer's path."""

from __future__ import annotations

__all__ = ["plot_landscape"]

from collections.abc import Mapping, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from shapegen.export.atomic import atomic_write  # noqa: E402
from shapegen.tolerances import ROUNDOFF_REL


def plot_landscape(
    landscape,
    path: str | Path,
    optimizer_path: Sequence[Mapping[str, float]] | None = None,
    *,
    title: str | None = None,
) -> None:
    """Write a PNG: log10 of y / W^2 as filled contours, the feasible region hatched green, the
    optimizer's path as a line of dots from its start (circle) to its end (star)."""
    fig, ax = plt.subplots(figsize=(6.4, 5.2), dpi=100)
    values = np.asarray(landscape.infeasibility, float)
    positive = values[np.isfinite(values) & (values > 0)]
    floor = positive.min() if positive.size else ROUNDOFF_REL
    shown = np.log10(np.where(np.isfinite(values), np.maximum(values, floor), np.nan))
    x, y = np.meshgrid(landscape.first, landscape.second)
    filled = ax.contourf(x, y, shown, levels=20, cmap="magma_r")
    fig.colorbar(filled, ax=ax, label=f"log10 {getattr(landscape, 'measure', 'y/W²')}")
    if landscape.feasible.any():
        ax.contourf(
            x,
            y,
            landscape.feasible.astype(float),
            levels=[0.5, 1.5],
            colors="none",
            hatches=["///"],
        )
        ax.contour(
            x, y, landscape.feasible.astype(float), levels=[0.5], colors="tab:green", linewidths=2
        )
        ax.plot([], [], color="tab:green", lw=2, label="feasible region")
    if optimizer_path:
        px = [p[landscape.first_name] for p in optimizer_path]
        py = [p[landscape.second_name] for p in optimizer_path]
        ax.plot(px, py, "-o", color="tab:cyan", ms=3, lw=1.2, label="optimizer path")
        ax.plot(px[0], py[0], "o", color="white", mec="black", ms=8)
        ax.plot(px[-1], py[-1], "*", color="yellow", mec="black", ms=14)
    ax.set_xlabel(landscape.first_name)
    ax.set_ylabel(landscape.second_name)
    ax.set_title(title or "infeasibility landscape")
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    with atomic_write(path, "wb") as handle:
        fig.savefig(handle, format="png")
    plt.close(fig)
