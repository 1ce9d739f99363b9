"""One exit-status rule for every verb (validation/run/exit_status.py): 0 all good, 1 a comparison
outside tolerance or a method that failed, refused or did not converge, 2 bad input.

The harness logic is tested with fake adapters (the solvers are not what is under test here); one
test runs a real solver end to end."""

from __future__ import annotations

import json
import sys
import types
from pathlib import Path

import pytest

from validation.run import cache
from validation.cli.main import main
from validation.run.exit_status import RULE, ExitStatus, combine, of_run_status
from validation.methods.base import Misconfigured, MethodRun, NotApplicable, RunStatus

from tests.validation.test_foundation import GOOD  # the toy cantilever with one PRBM claim

BEHAVIOURS = {
    "ok": lambda levels, requests: MethodRun(values={r: 2.0 * levels[r.level] for r in requests}),
    "not converged": lambda levels, requests: MethodRun(
        values={r: 2.0 * levels[r.level] for r in requests}, converged=False, message="no convergence at level 1"
    ),
    "refuses": lambda levels, requests: (_ for _ in ()).throw(NotApplicable("cannot model a toy")),
    "crashes": lambda levels, requests: (_ for _ in ()).throw(RuntimeError("singular matrix")),
    "misconfigured": lambda levels, requests: (_ for _ in ()).throw(Misconfigured("option 'x': unknown")),
}


@pytest.fixture
def fake(monkeypatch):
    """A fake 'prbm' adapter (y = 2 * load) whose behaviour the test picks."""
    state = {"behaviour": "ok"}

    def run(case, requests, options):
        return BEHAVIOURS[state["behaviour"]](case.loads[0].levels(), requests)

    module = types.ModuleType("validation.methods.prbm")
    module.run = run
    monkeypatch.setitem(sys.modules, "validation.methods.prbm", module)
    monkeypatch.setattr(cache, "code_hash", lambda method: "fake")
    return state


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_rule_combines_largest_and_maps_run_status():
    assert combine([0, 1, 2, 0]) is ExitStatus.BAD_INPUT and combine([]) is ExitStatus.OK
    assert combine([1, 130]) is ExitStatus.INTERRUPTED
    assert [of_run_status(s) for s in RunStatus] == [0, 1, 1, 1, 2, 1]  # timed out: 1, as a failed run


def test_rule_is_in_help(capsys):
    assert main(["--help"]) == 0
    assert "exit status" in capsys.readouterr().out
    for verb in ("run", "solve", "list", "report", "bench", "stress"):
        assert main([verb, "--help"]) == 0
        assert " ".join(capsys.readouterr().out.split()).endswith(RULE)


@pytest.mark.parametrize(
    "behaviour, expected", [("ok", 0), ("not converged", 1), ("refuses", 1), ("crashes", 1), ("misconfigured", 2)]
)
def test_run_and_solve_exit_by_method_status(tmp_path, capsys, fake, behaviour, expected):
    fake["behaviour"] = behaviour
    path = write(tmp_path, "toy.toml", GOOD)
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--quiet", "--no-cache"]) == expected
    out = capsys.readouterr().out
    if expected:  # the summary says which case and method, and why, in words
        assert any("toy" in line and "prbm" in line for line in out.splitlines()[-6:])
    assert main(["solve", str(path), "--method", "prbm"]) == expected
    document = json.loads(capsys.readouterr().out)
    assert (
        document["status"]
        == {
            "ok": "ok",
            "not converged": "not converged",
            "refuses": "not applicable",
            "crashes": "failed",
            "misconfigured": "misconfigured",
        }[behaviour]
    )


def test_run_and_solve_exit_1_on_tolerance_and_2_on_bad_case(tmp_path, capsys, fake):
    off = write(tmp_path, "off.toml", GOOD.replace("value = 4.0", "value = 4.4"))  # 10 % off
    assert main(["run", str(off), "--out", str(tmp_path / "o"), "--quiet"]) == 1
    bad = write(tmp_path, "bad.toml", GOOD.replace("length = 10.0", "length = -10.0"))
    assert main(["run", str(bad), "--out", str(tmp_path / "o"), "--quiet"]) == 2
    assert main(["solve", str(bad), "--method", "prbm"]) == 2
    assert main(["list", str(bad)]) == 2 and main(["list", str(off)]) == 0
    assert main(["run", "no_such_case_anywhere", "--out", str(tmp_path / "o"), "--quiet"]) == 2


