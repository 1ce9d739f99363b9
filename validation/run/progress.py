"""The progress of a run of many cases, on stderr: a bar that names the case just finished, a notice
while the numba kernels compile, and an expected time left only once it means something.

The bar counts finished case files; its postfix is the id of the case that just finished (the file's
name for a file that could not be used). The time left is shown once ``SETTLED`` cases have finished
since the kernels were compiled (or since the start, when nothing compiles): before that tqdm's rate
would divide the cases left by one case's time plus the compile, an hour for a two-minute run.
"""

from __future__ import annotations

import math
import sys

from tqdm import tqdm
from tqdm.std import EMA

from validation.run.parallel import CompileWatch, PathRun

# seconds a method's numba kernels take to compile with a cold cache, one process on an idle core
# (as ``validation.bench.compile_cost`` measures them: the FEM's load-control, warm-start and
# banded-solver kernels, the elastica's integrator)
COMPILE_SECONDS = {"fem": 5.0, "opensees": 5.0, "elastica": 6.0}
KERNEL_NAMES = {"fem": "FEM", "opensees": "FEM", "elastica": "elastica"}
SETTLED = 2
WITHOUT_ETA = "{l_bar}{bar}| {n_fmt}/{total_fmt} [{elapsed}{postfix}]"
WITH_ETA = "{l_bar}{bar}| {n_fmt}/{total_fmt} [{elapsed}<{remaining}{postfix}]"


def compile_notice(methods: tuple[str, ...], jobs: int = 1) -> str:
    """'compiling the elastica and FEM kernels (once per machine, ~10 s)': the kernels of ``methods``
    (the FEM's once, though the OpenSees peer's mesh uses them too), and their expected time on ``jobs``
    processes (the longest, or their sum shared out, whichever is longer), rounded up to 5 s."""
    methods = tuple(sorted(methods, key=lambda m: (-COMPILE_SECONDS.get(m, 10.0), m)))  # longest first
    names = list(dict.fromkeys(KERNEL_NAMES.get(m, m) for m in methods))
    words = " and ".join(names) if len(names) <= 2 else ", ".join(names[:-1]) + " and " + names[-1]
    kernels = {KERNEL_NAMES.get(m, m): COMPILE_SECONDS.get(m, 10.0) for m in methods}  # the FEM's once
    seconds = list(kernels.values())
    estimate = max(max(seconds, default=0.0), sum(seconds) / max(1, jobs))
    return f"compiling the {words} kernels (once per machine, ~{5 * math.ceil(estimate / 5):.0f} s)"


class CaseProgress:
    """A tqdm bar over case files (module docstring); ``watch`` is the ``CompileWatch`` to hand to
    ``run_paths``. The compile notice is printed with or without the bar: it explains a wait."""

    def __init__(self, total: int, enabled: bool = True, jobs: int = 1, stream=None):
        self.stream = stream or sys.stderr
        self.jobs = jobs
        self.bar = tqdm(
            total=total, unit="case", disable=not enabled, leave=False, file=self.stream, bar_format=WITHOUT_ETA
        )
        self.since_clock = 0  # cases finished since the rate's clock (re)started
        self.compiling = False
        self.watch = CompileWatch(compiling=self._compiling, compiled=self._compiled)

    def advance(self, run: PathRun) -> None:
        """One case file finished: its id in the postfix, the time left once the rate is settled."""
        self.since_clock += 1
        if not self.compiling and self.since_clock >= SETTLED:
            self.bar.bar_format = WITH_ETA
        self.bar.set_postfix_str(run.result.loaded.id if run.result is not None else run.path.stem, refresh=False)
        self.bar.update()

    def _compiling(self, methods: tuple[str, ...]) -> None:
        self.compiling = True
        line = compile_notice(methods, self.jobs)
        if self.bar.disable:
            print(line, file=self.stream, flush=True)
        else:
            self.bar.write(line, file=self.stream)

    def _compiled(self) -> None:
        """The primers are done: the rate starts again from here, without the compile in it."""
        self.compiling, self.since_clock = False, 0
        self.bar.bar_format = WITHOUT_ETA
        if not self.bar.disable:
            self.bar.last_print_n, self.bar.last_print_t = self.bar.n, self.bar._time()
            self.bar._ema_dn, self.bar._ema_dt = EMA(self.bar.smoothing), EMA(self.bar.smoothing)
            self.bar.refresh()

    def close(self) -> None:
        self.bar.close()
