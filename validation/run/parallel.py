"""Many case files run on a pool of worker processes, scheduled so that no core idles and no compiled
code is compiled twice.

``run_paths`` runs every case file (``case_run.run_case``), in this process when ``jobs`` is 1, else on
``jobs`` worker processes:

1. the methods whose code is compiled with numba (``compiled_method``: the adapter's sources, as the
   run cache walks them, import numba) are compiled first, each by one worker ("primer": that method
   alone on the smallest case file that will run it (not in the run cache), its run discarded so that
   no case's recorded time includes the compile), so that two workers never spend the same time
   compiling the same kernels; numba's on-disk cache (``cache=True``) then serves every other process;
2. while the primers compile, the other workers take the extra tasks (``extra``, e.g. the report's
   chapter-4 domain study) and the cases that need no compiled method, longest first (``estimate``);
   an extra task that runs compiled methods (its ``compiled``, e.g. the report's coarse atlas: the
   elastica's) waits for their primers, and then goes before the cases not yet started;
3. each case that needs compiled methods as soon as their primers are done, longest first.

Work is handed to the pool as workers free up (``WorkQueue``: at most one task queued beyond one a
worker), so that the order above holds for work whose primers finish late, rather than the pool's
first-come order of everything submitted at the start.

``after(result)`` (a picklable callable, e.g. the report's page writer) runs in the worker right after
its case, so the report's pages are drawn while other cases still run. Results come back in the
order of ``paths``; a case file that cannot be used comes back as its error line.

The collectors leave alone what this process holds when the pool starts and, in a worker, what its
primer compiled (``gc.freeze``): they live as long as the pool, and walking them in each full
collection costs more than the cases' own objects do.

With ``jobs`` = 1 the primers run first too, in this process, so that in neither path does a case
report numba's compile as its method's time. Every primer, case, method run, ``after`` and extra
task is timed (``validation.run.timeline``) into the ``timeline`` list given.

``watch`` (a ``CompileWatch``) is told, once, that the primers are compiling when they have taken more
than ``CompileWatch.after`` seconds (numba's on-disk cache is cold: the first run on a machine, or after
an edit of a kernel), and when every primer is done, so that a progress bar can say why it waits and
start its rate after the compile.
"""

from __future__ import annotations

import gc
import re
import threading
import time
import tomllib
from collections.abc import Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any, Callable, Sequence

from validation.case.loader import CaseError, load_case
from validation.run import cache
from validation.run.case_run import run_case
from validation.run.runner import CaseResult, run_method
from validation.run.timeline import Timed, timed


@dataclass
class PathRun:
    """One case file's run: its result (or the error line of a file that cannot be used) and what
    ``after`` returned for it."""

    path: Path
    result: CaseResult | None = None
    error: str | None = None
    after: Any = None
    times: list[Timed] = field(default_factory=list)


@dataclass
class Schedule:
    """The order of the work: primers (method, path), cases that need no compiled method, the rest
    with the compiled methods each waits for; each list longest first (``estimate``)."""

    primers: list[tuple[str, Path]] = field(default_factory=list)
    free: list[Path] = field(default_factory=list)
    compiled: list[Path] = field(default_factory=list)
    waits_for: dict[Path, frozenset[str]] = field(default_factory=dict)


# seconds of primers before a caller hears that they compile (a warm numba cache loads in less)
NOTICE_AFTER = 3.0
NUMBA_IMPORT = re.compile(r"^\s*(from|import)\s+numba\b", re.MULTILINE)


@lru_cache(maxsize=None)
def compiled_method(method: str) -> bool:
    """True when the method's code (its adapter and everything it imports) imports numba."""
    return any(NUMBA_IMPORT.search(path.read_text(encoding="utf-8")) for path in cache.source_files(method))


@dataclass(frozen=True)
class CaseFile:
    """What the schedule reads of a case file without validating it: its id (the file's stem when it
    has none), text and methods with their options (a bad file: none; its task reports the error)."""

    path: Path
    id: str
    text: str = ""
    methods: dict[str, Any] = field(default_factory=dict)

    @classmethod
    def read(cls, path: Path) -> CaseFile:
        try:
            text = Path(path).read_text(encoding="utf-8")
            data = tomllib.loads(text)
            methods = dict(data.get("methods", {}))
            return cls(Path(path), str(data.get("case", {}).get("id", Path(path).stem)), text, methods)
        except (OSError, tomllib.TOMLDecodeError, AttributeError, TypeError, ValueError):
            return cls(Path(path), Path(path).stem)

    def to_run(self, methods: list[str] | None, use_cache: bool) -> list[str]:
        """The methods that will run (asked for, and not in the run cache when it is used)."""
        return [
            m
            for m, options in self.methods.items()
            if (not methods or m in methods)
            and not (use_cache and cache.has(cache.run_key(self.text, m, dict(options or {}))))
        ]


