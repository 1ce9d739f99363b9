"""Run every method a case asks for, through the result cache (``run_case``): a method's run is read
from the cache when the case text, the method, its options and the code are unchanged
(``validation.run.cache``), else run by ``runner.run_method`` and stored.

The case's methods and its findings' re-runs together get the wall time of its ``[limits] seconds``
(``validation.run.deadline``): past it, the method running stops with status 'timed out', the methods
not yet run are 'timed out' too (not run), and the case's result is what ran before."""

from __future__ import annotations

import time

from validation.case.loader import LoadedCase
from validation.methods.base import MethodRun, RunStatus
from validation.run import cache
from validation.run.deadline import TimedOut, deadline
from validation.run.runner import CaseResult, reproduce_findings, run_method


def run_case(loaded: LoadedCase, methods: list[str] | None = None, use_cache: bool = True) -> CaseResult:
    result = CaseResult(loaded)
    wanted = [m for m in loaded.case.methods if not methods or m in methods]
    seconds = loaded.case.limits.seconds
    current, started = None, time.perf_counter()
    try:
        with deadline(seconds):
            for method in wanted:
                current, started = method, time.perf_counter()
                options = dict(loaded.case.methods[method] or {})
                key = cache.run_key(loaded.text, method, options)
                run = cache.load(key) if use_cache else None
                result.cached[method] = run is not None
                if run is None:
                    run = run_method(loaded.case, method)
                    if run.status in (RunStatus.OK, RunStatus.NOT_CONVERGED):
                        cache.store(key, run)
                result.runs[method] = run
            current = None
            reproduce_findings(result)
    except TimedOut:
        for method in wanted:
            if method not in result.runs:
                result.cached[method] = False
                result.runs[method] = timed_out(
                    seconds, time.perf_counter() - started if method == current else 0.0, ran=method == current
                )
    return result


def timed_out(seconds: float, wall_time: float, ran: bool) -> MethodRun:
    """The run of a method stopped (``ran``) or never started at the case's wall-time limit."""
    limit = f"the case's wall-time limit of {seconds:g} s ([limits] seconds)"
    return MethodRun(
        values={},
        converged=False,
        wall_time=wall_time,
        status=RunStatus.TIMED_OUT,
        message=f"timed out: stopped at {limit}" if ran else f"timed out: not run, {limit} was spent",
    )
