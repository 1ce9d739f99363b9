"""Fuzzing the command line: mutated case files (``validation.stress.fuzz``) run on worker processes,
each within a time bound, every failure shrunk and kept as a regression file.

``Pool`` keeps ``workers`` spawned processes (``fuzz_worker.serve``), each running one mutant at a
time through ``prbm-validate solve`` or ``run`` in its own interpreter, with its address space limited
(a huge count ends in a MemoryError, not in a machine out of memory). A mutant still running at its
time bound is killed with its worker, which is replaced; a worker that dies is an exit by signal.
The clock of a mutant starts when it is handed to a warm worker (imports and compiled code loaded);
its bound is ``timeout`` seconds, and ``S_PER_MB`` more per megabyte of a file made huge.

``run_fuzz`` runs ``count`` mutants of ``seed``. A failure (``Outcome.problem``: a traceback, a hang,
an exit other than 0, 1, 2, a message that is not one line, exit 0 with a number that is not finite)
is shrunk (``shrink``: its mutations dropped, then fields of the case deleted, one at a time while the
same problem persists) and written as a regression file: the mutated bytes under a comment header
naming the problem, the verb, the source and the mutations (``write_regression``). The files kept in
``tests/validation/fuzz_regressions/`` are replayed by ``tests/validation/test_fuzz.py``.
"""

from __future__ import annotations

import hashlib
import json
import multiprocessing
import re
import time
from collections import Counter, deque
from contextlib import suppress
from dataclasses import dataclass, field
from multiprocessing.connection import Connection, wait
from multiprocessing.process import BaseProcess
from pathlib import Path
from typing import Callable, Sequence

from tqdm import tqdm

from validation.case.loader import CASES_DIR
from validation.stress.fuzz import DELETE, LONG_LISTS, RAW_KINDS, Mutant, Mutation, generate, nodes, source_files
from validation.stress.fuzz_worker import Outcome, serve

# solved (and the first also run) by a new worker before its clock starts: the imports of both verbs and
# the compiled code of every method are loaded
WARM_UP = ("segments/slfp_alone.toml", "benchmarks/cantilever_tip_load.toml", "segments/parallel_guided_mechanism.toml")
# tables only ``run`` reads (the comparisons and their bookkeeping): a mutant touching them runs ``run``
RUN_ONLY = (
    ("references",),
    ("agreements",),
    ("case", "expected_failure"),
    ("case", "unchecked"),
    ("case", "findings"),
    ("case", "level_labels"),
)
RUN_EVERY = 20  # and every 20th mutant runs ``run`` whatever it touches
STARTUP_S = 300.0  # a worker that is not ready (imports, warm-up) within this is an error
S_PER_MB = 10.0  # the time bound grows by this per megabyte of file (tomllib reads ~1 MB/s; run reads it thrice)
MEMORY_BYTES = 6 << 30


def verb_for(mutant: Mutant, index: int) -> str:
    """``run`` for a mutant of the comparisons (and every ``RUN_EVERY``-th), else the cheaper ``solve``
    (the same loading and solving, without the comparisons and tables)."""
    touches = any(m.path[: len(prefix)] == prefix for m in mutant.mutations for prefix in RUN_ONLY)
    return "run" if touches or index % RUN_EVERY == 0 else "solve"


def seeded_mutants(count: int, seed: int, long: bool = False) -> list[Mutant]:
    """The mutants of a seed (``fuzz.generate`` over ``fuzz.source_files(long)``), each with its verb."""
    return [
        Mutant(m.source, m.mutations, verb_for(m, i)) for i, m in enumerate(generate(source_files(long), count, seed))
    ]


@dataclass
class _Worker:
    process: BaseProcess
    conn: Connection
    ready: bool = False
    task: int | None = None
    started: float = 0.0
    bound: float = 0.0


