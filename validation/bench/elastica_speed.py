"""Speed of the exact elastica: the whole adapter call ``run_method(case, "elastica")`` for every case
under cases/ with an elastica method, after a first call that pays numba's compile or cache load, in
CPU time per call and per load level (one equilibrium solve a level; target: at most 2 ms),
slowest per level first, with the load average printed beside (the machine is shared).

Run: ``.venv/bin/python -m validation.bench.elastica_speed`` (``--case=ID``, repeatable, times only
those cases). Timing lives here, never in the tests.
"""

from __future__ import annotations

import os
import sys
import time
import timeit
from dataclasses import dataclass

from validation.case.loader import find_case_files, load_case
from validation.run.runner import run_method

TARGET_S = 2e-3  # the target: at most 2 ms per solve (one load level)


@dataclass(frozen=True)
class ElasticaRow:
    """One case: best CPU seconds of the whole call over ``repeats``, its load levels, converged."""

    case_id: str
    cpu: float
    levels: int
    repeats: int
    converged: bool

    @property
    def per_level(self) -> float:
        return self.cpu / self.levels


def time_case(case, repeats: int = 7) -> ElasticaRow:
    """Best CPU time of ``repeats`` single calls after a warm-up call."""
    run = run_method(case, "elastica")
    timer = timeit.Timer(lambda: run_method(case, "elastica"), timer=time.process_time)
    cpu = min(timer.repeat(number=1, repeat=repeats))
    return ElasticaRow(case.case.id, cpu, case.n_levels(), repeats, run.converged)


def rows(only: list[str] | None = None) -> list[ElasticaRow]:
    found = []
    for path in find_case_files():
        case = load_case(path).case
        if "elastica" in case.methods and (not only or case.case.id in only):
            found.append(time_case(case))
    return sorted(found, key=lambda r: -r.per_level)


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    only = [a.split("=", 1)[1] for a in args if a.startswith("--case=")]
    table = rows(only or None)
    width = max((len(r.case_id) for r in table), default=4)
    print(
        f"{'case':<{width}}  {'CPU/level':>10}  {'CPU/call':>10}  levels  (best of {table[0].repeats if table else 0} "
        f"single calls, run_method(case, 'elastica'), first call excluded)"
    )
    for r in table:
        flag = "" if r.converged else "  NOT CONVERGED"
        print(f"{r.case_id:<{width}}  {r.per_level * 1e3:7.2f} ms  {r.cpu * 1e3:7.2f} ms  {r.levels:6d}{flag}")
    over = [r for r in table if r.per_level > TARGET_S]
    print(
        f"\n{len(over)} of {len(table)} case(s) above {TARGET_S * 1e3:.0f} ms a level"
        + (f": {', '.join(r.case_id for r in over)}" if over else "")
        + f"; load average {os.getloadavg()[0]:.1f}"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