@pytest.mark.parametrize(
    "option, words",
    [
        ("elemnts = 8", "methods.fem.elemnts: unknown option of method 'fem'; nearest: elements"),
        ('elements = "many"', "methods.fem.elements: Input should be a valid integer"),
    ],
)
def test_misspelled_or_mistyped_option_exits_2_naming_it(tmp_path, capsys, option, words):
    text = GOOD.replace("[methods.prbm]", f"[methods.fem]\n{option}").replace('compare = "prbm"', 'compare = "fem"')
    path = write(tmp_path, "opt.toml", text)
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--quiet"]) == 2
    assert words in capsys.readouterr().err
    assert main(["solve", str(path)]) == 2


def test_report_follows_the_rule(tmp_path, capsys, fake):
    from validation.report.build import build_report

    good = write(tmp_path, "toy.toml", GOOD)
    assert build_report(tmp_path / "r", use_cache=False, jobs=1, cases=[str(good)]) == 0
    fake["behaviour"] = "refuses"
    assert build_report(tmp_path / "r", use_cache=False, jobs=1, cases=[str(good)]) == 1
    said = [line for line in capsys.readouterr().out.splitlines() if line.startswith("not ok: toy")]
    assert said and all("prbm" in line for line in said) and any("cannot model a toy" in line for line in said)
    bad = write(tmp_path, "bad.toml", GOOD.replace("E = 30e6", "E = -1"))
    assert build_report(tmp_path / "r", use_cache=False, jobs=1, cases=[str(bad)]) == 2


def test_bench_stress_sweep_synthesize_bad_input_exit_2(tmp_path, capsys):
    blocker = write(tmp_path, "file", "not a folder")
    assert main(["bench", "--out", str(blocker / "x"), "--quick"]) == 2
    assert main(["stress", "--out", str(blocker / "x")]) == 2
    assert main(["sweep", str(write(tmp_path, "s.toml", "[sweep]\nid = 1\n"))]) == 2
    assert main(["synthesize", str(write(tmp_path, "spec.toml", "nonsense = 1\n"))]) == 2
    assert "Traceback" not in capsys.readouterr().err


def test_real_solver_end_to_end(tmp_path, capsys):
    """The elastica on the cantilever: a true claim exits 0, the same claim 10 % off exits 1."""
    source = Path(__file__).resolve().parents[2] / "cases" / "benchmarks" / "cantilever_tip_load.toml"
    text = source.read_text()
    assert (
        main(
            [
                "run",
                str(write(tmp_path, "c.toml", text)),
                "--method",
                "elastica",
                "--quiet",
                "--out",
                str(tmp_path / "o"),
            ]
        )
        == 0
    )
    wrong = text.replace("value = 0.810609", "value = 0.891670")  # 10 % above the exact 0.810609
    assert wrong != text
    assert (
        main(
            [
                "run",
                str(write(tmp_path, "w.toml", wrong)),
                "--method",
                "elastica",
                "--quiet",
                "--out",
                str(tmp_path / "o"),
            ]
        )
        == 1
    )


@pytest.mark.parametrize("behaviour, expected", [("ok", 0), ("not converged", 1), ("refuses", 1)])
def test_sweep_follows_the_rule(tmp_path, monkeypatch, behaviour, expected):
    from tests.validation.test_sweep import CASE, SPEC

    from validation.sweep.run import run_sweep

    def run(case, requests, options):
        return BEHAVIOURS[behaviour]([1.0, 2.0], requests)

    module = types.ModuleType("validation.methods.elastica")
    module.run = run
    monkeypatch.setitem(sys.modules, "validation.methods.elastica", module)
    (tmp_path / "toy.toml").write_text(CASE)
    spec = write(
        tmp_path,
        "toy_sweep.toml",
        SPEC.replace("samples = 100", "samples = 2").replace(
            "linspace = { start = 0.5, stop = 2.0, num = 10 }", "values = [1.0]"
        ),
    )
    assert run_sweep(spec, tmp_path / "out", executor="serial", progress=False) == expected


def test_unknown_method_option_on_the_command_line_exits_2(tmp_path, capsys):
    path = write(tmp_path, "toy.toml", GOOD)
    assert main(["run", str(path), "--method", "femm", "--quiet", "--out", str(tmp_path / "o")]) == 2
    assert "--method femm: unknown method; nearest: fem" in capsys.readouterr().err
    assert main(["solve", str(path), "--method", "fem"]) == 2  # the case does not ask for it
