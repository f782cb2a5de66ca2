"""Seconds to find the contact interfaces of, and check, walls and arches of 100 to 10 000 blocks.

Run: ``.venv/bin/python benchmarks/bench_contacts.py [N ...]``. Prints one row per model: blocks,
interfaces, seconds for ``find_interfaces`` and for ``check_model`` (best of ``--repeat`` runs,
each on a freshly built model so that no per-block cache is warm). Models: a running-bond brick
wall (:func:`walls.running_bond_wall`) and a single semicircular arch of N voussoirs with t/R =
0.2 (:func:`arches.semicircular_arch`), whose slender, slanted voussoirs are the hard case for a
bounding-box index.
"""

from __future__ import annotations

__all__ = ["main"]

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from arches import semicircular_arch  # noqa: E402
from walls import running_bond_wall  # noqa: E402

from shapegen.statics.checks import check_model  # noqa: E402
from shapegen.statics.contacts import find_interfaces  # noqa: E402

MODELS = {"wall": running_bond_wall, "arch": semicircular_arch}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sizes", nargs="*", type=int, default=[100, 1_000, 10_000])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--models", nargs="+", choices=sorted(MODELS), default=["wall", "arch"])
    args = parser.parse_args(argv)
    header = ("model", "blocks", "interfaces", "find_interfaces s", "check_model s")
    print(" ".join(f"{h:>{w}}" for h, w in zip(header, (5, 7, 10, 17, 13), strict=True)))
    for name in args.models:
        for size in args.sizes:
            find_seconds, check_seconds = [], []
            for _ in range(args.repeat):
                model = MODELS[name](size)
                start = time.perf_counter()
                interfaces = find_interfaces(model)
                find_seconds.append(time.perf_counter() - start)
                start = time.perf_counter()
                check_model(model, interfaces)
                check_seconds.append(time.perf_counter() - start)
            print(
                f"{name:>5} {len(model.blocks):>7} {len(interfaces):>10} "
                f"{min(find_seconds):>17.3f} {min(check_seconds):>13.3f}"
            )


if __name__ == "__main__":
    main()
