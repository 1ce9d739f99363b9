"""Speed of the mechanism elastica (``elastica.mechanism``) per load level, and the work behind it.

For each case (default: the parallel-guided mechanism, ``segment_parallel_guided_mechanism``; ``--case=ID``,
repeatable; ``--all``: every case whose elastica run reaches the mechanism solver) it prints the best CPU
time per load level of the whole adapter call ``run_method(case, "elastica")`` over several calls (after a
first call that pays numba's compile or cache load), and per level: the residual evaluations, the Jacobian
evaluations and the beam integrations (plain end states, from ``integrate_beam``) of one call.

Run: ``.venv/bin/python -m validation.bench.mechanism_speed [--case=ID ...] [--all] [--repeats=N]``.
The load average is printed beside (the machine is shared). Timing lives here, never in the tests.
"""

from __future__ import annotations

import os
import sys
import time
import timeit
from dataclasses import dataclass
from types import ModuleType
from typing import Any

from elastica import mechanism
from validation.case.loader import find_case_files, load_case
from validation.run.runner import run_method

DEFAULT_CASE = "segment_parallel_guided_mechanism"


@dataclass(frozen=True)
class MechanismRow:
    """One case: best CPU seconds of the whole call, its load levels, and the counts of one call."""

    case_id: str
    cpu: float
    levels: int
    residuals: int
    jacobians: int
    integrations: int
    converged: bool

    def per_level(self, count: float) -> float:
        return count / self.levels


class _Counts:
    """Counts the residual and Jacobian evaluations and the beam integrations of ``module`` while active."""

    def __init__(self, module: ModuleType) -> None:
        self.module = module
        self.counts = {"residual": 0, "jacobian": 0, "integrate_beam": 0}
        self._saved: list[tuple[Any, str, Any]] = []

    def _wrap(self, owner: Any, name: str, key: str) -> None:
        original = getattr(owner, name)

        def counted(*args: Any, **kwargs: Any) -> Any:
            self.counts[key] += 1
            return original(*args, **kwargs)

        self._saved.append((owner, name, original))
        setattr(owner, name, counted)

    def __enter__(self) -> _Counts:
        system = self.module._System
        self._wrap(system, "residual", "residual")
        if hasattr(system, "jacobian"):
            self._wrap(system, "jacobian", "jacobian")
        self._wrap(self.module, "integrate_beam", "integrate_beam")
        return self

    def __exit__(self, *exc: object) -> None:
        for owner, name, original in reversed(self._saved):
            setattr(owner, name, original)


def reaches_mechanism(case: Any, module: ModuleType = mechanism) -> bool:
    """Whether the case's elastica run calls the mechanism solver."""
    with _Counts(module) as counts:
        run_method(case, "elastica")
    return counts.counts["residual"] > 0


def time_case(case: Any, repeats: int = 9, module: ModuleType = mechanism) -> MechanismRow:
    """Best CPU time of ``repeats`` single calls after a warm-up call, and the counts of one call."""
    run_method(case, "elastica")
    with _Counts(module) as counts:
        run = run_method(case, "elastica")
    timer = timeit.Timer(lambda: run_method(case, "elastica"), timer=time.process_time)
    cpu = min(timer.repeat(number=1, repeat=repeats))
    c = counts.counts
    return MechanismRow(
        case.case.id, cpu, case.n_levels(), c["residual"], c["jacobian"], c["integrate_beam"], run.converged
    )


def cases(only: list[str], every: bool) -> list[Any]:
    found = []
    for path in find_case_files():
        case = load_case(path).case
        if case.case.id in only or (every and reaches_mechanism(case)):
            found.append(case)
    return found


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    only = [a.split("=", 1)[1] for a in args if a.startswith("--case=")]
    repeats = next((int(a.split("=", 1)[1]) for a in args if a.startswith("--repeats=")), 9)
    every = "--all" in args
    table = [time_case(case, repeats) for case in cases(only or ([] if every else [DEFAULT_CASE]), every)]
    width = max((len(r.case_id) for r in table), default=4)
    print(
        f"{'case':<{width}}  {'ms/level':>8}  {'residuals/level':>15}  {'Jacobians/level':>15}  "
        f"{'integrations/level':>18}  levels  (best of {repeats} CPU times)"
    )
    for r in sorted(table, key=lambda r: -r.cpu / r.levels):
        print(
            f"{r.case_id:<{width}}  {1e3 * r.per_level(r.cpu):8.3f}  {r.per_level(r.residuals):15.1f}  "
            f"{r.per_level(r.jacobians):15.1f}  {r.per_level(r.integrations):18.1f}  {r.levels:6d}"
            f"{'' if r.converged else '  (not converged)'}"
        )
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
