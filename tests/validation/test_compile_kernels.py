"""``validation.run.compile_kernels`` (what `.ci/run` runs beside the type checker so that the suite's
workers load numba's kernels instead of compiling them) runs a primer for every compiled method a shipped
case file runs, and nothing for the methods without compiled code."""

import tomllib

from validation.case.loader import find_case_files
from validation.run import compile_kernels
from validation.run.parallel import compiled_method


def test_it_primes_every_compiled_method_of_the_shipped_cases(capsys, monkeypatch):
    """The primers' runs themselves are `parallel.prime`'s (``test_startup_and_schedule``): counted here."""
    calls = []
    monkeypatch.setattr(compile_kernels, "prime", lambda path, method: calls.append(method))
    assert compile_kernels.main() == 0
    lines = capsys.readouterr().out.splitlines()
    primed = {line.split()[3] for line in lines if line.startswith("numba kernels of ")}
    assert sorted(calls) == sorted(primed)
    used = {m for p in find_case_files() for m in tomllib.loads(p.read_text(encoding="utf-8")).get("methods", {})}
    assert primed == {m for m in used if compiled_method(m)}
    assert {"fem", "elastica"} <= primed and not primed & {"prbm", "bcm"}
    assert lines[-1].startswith("numba kernels ready in the cache")
