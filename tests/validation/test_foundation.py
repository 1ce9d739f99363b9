"""Schema, loader, runner, cache and CLI of the harness (the solvers are faked here)."""

from __future__ import annotations

import json
import sys
import types
from pathlib import Path

import pytest

from validation.run import cache
from validation.cli.main import main
from validation.case.loader import CaseError, find_case_files, load_case
from validation.methods.base import MethodRun, NotApplicable
from validation.run.case_run import run_case
from validation.run.runner import requests_for
from validation.run.outcome import run_cases, tabulate

GOOD = """
[case]
id = "toy"
title = "toy cantilever"
group = "tests"
units = "in-lb"

[segment]
boundary = "fixed-free"
length = 10.0
E = 30e6
section = { kind = "rectangle", width = 0.5, thickness = 0.0625 }

[[loads]]
kind = "force"
direction = [0.0, 1.0]
values = [1.0, 2.0]

[[outputs]]
quantity = "y"

[methods.prbm]

[[references]]
quantity = "y"
level = 1
value = 4.0
label = "PRBM"
source = { file = "000_x.txt", table = "9.9", row = "2", column = "b" }
compare = "prbm"
tolerance = { rel = 1e-3 }
"""


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.fixture
def fake_prbm(monkeypatch):
    """A fake 'prbm' adapter: y = 2 * load, counting its calls."""
    calls = []

    def run(case, requests, options):
        calls.append(len(requests))
        levels = case.loads[0].levels()
        return MethodRun(values={r: 2.0 * levels[r.level] for r in requests}, converged=True)

    module = types.ModuleType("validation.methods.prbm")
    module.run = run
    monkeypatch.setitem(sys.modules, "validation.methods.prbm", module)
    monkeypatch.setattr(cache, "code_hash", lambda method: "fake")
    return calls


def test_good_case_loads_and_derives(tmp_path):
    case = load_case(write(tmp_path, "good.toml", GOOD)).case
    assert case.n_levels() == 2
    assert case.segment.bending_stiffness() == pytest.approx(
        30e6 * 0.5 * 0.0625**3 / 12
    )  # derived: E w h^3/12 of the case file
    assert case.unit("length") == "in" and case.unit("moment") == "lbf*in"


BAD = {
    "not TOML": (GOOD.replace("[case]", "[case"), "", "not valid TOML"),
    "missing field": (GOOD.replace('title = "toy cantilever"\n', ""), "case.title", "Field required"),
    "wrong type": (GOOD.replace("length = 10.0", 'length = "ten"'), "segment.length", "valid number"),
    "zero E": (GOOD.replace("E = 30e6", "E = 0"), "segment.E", "greater than 0"),
    "negative length": (GOOD.replace("length = 10.0", "length = -1"), "segment.length", "greater than 0"),
    "zero thickness": (
        GOOD.replace("thickness = 0.0625", "thickness = 0"),
        "segment.section.thickness",
        "greater than 0",
    ),
    "unknown unit": (GOOD.replace('units = "in-lb"', 'units = "furlong"'), "case.units", "unknown unit system"),
    "output not given": (
        GOOD.replace('quantity = "y"\n\n[methods', 'quantity = "dof"\n\n[methods')
        .replace("[methods.prbm]", "[methods.elastica]")
        .replace('compare = "prbm"\n', "")
        .replace("tolerance = { rel = 1e-3 }\n", ""),
        "outputs.0",
        "method 'elastica' cannot give 'dof'",
    ),
    "NaN": (GOOD.replace("values = [1.0, 2.0]", "values = [1.0, nan]"), "loads.0.values.1", "finite"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_input_gives_one_line_naming_file_and_field(tmp_path, name):
    text, field, words = BAD[name]
    path = write(tmp_path, "bad.toml", text)
    with pytest.raises(CaseError) as info:
        load_case(path)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(str(path))
    assert field in message and words in message


@pytest.mark.parametrize("name", sorted(BAD))
def test_cli_bad_input_exit_2_and_good_cases_still_run(tmp_path, capsys, fake_prbm, name):
    good = write(tmp_path, "good.toml", GOOD)
    bad = write(tmp_path, "bad.toml", BAD[name][0])
    out = tmp_path / "out"
    status = main(["run", str(bad), str(good), "--out", str(out), "--quiet"])
    captured = capsys.readouterr()
    assert status == 2
    error_lines = [line for line in captured.err.splitlines() if line.startswith("error:")]
    assert len(error_lines) == 1 and str(bad) in error_lines[0]
    assert "Traceback" not in captured.err
    results = (out / "results.csv").read_text()
    assert "toy" in results  # the good case was run and written


def test_runner_table_and_tolerance(tmp_path, fake_prbm):
    loaded = load_case(write(tmp_path, "good.toml", GOOD))
    table = tabulate(run_case(loaded))
    row = table[(table["level"] == 1) & table["reference_value"].notna()].iloc[0]
    assert row["value"] == 4.0 and row["within_tolerance"] == True  # noqa: E712
    assert row["unit"] == "in" and "table 9.9" in row["source"]
    assert requests_for(loaded.case, "prbm")[0].quantity == "y"


def test_tolerance_violation_exits_1(tmp_path, fake_prbm):
    path = write(tmp_path, "off.toml", GOOD.replace("value = 4.0", "value = 4.1"))
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--quiet"]) == 1
    assert main(["run", str(write(tmp_path, "good.toml", GOOD)), "--out", str(tmp_path / "o"), "--quiet"]) == 0


def test_cache_hit_and_no_cache(tmp_path, fake_prbm):
    path = write(tmp_path, "good.toml", GOOD)
    run_cases([path])
    run_cases([path])
    assert len(fake_prbm) == 1  # second run served from the cache
    run_cases([path], use_cache=False)
    assert len(fake_prbm) == 2
    write(tmp_path, "good.toml", GOOD.replace("values = [1.0, 2.0]", "values = [1.0, 2.5]"))
    run_cases([path])
    assert len(fake_prbm) == 3  # changed content, new key


def test_not_applicable_is_recorded_not_skipped(tmp_path, monkeypatch):
    module = types.ModuleType("validation.methods.prbm")

    def run(case, requests, options):
        raise NotApplicable("no PRBM for this toy")

    module.run = run
    monkeypatch.setitem(sys.modules, "validation.methods.prbm", module)
    table = tabulate(run_case(load_case(write(tmp_path, "good.toml", GOOD)), use_cache=False))
    assert (table["message"].str.contains("not applicable: no PRBM for this toy")).all()
    assert (table["converged"] == False).all()  # noqa: E712


def test_solve_prints_json(tmp_path, capsys, fake_prbm):
    path = write(tmp_path, "good.toml", GOOD)
    assert main(["solve", str(path), "--method", "prbm", "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["levels"][1]["outputs"]["y@tip"] == 4.0


def test_every_shipped_case_file_is_valid():
    paths = find_case_files(None)
    assert paths, "no case files under cases/"
    ids = [load_case(p).id for p in paths]
    assert len(ids) == len(set(ids)), "case ids must be unique"
