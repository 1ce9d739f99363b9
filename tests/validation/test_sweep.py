"""Sweeps: 1,000 points locally and on a Dask LocalCluster, resume, bad specs, failed points.

The method is a fake 'elastica' adapter (the linear cantilever tip deflection y = P L^3 / 3EI),
injected into ``sys.modules``; forked pool workers and in-process Dask workers inherit it.
"""

from __future__ import annotations

import json
import math
import sys
import time
import types
from pathlib import Path

import pytest

from validation.methods.base import MethodRun
from validation.cli import sweep as sweep_verb
from validation.cli.arguments import build_parser
from validation.sweep.run import SpecError, load_results, load_spec, make_points, run_sweep
from validation.case.overrides import apply

CASE = """
[case]
id = "toy_cantilever"
title = "toy"
group = "tests"
units = "dimensionless"

[segment]
boundary = "fixed-free"
length = 1.0
E = 1.0
section = { kind = "inertia", I = 1.0, A = 1.0e6 }

[[loads]]
kind = "force"
direction = [0.0, 1.0]
ramp = { start = 0.5, stop = 1.0, count = 2 }

[[outputs]]
quantity = "y"

[methods.elastica]
"""

# 10 grid values x 100 samples = 1,000 points
SPEC = """
[sweep]
id = "toy_sweep"
title = "toy sweep"
case = "toy.toml"
methods = ["elastica"]
samples = 100
seed = 7

[[parameters]]
path = "segment.E"
mode = "scale"
linspace = { start = 0.5, stop = 2.0, num = 10 }
name = "E_factor"

[[parameters]]
path = "segment.length"
distribution = { kind = "truncnormal", mean = 1.0, std = 0.05, low = 0.9, high = 1.1 }

[plot]
kind = "domain"
"""


@pytest.fixture
def fake(monkeypatch):
    """The fake adapter; ``fake.calls`` counts calls made in this process."""
    state = types.SimpleNamespace(calls=0, interrupt_at=None, fail_when=None)

    def run(case, requests, options):
        state.calls += 1
        if state.interrupt_at is not None and state.calls >= state.interrupt_at:
            raise KeyboardInterrupt
        seg = case.segment
        if state.fail_when is not None and state.fail_when(seg):
            raise RuntimeError("diverged on purpose")
        levels = case.loads[0].levels()
        direction = case.loads[0].direction
        values = {r: levels[r.level] * direction[1] * seg.length**3 / (3 * seg.bending_stiffness()) for r in requests}
        return MethodRun(values=values, converged=True)

    module = types.ModuleType("validation.methods.elastica")
    module.run = run
    monkeypatch.setitem(sys.modules, "validation.methods.elastica", module)
    return state


@pytest.fixture
def spec(tmp_path) -> Path:
    (tmp_path / "toy.toml").write_text(CASE)
    path = tmp_path / "toy_sweep.toml"
    path.write_text(SPEC)
    return path


def _runs(out: Path) -> list[dict]:
    return [json.loads(line) for line in (out / "runs.jsonl").read_text().splitlines()]


def _sorted(frame):
    return frame.sort_values(["point_id", "level"]).reset_index(drop=True)


def test_thousand_points_locally_and_on_dask_identical(spec, tmp_path, fake):
    from distributed import Client, LocalCluster

    started = time.perf_counter()
    assert run_sweep(spec, tmp_path / "local", executor="process", workers=2, progress=False) == 0
    local_time = time.perf_counter() - started
    with (
        LocalCluster(n_workers=2, processes=False, threads_per_worker=1, dashboard_address=None) as cluster,
        Client(cluster) as client,
    ):
        started = time.perf_counter()
        assert run_sweep(spec, tmp_path / "dask", executor=client, progress=False) == 0
        dask_time = time.perf_counter() - started
    local, dask = _sorted(load_results(tmp_path / "local")), _sorted(load_results(tmp_path / "dask"))
    assert local["point_id"].nunique() == 1000 and len(local) == 2000
    assert (local["status"] == "ok").all()
    columns = ["point_id", "case", "sample", "level", "value", "E_factor", "segment.length", "status"]
    assert local[columns].equals(dask[columns])
    # the fake's formula at one point: y = P L^3 / (3 E I)
    row = local.iloc[0]
    expected = [0.5, 1.0][row["level"]] * row["segment.length"] ** 3 / (3 * row["E_factor"])
    assert row["value"] == pytest.approx(expected, rel=1e-12)
    print(
        f"\n1,000 points: local 2 processes {local_time:.2f} s, Dask LocalCluster (2 in-process workers) "
        f"{dask_time:.2f} s"
    )


