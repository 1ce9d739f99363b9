"""Start-up and scheduling (issue 15, items 4 and the report budget): heavy imports only where used,
and the parallel run of many cases gives the same results as the serial one.

- ``import prbm`` and a PRBM solve of a straight segment load no solver library (scipy.optimize ~0.7 s
  to import): the names of ``prbm`` load their module at first use (PEP 562), the adapter's mechanism
  parts and scipy.optimize through ``prbm.lazy.LazyModule``;
- the run cache's source walk still sees every module loaded that way (a result must not go stale);
- ``validation.run.parallel`` compiles each numba method once (one primer per method whose sources
  import numba) and returns, on two workers, the values of the serial run (to the solves' tolerance).
(No timing here: speed is measured by the benchmarks, never asserted in a test.)"""

import json
import subprocess
import sys
from pathlib import Path

import pytest

import prbm
from prbm.lazy import LazyModule
from validation.case.loader import CASES_DIR, case_by_id, load_case
from validation.run import cache, parallel
from validation.run.parallel import compiled_method, run_paths, schedule

ROOT = Path(__file__).resolve().parents[2]
HEAVY = (
    "scipy.optimize",
    "scipy.integrate",
    "pandas",
    "numba",
    "skfem",
    "matplotlib",
    "prbm.network",
    "fem",
    "elastica",
)


def loaded_after(code: str) -> list[str]:
    """The HEAVY modules imported by a fresh interpreter after running ``code``."""
    probe = f"{code}\nimport sys, json\nprint(json.dumps([m for m in {HEAVY!r} if m in sys.modules]))"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True, cwd=ROOT)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_import_prbm_and_a_segment_solve_load_no_solver_library():
    assert loaded_after("import prbm") == []
    assert loaded_after("import prbm; prbm.fixed_pinned_tip(2.0, 0.5, length=1.0, EI=1.0)") == []


def test_solve_of_a_segment_case_by_the_prbm_imports_no_heavy_module(tmp_path):
    out = tmp_path / "solve.json"
    code = (
        "from validation.cli.main import main\n"
        f"assert main(['solve', 'cantilever_tip_load', '--method', 'prbm', '--out', {str(out)!r}]) == 0"
    )
    assert loaded_after(code) == []
    document = json.loads(out.read_text())
    assert document["method"] == "prbm" and document["levels"]


def test_every_public_name_of_prbm_is_its_module_object():
    for name in prbm.__all__:
        value = getattr(prbm, name)
        module = prbm._EXPORTS[name]
        assert value is getattr(sys.modules[module], name), name
    assert set(prbm.__all__) <= set(dir(prbm))
    with pytest.raises(AttributeError, match="no attribute 'not_a_model'"):
        prbm.not_a_model  # noqa: B018


def test_a_lazy_module_imports_at_first_attribute_read():
    lazy = LazyModule("json")
    assert "not imported" in repr(lazy)
    assert lazy.dumps([1]) == "[1]"
    assert "imported" in repr(lazy) and "not" not in repr(lazy)


def test_the_run_cache_hashes_the_modules_loaded_lazily():
    files = {p.relative_to(ROOT).as_posix() for p in cache.source_files("prbm")}
    for lazy in (
        "prbm/chain.py",
        "prbm/compliance.py",
        "prbm/segments.py",
        "prbm/network.py",
        "validation/methods/prbm_network.py",
        "validation/methods/prbm_fourbar.py",
        "prbm/lazy.py",
    ):
        assert lazy in files, lazy


def test_primers_compile_each_numba_method_once():
    assert compiled_method("fem") and compiled_method("elastica")  # fem/kernel.py, elastica/integrator.py
    assert not compiled_method("prbm")
    paths = [case_by_id(i).path for i in ("cantilever_tip_load", "bapat2015_table3_1", "seed004_parallel_guided")]
    plan = schedule(paths, None)
    assert sorted(m for m, _ in plan.primers) == ["elastica", "fem"]
    assert set(plan.free) | set(plan.compiled) == set(paths) and not set(plan.free) & set(plan.compiled)
    assert [m for m, _ in schedule(paths, ["prbm"]).primers] == []  # asked for the PRBM only: nothing to compile


def _values(runs) -> dict:
    return {
        (r.result.loaded.id, method, req): value
        for r in runs
        if r.result is not None
        for method, run in r.result.runs.items()
        for req, value in run.values.items()
    }


def case_id(result) -> str:
    return result.loaded.id


