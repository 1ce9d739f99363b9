"""The benchmark runs and writes its files, and its headline is honest (timings are measured there,
never asserted here: a whole ``run_bench`` times each configuration its minimum number of runs,
``bench_minimum_runs`` in tests/validation/conftest.py)."""

import json

import pandas as pd
import pytest

from dataclasses import asdict

from validation.bench import headline as bench
from validation.bench.opensees_script import SCRIPT
from validation.methods.base import MethodRun, Request


@pytest.mark.usefixtures("bench_minimum_runs")
def test_bench_quick_writes_csv_json_and_plots(tmp_path):
    cases = {"cantilever_tip_load": [0, 9], "no_such_case": None}
    # an unknown case is bad input (exit status 2, validation/run/exit_status.py); the others still run
    assert bench.run_bench(tmp_path, quick=True, cases=cases, max_elements=8) == 2
    headline = json.loads((tmp_path / "headline.json").read_text())
    assert any("no_such_case" in s for s in headline["skipped"])
    frame = pd.read_csv(tmp_path / "bench.csv")
    assert set(frame.columns) >= {"case", "method", "elements", "time_s", "error", "iterations", "peak_memory_mb"}
    assert frame["elements"].max() <= 8
    plain = frame[frame["method"] == "fem"].sort_values("elements")
    assert plain["error"].is_monotonic_decreasing  # O(h^2): each doubling cuts the error
    figures = sorted(p.name for p in tmp_path.glob("*.png"))
    assert figures == ["cantilever_tip_load_error_vs_time.png", "time_vs_elements.png"], figures


@pytest.mark.usefixtures("bench_minimum_runs")
def test_unavailable_peer_is_reported_as_unavailable_not_as_did_not_reach(tmp_path, monkeypatch):
    monkeypatch.setattr(bench, "_peer_status", lambda: "peer unavailable: OpenSeesPy cannot be imported (test)")
    one = [bench.BenchCase("cantilever_tip_load", [0], single_level=True)]
    bench.run_bench(tmp_path, quick=True, cases=one, max_elements=4, plots=False)
    headline = json.loads((tmp_path / "headline.json").read_text())
    for entry in headline["fem_over_opensees_time_at_error"].values():
        assert entry["note"].startswith("peer unavailable") and entry["ratio"] is None
    frame = pd.read_csv(tmp_path / "bench.csv")
    assert not frame["method"].str.startswith("opensees").any()


def test_richardson_step_removes_an_h_squared_error():
    # u_n = a + c/n^2: the step u_2n + (u_2n - u_n)/3 gives a exactly
    r = Request("y", "tip", 0)
    a, c, n = 0.75, 0.3, 8
    coarse, fine = MethodRun(values={r: a + c / n**2}), MethodRun(values={r: a + c / (2 * n) ** 2})
    assert bench._richardson(coarse, fine)[r] == pytest.approx(a, abs=1e-15)


def test_last_level_only_keeps_the_last_load_and_its_references():
    case = bench.case_by_id("cantilever_tip_load").case
    single = bench._last_level_only(case)
    assert single.n_levels() == 1
    assert single.loads[0].levels() == [case.loads[0].levels()[-1]]
    last = case.n_levels() - 1
    assert {(r.quantity, r.value) for r in single.references} == {
        (r.quantity, r.value) for r in case.references if r.level == last
    }


def test_per_iteration_times_the_load_stepping_of_both_codes_within_their_runs():
    # the stepping time (Newton iterations and step control, set-up and results left out) is part of
    # the run: positive and at most the whole run's CPU time, for our FEM and for the peer alike
    case = bench._last_level_only(bench.case_by_id("cantilever_tip_load").case)
    cost = bench._per_iteration(case, bench.BENCH_CASES[0], 2, bench._peer_status() == "", 8)
    entry = cost["8"]
    for method in ("fem", bench.PEER) if bench._peer_status() == "" else ("fem",):
        assert 0.0 < entry[method]["analysis_s"] <= entry[method]["time_s"]
        assert entry[method]["loop_per_iteration_s"] == entry[method]["analysis_s"] / entry[method]["iterations"]


