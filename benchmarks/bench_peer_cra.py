"""Peer benchmark: shapegen against compas_cra's RBE (the same Whiting QP, IPOPT) on the same walls.

The running-bond walls of ``benchmarks/walls.py`` (about 500, 1 000 and 2 000 bricks), upright
with friction 0.7 (they stand) and tilted by 12 degrees with friction 0.2 (they slide), are
judged twice: by shapegen (contact search + ``analyze``) in this process, and by compas_cra
(``assembly_interfaces_numpy`` + ``rbe_solve``) in another Python that has compas_cra installed,
to which the walls go as JSON boxes. It prints both CPU times and both verdicts.

compas_cra is not a dependency of shapegen; install it in a separate environment:

    python3 -m venv /tmp/cra && /tmp/cra/bin/pip install compas_cra
    .venv/bin/python benchmarks/bench_peer_cra.py --peer-python /tmp/cra/bin/python

Without a Python that imports compas_cra the script says so and exits (status 0). The peer's
verdict: compas_cra reports forces, not a verdict; the wall stands for it when the sum of its
tension forces is at most 1 % of the wall's weight (shapegen certifies 1e-7 of it). RBE penalises
tension (weight 1e6) instead of forbidding it, so some always remains: about 2e-4 W on the 100-brick
wall that stands, against 0.4 W on the one that slides.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

TILT_DEGREES = 12.0
CASES = {"stands": (0.0, 0.7), "slides": (TILT_DEGREES, 0.2)}  # tilt (degrees), friction
TENSION_REL = 1e-2  # the peer's wall stands when its tension sum is below this fraction of W


# ---------------------------------------------------------------- the peer side (compas_cra)
def peer_run(path: str) -> None:
    """In the compas_cra environment: judge the wall in ``path``, print one JSON line."""
    from compas.geometry import Box, Frame
    from compas_assembly.datastructures import Block
    from compas_cra.algorithms import assembly_interfaces_numpy
    from compas_cra.datastructures import CRA_Assembly
    from compas_cra.equilibrium import rbe_solve

    wall = json.loads(Path(path).read_text())
    start = time.process_time()
    assembly = CRA_Assembly()
    # compas is z-up: shapegen's (x, y, z) with y up is compas's (x, -z, y). The ground is one
    # support block under each brick of the first course: compas_cra's interface search only
    # looks at each block's ``nmax`` nearest blocks by centroid, so a single slab under the
    # whole wall would touch only the bricks nearest its centre and leave the rest hanging.
    supports = 0
    for (x0, y0, z0), (x1, _y1, z1) in wall["boxes"]:
        if abs(y0) < 1e-9:
            frame = Frame([(x0 + x1) / 2, -(z0 + z1) / 2, -0.05], [1, 0, 0], [0, 1, 0])
            assembly.add_block(Block.from_shape(Box(x1 - x0, z1 - z0, 0.1, frame=frame)))
            supports += 1
    volume = 0.0
    for (x0, y0, z0), (x1, y1, z1) in wall["boxes"]:
        frame = Frame([(x0 + x1) / 2, -(z0 + z1) / 2, (y0 + y1) / 2], [1, 0, 0], [0, 1, 0])
        assembly.add_block(Block.from_shape(Box(x1 - x0, z1 - z0, y1 - y0, frame=frame)))
        volume += (x1 - x0) * (y1 - y0) * (z1 - z0)
    assembly.set_boundary_conditions(list(range(supports)))
    if wall["tilt"]:
        # compas_cra takes the angle in degrees (is_rad=False by default)
        assembly.rotate_assembly([0, 0, 0], [0, 1, 0], wall["tilt"])
    setup = time.process_time()
    assembly_interfaces_numpy(assembly, nmax=10, amin=1e-4, tmax=1e-4)
    interfaces = time.process_time()
    failure = None
    try:
        rbe_solve(assembly, mu=wall["friction"], density=1.0)
    except ValueError as error:  # IPOPT did not converge
        failure = str(error)
    end = time.process_time()
    tension = 0.0
    for edge in assembly.graph.edges():
        for interface in assembly.graph.edge_attribute(edge, "interfaces"):
            tension += sum(max(f["c_nn"], 0.0) for f in getattr(interface, "forces", []) or [])
    print(
        json.dumps(
            {
                "setup": setup - start,
                "interfaces": interfaces - setup,
                "solve": end - interfaces,
                "cpu": end - start,
                "tension_rel": tension / volume,
                "stands": failure is None and tension <= TENSION_REL * volume,
                "failure": failure,
            }
        )
    )


# ---------------------------------------------------------------- the shapegen side
def shapegen_run(n_blocks: int, case: str) -> tuple[dict, dict]:
    import numpy as np

    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from benchmarks.walls import running_bond_wall
    from shapegen.statics import analyze, find_interfaces

    tilt, friction = CASES[case]
    model = running_bond_wall(n_blocks)
    boxes = [
        (b.vertices.min(axis=0).tolist(), b.vertices.max(axis=0).tolist()) for b in model.blocks
    ]
    angle = math.radians(tilt)
    model.gravity = 9.81 * np.array([math.sin(angle), -math.cos(angle), 0.0])
    model.friction = friction
    for block in model.blocks:  # mass properties are part of the model, not of the analysis
        _ = block.mass, block.centroid
    start = time.process_time()
    interfaces = find_interfaces(model)
    found = time.process_time()
    result = analyze(model, interfaces=interfaces, check=False)
    end = time.process_time()
    ours = {
        "blocks": len(model.blocks),
        "interfaces": found - start,
        "solve": end - found,
        "cpu": end - start,
        "stands": bool(result.feasible),
        "y": result.infeasibility_normalized,
    }
    return ours, {"boxes": boxes, "tilt": tilt, "friction": friction}


def peer_measure(python: str, wall: dict) -> tuple[dict | None, str]:
    """compas_cra's figures on ``wall`` (``{"boxes", "tilt", "friction"}``), measured by this
    script's peer side in ``python``: its JSON record, or None and what it printed on stderr."""
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as handle:
        json.dump(wall, handle)
    try:
        done = subprocess.run(
            [python, __file__, "--peer", handle.name], capture_output=True, text=True, check=False
        )
    finally:
        os.unlink(handle.name)
    lines = [line for line in done.stdout.splitlines() if line.startswith("{")]
    return (json.loads(lines[-1]) if lines else None), done.stderr.strip()


