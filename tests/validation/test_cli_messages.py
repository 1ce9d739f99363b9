"""What the command line says while and after it works: a notice while the numba kernels compile, a
progress bar naming cases with no time left before it means something, the run's and the report's last
lines (cases counted per verdict, where the results are), a refused method in one line (``run`` and
the pytest plugin), failed sweep points named, help for every option, units and rounding in ``solve``'s
JSON, the nearest name of a misspelled case field, and pytest installed with the package.

The methods are fakes (``sys.modules``) wherever the solvers are not what is under test."""

from __future__ import annotations

import argparse
import io
import json
import math
import subprocess
import sys
import textwrap
import time
import tomllib
import types
from pathlib import Path

import pytest

from tests.validation.test_exit_status import fake, write  # noqa: F401 - the fake 'prbm' adapter fixture
from tests.validation.test_foundation import GOOD
from validation.case.loader import CaseError, load_case
from validation.report.build import screen_lines
from validation.cli.arguments import build_parser
from validation.cli.main import main
from validation.cli.solve import significant, to_estimate
from validation.methods.base import MethodRun
from validation.run import parallel
from validation.run.outcome import run_cases
from validation.run.parallel import PathRun
from validation.run.progress import WITH_ETA, WITHOUT_ETA, CaseProgress, compile_notice
from validation.run.timeline import Timed

ROOT = Path(__file__).resolve().parents[2]
WITH_FEM = GOOD.replace("[methods.prbm]", "[methods.prbm]\n[methods.fem]")


def _actions(parser: argparse.ArgumentParser, verb: str = ""):
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for choice in action._choices_actions:
                yield f"{choice.dest}", choice
            for name, sub in action.choices.items():
                yield from _actions(sub, name)
        else:
            yield f"{verb} {'/'.join(action.option_strings) or action.dest}".strip(), action


def test_every_option_of_every_verb_has_help():
    missing = [name for name, action in _actions(build_parser()) if not action.help or action.help == argparse.SUPPRESS]
    assert not missing, f"options without --help text: {missing}"
    names = [name for name, _ in _actions(build_parser())]
    assert "solve --compact" in names and "report --jobs" in names and "report --out" in names


def test_a_cold_compile_is_said_once_and_the_bar_waits_for_it(tmp_path, monkeypatch, fake, capsys):  # noqa: F811
    """Primers that take longer than ``CompileWatch.after``: one line naming the kernels and the
    expected time, on stderr, even with the bar off; none when they are quick (a warm cache)."""
    fem = types.ModuleType("validation.methods.fem")
    fem.run = lambda case, requests, options: MethodRun(values={r: 1.0 for r in requests})
    monkeypatch.setitem(sys.modules, "validation.methods.fem", fem)

    def slow_prime(path, method):
        time.sleep(0.5)
        return Timed("compile", method, 0.5)

    monkeypatch.setattr(parallel, "prime", slow_prime)
    monkeypatch.setattr(parallel, "NOTICE_AFTER", 0.1)
    path = write(tmp_path, "toy.toml", WITH_FEM)
    run_cases([path], use_cache=False, jobs=1, progress=False)
    err = capsys.readouterr().err
    assert err.count("compiling the FEM kernels (once per machine, ~5 s)") == 1
    monkeypatch.setattr(parallel, "prime", lambda path, method: Timed("compile", method, 0.0))
    run_cases([path], use_cache=False, jobs=1, progress=False)
    assert "compiling" not in capsys.readouterr().err
    assert (
        compile_notice(("elastica", "fem", "opensees"), 2)
        == "compiling the elastica and FEM kernels (once per machine, ~10 s)"
    )


def test_the_bar_names_case_ids_and_shows_no_time_left_until_it_means_something():
    stream = io.StringIO()
    bar = CaseProgress(3, enabled=True, stream=stream)
    loaded = types.SimpleNamespace(id="cantilever_tip_load")
    first = PathRun(Path("cases/benchmarks/some_file_name.toml"), result=types.SimpleNamespace(loaded=loaded))
    bar.watch.compiling(("fem",))
    bar.advance(first)
    assert "cantilever_tip_load" in str(bar.bar) and "some_file_name" not in str(bar.bar)
    assert bar.bar.bar_format == WITHOUT_ETA  # the compile is still running: no rate yet
    bar.watch.compiled()
    bar.advance(first)
    assert bar.bar.bar_format == WITHOUT_ETA  # one case since the compile: no rate yet
    bar.advance(PathRun(Path("bad_file.toml"), error="bad"))
    assert bar.bar.bar_format == WITH_ETA and "bad_file" in str(bar.bar) and "<" in str(bar.bar)
    bar.close()
    assert "compiling the FEM kernels" in stream.getvalue()