def test_the_per_iteration_ratio_is_also_given_in_consecutive_parts_of_the_timing(monkeypatch, capsys):
    """The whole-run ratio per Newton iteration beside its value in each of NOISE_BLOCKS consecutive
    parts of the timing (`_part_bests` of each code's runs in the order they ran): fem 8 iterations,
    bests 8, 4, 6 us by part; the peer 9 iterations, 9, 9, 3 us: per iteration 1, 0.5, 0.75 over 1, 1,
    1/3, the parts' ratios 1, 0.5 and 2.25; the whole timing's (4/8)/(3/9) = 1.5."""

    def timing(times, its):
        run = MethodRun(values={"x": 1.0}, extras={"iterations": its})
        return bench.Timing(run, min(times), 0.0, len(times), 0, analysis=min(times) / 2, times=tuple(times))

    fake = {
        "fem": timing([8e-6, 9e-6, 4e-6, 5e-6, 7e-6, 6e-6], 8),
        bench.PEER: timing([9e-6, 9e-6, 9e-6, 9e-6, 3e-6, 4e-6], 9),
    }
    monkeypatch.setattr(bench, "_timed_in_turn", lambda subs, repeats, budget=None, memory=True: fake)
    case = bench._last_level_only(bench.case_by_id("cantilever_tip_load").case)
    entry = bench._per_iteration(case, bench.BENCH_CASES[0], 2, True, 8)["8"]
    assert entry["ratio"] == pytest.approx(1.5, rel=1e-12)
    assert entry["ratio_parts"] == pytest.approx([1.0, 0.5, 2.25], rel=1e-12)
    assert bench._part_bests((1.0, 2.0)) == [] and bench._part_bests((3.0, 1.0, 2.0)) == [3.0, 1.0, 2.0]
    bench._print_headline({"fem_over_opensees_time_at_error": {}, "per_iteration": {"8": entry}})
    line = next(x for x in capsys.readouterr().out.splitlines() if x.strip().startswith("n="))
    assert line == (
        "  n=   8: fem 0.5 us run / 0.2 us stepping (8 it), opensees 0.3 us run / 0.2 us stepping (9 it), "
        "ratio 1.50 run (in 3 consecutive parts of the timing 1.00 0.50 2.25) / 1.50 stepping"
    )


def test_the_two_codes_take_turns_mesh_by_mesh():
    """`_interleaved` steps each code's sweep one mesh at a time in turn (so a slow period of the machine
    falls on both codes' rows), runs the longer sweep to its end, and returns each sweep's result."""
    from validation.bench.headline import _interleaved

    order = []

    def sweep(name, meshes):
        for n in meshes:
            order.append((name, n))
            yield
        return [f"{name} rows"], []

    got = _interleaved({"fem": sweep("fem", [2, 4, 8]), "opensees": sweep("opensees", [2, 4])})
    assert order == [("fem", 2), ("opensees", 2), ("fem", 4), ("opensees", 4), ("fem", 8)]
    assert got == {"fem": (["fem rows"], []), "opensees": (["opensees rows"], [])}


def test_the_per_iteration_timings_take_turns_run_by_run(monkeypatch):
    """`_timed_in_turn` times the codes run by run in turn, the order reversed every round (A B, B A,
    ...), after one warm-up each; a configuration whose warm-up is slow is timed once; each code's
    best, median and stepping time come from its own runs."""
    order, cpu = [], {"fem": iter([3.0, 1.0, 2.0]), "opensees": iter([5.0, 4.0, 6.0]), "slow": iter([9.0])}

    def run_method(case, method):
        return MethodRun(values={}, wall_time=1.0 if method == "slow" else 1e-3)

    def one_run(case, method):
        order.append(method)
        return MethodRun(values={}, extras={"analysis_cpu_s": 0.5}), next(cpu[method])

    monkeypatch.setattr(bench, "run_method", run_method)
    monkeypatch.setattr(bench, "_one_run", one_run)
    monkeypatch.setattr(bench, "TIME_BUDGET_S", 2e-3)  # a 1 ms run: 2 fit, so the minimum of 3 counts
    got = bench._timed_in_turn({"fem": None, "opensees": None, "slow": None}, 3)
    assert order == ["fem", "opensees", "slow", "opensees", "fem", "fem", "opensees"]
    assert (got["fem"].best, got["fem"].median, got["fem"].repeats) == (1.0, 2.0, 3)
    assert (got["opensees"].best, got["opensees"].median) == (4.0, 5.0)
    assert (got["slow"].best, got["slow"].repeats, got["fem"].analysis) == (9.0, 1, 0.5)


