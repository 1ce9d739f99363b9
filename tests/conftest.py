"""Shared fixtures: a private cache folder per test, so no test reads another's cached runs.

BLAS runs single-threaded in the tests: the FEM's systems are small, and on a shared 2-core machine
a threaded BLAS busy-waits for cores it does not get (a case that takes 3 s of CPU then takes 30 s).

``--dist loadgroup`` (pyproject addopts) sends the tests marked ``xdist_group(name)`` to one worker,
so a result shared by several tests (a module- or session-scoped fixture, an ``lru_cache``) is
computed once.  pytest-xdist marks a grouped test by appending ``@name`` to its node id on the
workers (``item._nodeid``); pytest 9 keeps the node id in ``item._id`` instead, so that assignment is
lost and every group is silently spread over both workers.  ``pytest_collection_modifyitems`` below
appends the suffix where pytest 9 reads it (and does nothing where xdist's own suffix took).

Load balance: xdist hands the work units (a group, or one test) out one at a time in collection order
(``--no-loadscope-reorder`` in pyproject keeps that order), so a long test collected last can leave one
worker running alone at the end.  ``LONGEST_FIRST`` lists the tests measured slowest, longest first; they
are moved to the front (stable: everything else keeps its order; a module's or group's tests stay together).

Bytecode: with PYTHONDONTWRITEBYTECODE set in the environment, every worker re-compiles every module and
pytest re-rewrites the asserts of every test module on every run (collection 12 s instead of 6.7 s a
worker, measured). The test processes write their bytecode caches whatever that variable says; a
read-only tree only means the caches are not written.

Compile once: numba compiles the FEM and elastica kernels on first use and caches them beside the sources.
In a fresh clone each xdist worker would compile both itself (about 16 + 17 CPU-s each, measured); so the
controller process, before the workers start, compiles them in two processes at once, one per library,
each running the methods on a few case files that take their main code paths (``PRIMERS``).  The workers then
load the compiled code from the cache.  With a warm cache the primers only load it (about a second); without
xdist (``-n 0``) nothing is primed ahead, the one process compiles as it goes.
"""

import os
import subprocess
import sys
from pathlib import Path

sys.dont_write_bytecode = False

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")

import pytest  # noqa: E402

pytest_plugins = ["pytester"]  # test_library_use runs the case-file plugin on a user's folder in process

try:  # pytest >= 9: the structured node id
    from _pytest.nodeid import NodeId
except ImportError:  # older pytest: xdist's own suffix works
    NodeId = None


def group_suffix(item) -> str:
    """'@name' for a test marked xdist_group(name) (names joined as xdist joins them), else ''."""
    names = {str(m.args[0] if m.args else m.kwargs.get("name", "default")) for m in item.iter_markers("xdist_group")}
    return "@" + "_".join(sorted(names)) if names else ""


# Node-id fragments of the slowest tests, longest first (measured with --durations; update when they change).
LONGEST_FIRST = (
    "test_synthesis.py::test_printed_numbers[bapat2015_ch5_ex2]",
    "test_synthesis.py::test_chapter5_unsolvable_beam_is_a_message",
    "tests/validation/test_report.py::",
    "test_library_use.py::test_plugin_",
    "test_cases.py::test_case[example3_0]",
    "test_synthesis.py::test_printed_numbers[bapat2015_ch5_ex3]",
    "test_prbm_chapter2_models.py::test_chain_inverse_converges_where_the_inverse_is_ill_conditioned",
    "tests/project/test_layout.py::",
    "test_exit_status.py::test_report_follows_the_rule",
    "test_startup_and_schedule.py::",
    "test_fem_kernel.py::test_kernel_equals_the_numpy_element_on_random_states",
    "test_bench.py::",
    "test_cases.py::test_case[test1",
    "test_cases.py::test_case[cantilever_uniform_load]",
    "test_fem_model.py::",
    "tests/validation/test_paraview.py::",
    "test_same_problem.py::test_the_coupler_prbm",
    "test_synthesis.py::test_fem_check_beside_printed_ansys",
    "test_method_options.py::test_an_edit_invalidates_the_cache",
    "test_sweep.py::test_thousand_points_locally_and_on_dask_identical",
    "test_cases.py::test_case[example2",
    "test_cases.py::test_case[example3",
)


ROOT = Path(__file__).resolve().parent.parent

# method -> case files whose runs take the method's compiled code paths (load control, arc length, rigid
# links, a follower load, a mechanism, an inverse problem); the first one compiles almost everything.
PRIMERS = {
    "fem": (
        "benchmarks/cantilever_tip_load.toml",
        "benchmarks/lee_frame.toml",
        "benchmarks/williams_toggle.toml",
        "chapter9/test2_partially_compliant_fourbar.toml",
        "benchmarks/arch_215_clamped_hinged.toml",
        "benchmarks/follower_tip_load.toml",
    ),
    "elastica": (
        "benchmarks/cantilever_tip_load.toml",
        "chapter3/table3_3_case1_a_b_theta0.toml",
        "chapter4/fourbar_fixed_pinned_segment.toml",
        "chapter3/table3_6_exact_inverse.toml",
    ),
}

PRIME = (
    "import sys; from pathlib import Path; from validation.run.parallel import prime\n"
    "for path in sys.argv[2:]: prime(Path(path), sys.argv[1])"
)


def prime_compiled_code() -> None:
    """Compile (or load) each library's numba code in its own process, all at once, and wait for them.
    A primer that fails only costs the time: the tests that use that code report the failure."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}  # see "Bytecode" above
    primers = [
        subprocess.Popen(
            [sys.executable, "-c", PRIME, method, *(str(ROOT / "cases" / f) for f in files)],
            cwd=ROOT,
            env=env,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        for method, files in PRIMERS.items()
    ]
    for process in primers:
        process.wait()


def pytest_configure(config):
    """In the xdist controller, before the workers start: compile the numba code once (module docstring)."""
    workers = getattr(config.option, "numprocesses", None)
    if not hasattr(config, "workerinput") and workers and getattr(config.option, "dist", "no") != "no":
        prime_compiled_code()


def _rank(nodeid: str) -> int:
    return next((i for i, fragment in enumerate(LONGEST_FIRST) if fragment in nodeid), len(LONGEST_FIRST))


def pytest_collection_modifyitems(config, items):
    items.sort(key=lambda item: _rank(item.nodeid))  # stable: the rest keep their order
    if NodeId is None or not getattr(config.option, "loadgroup", False):
        return
    for item in items:
        suffix = group_suffix(item)
        if suffix and not item.nodeid.endswith(suffix):
            item._id = NodeId.parse(item.nodeid + suffix)


@pytest.fixture(autouse=True)
def _private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("PRBM_VALIDATE_CACHE", str(tmp_path / "cache"))
