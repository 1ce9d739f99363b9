"""Inputs held to their physical range before any solve, bounded work, and files that cannot be read.

Each bad input is a shipped case file with one field changed (as the fault campaign found them): it must
be refused by ``list`` (exit 2) in one ``error:`` line naming the file and the field, never reach a
solver. The ranges are ``validation/case/strict.py`` (finite, representable), ``validation/case/scale.py``
(on the case's own scale, and ``[limits]``) and ``validation/case/option_use.py`` (options a method would
not read)."""

from __future__ import annotations

import math
import signal
import sys
import time
import tomllib
import types
from pathlib import Path

import pandas as pd
import pytest
import tomli_w

from validation.case.loader import CASES_DIR, CaseError, find_case_files, load_case
from prbm import mechanisms
from validation.case import scale
from validation.case.scale import LOAD_LIMIT
from validation.case.schema import Case
from validation.cli.main import main
from validation.methods.base import RunStatus
from validation.run.exit_status import of_run_status
from validation.run.case_run import run_case
from validation.run.runner import run_method

CANTILEVER = CASES_DIR / "benchmarks" / "cantilever_tip_load.toml"
FOUR_BAR = CASES_DIR / "chapter6" / "example3.toml"  # PRB four-bar with springs k1..k4
SLIDER = CASES_DIR / "chapter7" / "example1.toml"  # slider mechanism, ma = {F_i, d_i}, joint springs
STRIP = CASES_DIR / "seed004" / "strip_moment_prbm.toml"  # a quick PRBM-only segment


def mutated(tmp_path: Path, source: Path, change, name: str = "bad.toml") -> Path:
    """``source`` with ``change(data)`` applied, written to ``tmp_path / name``."""
    data = tomllib.loads(source.read_text())
    change(data)
    path = tmp_path / name
    path.write_text(tomli_w.dumps(data))
    return path


def refused(path: Path, capsys) -> list[str]:
    """``list path`` exits 2; its error lines (each naming the file)."""
    assert main(["list", str(path)]) == 2
    lines = [line for line in capsys.readouterr().err.splitlines() if line.startswith("error: ")]
    assert lines and all(line.startswith(f"error: {path}: ") for line in lines), lines
    return lines


def reference(quantity="y", level=9, value=999.0, **tolerance) -> dict:
    return {
        "quantity": quantity,
        "level": level,
        "value": value,
        "label": "exact",
        "source": {"file": "x"},
        "compare": "elastica",
        "tolerance": tolerance,
    }


def test_an_infinite_spring_is_refused_naming_it(tmp_path, capsys):
    path = mutated(tmp_path, FOUR_BAR, lambda d: d["methods"]["prbm"]["springs"].__setitem__("k2", math.inf))
    lines = refused(path, capsys)
    assert len(lines) == 1 and "methods.prbm.springs.k2: " in lines[0] and "finite" in lines[0]


def test_a_negative_spring_is_refused_naming_it(tmp_path, capsys):
    path = mutated(tmp_path, FOUR_BAR, lambda d: d["methods"]["prbm"]["springs"].__setitem__("k3", -79.1763))
    lines = refused(path, capsys)
    assert len(lines) == 1 and "methods.prbm.springs.k3: " in lines[0] and "greater than or equal to 0" in lines[0]
    path = mutated(tmp_path, SLIDER, lambda d: d["mechanism"]["joints"][0].__setitem__("spring", -8.4515))
    assert any(
        "mechanism.joints.0.spring: " in line and "greater than or equal to 0" in line for line in refused(path, capsys)
    )


@pytest.mark.parametrize(
    "tolerance, words",
    [
        ({"abs": math.inf}, "finite"),
        ({"abs": 1e50}, "characteristic length"),
        ({"rel": math.inf}, "finite"),
        ({"rel": 5.0}, "less than 1"),
    ],
)
def test_a_tolerance_that_accepts_anything_is_refused(tmp_path, capsys, tolerance, words):
    # a printed 999 against a true 0.81: within an infinite (or 1e50 L, or 500 %) tolerance it would pass
    path = mutated(tmp_path, CANTILEVER, lambda d: d.__setitem__("references", [reference(**tolerance)]))
    lines = refused(path, capsys)
    field = f"references.0.tolerance.{next(iter(tolerance))}: "
    assert any(field in line and words in line for line in lines), lines