def test_a_fast_configuration_is_timed_as_often_as_fits_in_the_budget(monkeypatch):
    """The number of timed runs: one for a configuration slower than SLOW_RUN_S; for a fast one as many
    as fit in TIME_BUDGET_S (50 ms: 50 of a 1 ms run, 500 capped at MAX_REPEATS for 0.1 ms), never
    fewer than ``repeats``; and `_timed_in_turn` runs each code that often, in turn."""
    monkeypatch.setattr(bench, "TIME_BUDGET_S", 0.05)
    monkeypatch.setattr(bench, "MAX_REPEATS", 200)
    assert bench._rounds(0.5, 5) == 1
    assert bench._rounds(0.02, 5) == 5
    assert bench._rounds(1e-3, 5) == 50
    assert bench._rounds(1e-4, 5) == 200
    counts = {"fem": 0, "opensees": 0}

    def run_method(case, method):
        return MethodRun(values={}, wall_time={"fem": 1e-3, "opensees": 2.5e-3}[method])

    def one_run(case, method):
        counts[method] += 1
        return MethodRun(values={}), 1.0

    monkeypatch.setattr(bench, "run_method", run_method)
    monkeypatch.setattr(bench, "_one_run", one_run)
    got = bench._timed_in_turn({"fem": None, "opensees": None}, 3)
    assert counts == {"fem": 50, "opensees": 20}
    assert (got["fem"].repeats, got["opensees"].repeats) == (50, 20)


@pytest.mark.usefixtures("bench_minimum_runs")
def test_both_codes_are_offered_the_same_richardson_step_on_their_plain_runs(tmp_path):
    """Issue 15 item 1: the same post-processing for both codes. Each code's n and 2n plain runs are
    extrapolated by the bench (``paired_label``: ``fem+richardson (plain runs)`` beside the FEM's own
    ``fem+richardson``, ``opensees+richardson``): such a row is at n, costs the best times of the plain
    runs at n and 2n together, and the headline chooses among all of our rows. The plain-script peer
    (``opensees-script``) gets the same rows, with the adapter's errors (the same answers), and the
    headline's second ratio."""
    one = [bench.BenchCase("cantilever_tip_load", [0], single_level=True)]
    bench.run_bench(tmp_path, quick=True, cases=one, max_elements=16, plots=False)
    frame = pd.read_csv(tmp_path / "bench.csv")
    codes = ("fem", *bench.PEERS) if bench._peer_status() == "" else ("fem",)
    for code in codes:
        plain = frame[frame["method"] == code].set_index("elements")
        paired = frame[frame["method"] == bench.paired_label(code)].set_index("elements")
        assert sorted(paired.index) == [2, 4, 8]
        for n, row in paired.iterrows():
            assert row["time_s"] == pytest.approx(plain.loc[n, "time_s"] + plain.loc[2 * n, "time_s"], rel=1e-12)
            assert row["iterations"] == plain.loc[n, "iterations"] + plain.loc[2 * n, "iterations"]
            assert row["error"] < plain.loc[2 * n, "error"]  # the step improves on the finer run
    assert bench.paired_label("fem") != "fem+richardson"  # the FEM's own row stays beside it
    headline = json.loads((tmp_path / "headline.json").read_text())
    entry = headline["fem_over_opensees_time_at_error"]["cantilever_tip_load (last level only) @ 0.0001 L"]
    if entry["fem"] is not None:
        ours = frame[frame["method"].isin([*bench.OURS, bench.paired_label("fem")]) & (frame["error"] <= 1e-4)]
        assert entry["fem"]["time_s"] == pytest.approx(ours["time_s"].min(), rel=1e-12)
    if bench._peer_status() == "":  # the headline ratio: both configurations re-timed in turn
        again = entry["confirmed"]
        assert entry["ratio"] == pytest.approx(again["fem_s"] / again["opensees_s"], rel=1e-12)
        assert entry["ladder_ratio"] == pytest.approx(entry["fem"]["time_s"] / entry["opensees"]["time_s"])
        script = entry["script"]  # the second ratio: the same FEM configuration over the plain script's
        assert script["ratio"] == pytest.approx(again["fem_s"] / again["script_s"], rel=1e-12)
        assert script["ladder_ratio"] == pytest.approx(entry["fem"]["time_s"] / script["script"]["time_s"])
        assert script["retimed"]["method"].startswith(SCRIPT) and script["note"] == ""
        by_mesh = {m: frame[frame["method"] == m].set_index("elements") for m in bench.PEERS}
        assert list(by_mesh[SCRIPT].index) == list(by_mesh[bench.PEER].index)
        assert (by_mesh[SCRIPT]["error"] - by_mesh[bench.PEER]["error"]).abs().max() <= 1e-9
        assert by_mesh[SCRIPT]["peak_memory_mb"].isna().all()  # OpenSees' own memory: not Python's


