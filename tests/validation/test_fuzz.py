"""Fuzzing the command line (validation/stress/fuzz.py, fuzz_run.py, fuzz_worker.py): mutated shipped
case files through ``prbm-validate solve`` and ``run`` on two worker processes, each within its time bound.

- ``test_mutants_keep_the_contract``: the first 150 of the 300 mutants of the small shipped cases that
  ``prbm-validate stress`` runs (``fuzz.SOURCES``, its seed; the command runs all 300, ``--long`` 10,000):
  every one ends with exit 0, 1 or 2 within its bound, with no traceback, one-line messages and, on exit
  0, finite numbers. A failure of a defect listed in ``OPEN`` (found, not fixed yet) is allowed; any
  other fails the test, naming the mutant. The 150 take every mutation kind, both verbs, every source
  file and every ending (``test_mutants_cover_every_kind_verb_and_ending``); planted defects (a non-UTF-8
  file as a traceback, a NaN output on exit 0, a two-line message on exit 1) fail 16, 10 and 2 of them
  (29, 16 and 2 of the 300).
- ``test_regression_keeps_the_contract``: every shrunk failure kept in ``tests/validation/fuzz_regressions/`` replayed
  with its verb. A file whose header says ``status: open`` is an xfail(strict=True) with its defect's
  reason from ``OPEN``: once the defect is fixed the test fails, and the header becomes ``status: fixed``.
- the judge (``Outcome.problem``), an exception escaping ``main``, the time bound of the pool and the
  shrinker, each on a planted failure.
"""

from __future__ import annotations

import fnmatch
import math
from dataclasses import dataclass
from pathlib import Path

import pytest

from validation.case.loader import CASES_DIR
from validation.stress.fuzz import KINDS, SOURCES, Mutant, Mutation
from validation.stress.fuzz_run import Pool, read_header, seeded_mutants, shrink
from validation.stress.fuzz_worker import Outcome, run_mutant

pytestmark = pytest.mark.xdist_group("fuzz")  # one pool of workers for the whole module

COUNT = 150  # the first 150 of the command's 300 (the mutants of a seed do not depend on the count)
SEED = 20261122  # the seed of `prbm-validate stress`: the test runs the command's own mutants
BOUND = 10.0  # seconds a mutant may take (the shipped cases of fuzz.SOURCES solve in under 1 s)
REGRESSIONS = Path(__file__).resolve().parent / "fuzz_regressions"


@dataclass(frozen=True)
class Defect:
    """A defect the fuzzer found that is not fixed yet: the failures it explains (``problem`` starts with
    this, stderr holds ``said``, and a mutation is at a field matching one of ``fields``: dotted, list
    indices as '*'; empty: any), and what is wrong, where."""

    reason: str
    problem: str
    said: str = ""
    fields: tuple[str, ...] = ()

    def explains(self, mutant: Mutant, outcome: Outcome) -> bool:
        def at(m: Mutation) -> str:
            return ".".join("*" if isinstance(p, int) else str(p) for p in m.path)

        return (
            outcome.problem.startswith(self.problem)
            and self.said in outcome.stderr
            and (not self.fields or any(fnmatch.fnmatchcase(at(m), f) for m in mutant.mutations for f in self.fields))
        )


# name (a regression file's "defect:" line) -> a defect found and not fixed yet
OPEN: dict[str, Defect] = {}


@pytest.fixture(scope="module")
def pool():
    with Pool(workers=2, timeout=BOUND) as workers:
        yield workers


@pytest.fixture(scope="module")
def fuzzed(pool):
    mutants = seeded_mutants(COUNT, SEED)
    return list(zip(mutants, pool.map([(m.verb, m.bytes) for m in mutants])))


def _said(outcome: Outcome) -> str:
    return (outcome.stderr.strip().splitlines() or [""])[0][:200]


def test_mutants_keep_the_contract(fuzzed):
    unexplained = [(m, o) for m, o in fuzzed if o.problem and not any(d.explains(m, o) for d in OPEN.values())]
    assert not unexplained, "\n".join(
        f"{o.problem}: {m.verb} {m.source.relative_to(CASES_DIR)}: {m.describe()} ({_said(o)})" for m, o in unexplained
    )


def test_mutants_cover_every_kind_verb_and_ending(fuzzed):
    assert len(fuzzed) == COUNT
    kinds = {mutation.kind for m, _ in fuzzed for mutation in m.mutations}
    assert kinds == set(KINDS)
    assert {m.verb for m, _ in fuzzed} == {"solve", "run"}
    assert {m.source.relative_to(CASES_DIR).as_posix() for m, _ in fuzzed} == set(SOURCES)
    assert {0, 1, 2} <= {o.exit for _, o in fuzzed}