def test_two_workers_give_the_values_of_the_serial_run(tmp_path):
    """The same cases on two worker processes and serially: the same results in the same order.
    Values within 1e-8 of their quantity's largest value (per case and method), not to the bit: a
    worker is another process whose BLAS may run another kernel or thread count, so its roundings may
    differ. Each value is a converged solve, stopped at a residual of 1e-10 of its force scale (the FEM's
    `SolveOptions.rtol`; the elastica's 1e-11 and the PRBM's root finders are tighter); on these cases
    such a stop lies within 1e-10 of the equilibrium (tightening the FEM to 1e-14 and the elastica to
    1e-13 moves no value by more than 7e-11 of its scale), so 1e-8 leaves a factor 100. Values mixed up
    between levels, points, cases or methods differ by 1e-4 of the scale or more."""
    paths = [
        case_by_id(i).path
        for i in (
            "bapat2015_table3_1",
            "segment_curved_fixed_pinned_compressive",
            "bapat2015_theta_dependent_k_tension_baseline",
        )
    ]
    paths.append(tmp_path / "broken.toml")
    paths[-1].write_text("[case]\nid = 'broken'\n")
    serial = run_paths(paths, use_cache=False, jobs=1, after=case_id)
    parallel = run_paths(paths, use_cache=False, jobs=2, after=case_id)
    assert [r.path for r in parallel] == paths
    expected, got = _values(serial), _values(parallel)
    assert expected and got.keys() == expected.keys()
    scale = {}
    for (case, method, request), value in expected.items():
        key = (case, method, request.quantity)
        scale[key] = max(scale.get(key, 0.0), abs(value))
    for (case, method, request), value in expected.items():
        tol = 1e-8 * scale[case, method, request.quantity]
        assert abs(got[case, method, request] - value) <= tol, (case, method, request, value)
    assert (
        [r.after for r in parallel]
        == [r.after for r in serial]
        == [
            "bapat2015_table3_1",
            "segment_curved_fixed_pinned_compressive",
            "bapat2015_theta_dependent_k_tension_baseline",
            None,
        ]
    )
    assert parallel[-1].error and "broken.toml" in parallel[-1].error


def test_a_primer_compiles_without_keeping_its_run(tmp_path, monkeypatch):
    """The primer's run is mostly numba's compile: it must not enter the run cache, or the case it
    ran on would report the compile as its method time (a 29 s elastica time was seen in a cold report)."""
    monkeypatch.setenv("PRBM_VALIDATE_CACHE", str(tmp_path / "runs"))
    path = CASES_DIR / "benchmarks" / "cantilever_tip_load.toml"
    loaded = load_case(path)
    key = cache.run_key(loaded.text, "prbm", dict(loaded.case.methods["prbm"] or {}))
    parallel.prime(path, "prbm")
    assert cache.load(key) is None
    parallel.run_path(path, ["prbm"], use_cache=True)
    assert cache.load(key) is not None  # an ordinary run is kept (the check can fail)


def test_the_lazy_export_table_names_exactly_the_public_names():
    assert set(prbm._EXPORTS) == set(prbm.__all__)  # a missing comma once glued two names into one key


def test_the_serial_path_primes_before_any_case(monkeypatch):
    """``jobs`` = 1 compiles each numba method by a primer before the first case, so no case's method
    time holds the compile (the parallel path does the same on its workers)."""
    order = []
    monkeypatch.setattr(
        parallel,
        "prime",
        lambda path, method: order.append(("prime", method)) or parallel.Timed("compile", method, 0.0),
    )
    monkeypatch.setattr(
        parallel,
        "run_path",
        lambda path, methods, use_cache, after=None: order.append(("case", path.stem)) or parallel.PathRun(path),
    )
    paths = [case_by_id(i).path for i in ("bapat2015_table3_1", "cantilever_tip_load", "seed004_parallel_guided")]
    timeline = []
    run_paths(paths, use_cache=False, jobs=1, timeline=timeline)
    kinds = [kind for kind, _ in order]
    assert sorted(m for kind, m in order if kind == "prime") == ["elastica", "fem"]
    assert kinds.index("case") == 2 and kinds.count("case") == 3  # both primers before the first case
    assert [r.kind for r in timeline] == ["compile", "compile"]


