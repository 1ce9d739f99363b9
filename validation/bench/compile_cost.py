"""What numba's compile costs a first run: each primer of a report (`validation.run.parallel.schedule`
over every shipped case file: one compiled method on the smallest case file that runs it) in a fresh
interpreter with an empty ``NUMBA_CACHE_DIR`` (cold: everything compiles), then again in another fresh
interpreter on the cache the first one wrote (warm: the machine code is loaded).

Printed per primer: CPU seconds of the primer's call (``time.process_time`` of the process, so that
the other processes of a shared machine count less than in wall time; best and median of the
repeats), the CPU seconds numba spent compiling (inside its ``numba:compile`` events), the functions
it compiled with their own (exclusive) compile CPU seconds, the number of numba's own overload
implementations it compiled (``np.empty``, ``np.zeros``, ``min``, ...: one per distinct argument
types and calling function), and every compiled function of the project's modules with its number
of specialisations (``dispatcher.signatures``: more than one means the same code compiled again for
other argument types). A primer whose run failed is flagged: a compile error ends the run early and
would otherwise read as a fast compile.

Run: ``.venv/bin/python -m validation.bench.compile_cost`` (``--repeat=N``, default 3;
``--method=NAME``, repeatable, only those primers). Timing lives here, never in the tests.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from numba.core import event
from numba.core.registry import CPUDispatcher

from validation.case.loader import find_case_files, load_case
from validation.run.parallel import fewer_collections, schedule
from validation.run.runner import run_method

ROOT = Path(__file__).resolve().parents[2]
CHILD = "--child"


@dataclass
class PrimerCost:
    """One primer in one fresh interpreter: CPU seconds of the call and of numba's compile in it,
    per function compiled (count, exclusive CPU s), specialisations per project function, and the
    run's own verdict (``ok``: it returned values without an error)."""

    cpu: float
    compile_cpu: float
    functions: dict[str, tuple[int, float]] = field(default_factory=dict)
    specialisations: dict[str, int] = field(default_factory=dict)
    ok: bool = True
    message: str = ""

    @property
    def overloads(self) -> int:
        """numba's own implementations compiled (their names are ``<locals>`` closures)."""
        return sum(n for name, (n, _) in self.functions.items() if "<locals>" in name)


def _project_dispatchers() -> dict[str, CPUDispatcher]:
    """Every numba dispatcher defined in a loaded module of this project, by ``module.name``."""
    found: dict[str, CPUDispatcher] = {}
    for name, module in list(sys.modules.items()):
        path = getattr(module, "__file__", None) or ""
        if not path.startswith(str(ROOT)) or ".venv" in path:
            continue
        for attr, value in vars(module).items():
            if isinstance(value, CPUDispatcher) and value.py_func.__module__ == name:
                found[f"{name}.{attr}"] = value
    return found


def measure_here(method: str, path: Path) -> PrimerCost:
    """The primer ``method`` on ``path`` in this process, numba's compile events recorded."""
    stack: list[list] = []  # [name, start CPU s, CPU s of nested compiles]
    functions: dict[str, tuple[int, float]] = {}

    class Recorder(event.Listener):
        def on_start(self, ev):
            stack.append([ev.data["dispatcher"].py_func.__qualname__, time.process_time(), 0.0])

        def on_end(self, ev):
            name, start, nested = stack.pop()
            total = time.process_time() - start
            if stack:
                stack[-1][2] += total
            count, cpu = functions.get(name, (0, 0.0))
            functions[name] = (count + 1, cpu + total - nested)

    case = load_case(path).case
    event.register("numba:compile", Recorder())
    start = time.process_time()
    with fewer_collections():  # as `parallel.prime` runs it
        run = run_method(case, method)
    cpu = time.process_time() - start
    message = run.message or ""
    ok = bool(run.values) and not message.startswith("error")
    specialisations = {name: len(d.signatures) for name, d in _project_dispatchers().items() if d.signatures}
    return PrimerCost(
        cpu, sum(c for _, c in functions.values()), functions, specialisations, ok, "" if ok else message[:300]
    )


def measure(method: str, path: Path, cache_dir: str) -> PrimerCost:
    """``measure_here`` in a fresh interpreter whose numba cache is ``cache_dir``."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache_dir)
    out = subprocess.run(
        [sys.executable, "-m", "validation.bench.compile_cost", CHILD, method, str(path)],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env=env,
        check=True,
    )
    data = json.loads(out.stdout.strip().splitlines()[-1])
    data["functions"] = {k: tuple(v) for k, v in data["functions"].items()}
    return PrimerCost(**data)


def report_primers(methods: list[str] | None = None) -> list[tuple[str, Path]]:
    """The primers a report of every shipped case file runs (``methods``: only these)."""
    return [(m, p) for m, p in schedule(find_case_files(), None).primers if not methods or m in methods]


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if args and args[0] == CHILD:
        cost = measure_here(args[1], Path(args[2]))
        print(json.dumps(cost.__dict__))
        return 0
    repeats = next((int(a.split("=", 1)[1]) for a in args if a.startswith("--repeat=")), 3)
    only = [a.split("=", 1)[1] for a in args if a.startswith("--method=")]
    totals = []
    for method, path in report_primers(only or None):
        cold, warm = [], []
        for _ in range(repeats):
            with tempfile.TemporaryDirectory(prefix="numba-cold-") as cache_dir:
                cold.append(measure(method, path, cache_dir))
                warm.append(measure(method, path, cache_dir))
        first = cold[0]
        cpus = [c.cpu for c in cold]
        totals.append(min(cpus))
        print(
            f"primer {method} on {path.relative_to(ROOT)}"
            + (
                ""
                if all(c.ok for c in cold + warm)
                else f"  RUN FAILED: {next(c for c in cold + warm if not c.ok).message}"
            )
        )
        print(
            f"  cold: {min(cpus):6.2f} CPU s best, {statistics.median(cpus):6.2f} median of {repeats} "
            f"(numba compiling: {min(c.compile_cpu for c in cold):.2f}); "
            f"warm cache: {min(w.cpu for w in warm):.2f} CPU s, {max(len(w.functions) for w in warm)} function(s) compiled"
        )
        print(
            f"  compiled: {sum(n for name, (n, _) in first.functions.items() if '<locals>' not in name)} "
            f"project function(s), {first.overloads} of numba's overload implementations "
            f"({sum(c for name, (_, c) in first.functions.items() if '<locals>' in name):.2f} CPU s)"
        )
        for name, (count, cpu) in sorted(first.functions.items(), key=lambda kv: -kv[1][1]):
            if "<locals>" not in name:
                print(f"    {name:<28} {cpu:6.2f} CPU s (own){'' if count == 1 else f'  compiled {count} times'}")
        many = {k: v for k, v in first.specialisations.items() if v > 1}
        print(
            f"  specialisations: {len(first.specialisations)} function(s) compiled, "
            + (", ".join(f"{k}: {v}" for k, v in many.items()) if many else "each exactly once")
        )
    print(
        f"\ncold compile of every primer: {sum(totals):.2f} CPU s (best of {repeats} each); "
        f"load average {os.getloadavg()[0]:.1f}"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