def test_the_headline_prints_both_ratios_a_row(capsys):
    """Each headline row in two lines: our time over the adapter's (``fem/opensees``) with both
    configurations, then over the plain script's (``fem/script``) with the script's configuration and its
    re-timing in the same turns; a row without a script ratio says why. The per-iteration table gives the
    plain script's line under each mesh's."""
    config = dict(method="opensees-script+richardson", elements=8, time_s=3e-4, error=2e-5, iterations=18)
    fem = dict(method="fem", elements=64, time_s=6e-4, error=3e-5, iterations=9)
    peer = dict(method="opensees+richardson", elements=8, time_s=5e-4, error=2e-5, iterations=18)
    again = dict(
        ratio=1.1,
        fem_s=6e-4,
        fem=fem,
        opensees_s=5.5e-4,
        opensees=peer,
        candidates=5,
        repeats=9,
        block_ratios=[],
        script_s=3.5e-4,
        script=dict(config, time_s=3.5e-4),
        script_ratio=6 / 3.5,
        script_block_ratios=[1.7, 1.8, 1.7],
    )
    script = bench.ScriptRatio(6 / 3.5, 2.0, config, again["script"], (1.7, 1.8, 1.7), "")
    entry = dict(ratio=1.1, ladder_ratio=1.2, confirmed=again, fem=fem, opensees=peer, note="", reference="elastica")
    missing = bench.ScriptRatio(None, None, None, None, (), "plain script unavailable: a curved segment")
    per_iteration = dict(fem=dict(per_iteration_s=4e-5, loop_per_iteration_s=1.3e-5, iterations=9))
    per_iteration |= {
        bench.PEER: dict(per_iteration_s=2.6e-5, loop_per_iteration_s=1.1e-5, iterations=9),
        SCRIPT: dict(per_iteration_s=1.35e-5, loop_per_iteration_s=1.0e-5, iterations=9),
        "ratio": 1.54,
        "loop_ratio": 1.18,
        "script_ratio": 2.96,
        "script_loop_ratio": 1.3,
    }
    bench._print_headline(
        {
            "fem_over_opensees_time_at_error": {
                "case @ 0.0001 L": entry | {"script": asdict(script)},
                "arch @ 0.0001 L": entry | {"script": asdict(missing)},
            },
            "per_iteration": {"8": per_iteration},
        }
    )
    lines = capsys.readouterr().out.splitlines()
    first = next(i for i, line in enumerate(lines) if line.strip().startswith("case @"))
    assert "fem/opensees   1.10" in lines[first] and "opensees: opensees+richardson n=8 0.50 ms" in lines[first]
    assert lines[first + 1].strip().startswith("fem/script     1.71   opensees-script: opensees-script+richardson n=8")
    assert "opensees-script opensees-script+richardson n=8 0.35 ms" in lines[first + 1]
    assert "1.70 1.80 1.70; sweep 2.00" in lines[first + 1]
    assert (
        lines[first + 3].strip()
        == "fem/script      -     opensees-script: -   [plain script unavailable: a curved segment]"
    )
    n8 = next(i for i, line in enumerate(lines) if line.strip().startswith("n=   8"))
    assert lines[n8 + 1].strip() == (
        "opensees-script 13.5 us run / 10.0 us stepping (9 it), fem/script ratio 2.96 run / 1.30 stepping"
    )