def test_no_primer_for_a_method_whose_runs_are_all_cached(tmp_path, monkeypatch):
    """A primer compiles only what will run: a case whose FEM run is in the run cache needs no FEM primer."""
    monkeypatch.setenv("PRBM_VALIDATE_CACHE", str(tmp_path / "runs"))
    path = case_by_id("cantilever_tip_load").path
    assert sorted(m for m, _ in schedule([path], None, use_cache=True).primers) == ["elastica", "fem"]
    loaded = load_case(path)
    for method in ("fem", "elastica"):
        key = cache.run_key(loaded.text, method, dict(loaded.case.methods[method] or {}))
        cache.store(key, parallel.run_method(case_by_id("bapat2015_table3_1").case, "prbm"))  # any stored run
    plan = schedule([path], None, use_cache=True)
    assert plan.primers == [] and plan.free == [path]
    assert sorted(m for m, _ in schedule([path], None, use_cache=False).primers) == ["elastica", "fem"]


def test_cases_are_scheduled_longest_first_by_their_last_times():
    ids = ("bapat2015_table3_1", "segment_curved_fixed_pinned_compressive", "cantilever_tip_load", "bapat2015_test2")
    paths = [case_by_id(i).path for i in ids]
    costs = {
        "bapat2015_table3_1": 0.1,
        "segment_curved_fixed_pinned_compressive": 3.0,
        "cantilever_tip_load": 2.0,
        "bapat2015_test2": 5.0,
    }
    plan = schedule(paths, None, costs=costs)
    ordered = plan.free + plan.compiled
    for part in (plan.free, plan.compiled):
        times = [costs[parallel.CaseFile.read(p).id] for p in part]
        assert times == sorted(times, reverse=True)
    assert set(ordered) == set(paths)
    assert all(plan.waits_for[p] for p in plan.compiled) and not set(plan.waits_for) & set(plan.free)


def test_a_primer_runs_with_fewer_collections_and_restores_the_collector(monkeypatch):
    """numba's compiler makes millions of short-lived objects: `parallel.prime` raises the collector's
    first threshold while the primer runs (a tenth of a cold compile) and leaves it as it found it."""
    import gc

    from validation.run import parallel

    seen = []
    monkeypatch.setattr(parallel, "run_method", lambda case, method: seen.append(gc.get_threshold()) or None)
    before = gc.get_threshold()
    parallel.prime(case_by_id("cantilever_tip_load").path, "fem")
    assert seen == [(parallel.PRIMER_GC_THRESHOLD, *before[1:])]
    assert gc.get_threshold() == before


def test_an_extra_task_starts_once_the_primers_of_its_compiled_methods_are_done():
    """The pool's work in ``WorkQueue`` order: an extra task that runs the elastica's compiled code (the
    report's coarse atlas) is not handed out while the elastica's primer compiles (it would compile the
    same kernels a second time), the free cases go meanwhile, and once the primer is done the task goes
    before the cases not yet started; a case that needs the FEM waits for the FEM's primer alone."""
    from validation.report.build import DomainsAndAtlas

    assert DomainsAndAtlas(Path("stage"), Path("datasets")).compiled == ("elastica",)
    atlas = DomainsAndAtlas(Path("stage"), Path("datasets"))
    plain = DomainsAndAtlas(Path("stage"), Path("datasets"), compiled=())  # an extra task with none
    free, needs_fem, needs_both = [Path(f"free{i}.toml") for i in range(3)], Path("fem.toml"), Path("both.toml")
    plan = parallel.Schedule(
        primers=[("fem", needs_fem), ("elastica", needs_both)],
        free=free,
        compiled=[needs_both, needs_fem],
        waits_for={needs_fem: frozenset({"fem"}), needs_both: frozenset({"fem", "elastica"})},
    )
    queue = parallel.WorkQueue(plan, [atlas, plain], frozenset({"fem", "elastica"}))
    ready: set[str] = set()
    given = [queue.next(ready), queue.next(ready)]  # both primers compiling
    ready.add("fem")
    given += [queue.next(ready), queue.next(ready), queue.next(ready)]
    ready.add("elastica")
    given += [queue.next(ready), queue.next(ready), queue.next(ready)]
    assert given == [plain, free[0], free[1], free[2], needs_fem, atlas, needs_both, None]


def test_an_extra_task_waits_for_no_primer_a_run_does_not_have():
    """A compiled method the run has no primer for (no case needs it) leaves nothing to wait for."""
    from validation.report.build import DomainsAndAtlas

    atlas = DomainsAndAtlas(Path("stage"), Path("datasets"))
    queue = parallel.WorkQueue(parallel.Schedule(primers=[("fem", Path("a.toml"))]), [atlas], frozenset({"fem"}))
    assert queue.next(set()) is atlas