@pytest.mark.parametrize(
    "F_i, words",
    [(1e-300, "representable range"), (1e-9, "stiffest spring"), (0.0, "greater than 0"), (-10.0, "greater than 0")],
)
def test_an_input_force_the_mechanical_advantage_divides_by_is_not_tiny(tmp_path, capsys, F_i, words):
    path = mutated(tmp_path, SLIDER, lambda d: d["methods"]["prbm"]["ma"].__setitem__("F_i", F_i))
    lines = refused(path, capsys)
    assert len(lines) == 1 and "methods.prbm.ma.F_i: " in lines[0] and words in lines[0], lines


def test_ten_million_load_levels_are_refused_before_they_are_built(tmp_path, capsys):
    path = mutated(tmp_path, CANTILEVER, lambda d: d["loads"][0]["ramp"].__setitem__("count", 10**7))
    start = time.perf_counter()
    lines = refused(path, capsys)
    assert time.perf_counter() - start < 5.0  # 10^7 levels built would take seconds and gigabytes
    assert len(lines) == 1 and "loads.0.ramp.count: 10000000 load levels exceed the limit of 1000" in lines[0]
    assert "limits.levels" in lines[0]


def test_the_limits_table_raises_a_limit(tmp_path, capsys):
    def more_levels(data):
        data["loads"][0]["ramp"]["count"] = 1500
        data["limits"] = {"levels": 2000}
        data["references"], data["agreements"] = [], []

    assert load_case(mutated(tmp_path, CANTILEVER, more_levels)).case.n_levels() == 1500
    path = mutated(tmp_path, CANTILEVER, lambda d: d.__setitem__("limits", {"levels": 10**9}))
    assert any("limits.levels: " in line for line in refused(path, capsys))


def test_a_mesh_over_the_element_limit_is_refused(tmp_path, capsys):
    path = mutated(tmp_path, CANTILEVER, lambda d: d["methods"]["fem"].__setitem__("elements", 10_000))
    lines = refused(path, capsys)
    assert any(
        "methods.fem.elements: the finest mesh has 640000 elements, over the limit of 100000" in line for line in lines
    ), lines


@pytest.mark.parametrize(
    "E, field, words",
    [
        (1e-300, "segment.E: ", "representable range"),
        (1e-50, "loads.0.ramp: ", "non-dimensional load P L^2/EI = 1e+51"),
    ],
)
def test_a_vanishing_modulus_is_refused_before_the_elastica(tmp_path, capsys, E, field, words):
    path = mutated(tmp_path, CANTILEVER, lambda d: d["segment"].__setitem__("E", E))
    lines = refused(path, capsys)
    assert any(field in line and words in line for line in lines), lines


def test_every_shipped_case_is_inside_its_ranges_and_the_load_limit_is_sharp():
    for path in find_case_files(None):
        load_case(path)  # raises CaseError naming the file and the field otherwise
    # P L^2/EI = 1e4 accepted, 1.0001e4 refused (the shipped cases reach ~47)
    data = tomllib.loads(CANTILEVER.read_text())
    data["references"], data["agreements"] = [], []
    for stop, ok in ((LOAD_LIMIT, True), (1.0001 * LOAD_LIMIT, False)):
        data["loads"][0]["ramp"]["stop"] = stop
        try:
            Case.model_validate(data)
            accepted = True
        except ValueError:
            accepted = False
        assert accepted is ok, stop


@pytest.mark.parametrize(
    "change, field",
    [
        (lambda d: d["methods"]["fem"].__setitem__("arc_length", 0.1), "methods.fem.arc_length: "),
        (lambda d: d["methods"]["fem"].__setitem__("rtol", 1e300), "methods.fem.rtol: "),
        (lambda d: d["methods"]["fem"].__setitem__("inextensible_ratio", 1e6), "methods.fem.inextensible_ratio: "),
        (lambda d: d["methods"]["elastica"].__setitem__("b", [0.5] * 10), "methods.elastica.b: "),
        (lambda d: d["methods"]["prbm"].__setitem__("springs", {"k1": 1.0}), "methods.prbm.springs: "),
    ],
)
def test_an_option_the_method_does_not_use_or_cannot_use_is_an_error(tmp_path, capsys, change, field):
    lines = refused(mutated(tmp_path, CANTILEVER, change), capsys)
    assert any(field in line for line in lines), lines


@pytest.mark.parametrize("case_id", ["..", "a" * 5000, "../escape", "-leading-dash", "with space"])
def test_an_unsafe_id_is_refused_naming_the_field(tmp_path, capsys, case_id):
    lines = refused(mutated(tmp_path, CANTILEVER, lambda d: d["case"].__setitem__("id", case_id)), capsys)
    assert len(lines) == 1 and ": case.id: " in lines[0] and "not a valid id" in lines[0]
    assert len(lines[0]) < 400  # a 5,000-character id is not repeated whole