def test_run_says_a_refused_method_in_one_line_and_ends_with_counts_and_where(tmp_path, capsys, fake):  # noqa: F811
    fake["behaviour"] = "refuses"
    path = write(tmp_path, "toy.toml", GOOD)
    out = tmp_path / "o"
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-cache"]) == 1
    lines = capsys.readouterr().out.rstrip().splitlines()
    assert "  toy prbm: refused: cannot model a toy" in lines
    assert not any("outside the claimed limit:" in line for line in lines)  # no rows of NaN
    assert lines[-2].startswith("1 case: 1 refused")
    assert lines[-1].startswith(f"results: {out} (values.csv, comparisons.csv, summary.csv")


def test_the_report_ends_with_counts_and_where_and_keeps_the_breakdown_off_screen(tmp_path):
    """The builder's breakdown stays in timing.txt; the screen gets its first line (with where the rest is)
    and the slowest cases, then the cases counted per verdict."""
    breakdown = [
        "report: 63.2 s wall, 101.0 s CPU (this process and its 2 worker(s)); load average 1.0",
        "time breakdown (wall and CPU seconds of each piece of work; pooled work overlaps):",
    ]
    breakdown += [f"  main: step {i}    0.1 s wall    0.1 s CPU" for i in range(15)]
    breakdown += ["  slowest cases: a 4.0, b 2.0", "  workers busy 10 s of 2 x 34.0 s"]
    out = tmp_path / "r"
    out.mkdir()
    (out / "summary.csv").write_text("case,verdict\na,within the claimed limit\nb,refused\n")
    lines = screen_lines("\n".join(breakdown), out)
    assert len(lines) == 3 and "step" not in "\n".join(lines)
    assert lines[0].startswith("time: 63.2 s wall") and str(out / "timing.txt") in lines[0]
    assert lines[1] == "slowest cases: a 4.0, b 2.0"
    assert lines[2].startswith("2 cases: 1 within the claimed limit, 1 refused")


PLUGIN_FAKE = """
import sys, types
from validation.run import cache
from validation.methods.base import NotApplicable

def run(case, requests, options):
    raise NotApplicable("cannot model a toy")

module = types.ModuleType("validation.methods.prbm")
module.run = run
sys.modules["validation.methods.prbm"] = module
cache.code_hash = lambda method: "fake"
"""


def test_the_pytest_plugin_says_a_refused_method_in_one_line(tmp_path):
    folder = tmp_path / "my_cases"
    folder.mkdir()
    write(folder, "toy.toml", GOOD.replace("values = [1.0, 2.0]", "values = [1.0, 2.0, 3.0]"))
    write(folder, "conftest.py", PLUGIN_FAKE)
    write(tmp_path, "pytest.ini", "[pytest]\n")
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "pytest",
            "-q",
            "-p",
            "no:cacheprovider",
            "-c",
            str(tmp_path / "pytest.ini"),
            str(folder),
        ],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
    )
    said = done.stdout
    assert done.returncode == 1, said + done.stderr
    assert f"toy ({folder / 'toy.toml'}), method prbm: refused: cannot model a toy\n" in said
    assert "nan" not in said.lower() and "did not give every value" not in said