def estimate(case: CaseFile, costs: dict[str, float] | None = None) -> float:
    """The expected seconds of a case: its time in ``costs`` (e.g. the last report's timing), else its
    file's size in kB (a longer file holds more levels, outputs and references) times the number of
    its methods; only the order matters."""
    if costs and case.id in costs:
        return costs[case.id]
    return len(case.text) / 1000.0 * max(1, len(case.methods))


def schedule(
    paths: list[Path], methods: list[str] | None, use_cache: bool = False, costs: dict[str, float] | None = None
) -> Schedule:
    """Primers for the compiled methods the run will run, on the smallest case file that runs each;
    then the cases without and with them, each list longest first."""
    plan = Schedule()
    smallest: dict[str, tuple[int, Path]] = {}
    files = sorted((CaseFile.read(p) for p in paths), key=lambda c: -estimate(c, costs))
    for case in files:
        compiled = frozenset(m for m in case.to_run(methods, use_cache) if compiled_method(m))
        (plan.compiled if compiled else plan.free).append(case.path)
        if compiled:
            plan.waits_for[case.path] = compiled
        for method in compiled:
            if method not in smallest or len(case.text) < smallest[method][0]:
                smallest[method] = (len(case.text), case.path)
    plan.primers = sorted(((method, path) for method, (_, path) in smallest.items()), key=lambda mp: mp[0])
    return plan


# Python's cyclic garbage collector's first-generation threshold while a primer runs: numba's compiler
# allocates millions of short-lived objects, and at the default 700 the collector walks them for about a
# tenth of a cold compile
PRIMER_GC_THRESHOLD = 100_000


@contextmanager
def fewer_collections() -> Iterator[None]:
    """The collector's first threshold raised to PRIMER_GC_THRESHOLD inside, restored after."""
    before = gc.get_threshold()
    gc.set_threshold(PRIMER_GC_THRESHOLD, *before[1:])
    try:
        yield
    finally:
        gc.set_threshold(*before)


@contextmanager
def frozen_heap() -> Iterator[None]:
    """The objects this process holds on entry left out of the cyclic collector's walks inside
    (``gc.freeze``), and given back on exit (``gc.unfreeze``); a process whose objects some other code
    froze already is left as it is."""
    if gc.get_freeze_count():
        yield
        return
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()


def prime_in_worker(path: Path, method: str) -> Timed:
    """``prime`` in a pool worker, then every object the worker holds (numba's compiled code and type
    caches, and the compile's garbage alike) left out of the cyclic collector's walks for the rest of the
    worker's life (``gc.freeze``): the compile leaves hundreds of thousands of objects behind, which
    every later full collection of the worker would walk again, while the garbage among them is a few
    megabytes, held until the worker ends with the run."""
    record = prime(path, method)
    gc.freeze()
    return record


def prime(path: Path, method: str) -> Timed:
    """Compile ``method``'s numba code by running it once on ``path``; the run is not kept (its wall
    time is mostly the compile), and a case file that cannot be used is reported by its own run.
    Returns the primer's time."""
    with timed("compile", method) as watch, fewer_collections():
        try:
            run_method(load_case(path).case, method)
        except CaseError:
            pass
    return watch.ended()


@dataclass
class CompileWatch:
    """What a caller is told about the primers: ``compiling(methods)`` once, when they have run longer
    than ``after`` seconds (a warm numba cache loads in less), and ``compiled()`` once they are all done."""

    compiling: Callable[[tuple[str, ...]], None] = lambda methods: None
    compiled: Callable[[], None] = lambda: None
    after: float = field(default_factory=lambda: NOTICE_AFTER)


def _serial_primers(plan: Schedule, watch: CompileWatch) -> list[Timed]:
    """The primers in this process, ``watch.compiling`` called from a timer if they take long."""
    methods = tuple(method for method, _ in plan.primers)
    timer = threading.Timer(watch.after, watch.compiling, args=(methods,))
    timer.daemon = True
    if methods:
        timer.start()
    try:
        return [prime(path, method) for method, path in plan.primers]
    finally:
        timer.cancel()
        if methods:
            watch.compiled()


def run_extra(task: Callable[[], Any]) -> Timed:
    """An extra task, timed under its ``label`` (else its type's name)."""
    with timed("extra", getattr(task, "label", type(task).__name__)) as watch:
        task()
    return watch.ended()


def run_path(
    path: Path, methods: list[str] | None, use_cache: bool, after: Callable[[CaseResult], Any] | None = None
) -> PathRun:
    """One case file: load, run, then ``after`` on its result; each step timed."""
    try:
        loaded = load_case(path)
    except CaseError as exc:
        return PathRun(Path(path), error=str(exc))
    times: list[Timed] = []
    with timed("case", loaded.id, times) as watch:
        result = run_case(loaded, methods, use_cache)
    times += [
        Timed("method", f"{loaded.id}:{method}", run.wall_time, start=watch.ended().start, pid=watch.ended().pid)
        for method, run in result.runs.items()
        if not result.cached.get(method)
    ]
    value = None
    if after is not None:
        with timed("page", loaded.id, times):
            value = after(result)
    return PathRun(Path(path), result, after=value, times=times)