CHAPTER7 = CASES_DIR / "chapter7"
TEST2 = CASES_DIR / "chapter9" / "test2_dead_force.toml"


def _set(*path_and_value):
    """A change that sets data[path...] = value."""
    *path, value = path_and_value

    def change(data):
        node = data
        for key in path[:-1]:
            node = node[key]
        node[path[-1]] = value

    return change


# shipped case files with one value changed (NaN, inf, 0, negative, 1e300, 1e-300, a wrong shape): each was
# accepted and then failed inside a solve with a raw exception (or, for the support, crashed the load itself)
MUTANTS = [
    (
        "length 1e300: OverflowError in the PRBM and the elastica",
        CANTILEVER,
        _set("segment", "length", 1e300),
        "segment.length: ",
    ),
    (
        "length 1e-300: ZeroDivisionError in the FEM and the elastica",
        CANTILEVER,
        _set("segment", "length", 1e-300),
        "segment.length: ",
    ),
    (
        "A 1e-300: ZeroDivisionError in the FEM",
        CANTILEVER,
        _set("segment", "section", "A", 1e-300),
        "segment.section.A: ",
    ),
    (
        "elements 1e12: MemoryError, 7.28 TiB",
        CANTILEVER,
        _set("methods", "fem", "elements", 10**12),
        "methods.fem.elements: ",
    ),
    (
        "slider direction [0, 0]: 'SVD did not converge' while loading",
        SLIDER,
        _set("mechanism", "supports", 1, "direction", [0.0, 0.0]),
        "mechanism.supports.1.direction: ",
    ),
    (
        "precision psi as one number: TypeError 'float' object is not iterable",
        CHAPTER7 / "example2.toml",
        _set("methods", "prbm", "precision", "psi", 30.0),
        "methods.prbm.precision.psi: ",
    ),
    (
        "precision phi one short: a four-bar driven through fewer positions than levels",
        CHAPTER7 / "example2.toml",
        _set("methods", "prbm", "precision", "phi", [0.0, 20.0]),
        "methods.prbm.precision.phi: 2 values for 3",
    ),
    (
        "link r1 zeroed: ValueError, the four-bar loop does not close",
        FOUR_BAR,
        _set("methods", "prbm", "links", "r1", [0.0, 0.0]),
        "methods.prbm.links: the four-bar loop",
    ),
    (
        "free level 0.0: IndexError of a float index",
        TEST2,
        _set("methods", "prbm", "free_levels", [0.0]),
        "methods.prbm.free_levels.0: ",
    ),
    (
        "free level past the last: silently dropped",
        TEST2,
        _set("methods", "prbm", "free_levels", [7]),
        "methods.prbm.free_levels: level 7",
    ),
    (
        "flexure thickness ratio 1e-300: ZeroDivisionError building the SLFP",
        CHAPTER7 / "example3.toml",
        _set("methods", "fem", "slfp", "thickness_ratio", 1e-300),
        "methods.fem.slfp.thickness_ratio: ",
    ),
    (
        "a finding re-run with an infinite modulus",
        CANTILEVER,
        lambda d: d["references"][0].__setitem__("finding", {"text": "t", "reproduce_with": {"segment.E": 1e300}}),
        "references.0.finding.reproduce_with: ",
    ),
    (
        "a load with no levels: refused for itself, not through the levels of the references",
        CANTILEVER,
        lambda d: d["loads"][0].update({"values": []}) or d["loads"][0].pop("ramp"),
        "loads.0.values: ",
    ),
]


@pytest.mark.parametrize("what, source, change, field", MUTANTS, ids=[m[0].split(":")[0] for m in MUTANTS])
def test_a_mutant_that_failed_in_a_solve_is_refused_at_load(tmp_path, capsys, what, source, change, field):
    lines = refused(mutated(tmp_path, source, change), capsys)
    assert any(field in line for line in lines), lines


def test_a_slider_travel_the_links_cannot_reach_is_bad_input_not_a_crash():
    # r3 mirrored: the slider cannot reach 0.6 in; a ValueError of prbm.SliderCrank before (status 'failed', exit 1)
    data = tomllib.loads(SLIDER.read_text())
    data["methods"]["prbm"]["links"]["r3"] = [-2.6704, -2.2408]
    run = run_method(Case.model_validate(data), "prbm")
    assert run.status is RunStatus.MISCONFIGURED and of_run_status(run.status) == 2
    assert run.message.startswith("misconfigured: methods.prbm: links r11, r2, r3") and "cannot reach" in run.message


def test_the_loop_rule_is_the_four_bars_own():
    assert scale.LOOP_TOLERANCE == mechanisms.LOOP_TOLERANCE