def test_a_case_the_plain_script_does_not_express_says_so_beside_the_adapters_rows():
    """The clamped-hinged arch (two curved beams, a limit load): the adapter builds arcs, the plain script
    only straight beams, so the adapter has rows and the script none, its note "plain script unavailable:
    ..." (never a number, never "did not reach")."""
    pytest.importorskip("openseespy.opensees")
    case = bench.case_by_id("arch_215_clamped_hinged").case
    one = bench.BenchCase("arch_215_clamped_hinged")
    exact = bench._exact(case, None)
    rows, skipped, notes = bench._sweep_codes(case, one, [2], 1, exact, 1.9, "")
    assert {row["method"] for row in rows} >= {"fem", bench.PEER}
    assert not any(row["method"].startswith(SCRIPT) for row in rows)
    assert set(notes) == {SCRIPT} and notes[SCRIPT].startswith("plain script unavailable: the curved beam")
    assert any(s.startswith(f"{one.label}/{SCRIPT} n=2: unavailable:") for s in skipped)


def test_the_plain_script_is_re_timed_in_turn_with_both_codes(monkeypatch):
    """The script's candidates join the re-timing (`_confirmed`): all three codes' runs take turns, and
    the script's fastest as re-timed gives the second ratio (fem 3.0 over the script's 1.0)."""
    case = bench._last_level_only(bench.case_by_id("cantilever_tip_load").case)
    one = bench.BenchCase("cantilever_tip_load", [0], single_level=True)
    order = []
    cpu = {("fem", 8): 1.0, ("fem", 16): 2.0, ("opensees", 16): 1.5, (SCRIPT, 16): 1.0}

    def elements(sub, method):
        return sub.elements if method == SCRIPT else sub.methods[method]["elements"]

    def one_run(sub, method):
        order.append((method, elements(sub, method)))
        return MethodRun(values={}), cpu[(method, elements(sub, method))]

    monkeypatch.setattr(bench, "_run", lambda sub, method: MethodRun(values={}, wall_time=1e-3))
    monkeypatch.setattr(bench, "_one_run", one_run)
    monkeypatch.setattr(bench, "HEADLINE_BUDGET_S", 3e-3)
    ours = [dict(method=bench.paired_label("fem"), elements=8)]
    got = bench._confirmed(
        case, one, ours, [dict(method=bench.PEER, elements=16)], 2, [dict(method=SCRIPT, elements=16)]
    )
    assert order[:4] == [("fem", 8), ("fem", 16), ("opensees", 16), (SCRIPT, 16)] and order[4:8] == order[:4][::-1]
    assert (got["ratio"], got["script_ratio"], got["script_s"], got["candidates"]) == (2.0, 3.0, 1.0, 3)
    assert got["script"]["method"] == SCRIPT and got["script_block_ratios"] == [3.0, 3.0, 3.0]