def run_paths(
    paths: list[Path],
    methods: list[str] | None = None,
    use_cache: bool = True,
    jobs: int = 1,
    after: Callable[[CaseResult], Any] | None = None,
    extra: Sequence[Callable[[], Any]] = (),
    progress: Callable[[PathRun], None] | None = None,
    timeline: list[Timed] | None = None,
    costs: dict[str, float] | None = None,
    watch: CompileWatch | None = None,
) -> list[PathRun]:
    """Every case file run (module docstring); ``extra`` tasks run beside them; returns the runs in the
    order of ``paths``. Every piece of work's time is appended to ``timeline``; ``costs`` (case id ->
    seconds, e.g. from the last run) orders the cases longest first; ``watch`` hears about the primers."""
    paths = [Path(p) for p in paths]
    timeline = timeline if timeline is not None else []
    done: dict[Path, PathRun] = {}

    def collect(value: PathRun | Timed) -> None:
        if isinstance(value, Timed):
            timeline.append(value)
            return
        done[value.path] = value
        timeline.extend(value.times)
        if progress is not None:
            progress(value)

    plan = schedule(paths, methods, use_cache, costs)
    watch = watch or CompileWatch()
    if jobs <= 1 or len(paths) + len(extra) <= 1:
        timeline += _serial_primers(plan, watch)
        timeline += [run_extra(task) for task in extra]
        for path in paths:
            collect(run_path(path, methods, use_cache, after))
    else:
        _run_pool(plan, jobs, extra, lambda path: (run_path, path, methods, use_cache, after), collect, watch)
    return [done[p] for p in paths]


QUEUED_BEYOND_WORKERS = 1  # tasks handed to the pool beyond one a worker: a worker that finishes finds the next


@dataclass
class WorkQueue:
    """The work of a pool not yet handed to it, in the order ``run_paths`` gives it out (module
    docstring): the extra tasks, each once the primers of the compiled methods it runs (its
    ``compiled``, none when it has no such attribute) are done (a method without a primer in this run
    has nothing to wait for); then the free cases; then each compiled case once its primers are done.
    Each list keeps its own order (the cases longest first)."""

    plan: Schedule
    extra: list[Callable[[], Any]]
    primed: frozenset[str]  # the methods with a primer in this run

    def __post_init__(self) -> None:
        self.free = list(self.plan.free)
        self.compiled = list(self.plan.compiled)

    def waits_for(self, task: Callable[[], Any]) -> frozenset[str]:
        """The primers an extra task waits for."""
        return frozenset(getattr(task, "compiled", ())) & self.primed

    def next(self, ready: set[str]) -> Callable[[], Any] | Path | None:
        """The next piece of work that can start with the primers of ``ready`` done (an extra task, or a
        case file), taken off the queue; None when nothing can start yet (or nothing is left)."""
        for task in self.extra:
            if self.waits_for(task) <= ready:
                self.extra.remove(task)
                return task
        if self.free:
            return self.free.pop(0)
        for path in self.compiled:
            if self.plan.waits_for[path] <= ready:
                self.compiled.remove(path)
                return path
        return None


def _run_pool(plan: Schedule, jobs: int, extra, task_of: Callable[[Path], tuple], collect, watch: CompileWatch) -> None:
    """The parallel run: primers first, then the work of ``WorkQueue`` handed over as workers free up;
    ``watch`` told of the primers."""
    # this process's modules and objects outlive the pool: neither this process's collector nor a
    # worker's (which inherits them frozen, or freezes what it starts with) walks them again and again
    with frozen_heap(), ProcessPoolExecutor(max_workers=jobs, initializer=gc.freeze) as pool:
        primers: dict[Future, str] = {
            pool.submit(prime_in_worker, path, method): method for method, path in plan.primers
        }
        pending: set[Future] = set(primers)
        queue = WorkQueue(plan, list(extra), frozenset(primers.values()))
        ready: set[str] = set()

        def hand_over() -> None:
            while len(pending) < jobs + QUEUED_BEYOND_WORKERS:
                work = queue.next(ready)
                if work is None:
                    return
                pending.add(pool.submit(*task_of(work)) if isinstance(work, Path) else pool.submit(run_extra, work))

        hand_over()
        told, started = not primers, time.perf_counter()
        while pending:
            timeout = None if told else max(0.0, watch.after - (time.perf_counter() - started))
            finished, pending = wait(pending, timeout=timeout, return_when=FIRST_COMPLETED)
            if not told and len(ready) < len(primers) and time.perf_counter() - started >= watch.after:
                told = True
                watch.compiling(tuple(m for f, m in primers.items() if not f.done()))
            for future in finished:
                collect(future.result())
                ready |= {primers[future]} if future in primers else set()
                if future in primers and len(ready) == len(primers):
                    told = True
                    watch.compiled()
            hand_over()
