"""What numba compiles stays small: the structural facts that keep a first run's compile to what it needs
(its cost is measured by ``validation.bench.compile_cost``, never asserted here).

- every compiled function of the project is cached on disk (``cache=True``): a worker process loads
  what a primer compiled instead of compiling it again;
- one specialisation per compiled function after the FEM and the elastica ran on shipped cases (a
  segment and a mechanism): the adapters pass one set of argument types (float64 C-contiguous arrays,
  int64, bool), so no function is compiled twice for other types or layouts;
- a case run by methods whose code imports no numba schedules no primer and, run by the BCM, imports
  no compiled module (the PRBM's solve: ``test_startup_and_schedule``).
"""

import ast
import json
import subprocess
import sys
import tomllib
from pathlib import Path

from validation.case.loader import find_case_files
from validation.run.parallel import compiled_method, schedule

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("prbm", "fem", "elastica", "bcm", "argcheck", "planar", "references", "validation")
COMPILED = ("numba", "llvmlite", "fem.kernel", "fem.warm_kernel", "fem.numbering", "elastica.integrator")

SPECIALISATIONS = """
import json, sys
from numba.core.registry import CPUDispatcher
from validation.case.loader import case_by_id
from validation.run.runner import run_method
for case_id in ("cantilever_tip_load", "seed003_slant_parallelogram"):
    case = case_by_id(case_id).case
    for method in ("fem", "elastica"):
        run = run_method(case, method)
        assert run.values and not (run.message or "").startswith("error"), (case_id, method, run.message)
found = {}
for name, module in list(sys.modules.items()):
    if name.split(".")[0] in ("fem", "elastica"):
        for attr, value in vars(module).items():
            if isinstance(value, CPUDispatcher) and value.py_func.__module__ == name and value.signatures:
                found[name + "." + attr] = [str(s) for s in value.signatures]
print(json.dumps(found))
"""


def _jit_decorators(tree: ast.AST):
    """(function name, decorator call) of every ``njit``/``jit`` decorated function."""
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef):
            for d in node.decorator_list:
                target = d.func if isinstance(d, ast.Call) else d
                name = target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", "")
                if name in ("njit", "jit"):
                    yield node.name, d


def test_every_compiled_function_is_cached_on_disk():
    missing, seen = [], 0
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            text = path.read_text(encoding="utf-8")
            if "jit" not in text:
                continue
            for function, decorator in _jit_decorators(ast.parse(text)):
                seen += 1
                cached = isinstance(decorator, ast.Call) and any(
                    k.arg == "cache" and isinstance(k.value, ast.Constant) and k.value.value is True
                    for k in decorator.keywords
                )
                if not cached:
                    missing.append(f"{path.relative_to(ROOT)}:{function}")
    assert seen > 10 and missing == []


def test_one_specialisation_per_compiled_function_after_segment_and_mechanism_runs():
    out = subprocess.run([sys.executable, "-c", SPECIALISATIONS], capture_output=True, text=True, check=True, cwd=ROOT)
    found = json.loads(out.stdout.strip().splitlines()[-1])
    for entry in (
        "fem.kernel.newton_load",
        "fem.warm_kernel.level_guesses_compiled",
        "elastica.integrator.follow_path",
        "elastica.integrator._samples",
    ):
        assert entry in found, (entry, sorted(found))
    assert {name: sigs for name, sigs in found.items() if len(sigs) != 1} == {}


def test_methods_without_compiled_code_schedule_no_primer():
    paths = find_case_files()
    free = sorted(
        {
            m
            for p in paths
            for m in tomllib.loads(p.read_text(encoding="utf-8")).get("methods", {})
            if not compiled_method(m)
        }
    )
    assert "bcm" in free and "prbm" in free
    assert schedule(paths, free).primers == []


def test_a_bcm_run_imports_no_compiled_module():
    code = (
        "import sys\n"
        "from validation.case.loader import case_by_id\n"
        "from validation.run.runner import run_method\n"
        "run = run_method(case_by_id('seed003_slant_parallelogram').case, 'bcm')\n"
        "assert run.values, run.message\n"
        f"print(' '.join(m for m in {COMPILED!r} if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.split() == []