def test_the_plain_scripts_candidates_are_its_fastest_within_the_spread():
    """`_script_candidates`: of the script's CANDIDATES fastest in the sweep, those within CANDIDATE_SPREAD
    times its fastest (here 0.31 and 0.6 ms, not 0.63 or 0.92 ms); ours and the adapter's keep their
    three fastest whatever their spread."""
    rows = [
        (SCRIPT + "+richardson", 8, 0.31),
        (SCRIPT + "+richardson", 16, 0.63),
        (SCRIPT, 32, 0.6),
        (SCRIPT, 64, 0.92),
        (bench.PEER, 64, 1.0),
        (bench.PEER, 128, 4.0),
        (bench.PEER, 256, 9.0),
    ]
    frame = pd.DataFrame([dict(method=m, elements=n, time_s=t * 1e-3, error=1e-5, iterations=1) for m, n, t in rows])
    assert [(c["method"], c["elements"]) for c in bench._script_candidates(frame, 1e-4)] == [
        (SCRIPT + "+richardson", 8),
        (SCRIPT, 32),
    ]
    assert len(bench._candidates(frame, 1e-4)[1]) == 3


def test_the_headline_configurations_are_timed_again_in_turn(monkeypatch):
    """The headline ratio comes from the two fastest configurations timed again with the runs of both
    taking turns run by run (`_confirmed`), each as often as fits in the headline's budget (not the
    sweep's): a Richardson row on plain runs is its runs at n and 2n, its time their bests summed; the
    FEM's own n/2n solve is one run."""
    case = bench._last_level_only(bench.case_by_id("cantilever_tip_load").case)
    one = bench.BenchCase("cantilever_tip_load", [0], single_level=True)
    order = []
    cpu = {("fem", 8): 1.0, ("fem", 16): 2.0, ("opensees", 8): 0.5, ("opensees", 16): 1.5}

    def run_method(sub, method):
        return MethodRun(values={}, wall_time=1e-3)

    def one_run(sub, method):
        n = sub.methods[method]["elements"]
        order.append((method, n))
        return MethodRun(values={}), cpu[(method, n)]

    monkeypatch.setattr(bench, "run_method", run_method)
    monkeypatch.setattr(bench, "_one_run", one_run)
    monkeypatch.setattr(bench, "TIME_BUDGET_S", 2e-3)  # the sweep's: 2 runs of a 1 ms configuration
    monkeypatch.setattr(bench, "HEADLINE_BUDGET_S", 6e-3)  # the headline's: 6
    ours = dict(method=bench.paired_label("fem"), elements=8)
    peer = dict(method=bench.paired_label(bench.PEER), elements=8)
    got = bench._confirmed(case, one, [ours], [peer], 2)
    assert order[:4] == [("fem", 8), ("fem", 16), ("opensees", 8), ("opensees", 16)]
    assert order[4:8] == order[:4][::-1]  # every run in turn, the order reversed
    assert len(order) == 4 * 6 and got["repeats"] == 6
    assert (got["fem_s"], got["opensees_s"], got["ratio"]) == (3.0, 2.0, 1.5)
    own = bench._runs_of(case, one, dict(method="fem+richardson", elements=8))
    ((sub, method),) = own.values()
    assert method == "fem" and sub.methods["fem"]["richardson"] and sub.methods["fem"]["elements"] == 8