def test_failed_sweep_points_are_named_with_where_the_rest_are(tmp_path, monkeypatch, capsys):
    from tests.validation.test_sweep import CASE, SPEC

    def run(case, requests, options):  # every point with E below 0.7 fails (E_factor 0.5 and 0.67)
        if case.segment.E < 0.7:
            return MethodRun(values={}, converged=False, message=f"no convergence at E = {case.segment.E:g}")
        return MethodRun(values={r: 1.0 for r in requests}, converged=True)

    module = types.ModuleType("validation.methods.elastica")
    module.run = run
    monkeypatch.setitem(sys.modules, "validation.methods.elastica", module)
    write(tmp_path, "toy.toml", CASE)
    spec = write(tmp_path, "toy_sweep.toml", SPEC.replace("samples = 100", "samples = 2"))  # 20 points
    out = tmp_path / "sweep"
    assert main(["sweep", str(spec), "--out", str(out), "--serial", "--quiet", "--no-plot"]) == 1
    lines = capsys.readouterr().out.splitlines()
    named = [line for line in lines if line.startswith("  failed: point ")]
    assert len(named) == 3 and all("E_factor = 0.5" in line or "E_factor = 0.66" in line for line in named)
    assert all("toy_cantilever elastica not_converged: no convergence at E = " in line for line in named)
    assert f"1 more; every failed point with its parameters and message: {out / 'failed.csv'}" in "\n".join(lines)
    failed = (out / "failed.csv").read_text().splitlines()
    assert len(failed) == 1 + 4 and failed[0] == "point_id,E_factor,segment.length,case,method,status,message"


def test_solve_json_gives_units_and_rounds_to_the_methods_precision(capsys):
    assert main(["solve", "cantilever_tip_load", "--method", "fem", "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["units"] == "dimensionless"  # the unit system, as before
    assert document["output_units"] == {"x@tip": "L", "y@tip": "L", "rotation@tip": "deg"}
    assert "significant digits" in document["rounding"]
    for level in document["levels"]:
        outputs = level["outputs"]
        for name in ("x@tip", "y@tip", "rotation@tip"):
            value, estimate = outputs[name], outputs[f"{name}:error_estimate"]
            assert estimate == float(f"{estimate:.2g}")  # two significant digits
            # the value rounded at the estimate's second significant digit
            assert value == round(value, 1 - math.floor(math.log10(estimate)))
        # derived: a load of 10 significant digits prints in fewer than 17 characters (no 0.6000000000000001)
        assert all(len(repr(load["value"])) < 17 for load in level["loads"])


def test_solve_rounds_float_noise_off_values_without_an_estimate():
    """The arguments are arbitrary doubles (input, not output); each expected number is derived by hand:
    the argument cut at its 10th significant digit, or at its estimate's second."""

    assert significant(0.6000000000000001) == 0.6 and significant(0.1 + 0.2) == 0.3
    assert significant(123456.78901234567) == 123456.789 and significant(0.0) == 0.0
    assert to_estimate(0.9435690686275944, 2.3042253422348815e-06) == 0.9435691
    assert to_estimate(26.433658768641116, 1.392330092408294e-04) == 26.43366


def test_a_misspelled_case_field_gets_the_nearest_name(tmp_path):
    path = write(
        tmp_path,
        "typo.toml",
        GOOD.replace("length = 10.0", "lenght = 10.0").replace(
            "values = [1.0, 2.0]", "values = [1.0, 2.0]\nvaleus = 3"
        ),
    )
    with pytest.raises(CaseError) as info:
        load_case(path)
    lines = str(info.value).splitlines()
    assert f"{path}: segment.lenght: unknown field; did you mean 'length'?" in lines
    assert f"{path}: loads.0.valeus: unknown field; did you mean 'values'?" in lines
    assert not any("segment.length: Field required" in line for line in lines)  # the typo explains it
    far = write(tmp_path, "far.toml", GOOD.replace("length = 10.0", "length = 10.0\nzzzz = 1"))
    with pytest.raises(CaseError) as info:
        load_case(far)
    assert "segment.zzzz: unknown field; valid: " in str(info.value) and "length" in str(info.value)


def test_pytest_comes_with_the_package_for_its_plugin():
    """README command 1 installs the package alone, then `pytest my_cases/` runs the plugin: pytest is a
    main dependency (with pytest-xdist, which this repository's pytest settings use), not only the test extra's."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    names = {dep.split(">")[0].split("=")[0].split("[")[0].strip() for dep in project["dependencies"]}
    assert {"pytest", "pytest-xdist"} <= names
    assert project["entry-points"]["pytest11"] == {"prbm_validate": "validation.pytest_plugin"}
    readme = (ROOT / "README.md").read_text()
    install = readme[readme.index("## The two commands") : readme.index("## Everyday use")]
    assert "pytest my_cases/" in install and "pip install -q -e . &&" in install


def test_the_help_of_every_verb_names_its_options(capsys):
    for verb in ("solve", "report"):
        assert main([verb, "--help"]) == 0
    text = capsys.readouterr().out
    assert "the JSON on one line" in textwrap.dedent(text) and "folder of the report" in text