class Pool:
    """Spawned worker processes, each running one mutant at a time under a time bound (module docstring)."""

    def __init__(self, workers: int = 2, timeout: float = 20.0, memory_bytes: int = MEMORY_BYTES):
        self.timeout, self.memory_bytes = timeout, memory_bytes
        self.context = multiprocessing.get_context("spawn")
        self.warm_up = [str(CASES_DIR / name) for name in WARM_UP]
        self.workers = [self._start() for _ in range(max(1, workers))]
        self.restarts = 0

    def _start(self) -> _Worker:
        parent, child = self.context.Pipe()
        process = self.context.Process(
            target=serve, args=(child, self.memory_bytes, self.warm_up), daemon=True, name="prbm-fuzz-worker"
        )
        process.start()
        child.close()
        return _Worker(process, parent, started=time.perf_counter())

    def _replace(self, worker: _Worker) -> None:
        worker.process.kill()
        worker.process.join()
        worker.conn.close()
        self.workers[self.workers.index(worker)] = self._start()
        self.restarts += 1

    def close(self) -> None:
        """Idle workers are told to stop; one still warming up or running a mutant is killed."""
        for worker in self.workers:
            if worker.ready and worker.task is None:
                with suppress(OSError):  # a worker that died meanwhile
                    worker.conn.send(None)
                worker.process.join(timeout=5)
            if worker.process.is_alive():
                worker.process.kill()
                worker.process.join()
            worker.conn.close()

    def __enter__(self) -> "Pool":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def map(
        self, tasks: Sequence[tuple[str, Callable[[], bytes]]], progress: Callable[[Outcome], None] | None = None
    ) -> list[Outcome]:
        """The outcome of each (verb, bytes-maker) task, in order; the bytes are made when the task
        is handed out."""
        pending = deque(range(len(tasks)))
        results: list[Outcome | None] = [None] * len(tasks)
        while pending or any(w.task is not None for w in self.workers):
            for worker in self.workers:
                if worker.ready and worker.task is None and pending:
                    index = pending.popleft()
                    verb, make = tasks[index]
                    data = make()
                    worker.conn.send((verb, data))
                    worker.task, worker.started = index, time.perf_counter()
                    worker.bound = self.bound(len(data))
            self._collect(results, progress)
        done = [outcome for outcome in results if outcome is not None]
        if len(done) != len(results):
            raise RuntimeError("a fuzz task ended without an outcome")
        return done

    def bound(self, size: int) -> float:
        """The time bound of a file of ``size`` bytes: ``timeout``, and ``S_PER_MB`` more per megabyte."""
        return self.timeout + S_PER_MB * size / 1e6

    def _deadline(self, worker: _Worker) -> float:
        return worker.started + (worker.bound if worker.ready else STARTUP_S)

    def _collect(self, results: list, progress) -> None:
        """Wait for the first worker to answer or pass its bound; record what happened."""
        now = time.perf_counter()
        waiting = [w for w in self.workers if not w.ready or w.task is not None]
        until = min(self._deadline(w) for w in waiting) - now
        answered = wait([w.conn for w in waiting], timeout=max(0.0, until))
        for worker in list(self.workers):
            if worker.conn in answered:
                self._receive(worker, results, progress)
            elif worker in waiting and time.perf_counter() > self._deadline(worker):
                if not worker.ready:
                    raise RuntimeError(f"a fuzz worker was not ready within {STARTUP_S:.0f} s")
                self._finish(worker, results, Outcome(exit=None, seconds=worker.bound), progress)
                self._replace(worker)

    def _receive(self, worker: _Worker, results: list, progress) -> None:
        try:
            message = worker.conn.recv()
        except (EOFError, OSError):  # the worker died: by a signal (negative exit code) or an exit
            worker.process.join()
            if not worker.ready:
                raise RuntimeError(f"a fuzz worker died while starting (exit {worker.process.exitcode})") from None
            code = worker.process.exitcode
            self._finish(
                worker,
                results,
                Outcome(
                    exit=code if code is not None else -1,
                    seconds=time.perf_counter() - worker.started,
                    stderr="the worker process died",
                ),
                progress,
            )
            self._replace(worker)
            return
        if message == "ready":
            worker.ready = True
            return
        self._finish(worker, results, message, progress)

    @staticmethod
    def _finish(worker: _Worker, results: list, outcome: Outcome, progress) -> None:
        if worker.task is None:
            raise RuntimeError("a fuzz worker answered without a task")
        results[worker.task] = outcome
        worker.task = None
        if progress:
            progress(outcome)


