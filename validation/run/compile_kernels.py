"""Compile the numba kernels of every compiled method the shipped case files run, once, into numba's
on-disk cache (``__pycache__`` beside each kernel's source), and say what it took.

A process that finds a kernel in the cache loads its machine code instead of compiling it, so a job that
starts several processes at once (the suite's two pytest-xdist workers, a report's pool) compiles each
kernel once when this ran before it, rather than once per process that reaches it first. `.ci/run`
runs it beside the type checker, so that the suite pays no compile. It runs the report's primers
(`validation.run.parallel.schedule`: each compiled method on the smallest case file that runs it), one
after the other in this process; a warm cache makes it a load of a second or two.

Run: ``python -m validation.run.compile_kernels``.
"""

from __future__ import annotations

import time

from validation.case.loader import find_case_files
from validation.run.parallel import prime, schedule


def main() -> int:
    """Run every primer; print each one's method, case file and CPU seconds."""
    start = time.process_time()
    for method, path in schedule(find_case_files(), None).primers:
        began = time.process_time()
        prime(path, method)
        print(f"numba kernels of {method} (primer {path.name}): {time.process_time() - began:.1f} CPU s", flush=True)
    print(f"numba kernels ready in the cache: {time.process_time() - start:.1f} CPU s", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