def test_resume_after_a_partial_run_recomputes_nothing(spec, tmp_path, fake):
    out = tmp_path / "out"
    assert run_sweep(spec, out, executor="serial", progress=False, limit=300) == 0
    assert fake.calls == 300
    assert load_results(out)["point_id"].nunique() == 300
    assert run_sweep(spec, out, executor="serial", progress=False) == 0
    assert fake.calls == 1000  # the 300 done points were not run again
    last = _runs(out)[-1]
    assert (last["skipped"], last["ran"], last["left"]) == (300, 700, 0)
    frame = load_results(out)
    assert frame["point_id"].nunique() == 1000 and len(frame) == 2000
    assert run_sweep(spec, out, executor="serial", progress=False) == 0
    assert fake.calls == 1000 and _runs(out)[-1]["ran"] == 0


def test_interrupted_sweep_keeps_what_finished_and_resumes(spec, tmp_path, fake, capsys):
    out = tmp_path / "out"
    fake.interrupt_at = 455  # Ctrl-C in the middle of the 455th point
    assert run_sweep(spec, out, executor="serial", progress=False, chunk=10) == 130
    assert "run the same command again to resume" in capsys.readouterr().err
    saved = load_results(out)["point_id"].nunique()
    assert saved == 450  # every finished chunk of 10 was written on the way out
    fake.interrupt_at, fake.calls = None, 0
    assert run_sweep(spec, out, executor="serial", progress=False) == 0
    assert fake.calls == 1000 - saved
    frame = load_results(out)
    assert frame["point_id"].nunique() == 1000 and not frame.duplicated(["point_id", "level"]).any()


def test_failed_points_are_recorded_with_their_message(spec, tmp_path, fake):
    text = spec.read_text().replace("linspace = { start = 0.5, stop = 2.0, num = 10 }", "values = [-1.0, 1.0, 3.0]")
    spec.write_text(text)
    fake.fail_when = lambda seg: seg.E == 3.0
    out = tmp_path / "out"
    assert run_sweep(spec, out, executor="serial", progress=False) == 1  # finished, with failed points
    frame = load_results(out)
    assert frame["point_id"].nunique() == 300  # none dropped
    invalid = frame[frame["E_factor"] == -1.0]
    assert (invalid["status"] == "invalid").all() and len(invalid) == 100
    assert invalid["message"].iloc[0] == "segment.E: Input should be greater than 0"
    failed = frame[frame["E_factor"] == 3.0]
    assert (failed["status"] == "error").all()
    assert failed["message"].str.contains("RuntimeError: diverged on purpose").all()
    assert (frame[frame["E_factor"] == 1.0]["status"] == "ok").all()
    assert _runs(out)[-1]["failed"] == 200


