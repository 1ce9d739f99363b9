"""Which storage of the tangent a FEM run should factorise: dense (LAPACK ``dgetrf``) or banded (the
compiled corrector's band LU), measured on the benchmark's cases.

`fem.linear_solver.MatrixLayout` picks the storage of the reduced tangent from its size n and
half-bandwidth b (``kind="auto"``). For each case of `validation.bench.headline.BENCH_CASES` and each
mesh it prints n, b, the storage ``auto`` picks, and the best CPU time of a whole ``fem.solve`` of the
case's load levels with the tangent stored dense and banded, the two taking turns run by run (a slow
period of the shared machine falls on both), their ratio (banded / dense: below 1, the band is
faster), and the largest difference of the two runs' displacements over the characteristic length
(the two factorisations round differently; the converged states agree to within the Newton
tolerance; NaN when the two runs recorded different levels, or none).

Run: ``.venv/bin/python -m validation.bench.solver_choice [--elements 2,4,8,16,32]``.
Timing lives here, never in the tests.
"""

from __future__ import annotations

import argparse
import gc
import os
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import fem
import numpy as np
from fem.options import SolveOptions
from fem.solver import _prepare
from validation.bench.headline import BENCH_CASES, _at, _last_level_only
from validation.case.loader import case_by_id
from validation.case.method_options import FemOptions
from validation.methods.fem import build_model

KINDS = ("dense", "banded")
BUDGET_S = 0.4  # each case and mesh: runs taking turns until this many seconds have passed (at least MIN_RUNS)
MIN_RUNS = 15


@dataclass(frozen=True)
class Choice:
    """One case at one mesh: the tangent's size and half-bandwidth, the storage ``auto`` picks, the best
    CPU seconds of a whole solve with each storage, and the largest displacement difference over L."""

    case_id: str
    elements: int
    n: int
    bandwidth: int
    auto: str
    best: dict[str, float]
    difference: float

    @property
    def ratio(self) -> float:
        return self.best["banded"] / self.best["dense"]


def _in_turn(runs: Mapping[str, Callable[[], object]]) -> dict[str, float]:
    """Best CPU seconds of each run, the runs taking turns, the collector off while each runs."""
    times: dict[str, list[float]] = {kind: [] for kind in runs}
    for run in runs.values():  # warm-up
        run()
    end = time.perf_counter() + BUDGET_S
    while time.perf_counter() < end or len(times[KINDS[0]]) < MIN_RUNS:
        for kind, run in runs.items():
            gc.disable()
            start = time.process_time()
            run()
            times[kind].append(time.process_time() - start)
            gc.enable()
    return {kind: min(t) for kind, t in times.items()}


def measure(case_id: str, single_level: bool, elements: int) -> Choice:
    """Dense against banded storage on one case (all its levels, or its last alone) at one mesh."""
    case = case_by_id(case_id).case
    if single_level:
        case = _last_level_only(case)
    bench = next(b for b in BENCH_CASES if b.case_id == case_id and b.single_level == single_level)
    at = _at(case, bench, "fem", elements)
    options = FemOptions.model_validate(at.methods["fem"])
    model = build_model(at, elements, options)
    levels = at.n_levels()
    system = _prepare(model, SolveOptions(), levels)
    runs = {
        kind: (lambda kind=kind: fem.solve(model, n_levels=levels, rtol=options.rtol, solver=kind)) for kind in KINDS
    }
    results = {kind: run() for kind, run in runs.items()}
    u = [np.asarray(results[kind].mesh_positions) for kind in KINDS]
    same_shape = u[0].shape == u[1].shape and u[0].size > 0
    difference = float(np.abs(u[0] - u[1]).max()) / model.characteristic_length() if same_shape else np.nan
    return Choice(case_id, elements, system.n, system.layout.bw, system.layout.kind, _in_turn(runs), difference)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", default="2,4,8,16,32", help="meshes, comma-separated (default %(default)s)")
    args = parser.parse_args(argv)
    meshes = [int(n) for n in args.elements.split(",")]
    print(f"load average {os.getloadavg()[0]:.1f}; best CPU time of a whole fem.solve, dense and banded in turn")
    seen: set[tuple[str, bool]] = set()
    for bench in BENCH_CASES:
        key = (bench.case_id, bench.single_level)
        if key in seen:
            continue
        seen.add(key)
        for elements in meshes:
            c = measure(bench.case_id, bench.single_level, elements)
            print(
                f"{bench.label:42s} n_el={elements:4d} n={c.n:4d} b={c.bandwidth:3d} auto={c.auto:7s} "
                f"dense {c.best['dense'] * 1e6:9.1f} us  banded {c.best['banded'] * 1e6:9.1f} us  "
                f"banded/dense {c.ratio:5.2f}  |du|/L {c.difference:.1e}",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
