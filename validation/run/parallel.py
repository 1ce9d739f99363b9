"""Many case files run on a pool of worker processes, scheduled so that no core idles and no compiled
code is compiled twice.

``run_paths`` runs every case file (``runner.run_case``), in this process when ``jobs`` is 1, else on
``jobs`` worker processes:

1. the methods whose code is compiled with numba (``compiled_method``: the adapter's sources, as the
   run cache walks them, import numba) are compiled first, each by one worker ("primer": that method
   alone on the smallest case file that asks for it, its run discarded so that no case's recorded
   time includes the compile), so that two workers never spend the same ~10 s compiling the same
   kernels; numba's on-disk cache (``cache=True``) then serves every other process;
2. while the primers compile, the other workers take the extra tasks (``extra``, e.g. the report's
   chapter-4 domain study) and the cases that need no compiled method;
3. once every primer is done, the cases that need a compiled method.

``after(result)`` (a picklable callable, e.g. the report's page writer) runs in the worker right after
its case, so the report's pages are drawn while other cases still run. Results come back in the
order of ``paths``; a case file that cannot be used comes back as its error line.
"""
from __future__ import annotations

import re
import tomllib
from concurrent.futures import Future, ProcessPoolExecutor, as_completed, wait
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any, Callable

from validation.case.loader import CaseError, load_case
from validation.run import cache
from validation.run.runner import CaseResult, run_case, run_method


@dataclass
class PathRun:
    """One case file's run: its result (or the error line of a file that cannot be used) and what
    ``after`` returned for it."""

    path: Path
    result: CaseResult | None = None
    error: str | None = None
    after: Any = None


@dataclass
class Schedule:
    """The order of the work: primers (method, path), cases that need no compiled method, the rest."""

    primers: list[tuple[str, Path]] = field(default_factory=list)
    free: list[Path] = field(default_factory=list)
    compiled: list[Path] = field(default_factory=list)


NUMBA_IMPORT = re.compile(r"^\s*(from|import)\s+numba\b", re.MULTILINE)


@lru_cache(maxsize=None)
def compiled_method(method: str) -> bool:
    """True when the method's code (its adapter and everything it imports) imports numba."""
    return any(NUMBA_IMPORT.search(path.read_text(encoding="utf-8")) for path in cache.source_files(method))


def _methods_of(path: Path) -> list[str]:
    """The methods a case file asks for, read without validating it (a bad file: none; its task
    reports the error)."""
    try:
        return list(tomllib.loads(Path(path).read_text(encoding="utf-8")).get("methods", {}))
    except (OSError, tomllib.TOMLDecodeError, AttributeError):
        return []


def schedule(paths: list[Path], methods: list[str] | None) -> Schedule:
    """Primers for the compiled methods the run needs, then the cases without and with them."""
    plan = Schedule()
    smallest: dict[str, tuple[int, Path]] = {}
    for path in paths:
        wanted = [m for m in _methods_of(path) if not methods or m in methods]
        compiled = [m for m in wanted if compiled_method(m)]
        (plan.compiled if compiled else plan.free).append(path)
        size = Path(path).stat().st_size if compiled else 0
        for method in compiled:
            if method not in smallest or size < smallest[method][0]:
                smallest[method] = (size, path)
    plan.primers = [(method, path) for method, (_, path) in smallest.items()]
    return plan


def prime(path: Path, method: str) -> None:
    """Compile ``method``'s numba code by running it once on ``path``; the run is not kept (its wall
    time is mostly the compile), and a case file that cannot be used is reported by its own run."""
    try:
        loaded = load_case(path)
    except CaseError:
        return
    run_method(loaded.case, method)


def run_path(path: Path, methods: list[str] | None, use_cache: bool,
             after: Callable[[CaseResult], Any] | None = None) -> PathRun:
    """One case file: load, run, then ``after`` on its result."""
    try:
        loaded = load_case(path)
    except CaseError as exc:
        return PathRun(Path(path), error=str(exc))
    result = run_case(loaded, methods, use_cache)
    return PathRun(Path(path), result, after=after(result) if after is not None else None)


def run_paths(paths: list[Path], methods: list[str] | None = None, use_cache: bool = True, jobs: int = 1,
              after: Callable[[CaseResult], Any] | None = None, extra: list[Callable[[], Any]] = (),
              progress: Callable[[PathRun], None] | None = None) -> list[PathRun]:
    """Every case file run (module docstring); ``extra`` tasks run beside them; returns the runs in the
    order of ``paths``."""
    paths = [Path(p) for p in paths]
    done: dict[Path, PathRun] = {}

    def collect(run: PathRun) -> None:
        done[run.path] = run
        if progress is not None:
            progress(run)

    if jobs <= 1 or len(paths) + len(extra) <= 1:
        for task in extra:
            task()
        for path in paths:
            collect(run_path(path, methods, use_cache, after))
        return [done[p] for p in paths]
    plan = schedule(paths, methods)
    with ProcessPoolExecutor(max_workers=jobs) as pool:
        primers = [pool.submit(prime, path, method) for method, path in plan.primers]
        futures: list[Future] = [pool.submit(task) for task in extra]
        futures += [pool.submit(run_path, path, methods, use_cache, after) for path in plan.free]
        wait(primers)
        futures += [pool.submit(run_path, path, methods, use_cache, after) for path in plan.compiled]
        for future in as_completed(futures):
            value = future.result()
            if isinstance(value, PathRun):
                collect(value)
    return [done[p] for p in paths]
