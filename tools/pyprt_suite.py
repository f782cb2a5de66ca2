"""Run PyPRT's own test suite against shapegen's PyPRT API and print how many tests pass.

PyPRT (CityEngine's Python runtime, Esri/pyprt) ships its tests in ``tests/`` with their data;
this tool runs them, unchanged, from a checkout the user names, with ``import pyprt`` answered
by :mod:`shapegen.prt`. Nothing of PyPRT is copied into shapegen. The two ``arcgis`` tests need
the arcgis package and are left out, as the issue of record says::

    git clone https://github.com/Esri/pyprt /tmp/pyprt
    .venv/bin/python tools/pyprt_suite.py /tmp/pyprt

It prints pytest's summary line and one line per failing test with its first error line, and
exits with pytest's status.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

SHIM = "import sys\nimport shapegen.prt\n\nsys.modules[__name__] = shapegen.prt\n"
LEFT_OUT = ("arcgis_test.py",)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("checkout", type=Path, help="a checkout of Esri/pyprt (its tests/ folder)")
    parser.add_argument("-k", default=None, help="pytest's -k expression, to run some tests")
    args = parser.parse_args(argv)
    tests = args.checkout / "tests"
    if not tests.is_dir():
        print(f"pyprt_suite: {tests} is not a folder: name a checkout of Esri/pyprt",
              file=sys.stderr)  # fmt: skip
        return 2
    with tempfile.TemporaryDirectory() as shim_root:
        (Path(shim_root) / "pyprt").mkdir()
        (Path(shim_root) / "pyprt" / "__init__.py").write_text(SHIM)
        environment = dict(os.environ)
        # the shapegen of this checkout, not whichever one the interpreter has installed
        checkout = str(Path(__file__).resolve().parents[1])
        environment["PYTHONPATH"] = os.pathsep.join(
            [shim_root, checkout, *filter(None, [environment.get("PYTHONPATH")])]
        )
        command = [sys.executable, "-m", "pytest", "-q", "-rf", "-p", "no:cacheprovider",
                   "--rootdir", str(args.checkout), str(tests)]  # fmt: skip
        command += [f"--ignore={tests / name}" for name in LEFT_OUT]
        if args.k:
            command += ["-k", args.k]
        result = subprocess.run(command, cwd=args.checkout, env=environment, text=True,
                                capture_output=True)  # fmt: skip
    lines = result.stdout.splitlines()
    for line in lines:
        if line.startswith(("FAILED", "ERROR")) or " passed" in line or " failed" in line:
            print(line)
    if result.returncode not in (0, 1):
        print(result.stderr.strip().splitlines()[-1:] or "", file=sys.stderr)
    return result.returncode


if __name__ == "__main__":
    sys.exit(main())
