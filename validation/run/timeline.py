"""Where a long run's time goes: one ``Timed`` record per piece of work (a numba primer, a case, a
method of a case, a page, an extra task such as the chapter-4 domain study, a step of the report in
the main process), with its wall and CPU seconds and the process it ran in, and ``breakdown``, the
text the report prints and writes beside ``timing.csv``.

Wall time is ``time.perf_counter`` around the work; CPU time is ``time.process_time`` of the process
that did it (so a worker's CPU while it waited for nothing but the CPU shows as wall > CPU: the load
of the machine). A method's time is its run's own ``wall_time`` (the run cache keeps no CPU time);
its CPU is not measured apart from its case's.
"""

from __future__ import annotations

import csv
import io
import math
import os
import time
from contextlib import contextmanager
from dataclasses import dataclass, field, fields
from typing import Iterator


@dataclass
class Timed:
    """One piece of work: ``kind`` (compile, case, method, page, extra, main), its ``name``, wall and
    CPU seconds, its start (seconds since the epoch, comparable between processes) and process id."""

    kind: str
    name: str
    wall: float
    cpu: float = math.nan
    start: float = math.nan
    pid: int = 0

    @property
    def end(self) -> float:
        return self.start + self.wall


@dataclass
class Stopwatch:
    """Filled by ``timed`` when its block ends."""

    record: Timed | None = None
    into: list[Timed] = field(default_factory=list)

    def ended(self) -> Timed:
        """The block's ``Timed``, once it has ended."""
        if self.record is None:
            raise RuntimeError("the timed block has not ended")
        return self.record


@contextmanager
def timed(kind: str, name: str, into: list[Timed] | None = None) -> Iterator[Stopwatch]:
    """Time the block: its ``Timed`` is ``watch.record`` afterwards (and appended to ``into``)."""
    watch = Stopwatch(into=into if into is not None else [])
    start, wall, cpu = time.time(), time.perf_counter(), time.process_time()
    try:
        yield watch
    finally:
        watch.record = Timed(kind, name, time.perf_counter() - wall, time.process_time() - cpu, start, os.getpid())
        watch.into.append(watch.record)


_command_start = math.nan  # ``time.perf_counter`` when the command's first line ran (`mark_command_start`)


def mark_command_start(at: float) -> None:
    """Note when the command began (``time.perf_counter`` at the first line of ``prbm-validate``, before
    its imports; at its own call for a later ``main()`` of the same process), for `command_age`."""
    global _command_start
    _command_start = at


def command_age() -> float:
    """Seconds since the command began: its imports and argument parsing included (what the person who
    typed it has waited, less the interpreter's own start-up of a few tens of milliseconds); NaN when no
    command marked its start (the library called from Python)."""
    return time.perf_counter() - _command_start


def csv_text(records: list[Timed]) -> str:
    """The records as CSV (header: the ``Timed`` fields), longest first."""
    names = [f.name for f in fields(Timed)]
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")  # quotes a name with a comma ("tables (results.csv, ...)")
    writer.writerow(names)
    for r in sorted(records, key=lambda r: -r.wall):
        writer.writerow(
            [f"{getattr(r, n):.4f}" if isinstance(getattr(r, n), float) else str(getattr(r, n)) for n in names]
        )
    return text.getvalue()


def _sum(records: list[Timed]) -> tuple[float, float]:
    return sum(r.wall for r in records), sum(r.cpu for r in records if not math.isnan(r.cpu))


def _line(label: str, records: list[Timed]) -> str:
    wall, cpu = _sum(records)
    count = f" ({len(records)})" if len(records) > 1 else ""
    return f"  {label + count:<44} {wall:8.1f} s wall {cpu:8.1f} s CPU"


def _pool_use(records: list[Timed], jobs: int) -> str:
    """How busy the workers were between the first and the last piece of pooled work."""
    pooled = [r for r in records if r.kind in ("compile", "case", "page", "extra") and not math.isnan(r.start)]
    if not pooled or jobs < 1:
        return ""
    span = max(r.end for r in pooled) - min(r.start for r in pooled)
    busy = sum(r.wall for r in pooled)
    return (
        f"  workers busy {busy:.1f} s of {jobs} x {span:.1f} s = {100 * busy / max(jobs * span, 1e-9):.0f} % "
        f"({len({r.pid for r in pooled})} process(es))"
    )


def critical_path(records: list[Timed]) -> str:
    """What the run waited for: the worker that finished last (its compile, cases, pages and extra
    tasks, and the time it sat idle from the first pooled start to its end), then the main process's
    steps after the pool; empty without pooled work."""
    pooled = [r for r in records if r.kind in ("compile", "case", "page", "extra") and not math.isnan(r.start)]
    if not pooled:
        return ""
    first = min(r.start for r in pooled)
    last_pid = max(pooled, key=lambda r: r.end).pid
    mine = [r for r in pooled if r.pid == last_pid]
    span = max(r.end for r in mine) - first
    parts = {kind: sum(r.wall for r in mine if r.kind == kind) for kind in ("compile", "case", "page", "extra")}
    idle = span - sum(parts.values())
    main = sum(r.wall for r in records if r.kind == "main")
    words = " + ".join(f"{kind} {wall:.1f} s" for kind, wall in parts.items() if wall > 0)
    return (
        f"  critical path: the last worker to finish {span:.1f} s ({words}, idle {max(idle, 0.0):.1f} s), then "
        f"the main process's steps {main:.1f} s"
    )


def breakdown(records: list[Timed], jobs: int, top: int = 8) -> str:
    """The text summary: compile per method, cases (and their methods per method), pages, extra tasks,
    the main process's steps, the slowest cases and pages, how busy the workers were and the critical path."""
    by_kind: dict[str, list[Timed]] = {}
    for r in records:
        by_kind.setdefault(r.kind, []).append(r)
    lines = ["time breakdown (wall and CPU seconds of each piece of work; pooled work overlaps):"]
    for r in sorted(by_kind.get("compile", []), key=lambda r: -r.wall):
        lines.append(_line(f"numba compile (primer) {r.name}", [r]))
    methods: dict[str, list[Timed]] = {}
    for r in by_kind.get("method", []):
        methods.setdefault(r.name.rsplit(":", 1)[-1], []).append(r)
    lines.append(_line("cases (run, incl. findings' re-runs)", by_kind.get("case", [])))
    for method, part in sorted(methods.items(), key=lambda kv: -_sum(kv[1])[0]):
        wall, _ = _sum(part)
        lines.append(f"    method {method + f' ({len(part)})':<36} {wall:8.1f} s wall")
    lines.append(_line("pages (plots, ParaView files, render)", by_kind.get("page", [])))
    for r in by_kind.get("extra", []):
        lines.append(_line(r.name, [r]))
    for r in by_kind.get("main", []):
        lines.append(_line(f"main: {r.name}", [r]))
    for kind in ("case", "page"):
        slow = sorted(by_kind.get(kind, []), key=lambda r: -r.wall)[:top]
        if slow:
            lines.append(f"  slowest {kind}s: " + ", ".join(f"{r.name} {r.wall:.1f}" for r in slow))
    slow = sorted(by_kind.get("method", []), key=lambda r: -r.wall)[:top]
    if slow:
        lines.append("  slowest methods: " + ", ".join(f"{r.name} {r.wall:.1f}" for r in slow))
    use = _pool_use(records, jobs)
    if use:
        lines.append(use)
    path = critical_path(records)
    if path:
        lines.append(path)
    return "\n".join(lines)