# --- shrinking -----------------------------------------------------------------------------------


def _field_paths(mutant: Mutant) -> list[tuple]:
    """Fields of the mutated document a shrink may delete, largest first: top-level tables and keys,
    entries of lists (last first), then keys of tables; none on the way to or below a mutation."""
    document = mutant.document()
    touched = [m.path for m in mutant.mutations if m.kind not in RAW_KINDS]

    def related(path: tuple) -> bool:
        return any(t[: len(path)] == path or path[: len(t)] == t for t in touched)

    every = [p for p, _ in nodes(document) if not related(p)]
    return sorted(every, key=lambda p: (len(p), -p[-1] if isinstance(p[-1], int) else 0))


def _shortened(mutant: Mutant, index: int) -> Mutant:
    """The mutant with its index-th mutation's huge list cut to the shortest huge length."""
    mutation = mutant.mutations[index]
    if not isinstance(mutation.value, list):
        raise ValueError(f"mutation {index} sets no list to shorten")
    short = Mutation(mutation.kind, mutation.path, mutation.value[: LONG_LISTS[0]])
    return Mutant(mutant.source, mutant.mutations[:index] + (short,) + mutant.mutations[index + 1 :], mutant.verb)


def _huge_list(value: object) -> bool:
    """A list longer than the shortest huge length (``LONG_LISTS``): one a shrink may shorten."""
    return isinstance(value, list) and len(value) > LONG_LISTS[0]


def _candidates(mutant: Mutant, deletions: bool, rejected: set[tuple]) -> list[tuple[Mutant, tuple | None]]:
    """Smaller mutants, each with the field it deletes (None for a dropped or shortened mutation)."""
    found = [i for i, m in enumerate(mutant.mutations) if m.kind != "shrink"]
    smaller: list[tuple[Mutant, tuple | None]] = []
    if len(found) > 1:
        smaller += [
            (Mutant(mutant.source, mutant.mutations[:i] + mutant.mutations[i + 1 :], mutant.verb), None) for i in found
        ]
    smaller += [(_shortened(mutant, i), None) for i in found if _huge_list(mutant.mutations[i].value)]
    if deletions:
        smaller += [
            (Mutant(mutant.source, mutant.mutations + (Mutation("shrink", p, DELETE),), mutant.verb), p)
            for p in _field_paths(mutant)
            if p not in rejected
        ]
    return smaller


def shrink(pool: Pool, mutant: Mutant, outcome: Outcome, budget: int = 60) -> tuple[Mutant, Outcome]:
    """A smaller mutant with the same problem (and the same offending line): its mutations dropped one
    at a time (a huge list cut to the shortest huge length), then fields of the case deleted one at a
    time (not for a hang: each try costs the time bound), while the problem persists; at most ``budget``
    runs, ``len(pool.workers)`` tried at once."""
    problem, line, runs = outcome.problem, outcome.offending_line, 0
    rejected: set[tuple] = set()
    current = mutant
    while runs < budget:
        candidates = _candidates(current, not outcome.timed_out, rejected)[: budget - runs]
        found = None
        for start in range(0, len(candidates), len(pool.workers)):
            batch = candidates[start : start + len(pool.workers)]
            results = pool.map([(m.verb, m.bytes) for m, _ in batch])
            runs += len(batch)
            for (candidate, deleted), result in zip(batch, results):
                if result.problem == problem and result.offending_line == line:
                    found = (candidate, result)
                    break
                if deleted is not None:
                    rejected.add(deleted)
            if found:
                break
        if not found:
            break
        current, outcome = found
    return current, outcome


# --- regression files ----------------------------------------------------------------------------


def _ascii(text: str) -> str:
    return text.encode("ascii", "backslashreplace").decode("ascii").replace("\r", "\\r").replace("\n", "\\n")