def test_the_headline_ratio_is_also_given_in_consecutive_parts_of_the_re_timing(monkeypatch):
    """Beside the re-timed ratio, the same ratio in each of NOISE_BLOCKS consecutive parts of the
    re-timing (`_block_ratios`): each label's runs, in the order they ran, cut into equal parts; per
    part each run's best, a Richardson row the sum of its two runs' bests. Six runs a label in three
    parts: fem n=8 bests 1.0, 2.0, 1.0 and n=16 2.0, 2.0, 4.0; the peer's n=8 0.5 throughout and n=16
    1.5, 1.0, 1.5: the parts' ratios 3/2, 4/1.5 and 5/2, the whole re-timing's (3.0/1.5) 2.0. A
    configuration timed fewer times than there are parts gives none."""
    case = bench._last_level_only(bench.case_by_id("cantilever_tip_load").case)
    one = bench.BenchCase("cantilever_tip_load", [0], single_level=True)
    cpu = {
        ("fem", 8): [1.0, 1.1, 2.0, 2.2, 1.0, 3.0],
        ("fem", 16): [2.0, 2.0, 2.0, 2.0, 4.0, 4.0],
        ("opensees", 8): [0.5] * 6,
        ("opensees", 16): [1.5, 1.5, 1.0, 1.0, 1.5, 1.5],
    }
    runs = {key: iter(times) for key, times in cpu.items()}
    monkeypatch.setattr(bench, "run_method", lambda sub, method: MethodRun(values={}, wall_time=1e-3))
    monkeypatch.setattr(
        bench,
        "_one_run",
        lambda sub, method: (MethodRun(values={}), next(runs[(method, sub.methods[method]["elements"])])),
    )
    monkeypatch.setattr(bench, "HEADLINE_BUDGET_S", 6e-3)  # six runs of a 1 ms configuration
    ours = dict(method=bench.paired_label("fem"), elements=8)
    peer = dict(method=bench.paired_label(bench.PEER), elements=8)
    got = bench._confirmed(case, one, [ours], [peer], 2)
    assert bench.NOISE_BLOCKS == 3 and got["ratio"] == 2.0
    assert got["block_ratios"] == pytest.approx([1.5, 4.0 / 1.5, 2.5], rel=1e-12)
    assert "1.50 2.67 2.50" in bench._noise(got)
    runs = {key: iter(times) for key, times in cpu.items()}
    monkeypatch.setattr(bench, "HEADLINE_BUDGET_S", 1e-3)  # two runs each (``repeats``): no parts
    got = bench._confirmed(case, one, [ours], [peer], 2)
    assert got["block_ratios"] == [] and bench._noise(got) == ""


def test_the_headline_takes_each_codes_fastest_candidate_as_re_timed(monkeypatch):
    """With several candidates per code (`_candidates`: the sweep's fastest that reach the error), every
    run of all of them takes turns, a run two candidates share is timed once, and each code's fastest
    as re-timed is the headline's: here the sweep put the plain run at 32 elements first (a slow period
    on the Richardson row's runs, say), and re-timed the Richardson row on the plain runs at 8 and 16
    (1 + 2 = 3) beats it (4); the peer's plain run at 16 (1.5), a run its Richardson row (0.5 + 1.5)
    shares, beats that row."""
    case = bench._last_level_only(bench.case_by_id("cantilever_tip_load").case)
    one = bench.BenchCase("cantilever_tip_load", [0], single_level=True)
    order = []
    cpu = {("fem", 8): 1.0, ("fem", 16): 2.0, ("fem", 32): 4.0, ("opensees", 8): 0.5, ("opensees", 16): 1.5}

    monkeypatch.setattr(bench, "run_method", lambda sub, method: MethodRun(values={}, wall_time=1e-3))

    def one_run(sub, method):
        n = sub.methods[method]["elements"]
        order.append((method, n))
        return MethodRun(values={}), cpu[(method, n)]

    monkeypatch.setattr(bench, "_one_run", one_run)
    monkeypatch.setattr(bench, "HEADLINE_BUDGET_S", 4e-3)
    ours = [dict(method="fem", elements=32), dict(method=bench.paired_label("fem"), elements=8)]
    peer = [dict(method=bench.paired_label(bench.PEER), elements=8), dict(method=bench.PEER, elements=16)]
    got = bench._confirmed(case, one, ours, peer, 2)
    first_round = order[: len(cpu)]
    assert sorted(first_round) == sorted(cpu)  # every run once a round: the shared opensees n=16 too
    assert got["fem"]["method"] == bench.paired_label("fem") and got["fem"]["elements"] == 8
    assert got["opensees"]["method"] == bench.PEER and got["opensees"]["elements"] == 16
    assert (got["fem_s"], got["opensees_s"], got["ratio"]) == (3.0, 1.5, 2.0)
    assert got["fem"]["time_s"] == 3.0 and got["candidates"] == 4
    frame = pd.DataFrame(
        [
            dict(method=m, elements=n, time_s=t, error=e, iterations=1)
            for m, n, t, e in (
                ("fem+richardson", 8, 3.0, 1e-5),
                ("fem", 16, 0.5, 2e-4),
                (bench.paired_label("fem"), 8, 2.0, 3e-5),
                ("fem", 32, 1.0, 5e-5),
                (bench.PEER, 32, 1.5, 5e-5),
            )
        ]
    )  # fem n=16 misses the error
    mine, theirs = bench._candidates(frame, 1e-4)
    assert [(c["method"], c["elements"]) for c in mine] == [
        ("fem", 32),
        (bench.paired_label("fem"), 8),
        ("fem+richardson", 8),
    ][: bench.CANDIDATES]
    assert [(c["method"], c["elements"]) for c in theirs] == [(bench.PEER, 32)]