def peer_python(requested: str | None) -> str | None:
    """A Python that imports compas_cra, or None."""
    candidates = (
        [requested] if requested else [os.environ.get("SHAPEGEN_PEER_PYTHON"), sys.executable]
    )
    for python in filter(None, candidates):
        probe = subprocess.run(
            [python, "-c", "import compas_cra"], capture_output=True, text=True, check=False
        )
        if probe.returncode == 0:
            return python
    return None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[500, 1000, 2000])
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--peer-python", help="a Python with compas_cra installed")
    parser.add_argument("--peer", help=argparse.SUPPRESS)  # internal: run the peer on a file
    args = parser.parse_args()
    if args.peer:
        peer_run(args.peer)
        return
    python = peer_python(args.peer_python)
    if python is None:
        print(
            "compas_cra is not importable (give --peer-python, or set SHAPEGEN_PEER_PYTHON, to a "
            "Python that has it: python3 -m venv /tmp/cra && /tmp/cra/bin/pip install compas_cra); "
            "skipped"
        )
        return
    print(f"# peer: {python}; CPU seconds (interfaces + solve); load {os.getloadavg()[0]:.1f}")
    print(
        f"{'case':7s} {'blocks':>6s} | {'shapegen':>8s} {'verdict':>7s} | {'compas_cra':>10s} "
        f"{'(interf.':>8s} {'solve)':>7s} {'verdict':>7s} | {'ratio':>6s}"
    )
    for case in args.cases:
        for size in args.sizes:
            ours, wall = shapegen_run(size, case)
            peer, errors = peer_measure(python, wall)
            if peer is None:
                print(f"{case:7s} {ours['blocks']:6d} | peer failed: {errors[-300:]}")
                continue

            def verdict(stands: bool) -> str:
                return "stands" if stands else "fails"

            print(
                f"{case:7s} {ours['blocks']:6d} | {ours['cpu']:7.2f}s "
                f"{verdict(ours['stands']):>7s} | {peer['cpu']:9.1f}s "
                f"{peer['interfaces']:7.1f}s {peer['solve']:6.1f}s "
                f"{verdict(peer['stands']):>7s} | {peer['cpu'] / ours['cpu']:5.0f}x"
                + f"  (peer tension {peer['tension_rel']:.2g} W)"
                + (f"  (peer: {peer['failure']})" if peer["failure"] else ""),
                flush=True,
            )


if __name__ == "__main__":
    main()