def regression_bytes(mutant: Mutant, outcome: Outcome) -> bytes:
    """The mutated file under a comment header (ASCII) naming the failure, the verb, the source, the
    mutations and the status (``open`` until the defect is fixed)."""
    first = [re.sub(r"/\S*/", "", line) for line in outcome.stderr.strip().splitlines()[:1]]  # no folders
    root = CASES_DIR.parent
    header = [
        f"# fuzz regression: {outcome.problem}",
        f"# verb: {mutant.verb}",
        f"# source: {mutant.source.relative_to(root) if mutant.source.is_relative_to(root) else mutant.source}",
        *(f"# mutation: {m.describe()}" for m in mutant.mutations),
        (
            f"# seen: timed out at {outcome.seconds:.2f} s"
            if outcome.timed_out
            else f"# seen: exit {outcome.exit}, {outcome.seconds:.2f} s"
            + (f"; stderr: {first[0][:200]}" if first else "")
        ),
        "# status: open",
        "# defect: not described yet",
    ]
    return ("\n".join(_ascii(line) for line in header) + "\n").encode("ascii") + mutant.bytes()


def write_regression(mutant: Mutant, outcome: Outcome, folder: Path) -> Path:
    """``regression_bytes`` written as ``folder/fuzz_<hash>.toml``."""
    data = regression_bytes(mutant, outcome)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"fuzz_{hashlib.sha256(data).hexdigest()[:10]}.toml"
    path.write_bytes(data)
    return path


def read_header(data: bytes) -> dict[str, list[str]]:
    """The header of a regression file (its comment lines up to 'defect'): key -> its values
    ('mutation' repeats)."""
    header: dict[str, list[str]] = {}
    for line in data.split(b"\n"):
        if not line.startswith(b"# ") or "defect" in header:
            break
        key, _, value = line[2:].decode("ascii", errors="replace").partition(": ")
        header.setdefault(key, []).append(value)
    return header


# --- the run -------------------------------------------------------------------------------------


@dataclass
class FuzzSummary:
    """What ``run_fuzz`` did: counts by ending, the failures (each with its mutant), the files kept."""

    seed: int
    tried: int = 0
    exits: Counter = field(default_factory=Counter)
    timed_out: int = 0
    tracebacks: int = 0
    nonfinite: int = 0
    messages: int = 0
    failures: list[tuple[Mutant, Outcome]] = field(default_factory=list)
    regressions: dict[tuple, Path] = field(default_factory=dict)  # failure_key -> its shrunk regression file
    wall_time_s: float = 0.0

    def line(self) -> str:
        return (
            f"fuzz: {self.tried} mutants (seed {self.seed}): exit 0/1/2 {self.exits[0]}/{self.exits[1]}/"
            f"{self.exits[2]}, timed out {self.timed_out}, tracebacks {self.tracebacks}, exit 0 with "
            f"non-finite numbers {self.nonfinite}, messages not one line {self.messages}; "
            f"{len(self.failures)} failure(s), {len(self.regressions)} regression file(s); "
            f"{self.wall_time_s:.0f} s"
        )

    def as_dict(self) -> dict:
        return {
            "seed": self.seed,
            "tried": self.tried,
            "exits": {str(k): v for k, v in self.exits.items()},
            "timed_out": self.timed_out,
            "tracebacks": self.tracebacks,
            "nonfinite": self.nonfinite,
            "messages": self.messages,
            "wall_time_s": self.wall_time_s,
            "regressions": [p.name for p in self.regressions.values()],
            "failures": [
                {"source": m.source.name, "verb": m.verb, "mutations": m.describe(), **o.as_dict()}
                for m, o in self.failures
            ],
        }


def tally(summary: FuzzSummary, outcome: Outcome) -> None:
    summary.tried += 1
    if outcome.timed_out:
        summary.timed_out += 1
    else:
        summary.exits[outcome.exit] += 1
    problem = outcome.problem
    summary.tracebacks += problem.startswith("traceback")
    summary.nonfinite += problem.startswith("exit 0 with")
    summary.messages += problem == "a message that is not one line"


