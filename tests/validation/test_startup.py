"""Start-up: the CLI builds its parser and solves one case without the heavy libraries it does not use
(a fresh interpreter, so that other tests' imports do not count)."""

import subprocess
import sys

SCRIPT = """
import sys
from validation.cli.main import build_parser
build_parser()
from validation.case.loader import case_by_id
from validation.run.runner import run_method
run = run_method(case_by_id("cantilever_tip_load").case, "prbm")
assert run.values, run.message
print(" ".join(sorted(m for m in ("pandas", "validation.synthesis.design", "matplotlib", "fem", "elastica", "numba",
                                 "validation.run.cache") if m in sys.modules)))
"""


def test_parser_and_a_prbm_solve_load_no_pandas_synthesis_solvers_cache_or_other_methods():
    out = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, check=True)
    assert out.stdout.split() == []
