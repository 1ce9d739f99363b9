"""Run every method a case asks for, through the result cache (``run_case``): a method's run is read
from the cache when the case text, the method, its options and the code are unchanged
(``validation.run.cache``), else run by ``runner.run_method`` and stored."""
from __future__ import annotations

from validation.case.loader import LoadedCase
from validation.methods.base import RunStatus
from validation.run import cache
from validation.run.runner import CaseResult, reproduce_findings, run_method


def run_case(loaded: LoadedCase, methods: list[str] | None = None, use_cache: bool = True) -> CaseResult:
    result = CaseResult(loaded)
    for method in loaded.case.methods:
        if methods and method not in methods:
            continue
        options = dict(loaded.case.methods[method] or {})
        key = cache.run_key(loaded.text, method, options)
        run = cache.load(key) if use_cache else None
        result.cached[method] = run is not None
        if run is None:
            run = run_method(loaded.case, method)
            if run.status in (RunStatus.OK, RunStatus.NOT_CONVERGED):
                cache.store(key, run)
        result.runs[method] = run
    reproduce_findings(result)
    return result
