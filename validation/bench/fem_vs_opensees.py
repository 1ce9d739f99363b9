"""Benchmark of our FEM against OpenSeesPy alone: the FEM and peer rows of ``prbm-validate bench``.

Both codes are driven by `validation.bench.headline`, each as its best user would (one load step per
level, halved only on failure with the failed tries counted; meshes doubled to 1024 elements; plain
and Richardson rows for both). OpenSeesPy runs twice: through the harness's adapter (``opensees``,
timed through ``run_method`` as our FEM is) and as a plain script (``opensees-script``,
`validation.bench.opensees_script`: its OpenSees calls alone timed). The headline at 1e-4 L and 1e-6 L
gives both ratios, our best time over the adapter's best and over the plain script's best, with the
configurations printed.

Run: ``python -m validation.bench.fem_vs_opensees [--quick] [--out reports/bench]``
(the same as ``prbm-validate bench``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from validation.bench.headline import run_bench


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="reports/bench", help="output folder (default %(default)s)")
    parser.add_argument("--quick", action="store_true", help="meshes up to 256 elements, fewer repeats")
    args = parser.parse_args(argv)
    return run_bench(Path(args.out), quick=args.quick)


if __name__ == "__main__":
    raise SystemExit(main())