def test_the_headline_re_times_every_configuration_close_to_the_sweeps_fastest():
    """`_candidates`: of each code the sweep's CANDIDATES fastest that reach the error, and any other within
    CANDIDATE_SPREAD times its fastest (at most CANDIDATES_MAX): a configuration one slow sweep time put
    fourth (1.45 ms for a run re-timed at 0.88 ms, a bench of the single-level cantilever) is re-timed,
    one far slower is not; `_choices` (the sweep's own pick) is the fastest alone."""
    rows = [
        ("fem+richardson", 8, 1.15, 2e-5),
        ("fem+richardson", 16, 1.20, 1e-6),
        (bench.paired_label("fem"), 8, 1.27, 2e-5),
        ("fem", 64, 1.45, 3e-5),
        ("fem", 128, 2.25, 7e-6),
        ("fem", 256, 4.03, 2e-6),
        ("fem", 32, 0.60, 1.1e-4),  # misses the error
        (bench.PEER, 8, 0.9, 5e-5),
        (bench.PEER, 64, 3.0, 1e-5),
    ]
    frame = pd.DataFrame([dict(method=m, elements=n, time_s=t * 1e-3, error=e, iterations=1) for m, n, t, e in rows])
    mine, theirs = bench._candidates(frame, 1e-4)
    assert bench.CANDIDATES == 3 and bench.CANDIDATE_SPREAD == 2.0
    assert [(c["method"], c["elements"]) for c in mine] == [
        ("fem+richardson", 8),
        ("fem+richardson", 16),
        (bench.paired_label("fem"), 8),
        ("fem", 64),
        ("fem", 128),
    ]
    assert [(c["method"], c["elements"]) for c in theirs] == [(bench.PEER, 8), (bench.PEER, 64)]
    ours, peer = bench._choices(frame, 1e-4)
    assert (ours["method"], ours["elements"], peer["elements"]) == ("fem+richardson", 8, 8)
    crowded = pd.DataFrame(
        [dict(method="fem", elements=n, time_s=1.0 + n * 1e-3, error=1e-5, iterations=1) for n in range(1, 20)]
    )
    assert len(bench._candidates(crowded, 1e-4)[0]) == bench.CANDIDATES_MAX


def test_a_run_that_stopped_before_the_end_of_its_path_never_reaches_a_target():
    """A peer that stops partway (OpenSees' Newton past M L/EI = pi on the roll-up) has values only for
    the levels it reached, all exact: its row keeps its time and ``converged`` False, with an infinite
    error, so the headline never counts it as reaching 1e-4 L against a complete run of ours."""
    r0, r1 = Request("y", "tip", 0), Request("y", "tip", 1)
    exact = {r0: 0.5, r1: 0.9}
    stopped = MethodRun(values={r0: 0.5}, converged=False, message="no convergence at level 1")
    complete = MethodRun(values={r0: 0.5, r1: 0.9 + 1e-5}, converged=True)
    assert bench._reached_error(stopped, exact, 1.0) == float("inf")
    assert bench._reached_error(complete, exact, 1.0) == pytest.approx(1e-5, rel=1e-9)
    frame = pd.DataFrame(
        [
            dict(
                method="opensees",
                elements=4,
                time_s=1e-4,
                error=bench._reached_error(stopped, exact, 1.0),
                iterations=3,
            ),
            dict(
                method="opensees",
                elements=8,
                time_s=5e-4,
                error=bench._reached_error(complete, exact, 1.0),
                iterations=9,
            ),
        ]
    )
    found = bench._fastest_at_error(frame, ("opensees",), 1e-4, 3)
    assert [c["elements"] for c in found] == [8]
