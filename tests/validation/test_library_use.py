"""The harness as a library: the pytest plugin on case files it has never seen, the Python API,
the tidy tables against their one schema, and the README's examples."""

from __future__ import annotations

import doctest
import re
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

import validation.run.api
from validation.run import tables
from validation.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
CANTILEVER = (ROOT / "cases" / "benchmarks" / "cantilever_tip_load.toml").read_text()
EXACT_Y_10 = "value = 0.810609"  # exact elastica y/L at PL^2/EI = 10 (notes/anchors.md 2.1)


def user_case(tmp_path: Path, name: str, text: str) -> Path:
    folder = tmp_path / "my_cases"
    folder.mkdir(exist_ok=True)
    path = folder / name
    path.write_text(text.replace('id = "cantilever_tip_load"', f'id = "{Path(name).stem}"'))
    return path


def run_pytest(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    """``pytest -q ARGS`` in a fresh interpreter in ``cwd``, as a user runs it (the plugin found through its
    ``pytest11`` entry point); hypothesis's and pytest-benchmark's plugins, which a case-file run never
    uses, are not loaded (a few CPU-seconds of imports on the shared machine)."""
    return subprocess.run(
        [
            sys.executable,
            "-m",
            "pytest",
            "-q",
            "-p",
            "no:cacheprovider",
            "-p",
            "no:hypothesispytest",
            "-p",
            "no:benchmark",
            *args,
        ],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=300,
    )


UNIFORM = (ROOT / "cases" / "benchmarks" / "cantilever_uniform_load.toml").read_text()


def _uniform_files(tmp_path: Path) -> None:
    """The second test's files: a case asking a one-spring PRBM (model = 'theta-dependent') for a distributed
    load, which only the Chain Algorithm takes, and the same case recording that refusal as its expected
    outcome."""
    asks_prbm = UNIFORM.replace('model = "chain"', 'model = "theta-dependent"')
    assert asks_prbm != UNIFORM
    expects = asks_prbm.replace(
        'group = "benchmarks"',
        'group = "benchmarks"\nexpected_failure = { prbm = "no seed PRBM for a distributed load" }',
    )
    assert expects != asks_prbm
    user_case(tmp_path, "refused.toml", asks_prbm.replace('id = "cantilever_uniform_load"', 'id = "refused"'))
    user_case(tmp_path, "expected.toml", expects.replace('id = "cantilever_uniform_load"', 'id = "expected"'))


@pytest.fixture(scope="module")
def plugin_run(tmp_path_factory) -> subprocess.CompletedProcess:
    """One ``pytest my_cases/ --case-method elastica --case-method prbm -rA`` over the files of both plugin
    tests (one interpreter start instead of two; the tests share an xdist group, so it runs once)."""
    tmp_path = tmp_path_factory.mktemp("plugin")
    assert EXACT_Y_10 in CANTILEVER
    user_case(tmp_path, "true_claim.toml", CANTILEVER)
    user_case(tmp_path, "false_claim.toml", CANTILEVER.replace(EXACT_Y_10, "value = 0.891670"))  # +10 %
    user_case(
        tmp_path,
        "bad.toml",
        CANTILEVER.replace("length = 1.0", "length = -1.0").replace("E = 1.0", "E = 1.0\nlenght = 2.0"),
    )
    (tmp_path / "my_cases" / "notes.toml").write_text("[tool]\nx = 1\n")  # not a case file: not collected
    _uniform_files(tmp_path)
    return run_pytest("my_cases/", "--case-method", "elastica", "--case-method", "prbm", "-rA", cwd=tmp_path)


def _outcomes(out: str) -> set[str]:
    """The short summary's 'PASSED/FAILED item' lines (without the reason after ' - ')."""
    return {line.split(" - ")[0] for line in out.splitlines() if line.startswith(("PASSED ", "FAILED "))}


@pytest.mark.xdist_group("plugin_run")
def test_plugin_passes_a_true_claim_and_fails_a_false_one(plugin_run):
    """``pytest my_cases/`` on files the project has never seen: one item per case and method."""
    done, out = plugin_run, plugin_run.stdout
    assert done.returncode == 1, out + done.stderr
    # one item per (case file, method it lists and the run chose), one for a bad file, none for notes.toml
    assert _outcomes(out) == {
        "PASSED my_cases/true_claim.toml::true_claim[elastica]",
        "FAILED my_cases/false_claim.toml::false_claim[elastica]",
        # the PRBM's own check (its agreement with the elastica) holds in both: the false claim is the elastica's
        "PASSED my_cases/true_claim.toml::true_claim[prbm]",
        "PASSED my_cases/false_claim.toml::false_claim[prbm]",
        "FAILED my_cases/bad.toml::input",
        "PASSED my_cases/refused.toml::refused[elastica]",
        "FAILED my_cases/refused.toml::refused[prbm]",
        "PASSED my_cases/expected.toml::expected[elastica]",
        "PASSED my_cases/expected.toml::expected[prbm]",
    }
    assert "3 failed, 6 passed" in out
    # the message a person reads: quantity, point, level and load with unit, value, reference, error,
    # tolerance, source
    assert (
        "y at tip, level 9, force at tip = 10 EI/L^2: 0.810609 L against exact 0.89167; error 0.0811 abs, "
        "0.0909 rel; tolerance abs 2e-06; source notes/anchors.md, section 2.1"
    ) in out
    # a bad file is one failing item listing every problem
    assert "segment.length: Input should be greater than 0" in out
    assert "segment.lenght: unknown field; did you mean 'length'?" in out


def test_plot_against_load_from_the_table_alone(tmp_path):
    """PRBM and FEM against load with no TOML reading and no de-duplication."""
    path = user_case(tmp_path, "mine.toml", CANTILEVER)
    assert (
        main(["run", str(path), "--method", "prbm", "--method", "elastica", "--quiet", "--out", str(tmp_path / "out")])
        == 0
    )
    values = tables.read(tmp_path / "out" / "values.parquet", "values")
    tip = values[(values["quantity"] == "y") & (values["point"] == "tip")]
    curve = tip.pivot(index="load_value", columns="method", values="value")  # raises on duplicates
    assert list(curve.index) == [float(p) for p in range(1, 11)]  # the file's ramp 1..10, read from the table
    assert set(tip["load_unit"]) == {"EI/L^2"} and set(tip["load"]) == {"force at tip"}
    assert curve.loc[10.0, "elastica"] == pytest.approx(0.810609, abs=2e-6)  # exact, anchors 2.1
    assert curve["prbm"].is_monotonic_increasing


@pytest.mark.parametrize("kind", ["csv", "parquet"])
def test_written_tables_match_the_one_schema(tmp_path, kind):
    path = user_case(tmp_path, "mine.toml", CANTILEVER)
    assert main(["run", str(path), "--method", "elastica", "--quiet", "--out", str(tmp_path / "out")]) == 0
    for name, columns in tables.SCHEMA.items():
        raw = (
            pd.read_csv(tmp_path / "out" / f"{name}.csv")
            if kind == "csv"
            else pd.read_parquet(tmp_path / "out" / f"{name}.parquet")
        )
        assert list(raw.columns)[: len(columns)] == [c.name for c in columns], name
        typed = tables.read(tmp_path / "out" / f"{name}.{kind}", name)
        for col in columns:
            assert str(typed[col.name].dtype) == str(pd.Series([], dtype=col.dtype).dtype), (name, col.name)
    comparisons = tables.read(tmp_path / "out" / "comparisons.parquet", "comparisons")
    assert comparisons["within_tolerance"].dtype == "boolean" and comparisons["within_tolerance"].all()
    values = tables.read(tmp_path / "out" / "values.csv", "values")
    assert not values.duplicated(["case", "method", "quantity", "point", "level"]).any()


def test_readme_documents_the_schema():
    readme = (ROOT / "README.md").read_text()
    for name, columns in tables.SCHEMA.items():
        match = re.search(rf"^`{name}`[^\n]*: (`[^\n]+)$", readme, re.MULTILINE)
        assert match, f"README lists no columns for {name}"
        assert re.findall(r"`([a-z_]+)`", match.group(1)) == [c.name for c in columns], name


def test_api_and_readme_doctests():
    assert doctest.testmod(validation.run.api).failed == 0
    result = doctest.testfile(str(ROOT / "README.md"), module_relative=False)
    assert result.attempted >= 3 and result.failed == 0


def test_solve_json_has_the_loads(tmp_path, capsys):
    path = user_case(tmp_path, "mine.toml", CANTILEVER)
    assert (
        main(["solve", str(path), "--method", "prbm", "--method", "elastica", "--out", str(tmp_path / "s.json")]) == 0
    )
    import json

    document = json.loads((tmp_path / "s.json").read_text())
    assert [run["method"] for run in document["runs"]] == ["prbm", "elastica"]
    last = document["runs"][1]["levels"][-1]
    assert last["loads"] == [{"name": "force at tip", "value": 10.0, "unit": "EI/L^2", "direction": [0.0, 1.0]}]
    assert last["outputs"]["y@tip"] == pytest.approx(0.810609, abs=2e-6)  # exact, notes/anchors.md 2.1


def test_every_named_load_as_a_column():
    """Table 3.1's load combination (P and a moment per level) as columns beside each value."""
    result = validation.run.api.validate(
        ROOT / "cases" / "chapter3" / "table3_1_load_combination.toml", methods=["prbm"]
    )
    wide = result.values_with_loads
    columns = [c for c in wide.columns if c.endswith("]")]
    assert columns == ["-M (printed M > 0 is clockwise, opposing P) [lbf*in]", "P [lbf]"]
    last = wide[wide["level"] == 2].iloc[0]
    assert last["P [lbf]"] == 6.652 and last["-M (printed M > 0 is clockwise, opposing P) [lbf*in]"] == -71.16
    assert len(wide) == len(result.values)


@pytest.mark.xdist_group("plugin_run")
def test_plugin_judges_like_the_suite_expected_failures_and_unchecked(plugin_run):
    """The plugin applies the suite's rule (compare.verdict_by_method): the PRBM has no one-spring model
    for a distributed load (only the Chain Algorithm takes it), so a case asking a one-spring PRBM for one
    fails, unless the case records that refusal as its expected outcome
    (``_uniform_files``); the FEM's item is judged on its own checks either way."""
    done = plugin_run
    out = done.stdout
    assert done.returncode == 1, out + done.stderr
    assert "FAILED my_cases/refused.toml::refused[prbm]" in out
    assert "method prbm: refused: " in out  # one line: the verdict and its reason
    assert "PASSED my_cases/expected.toml::expected[prbm]" in out
    assert "PASSED my_cases/refused.toml::refused[elastica]" in out