BAD = {
    "not TOML": (lambda s: s.replace("[sweep]", "[sweep"), "", "not valid TOML"),
    "unknown field": (
        lambda s: s.replace("seed = 7", "seed = 7\nsed = 8"),
        "sweep.sed",
        "unknown field; did you mean 'seed'?",
    ),
    "unknown method": (
        lambda s: s.replace('methods = ["elastica"]', 'methods = ["fea"]'),
        "sweep",
        "unknown method 'fea'",
    ),
    "normal without std": (
        lambda s: s.replace(
            'kind = "truncnormal", mean = 1.0, std = 0.05, low = 0.9, high = 1.1', 'kind = "normal", mean = 1.0'
        ),
        "parameters.1.distribution",
        "needs 'std'",
    ),
    "two sources": (lambda s: s.replace("num = 10 }", "num = 10 }\nvalues = [1.0]"), "parameters.0", "exactly one of"),
    "no samples": (lambda s: s.replace("samples = 100\n", ""), "(top level)", "need 'sweep.samples'"),
    "path not in case": (
        lambda s: s.replace('path = "segment.length"', 'path = "segment.lenght"'),
        "parameters.1.path",
        "case 'toy_cantilever': 'segment.lenght': no such field",
    ),
    "path into a value": (
        lambda s: s.replace('path = "segment.length"', 'path = "segment.E.x"'),
        "parameters.1.path",
        "segment.E is a value",
    ),
    "list index": (
        lambda s: s.replace('path = "segment.length"', 'path = "loads.3.values"'),
        "parameters.1.path",
        "no item 3",
    ),
    "unknown case id": (
        lambda s: s.replace('case = "toy.toml"', 'case = "test2_four_bar_nonexistent"'),
        "sweep.case",
        "no case file under cases/ has id 'test2_four_bar_nonexistent'",
    ),
    "missing case file": (lambda s: s.replace('case = "toy.toml"', 'case = "nowhere.toml"'), "sweep.case", "not found"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_spec_gives_one_line_naming_file_and_field(spec, capsys, name):
    edit, field, words = BAD[name]
    spec.write_text(edit(SPEC))
    with pytest.raises(SpecError) as info:
        load_spec(spec)
    message = str(info.value)
    assert "\n" not in message and message.startswith(str(spec))
    assert f": {field}: " in message or not field
    assert words in message
    assert run_sweep(spec, spec.parent / "out", progress=False) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"error: {message}"]


def test_cli_subcommand_runs_and_plots(spec, tmp_path, fake, capsys):
    parser = build_parser()
    (tmp_path / "toy.toml").write_text(CASE.replace('quantity = "y"', 'quantity = "x"\n[[outputs]]\nquantity = "y"'))
    text = spec.read_text().replace("samples = 100", "samples = 3")
    spec.write_text(text)
    out = tmp_path / "cli"
    args = parser.parse_args(["sweep", str(spec), "--out", str(out), "--serial", "--quiet"])
    assert sweep_verb.run(args) == 0
    assert (out / "domain.png").is_file()
    assert "plot:" in capsys.readouterr().out


def test_random_draws_are_seeded_prefix_stable_and_truncated(spec, tmp_path):
    (tmp_path / "toy.toml").write_text(CASE)
    small = make_points(load_spec(spec))
    spec.write_text(SPEC.replace("samples = 100", "samples = 150"))
    large = make_points(load_spec(spec))
    assert [p["id"] for p in small] == [p["id"] for p in large if p["sample"] < 100]
    lengths = [p["values"]["segment.length"] for p in large]
    assert 0.9 <= min(lengths) and max(lengths) <= 1.1
    assert abs(sum(lengths) / len(lengths) - 1.0) < 0.01


def test_parameter_modes():
    data = {
        "segment": {"E": 2.0, "section": {"thickness": 0.1}},
        "loads": [
            {"kind": "force", "direction": [0.0, 2.0], "values": [1.0, 2.0]},
            {"kind": "force", "direction": [1.0, 0.0], "ramp": {"start": 1.0, "stop": 3.0, "count": 3}},
        ],
        "methods": {"fem": {}},
    }
    apply(data, "segment.E", "scale", 1.5)
    apply(data, "segment.section.thickness", "offset", -0.02)
    apply(data, "loads.0", "scale", 2.0)
    apply(data, "loads.1.ramp", "scale", 0.5)
    apply(data, "loads.0.direction", "angle", 180.0)
    apply(data, "methods.fem.elements", "set", 8)
    assert data["segment"]["E"] == 3.0
    assert data["segment"]["section"]["thickness"] == pytest.approx(0.08)
    assert data["loads"][0]["values"] == [2.0, 4.0]
    assert data["loads"][1]["ramp"] == {"start": 0.5, "stop": 1.5, "count": 3}
    assert data["loads"][0]["direction"] == pytest.approx([-2.0, 0.0], abs=1e-12)
    assert data["methods"]["fem"]["elements"] == 8
    assert math.isclose(data["loads"][1]["ramp"]["stop"], 1.5)


def test_a_killed_worker_s_points_are_retried_on_resume_and_counted(spec, tmp_path, fake, capsys):
    """A pool worker killed mid-sweep (os._exit in the task) breaks the pool: the points of every task
    it took down are 'task_failed' (exit 1), not final outcomes. The same command again runs exactly
    those points, says how many were retried and how many failed again, and exits 0 only when every
    point has its own result; a crash that persists is counted as failed again (exit 1)."""
    import os

    out = tmp_path / "out"
    fake.fail_when = lambda seg: seg.E == 2.0 and os._exit(1)
    assert run_sweep(spec, out, executor="process", workers=2, progress=False, chunk=25) == 1
    first = load_results(out)
    lost = set(first.loc[first["status"] == "task_failed", "point_id"])
    assert lost and first["point_id"].nunique() == 1000
    assert first.loc[first["status"] == "task_failed", "message"].str.contains("BrokenProcessPool").all()
    assert "run the same command again to retry them" in capsys.readouterr().err

    assert run_sweep(spec, out, executor="process", workers=2, progress=False, chunk=25) == 1
    again = _runs(out)[-1]
    assert again["skipped"] == 1000 - len(lost) and again["retried"] == len(lost) and again["task_failed"] > 0
    assert f"{len(lost)} retried after a failed task" in capsys.readouterr().out

    fake.fail_when, fake.calls = None, 0
    assert run_sweep(spec, out, executor="serial", progress=False) == 0
    last = _runs(out)[-1]
    assert last["ran"] == fake.calls and last["task_failed"] == 0 and last["retried"] == last["ran"] > 0
    frame = load_results(out)
    assert frame["point_id"].nunique() == 1000 and (frame["status"] == "ok").all() and len(frame) == 2000
    assert "0 of them failed again" in capsys.readouterr().out