def copies(tmp_path: Path) -> Path:
    """A folder with two good case files and one that is not UTF-8 text."""
    folder = tmp_path / "cases"
    folder.mkdir()
    (folder / "a_good.toml").write_text(STRIP.read_text())
    (folder / "b_latin1.toml").write_bytes(
        STRIP.read_text()
        .replace('id = "seed004_prbm_strip_moment"', 'id = "latin1"')
        .replace("Seed", "S\u00e9ed")
        .encode("latin-1")
    )
    (folder / "c_good.toml").write_text(
        STRIP.read_text().replace('id = "seed004_prbm_strip_moment"', 'id = "second_good"')
    )
    return folder


def test_a_file_that_is_not_utf8_is_one_error_line_and_the_others_are_listed(tmp_path, capsys):
    folder = copies(tmp_path)
    with pytest.raises(CaseError) as info:
        load_case(folder / "b_latin1.toml")
    assert "not UTF-8 text" in str(info.value)
    assert main(["list", str(folder)]) == 2
    out, err = capsys.readouterr()
    assert "seed004_prbm_strip_moment" in out and "second_good" in out
    errors = err.splitlines()
    assert len(errors) == 1 and errors[0].startswith(f"error: {folder / 'b_latin1.toml'}: not UTF-8 text")


def test_a_file_that_is_not_utf8_does_not_stop_a_run(tmp_path, capsys):
    folder = copies(tmp_path)
    out = tmp_path / "out"
    assert main(["run", str(folder), "--method", "prbm", "--out", str(out), "--quiet", "--no-cache"]) == 2
    errors = [line for line in capsys.readouterr().err.splitlines() if line.startswith("error:")]
    assert len(errors) == 1 and "b_latin1.toml: not UTF-8 text" in errors[0]
    runs = pd.read_csv(out / "runs.csv")
    assert set(runs["case"]) == {"seed004_prbm_strip_moment", "second_good"} and (runs["status"] == "ok").all()


def test_a_case_over_its_wall_time_stops_timed_out_and_the_others_run(tmp_path, capsys):
    folder = tmp_path / "cases"
    folder.mkdir()
    (folder / "quick.toml").write_text(STRIP.read_text())
    slow = tomllib.loads(CANTILEVER.read_text())
    slow["case"]["id"] = "over_its_limit"
    slow["limits"] = {"seconds": 1e-6}  # over before its first method has run
    (folder / "slow.toml").write_text(tomli_w.dumps(slow))
    out = tmp_path / "out"
    assert main(["run", str(folder), "--out", str(out), "--quiet", "--no-cache"]) == 1
    runs = pd.read_csv(out / "runs.csv")
    timed = runs[runs["case"] == "over_its_limit"]
    assert set(timed["method"]) == {"fem", "prbm", "elastica"} and (timed["status"] == "timed out").all()
    assert timed["message"].str.contains(r"wall-time limit of 1e-06 s \(\[limits\] seconds\)").all()
    assert (runs[runs["case"] == "seed004_prbm_strip_moment"]["status"] == "ok").all()
    assert "over_its_limit fem: timed out" in capsys.readouterr().out


def test_a_method_past_the_limit_is_stopped_even_inside_its_own_except_exception(tmp_path, monkeypatch):
    """A fake PRBM adapter that would run 30 s and turns every Exception of a level into a message (as the
    solvers' level loops do) is stopped at the case's 0.3 s; the method after it is not run."""

    def endless(case, requests, options):
        for _ in range(3000):
            try:
                time.sleep(0.01)
            except Exception:  # noqa: BLE001 - what a level loop does; TimedOut is not an Exception
                continue
        raise AssertionError("not stopped")

    monkeypatch.setitem(sys.modules, "validation.methods.prbm", types.SimpleNamespace(run=endless))
    data = tomllib.loads(STRIP.read_text())
    data["limits"] = {"seconds": 0.3}
    data["methods"] = {"prbm": {}, "elastica": {}}
    path = tmp_path / "endless.toml"
    path.write_text(tomli_w.dumps(data))
    handler, start = signal.getsignal(signal.SIGALRM), time.perf_counter()
    result = run_case(load_case(path), use_cache=False)
    assert time.perf_counter() - start < 5.0
    assert signal.getsignal(signal.SIGALRM) == handler and signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)
    prbm, elastica = result.runs["prbm"], result.runs["elastica"]
    assert prbm.status is RunStatus.TIMED_OUT and prbm.message.startswith("timed out: stopped at")
    assert 0.25 < prbm.wall_time < 3.0
    assert elastica.status is RunStatus.TIMED_OUT and "not run" in elastica.message