def _regression(path: Path):
    header = read_header(path.read_bytes())
    status, defect = header["status"][0], header.get("defect", [""])[0]
    if status == "open":
        reason = OPEN[defect].reason if defect in OPEN else f"open defect '{defect}' (not in OPEN)"
        return pytest.param(path, id=path.stem, marks=pytest.mark.xfail(strict=True, reason=reason))
    return pytest.param(path, id=path.stem)


@pytest.mark.parametrize("path", [_regression(p) for p in sorted(REGRESSIONS.glob("*.toml"))])
def test_regression_keeps_the_contract(pool, path):
    header = read_header(path.read_bytes())
    outcome = pool.map([(header["verb"][0], path.read_bytes)])[0]
    assert not outcome.problem, f"{header['fuzz regression'][0]} -> {outcome.problem} ({_said(outcome)})"


def test_the_judge_names_each_failure():
    assert (
        Outcome(
            exit=2,
            seconds=0.1,
            stderr="error: f.toml: segment.E: Input should be greater than 0\n"
            "nothing written; the previous results in out are unchanged\n",
        ).problem
        == ""
    )
    assert Outcome(exit=None, seconds=10.0).problem == "timed out"
    assert Outcome(exit=1, seconds=0.1, exception="KeyError at x.py:f").problem == "traceback: KeyError at x.py:f"
    assert Outcome(exit=-9, seconds=0.1, stderr="the worker process died").problem == "exit -9"
    assert Outcome(exit=1, seconds=0.1, silent=True).problem == "exit 1 without a message"
    assert Outcome(exit=2, seconds=0.1, stderr="nothing written\n").problem == "exit 2 without an error line"
    assert (
        Outcome(exit=2, seconds=0.1, stderr="error: f.toml: bad\n  For further information visit x\n").problem
        == "a message that is not one line"
    )
    warned = "/x/prbm/mechanisms.py:349: RuntimeWarning: invalid value encountered in arcsin\n  t = np.arcsin(s)\n"
    assert Outcome(exit=1, seconds=0.1, stderr=warned).problem == "a message that is not one line"
    assert Outcome(exit=1, seconds=0.1, stderr=warned).offending_line.startswith("mechanisms.py:349: RuntimeWarning")
    assert (
        Outcome(exit=0, seconds=0.1, nonfinite="prbm y@P at level 2 = None").problem
        == "exit 0 with a number that is not finite"
    )


def test_an_exception_escaping_main_is_a_traceback(tmp_path, monkeypatch):
    source = (CASES_DIR / SOURCES[0]).read_bytes()
    assert run_mutant(source, "solve", tmp_path).problem == ""

    def boom(path):
        raise RuntimeError("planted")

    monkeypatch.setattr("validation.cli.solve.load_case", boom)
    outcome = run_mutant(source, "solve", tmp_path)
    assert outcome.exit == 1 and outcome.problem == "traceback: RuntimeError at tests/validation/test_fuzz.py:boom"


def test_a_mutant_past_its_bound_is_stopped_and_its_worker_replaced(pool):
    slow = (CASES_DIR / "benchmarks" / "arch_215_clamped_hinged.toml").read_bytes  # about 1 s to solve
    restarts, pool.timeout = pool.restarts, 0.0  # the bound: the file's size allowance alone, a few ms
    try:
        outcome = pool.map([("solve", slow)])[0]
    finally:
        pool.timeout = BOUND
    assert outcome.timed_out and outcome.problem == "timed out" and pool.restarts == restarts + 1
    assert pool.map([("solve", slow)])[0].exit == 0  # the replacement worker runs the next one


class PlantedPool:
    """A pool whose 'command' fails (a planted traceback) while the file holds NaN, else exits 2."""

    workers = [None, None]

    def map(self, tasks):
        return [
            Outcome(exit=1, seconds=0.0, exception="Planted at x.py:f")
            if b"nan" in make()
            else Outcome(exit=2, seconds=0.0, stderr="error: bad")
            for _, make in tasks
        ]


def test_shrink_keeps_the_failing_mutation_and_drops_the_rest():
    source = CASES_DIR / "segments" / "slfp_alone.toml"
    failing = Mutation("nan", ("mechanism", "E"), float("nan"))
    mutant = Mutant(source, (Mutation("unknown_key", ("case", "lenght"), 2.5), failing), "solve")
    pool = PlantedPool()
    outcome = pool.map([("solve", mutant.bytes)])[0]
    small, small_outcome = shrink(pool, mutant, outcome, budget=200)
    assert small_outcome.problem == outcome.problem
    assert [m for m in small.mutations if m.kind != "shrink"] == [failing]
    assert len(small.bytes()) < len(source.read_bytes()) / 2  # references, agreements, ... deleted
    assert "references" not in small.document() and math.isnan(small.document()["mechanism"]["E"])