def failure_key(mutant: Mutant, outcome: Outcome) -> tuple:
    """Failures alike (one of each is shrunk): a traceback of the same exception at the same place, a
    message broken at the same line of code; a hang or a number that is not finite from the same kinds
    of mutation at the same fields (list indices left out)."""
    if outcome.problem.startswith("traceback"):
        return (outcome.problem,)
    if outcome.offending_line:
        return outcome.problem, outcome.offending_line
    where = tuple((m.kind, tuple("*" if isinstance(p, int) else p for p in m.path)) for m in mutant.mutations)
    return outcome.problem, where


def run_fuzz(
    out: Path,
    count: int,
    seed: int,
    *,
    long: bool = False,
    workers: int = 2,
    timeout: float = 20.0,
    progress: bool = False,
    shrink_budget: int = 60,
    max_shrunk: int = 40,
) -> FuzzSummary:
    """``count`` mutants of ``seed`` (of every shipped case with ``long``, else of ``fuzz.SOURCES``),
    each within ``timeout`` seconds; failures shrunk into ``out/fuzz_regressions``, one per
    ``failure_key`` (at most ``max_shrunk``); ``out/fuzz.json`` has the counts and every failure."""
    started = time.perf_counter()
    mutants = seeded_mutants(count, seed, long=long)
    summary = FuzzSummary(seed=seed)
    bar = tqdm(total=count, desc="fuzz", unit="mutant", disable=not progress)

    def advance(outcome: Outcome) -> None:
        bar.update()

    with Pool(workers=workers, timeout=timeout) as pool:
        outcomes = pool.map([(m.verb, m.bytes) for m in mutants], progress=advance)
        bar.close()
        for mutant, outcome in zip(mutants, outcomes):
            tally(summary, outcome)
            if not outcome.problem:
                continue
            summary.failures.append((mutant, outcome))
            key = failure_key(mutant, outcome)
            if key in summary.regressions or len(summary.regressions) >= max_shrunk:
                continue
            small, small_outcome = shrink(pool, mutant, outcome, budget=shrink_budget)
            summary.regressions[key] = write_regression(small, small_outcome, out / "fuzz_regressions")
    summary.wall_time_s = time.perf_counter() - started
    out.mkdir(parents=True, exist_ok=True)
    (out / "fuzz.json").write_text(json.dumps(summary.as_dict(), indent=1))
    return summary


def fuzz_checks(
    out: Path, count: int, seed: int, *, long: bool = False, workers: int | None = None, timeout: float = 20.0
) -> list[tuple[str, str, bool, str]]:
    """``run_fuzz`` as the stress command's checks (category, name, passed, detail): one for the whole
    run, and one per kind of failure (``failure_key``) naming an example and its regression file."""
    summary = run_fuzz(out, count, seed, long=long, workers=workers or 2, timeout=timeout, progress=long)
    print(summary.line())
    rows = [
        (
            "fuzz",
            f"{summary.tried} mutated case files: exit 0, 1 or 2 within {timeout:g} s, one-line "
            "messages, no traceback, finite numbers on exit 0",
            not summary.failures,
            summary.line(),
        )
    ]
    alike: dict[tuple, list[tuple[Mutant, Outcome]]] = {}
    for mutant, outcome in summary.failures:
        alike.setdefault(failure_key(mutant, outcome), []).append((mutant, outcome))
    for key, failures in alike.items():
        mutant, outcome = failures[0]
        kept = summary.regressions.get(key)
        said = outcome.stderr.strip().splitlines()[:1]
        rows.append(
            (
                "fuzz",
                f"{outcome.problem}: {'; '.join(m.describe() for m in mutant.mutations)[:160]}",
                False,
                f"{len(failures)} mutant(s), e.g. {mutant.verb} of {mutant.source.name}"
                + (f" ({said[0][:200]})" if said else "")
                + (f"; shrunk into fuzz_regressions/{kept.name}" if kept else ""),
            )
        )
    return rows
