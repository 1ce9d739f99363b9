"""``prbm-validate bench``: run time against error for every method, on the same cases, in one run.

Each code is driven the way its best user would drive it, and the same post-processing is offered to
both: our FEM (adaptive load steps from one step per level) and the OpenSeesPy peer (one load step
per level, halved only on failure, failed tries counted in the time) both run on meshes of 2, 4, 8,
... elements per member, doubled until the method has reached every target error or 1024 elements
(256 with ``--quick``), or until two doublings in a row no longer halve the error (an error floor:
the reference's precision), plain and with Richardson extrapolation on the n and 2n results, as separate
rows: each code's n and 2n plain runs extrapolated here by one Richardson step, the time of both
(``fem+richardson (plain runs)``, ``opensees+richardson``: the same post-processing for both codes),
and the FEM's own n/2n solve (``fem+richardson``: the 2n solve warm-started from the n one, with the
FEM's error estimate). Beside them: the PRBM, the exact elastica and the FEM with the case's own options.

OpenSeesPy is timed two ways. Through the harness's adapter (``opensees``, `validation.methods.opensees`),
through ``run_method`` as our FEM is (the path ``run``, ``report`` and sweeps take): its time includes
the harness's fixed costs (the case read into a model, the results back). And driven by a plain script
(``opensees-script``, `validation.bench.opensees_script`): the same model, loads and solver settings, the
problem's numbers read from the case before the timing, the script's OpenSees calls alone timed, as an
engineer using OpenSeesPy directly would run it; it gives the adapter's answers at the same mesh, and
gets the same Richardson rows (``opensees-script+richardson``). A case the script does not express says
so ("plain script unavailable: ..."), with no numbers.

The codes take turns mesh by mesh on each case (a slow period of a shared machine falls on all the
codes' rows alike). Each configuration is timed in this process: one warm-up, then the best (smallest)
CPU time of this process (``time.process_time``; BLAS and the compiled kernels run on one thread, so on
an idle machine it is the wall time, and on a shared one it leaves out the waits for a core) over
``repeats`` runs or more (a fast configuration as many as fit in TIME_BUDGET_S, up to MAX_REPEATS), their
median (for the noise) and the best wall time; its error is the largest
tip-position error over the benchmarked load levels, over the characteristic length, against the
exact solution (the elastica method on the same case, or the case's 'exact' references). Peak Python
memory is measured in a separate run with ``tracemalloc`` (not the plain script's: its memory is
OpenSees' own, C++, which ``tracemalloc`` does not see). The BLAS thread settings are recorded.

The headline, at each target error, gives two ratios: our best time over the adapter's best, and over
the plain script's best, with the configurations beside them: the CANDIDATES configurations of ours and
the adapter's the sweep found fastest (and any other within CANDIDATE_SPREAD times its fastest, at most
CANDIDATES_MAX), and those of the script's CANDIDATES fastest within CANDIDATE_SPREAD times its fastest
(`_script_candidates`), are timed again, every run
of all of them taking turns (a Richardson row on plain runs: its two runs; a run two candidates share is
timed once), so that all are measured in the same minutes of the shared machine, each as often as fits
in HEADLINE_BUDGET_S (ten times the sweep's budget: on a shared machine the best of a few dozen runs of a
millisecond configuration is not yet steady enough to place a ratio near 1); each code's fastest as
re-timed gives the headline ratios (the sweep's own ratio beside each: one noisy sweep time could otherwise
pick the slower of two close configurations). Beside it, the same ratio in each of NOISE_BLOCKS
consecutive parts of the re-timing (`_block_ratios`): how far the machine's load moved it while it was
measured, so that a ratio near a target says whether it is under it in every part or only on average;
a peer that cannot run (not installed, no system BLAS) is "peer unavailable", a case it cannot model "peer not
applicable", never "did not reach". Also the time of one Newton iteration
(time over iterations, failed tries included) of our FEM, the adapter and the plain script at 8 to 256
elements, on the single-level cantilever, timed in turn with the headline's budget.

Writes ``bench.csv``, ``headline.json`` and plots (error against time with the Pareto front; time
against elements with the fitted growth exponent) under the output folder.
"""

from __future__ import annotations

import gc
import importlib
import json
import math
import os
import statistics
import time
import tracemalloc
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
import pandas as pd

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402

from validation.bench.opensees_script import SCRIPT, script_job
from validation.run.exit_status import ExitStatus, decide
from validation.run.output_set import OutputSet
from validation.case.loader import CaseError, case_by_id, find_case_files
from validation.methods.base import MethodRun, Request
from validation.case.scale import characteristic_length
from validation.run.runner import requests_for, run_method
from validation.run.outcome import run_cases


@dataclass(frozen=True)
class BenchCase:
    """A case of the benchmark: which levels are compared, and whether only the last level is loaded
    (``single_level``: the loads jump from zero to their last value in one level)."""

    case_id: str
    levels: list[int] | None = None  # None = all
    single_level: bool = False

    @property
    def label(self) -> str:
        return f"{self.case_id} (last level only)" if self.single_level else self.case_id


BENCH_CASES: list[BenchCase] = [
    BenchCase("cantilever_tip_load", [0], single_level=True),  # PL^2/EI = 10 in one level
    BenchCase("cantilever_tip_load", [0, 4, 9]),  # PL^2/EI = 1..10, ten levels
    BenchCase("pure_moment_roll_up"),
    BenchCase("lee_frame"),
    BenchCase("bapat2015_test1a"),
    BenchCase("bapat2015_test2"),
    BenchCase("seed004_parallel_guided", [0], single_level=True),  # a four-link PRB network: F L^2/EI = 16 in one level
]
POSITION = ("x", "y", "dx", "dy")
TARGETS = (1e-4, 1e-6)
PEER = "opensees"  # OpenSeesPy through the harness's adapter (validation.methods.opensees), timed through run_method
# the peers: OpenSeesPy through the adapter, and driven by a plain script (validation.bench.opensees_script),
# the script's OpenSees calls alone timed
PEERS = (PEER, SCRIPT)
OURS = ("fem", "fem+richardson")  # the FEM's plain runs and its own n/2n solve
ITERATION_MESHES = (8, 16, 32, 64, 128, 256)
RUN_BUDGET_S = 20.0  # a method's mesh doubling stops after a run slower than this
SLOW_RUN_S = 0.2  # a configuration slower than this is timed once after its warm-up
QUICK_REPEATS = 3  # timed runs per configuration with --quick (5 without), at least
TIME_BUDGET_S = 0.05  # a fast configuration is run as often as fits in this (its best is then its
MAX_REPEATS = 200  # quiet-machine time, not a noise spike's), up to MAX_REPEATS runs
HEADLINE_BUDGET_S = 0.5  # the same for the headline's re-timing and the per-iteration table
CANDIDATES = 3  # configurations of each code re-timed for the headline (the sweep's fastest: one
# noisy sweep time can rank a code's truly fastest configuration second or third)
CANDIDATE_SPREAD = 2.0  # and every other one the sweep timed within this factor of the code's fastest (one
# slow sweep time can rank a code's truly fastest configuration past CANDIDATES)
CANDIDATES_MAX = 6  # at most this many of each code
NOISE_BLOCKS = 3  # the re-timing cut into this many consecutive parts, the ratio of each printed
CONFIGURATIONS = {  # how each code is driven (printed beside the headline)
    "fem": (
        "corotational Euler-Bernoulli beams (validation.methods.fem); load control: each level tried in "
        "one step, cut only on failure (failed tries counted), Newton with the consistent tangent "
        "compiled whole (numba; RCM-banded tangents by a compiled band LU, LAPACK's dgbtf2 step for "
        "step, at any size; wide-band ones by LAPACK dgetrf), |r| <= 1e-10 max(|f_ext|, |f_int|); "
        "limit loads by arc length (its corrector, and any model with follower loads, in NumPy, "
        "not compiled); fem+richardson: the n and 2n solves (warm-started) extrapolated; "
        "fem+richardson (plain runs): the n and 2n plain runs extrapolated by the bench, as for the peer, "
        "time of both"
    ),
    "opensees": (
        "OpenSeesPy elasticBeamColumn with the Corotational transformation "
        "(validation.methods.opensees; rigid links as elements 1e6 times the stiffest beam, hinges "
        "by -release of the element ends); LoadControl one step per level, halved on failure (up to 12 "
        "halvings, failed tries counted), Newton, NormDispIncr 1e-10 (50 iterations), BandGeneral, "
        "RCM numbering; limit loads by DisplacementControl and a parabola through the peak; "
        "opensees+richardson: the n and 2n runs extrapolated, time of both; timed through the harness "
        "(run_method: the case read into the model, the results back), as our FEM is"
    ),
    SCRIPT: (
        "the same OpenSeesPy model, loads and solver settings written as a plain script "
        "(validation.bench.opensees_script: the problem's numbers read from the case before the timing, "
        "the script's OpenSees calls alone timed: nodes, elements, supports, loads, one LoadControl step per "
        "level halved on failure, Newton, NormDispIncr 1e-10, BandGeneral, the displacements read); "
        "opensees-script+richardson: the n and 2n runs extrapolated, time of both"
    ),
}


def _pin_blas() -> dict[str, str]:
    """The BLAS thread settings of the environment, recorded with the results (set
    OPENBLAS_NUM_THREADS=1 before the run to pin them: the factorisations here are small, and both codes
    call LAPACK on one thread either way)."""
    return {
        k: os.environ.get(k, "")
        for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_CORETYPE")
    }


def _last_level_only(case):
    """The case with every load jumping from zero to its last value in one level (level 0), and the
    references of the last level moved to level 0."""
    last = case.n_levels() - 1
    loads = [load.model_copy(update={"values": [load.levels()[-1]], "ramp": None}) for load in case.loads]
    outputs = [out.model_copy(update={"levels": "all"}) for out in case.outputs]
    refs = [r.model_copy(update={"level": 0}) for r in case.references if r.level == last]
    labels = None if case.level_labels is None else [case.level_labels[-1]]
    return case.model_copy(update={"loads": loads, "outputs": outputs, "references": refs, "level_labels": labels})


def paired_label(method: str) -> str:
    """The label of a method's row of Richardson on its n and 2n plain runs, extrapolated by the bench
    (``_sweep``): ``opensees+richardson`` for the peer, ``fem+richardson (plain runs)`` beside the
    FEM's own ``fem+richardson``."""
    return f"{method}+richardson (plain runs)" if method == "fem" else f"{method}+richardson"


def _at(case, bench: BenchCase, method: str, n: int, own_richardson: bool = False):
    """The case as the benchmark runs ``method`` on it with n elements per member: the case's own
    options of the method, the mesh, and for the FEM no error estimate (a plain run) or, with
    ``own_richardson``, its own n/2n solve with Richardson extrapolation; for the plain script
    (``opensees-script``) its job (`script_job`: the case read into the script's inputs, untimed)."""
    mesh = {"elements": n}
    if method == SCRIPT:  # the peer's options of the case, read into the plain script's inputs
        return script_job(_restrict(case, PEER, dict(case.methods.get(PEER) or {}) | mesh, bench.levels), n)
    if method == "fem":
        mesh |= {"error_estimate": True, "richardson": True} if own_richardson else {"error_estimate": False}
    return _restrict(case, method, dict(case.methods.get(method) or {}) | mesh, bench.levels)


def _restrict(case, method: str, options: dict, levels: list[int] | None):
    outputs = []
    for out in case.outputs:
        if out.quantity in POSITION + ("limit_load",):
            update: dict[str, list[int] | None] = {"methods": None}
            if levels is not None and out.quantity != "limit_load":
                update["levels"] = levels
            outputs.append(out.model_copy(update=update))
    return case.model_copy(update={"methods": {method: options}, "outputs": outputs})


@dataclass
class Timing:
    """One configuration timed: the last run, the best and median CPU time of this process around
    the run, the best wall time, the peak Python memory, the best CPU time of the load stepping
    alone (``analysis``: the adapter's ``analysis_cpu_s``, without model set-up and results), and the
    CPU time of every timed run in the order they ran (``times``)."""

    run: MethodRun
    best: float
    median: float
    repeats: int
    peak_bytes: float
    wall: float = math.nan
    analysis: float = math.nan
    times: tuple[float, ...] = ()


def _run(case, method: str) -> MethodRun:
    """One run of a configuration: the plain script's job (``case`` a `ScriptJob`), else the method through
    the harness (``run_method``, the path ``run``, ``report`` and sweeps take)."""
    return case.run() if method == SCRIPT else run_method(case, method)


def _one_run(case, method: str) -> tuple[MethodRun, float]:
    """One run and its CPU time, with the garbage collector off while it runs (as ``timeit`` does:
    a collection walks the whole process's heap, this benchmark's tables included, whichever code
    happens to trigger it). The plain script's time is its OpenSees calls alone (`ScriptJob.timed`); every
    other method's is the whole ``run_method``."""
    gc.disable()
    try:
        if method == SCRIPT:
            return case.timed()
        start = time.process_time()
        run = run_method(case, method)
        return run, time.process_time() - start
    finally:
        gc.enable()


def _timed(case, method: str, repeats: int) -> Timing:
    """One configuration timed (`_timed_in_turn` of it alone)."""
    return _timed_in_turn({method: case}, repeats)[method]


def _rounds(warm_wall: float, repeats: int, budget: float | None = None) -> int:
    """How many timed runs a configuration gets, from its warm-up's wall time (`_timed_in_turn`), as
    many as fit in ``budget`` (default TIME_BUDGET_S)."""
    if warm_wall > SLOW_RUN_S:
        return 1
    budget = TIME_BUDGET_S if budget is None else budget
    return max(repeats, min(MAX_REPEATS, int(budget / max(warm_wall, 1e-9))))


def _timed_in_turn(configs: dict, repeats: int, budget: float | None = None, memory: bool = True) -> dict[str, Timing]:
    """Each method's case (method -> case) timed, the methods taking turns run by run
    (`_labelled_in_turn`)."""
    return _labelled_in_turn({method: (case, method) for method, case in configs.items()}, repeats, budget, memory)


def _labelled_in_turn(
    configs: dict[str, tuple], repeats: int, budget: float | None = None, memory: bool = True
) -> dict[str, Timing]:
    """Each configuration (label -> (case, method)) timed, the configurations taking turns run by run,
    the order reversed every round (A B, B A, ...), so that a slow period of the shared machine falls on
    every one alike; after one warm-up run each (imports, caches, compiled kernels). A configuration whose
    warm-up is slower than SLOW_RUN_S is timed once (its noise is small against its time); a fast one
    as often as fits in ``budget`` (default TIME_BUDGET_S), at least ``repeats`` and at most MAX_REPEATS
    times (a millisecond run's best of 5 on a shared machine can still be a slow period's), the same rule
    for every code. With ``memory``, one more run of each measures its peak memory (`_peak_bytes`; the
    headline's re-timing and the per-iteration table read none, and leave it out)."""
    first = {label: _run(*config) for label, config in configs.items()}
    rounds = {label: _rounds(run.wall_time, repeats, budget) for label, run in first.items()}
    times: dict[str, list[float]] = {label: [] for label in configs}
    walls: dict[str, list[float]] = {k: [] for k in configs}
    analyses: dict[str, list[float]] = {k: [] for k in configs}
    last = dict(first)
    order = list(configs)
    for r in range(max(rounds.values(), default=0)):
        for label in order if r % 2 == 0 else order[::-1]:
            if len(times[label]) < rounds[label]:
                run, cpu = _one_run(*configs[label])
                last[label] = run
                times[label].append(cpu)
                walls[label].append(run.wall_time)
                analyses[label].append(run.extras.get("analysis_cpu_s", math.nan))
    out = {}
    for label, config in configs.items():
        out[label] = Timing(
            last[label],
            min(times[label]),
            statistics.median(times[label]),
            rounds[label],
            _peak_bytes(*config) if memory else math.nan,
            min(walls[label]),
            min(analyses[label]),
            tuple(times[label]),
        )
    return out


def _peak_bytes(case, method: str) -> float:
    """The peak Python memory of one run (``tracemalloc``); NaN for the plain script, whose memory is
    OpenSees' own (C++ allocations, which ``tracemalloc`` does not see; its Python side allocates next to
    nothing), so that its run is not repeated for a number that would say nothing."""
    if method == SCRIPT:
        return math.nan
    tracemalloc.start()
    try:
        _run(case, method)
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def _runs_of(case, bench: BenchCase, choice: dict) -> dict[str, tuple]:
    """The runs a headline configuration (a row of `_fastest_at_error`) is made of, label -> (case, method):
    one run, or for a Richardson row on plain runs (`paired_label`) the plain runs at n and 2n."""
    label, n = choice["method"], choice["elements"]
    method = label.split("+")[0]
    meshes: tuple[int, ...]
    if label == paired_label(method):
        meshes = (n, 2 * n)
    elif label == method:
        meshes = (n,)
    else:  # the FEM's own n/2n solve
        return {f"{label} n={n}": (_at(case, bench, method, n, own_richardson=True), method)}
    return {f"{method} n={m}": (_at(case, bench, method, m), method) for m in meshes}


def _confirmed(
    case, bench: BenchCase, ours: list[dict], peer: list[dict], repeats: int, script: list[dict] | None = None
) -> dict:
    """The headline's candidate configurations of the codes (`_candidates`: ours, the peer's through the
    adapter and, given, the plain script's) timed again, every run of all of them taking turns run by run
    (`_labelled_in_turn`; a run two candidates share, e.g. the plain 2n run of a Richardson row and the
    plain row at 2n, timed once), so that all are measured in the same minutes of the shared machine. Each
    candidate's time is the sum of its runs' bests (a Richardson row on plain runs: its n and 2n runs); each
    code's fastest candidate as re-timed (``fem``, ``opensees``, ``script``: the configuration with that
    time, ``*_s`` the time) and our time over each peer's (``ratio``: the adapter's, ``script_ratio``), with
    the same ratios in consecutive parts of the re-timing (`_block_ratios`)."""
    choices = {code: found for code, found in (("fem", ours), (PEER, peer), (SCRIPT, script or [])) if found}
    runs = {
        (code, i): _runs_of(case, bench, choice) for code, found in choices.items() for i, choice in enumerate(found)
    }
    configs = {label: config for part in runs.values() for label, config in part.items()}
    timings = _labelled_in_turn(configs, repeats, HEADLINE_BUDGET_S, memory=False)
    best = {}
    for code, found in choices.items():
        time_s, i = _fastest_candidate(runs, code, lambda label: timings[label].best)
        best[code] = (time_s, dict(found[i], time_s=time_s))
    fem_s, fem = best["fem"]
    got = dict(
        fem_s=fem_s,
        fem=fem,
        candidates=sum(len(found) for found in choices.values()),
        repeats=min(timings[label].repeats for label in timings),
    )
    for code, key, ratio, parts in (
        (PEER, "opensees", "ratio", "block_ratios"),
        (SCRIPT, "script", "script_ratio", "script_block_ratios"),
    ):
        peer_s, choice = best.get(code, (None, None))
        got |= {
            f"{key}_s": peer_s,
            key: choice,
            ratio: fem_s / peer_s if peer_s else None,
            parts: _block_ratios(timings, runs, code) if peer_s else [],
        }
    return got


def _fastest_candidate(runs: dict, code: str, time_of) -> tuple[float, int]:
    """A code's fastest candidate (``runs``: (code, i) -> its runs' labels) and its time: the sum of its
    runs' times, ``time_of(label)``."""
    return min((sum(time_of(label) for label in labels), i) for (c, i), labels in runs.items() if c == code)


def _block_ratios(timings: dict[str, Timing], runs: dict, peer: str = PEER, blocks: int = NOISE_BLOCKS) -> list[float]:
    """The headline ratio, our time over ``peer``'s, again in each of ``blocks`` consecutive parts of the
    re-timing (each label's runs, in the order they ran, cut into ``blocks`` equal parts: with the runs
    taking turns, part k of every label falls in the same minutes of the machine): per part, each
    candidate's time is the sum of its runs' bests within the part, each code's the fastest candidate's.
    How far these ratios spread is how far the machine's load moved the ratio while it was measured. Empty
    when a configuration of the two codes ran fewer than ``blocks`` times (a slow one, timed once)."""
    labels = {label for (code, _), part in runs.items() if code in ("fem", peer) for label in part}
    parts = {label: _part_bests(timings[label].times, blocks) for label in labels}
    if not all(parts.values()):
        return []
    return [
        _fastest_candidate(runs, "fem", lambda label: parts[label][k])[0]
        / _fastest_candidate(runs, peer, lambda label: parts[label][k])[0]
        for k in range(blocks)
    ]


def _part_bests(times: tuple[float, ...], blocks: int = NOISE_BLOCKS) -> list[float]:
    """The best of each of ``blocks`` consecutive, equal parts of ``times`` (in the order the runs ran);
    empty when there are fewer times than parts."""
    if len(times) < blocks:
        return []
    return [min(times[k * len(times) // blocks : (k + 1) * len(times) // blocks]) for k in range(blocks)]


def _exact(case, levels) -> tuple[dict, str]:
    """Exact tip positions: the elastica on this case, else the case's 'exact' references."""
    if "elastica" in case.methods:
        run = run_method(_restrict(case, "elastica", dict(case.methods["elastica"] or {}), levels), "elastica")
        if run.converged and run.values:
            return run.values, "elastica"
    refs = {
        Request(r.quantity, r.point if r.quantity != "limit_load" else "", r.level): r.value
        for r in case.references
        if r.label in ("exact", "elliptic") or (r.quantity == "limit_load" and r.label == "published")
    }
    return refs, "references"


def _error(values: dict, exact: dict, scale: float) -> float:
    """Largest tip-position (or limit-load) error over the levels, relative to the scale."""
    worst = 0.0
    found = False
    by_point: dict[tuple[str, int], dict[str, float]] = {}
    for req, value in values.items():
        if req.quantity == "limit_load" and req in exact:
            worst = max(worst, abs(value - exact[req]) / abs(exact[req]))
            found = True
        elif req.quantity in POSITION and req in exact:
            by_point.setdefault((req.point, req.level), {})[req.quantity] = value - exact[req]
    for diffs in by_point.values():
        worst = max(worst, math.hypot(*diffs.values()) / scale)
        found = True
    return worst if found else math.nan


def _reached_error(run: MethodRun, exact: dict, scale: float) -> float:
    """`_error` of a run that reached the end of its path; infinite for one that stopped before (its
    error on the levels it reached does not say it reached the target: such a row stays in the table,
    with ``converged`` False, and never enters the headline)."""
    return _error(run.values, exact, scale) if run.converged else math.inf


def _pareto(frame: pd.DataFrame) -> pd.Series:
    order = frame.sort_values("time_s")
    best, flags = math.inf, {}
    for idx, row in order.iterrows():
        flags[idx] = row["error"] < best
        best = min(best, row["error"]) if not math.isnan(row["error"]) else best
    return pd.Series(flags).reindex(frame.index)


def _fastest_at_error(frame: pd.DataFrame, methods: tuple[str, ...], target: float, count: int) -> list[dict]:
    """The ``count`` fastest rows of these methods whose error is at most the target (fastest first, the
    first of equal times as the rows come), as configurations."""
    rows = frame[frame["method"].isin(methods) & (frame["error"] <= target)]
    rows = rows.sort_values("time_s", kind="stable").head(count)
    return [
        dict(
            method=row["method"],
            elements=int(row["elements"]),
            time_s=float(row["time_s"]),
            error=float(row["error"]),
            iterations=None if pd.isna(row["iterations"]) else int(row["iterations"]),
        )
        for _, row in rows.iterrows()
    ]


def _richardson(coarse: MethodRun, fine: MethodRun) -> dict:
    """u_2n + (u_2n - u_n)/3 on every value both runs gave (the O(h^2) Richardson step)."""
    return {r: v + (v - coarse.values[r]) / 3.0 for r, v in fine.values.items() if r in coarse.values}


def _row(case_label, label, n, timing: Timing, exact_from) -> dict:
    run = timing.run
    iterations = run.extras.get("iterations", math.nan)
    return dict(
        case=case_label,
        method=label,
        elements=n,
        time_s=timing.best,
        time_median_s=timing.median,
        wall_s=timing.wall,
        repeats=timing.repeats,
        error=math.nan,
        error_reference=exact_from,
        iterations=iterations,
        failed_iterations=run.extras.get("rejected_iterations", 0),
        peak_memory_mb=timing.peak_bytes / 2**20,
        converged=run.converged,
        message=run.message[:200],
    )


def _sweep(case, bench: BenchCase, method: str, meshes: list[int], repeats: int, exact, scale, log):
    """Plain and Richardson rows of one method on doubling meshes, until every target is reached: a
    generator that pauses after each mesh (`_interleaved` alternates the codes mesh by mesh) and returns
    (rows, skipped)."""
    rows, skipped, plain = [], [], {}
    paired = paired_label(method)
    labels = (f"{method}", f"{method}+richardson")  # the plain runs, and the FEM's own n/2n solve
    reached = {label: False for label in {*labels, paired}}
    errors: dict[str, list[float]] = {label: [] for label in reached}

    def done(label, error, slow):
        """Reached the smallest target, too slow, or on an error floor (two doublings in a row
        that did not halve the error: the reference's own precision, or the solver's, is reached)."""
        errors[label].append(error)
        e = errors[label]
        floor = len(e) >= 3 and e[-1] > 0.5 * e[-2] and e[-2] > 0.5 * e[-3]
        return error <= min(TARGETS) or slow or floor

    for n in meshes:
        configs = [(labels[0], False)] + ([(labels[1], True)] if method == "fem" else [])
        for label, own_richardson in configs:
            if reached[label]:
                continue
            sub = _at(case, bench, method, n, own_richardson)
            timing = _timed(sub, method, repeats)
            if not timing.run.values:
                skipped.append(f"{bench.label}/{label} n={n}: {timing.run.message}")
                reached[label] = True  # nothing more to learn from finer meshes
                continue
            row = _row(bench.label, label, n, timing, exact[1])
            row["error"] = _reached_error(timing.run, exact[0], scale)
            rows.append(row)
            log(row)
            reached[label] = done(label, row["error"], timing.best > RUN_BUDGET_S)
            if label == labels[0]:
                plain[n] = timing
        if n // 2 in plain and n in plain and not reached[paired]:
            coarse, fine = plain[n // 2], plain[n]
            both = Timing(
                MethodRun(
                    values=_richardson(coarse.run, fine.run),
                    converged=coarse.run.converged and fine.run.converged,
                    message=fine.run.message if fine.run.converged else coarse.run.message,
                    extras={
                        "iterations": coarse.run.extras.get("iterations", 0) + fine.run.extras.get("iterations", 0)
                    },
                ),
                coarse.best + fine.best,
                coarse.median + fine.median,
                fine.repeats,
                max(coarse.peak_bytes, fine.peak_bytes),
                coarse.wall + fine.wall,
            )
            row = _row(bench.label, paired, n // 2, both, exact[1])
            row["error"] = _reached_error(both.run, exact[0], scale)
            rows.append(row)
            log(row)
            reached[paired] = done(paired, row["error"], both.best > RUN_BUDGET_S)
        if all(reached.values()):
            break
        yield
    return rows, skipped


def _interleaved(sweeps: dict) -> dict:
    """Run the sweeps (method -> `_sweep` generator) one mesh at a time in turn, so that a slow period of a
    shared machine falls on both codes' rows alike; method -> (rows, skipped)."""
    results, active = {}, dict(sweeps)
    while active:
        for method, steps in list(active.items()):
            try:
                next(steps)
            except StopIteration as end:
                results[method] = end.value
                del active[method]
    return results


def _per_iteration(case, bench: BenchCase, repeats: int, with_peer: bool, cap: int) -> dict:
    """Wall time over Newton iterations (failed tries included) of the plain FEM and the peer (through the
    adapter and by the plain script) on the same meshes of this case, the codes timed run by run in turn
    (`_timed_in_turn`)."""
    cost = {}
    for n in (m for m in ITERATION_MESHES if m <= cap):
        entry: dict[str, Any] = {}
        subs = {method: _at(case, bench, method, n) for method in ("fem",) + (PEERS if with_peer else ())}
        timings = _timed_in_turn(subs, repeats, HEADLINE_BUDGET_S, memory=False)  # the codes in turn
        for method, timing in timings.items():
            if not timing.run.values:
                continue
            its = timing.run.extras.get("iterations", 0) + timing.run.extras.get("rejected_iterations", 0)
            entry[method] = dict(
                time_s=timing.best,
                iterations=its,
                per_iteration_s=timing.best / max(its, 1),
                analysis_s=timing.analysis,
                loop_per_iteration_s=timing.analysis / max(its, 1),
            )
        for peer, prefix in ((PEER, ""), (SCRIPT, "script_")):
            if "fem" in entry and peer in entry:
                entry |= _iteration_ratios(entry, timings, peer, prefix)
        cost[str(n)] = entry
    return cost


def _iteration_ratios(entry: dict, timings: dict[str, Timing], peer: str, prefix: str) -> dict:
    """Our time per Newton iteration over the peer's (``ratio``: the whole runs; ``loop_ratio``: the load
    stepping alone), and the run ratio in consecutive parts of the timing (``ratio_parts``,
    `_block_ratios`: the machine's noise on it); each key prefixed with ``prefix``."""
    its = entry[peer]["iterations"] / max(entry["fem"]["iterations"], 1)
    return {
        f"{prefix}ratio": entry["fem"]["per_iteration_s"] / entry[peer]["per_iteration_s"],
        f"{prefix}loop_ratio": entry["fem"]["loop_per_iteration_s"] / entry[peer]["loop_per_iteration_s"],
        f"{prefix}ratio_parts": [f / p * its for f, p in zip(*(_part_bests(timings[m].times) for m in ("fem", peer)))],
    }


def _peer_status() -> str:
    """'' when the OpenSeesPy peer can run here, else why not."""
    try:
        importlib.import_module("openseespy.opensees")
    except Exception as exc:  # not installed, or a missing system BLAS
        return f"peer unavailable: OpenSeesPy cannot be imported ({exc})"
    return ""


def _log(row) -> None:
    print(
        f"  {row['case']:<40} {row['method']:<20} n={row['elements']!s:<5} {row['time_s'] * 1e3:10.2f} ms  "
        f"error={row['error']:.2e}  iterations={row['iterations']}",
        flush=True,
    )


def _case_option_rows(case, bench: BenchCase, repeats: int, exact, skipped: list, failed: list) -> list:
    """(row, run) of the PRBM, the elastica and the FEM with the case's own options (errors filled in
    later, against the exact solution)."""
    fixed = []
    for label in ("prbm", "elastica", "fem"):
        if label not in case.methods:
            continue
        sub = _restrict(case, label, dict(case.methods.get(label) or {}), bench.levels)
        if not requests_for(sub, label):
            skipped.append(f"{bench.label}/{label}: no tip-position or limit-load output to time")
            continue
        timing = _timed(sub, label, repeats)
        if not timing.run.converged:  # a method of the case, with the case's own options
            failed.append(f"{bench.label}/{label}: {timing.run.message}")
        if not timing.run.values:
            skipped.append(f"{bench.label}/{label}: {timing.run.message}")
            continue
        fixed.append(
            (_row(bench.label, label if label != "fem" else "fem (case options)", None, timing, exact[1]), timing.run)
        )
    return fixed


BENCH_FILES = ("bench.csv", "headline.json", "*.png")  # what the benchmark writes in its folder


def run_bench(
    out: Path,
    quick: bool = False,
    cases: list[BenchCase] | dict | None = None,
    max_elements: int | None = None,
    plots: bool = True,
) -> int:
    """Run the benchmark into ``out``, one output set (``validation.run.output_set``: put in place whole,
    nothing written when no case could run); ``max_elements`` caps the mesh doubling (default 1024, 256
    quick); ``plots=False`` leaves out the PNG figures (the CSV and JSON are always written)."""
    with OutputSet(out, owned=BENCH_FILES) as output:
        status = _bench_into(output.path, quick, cases, max_elements, plots)
        if status is not None:
            output.commit()
    return int(ExitStatus.BAD_INPUT if status is None else status)


def _bench_into(
    out: Path, quick: bool, cases: list[BenchCase] | dict | None, max_elements: int | None, plots: bool
) -> int | None:
    """The benchmark written in ``out``; its exit status, None when no case could run (nothing written)."""
    blas = _pin_blas()
    cap = max_elements or (256 if quick else 1024)
    meshes = [n for n in (2, 4, 8, 16, 32, 64, 128, 256, 512, 1024) if n <= cap]
    repeats = QUICK_REPEATS if quick else 5
    if isinstance(cases, dict):  # {case id: levels}
        cases = [BenchCase(case_id, levels) for case_id, levels in cases.items()]
    peer_status = _peer_status()
    rows, skipped, per_iteration = [], [], {}
    confirmed: dict[str, dict] = {}  # headline row -> its configurations re-timed in turn (`_confirmed`)
    peer_notes: dict[str, dict[str, str]] = {code: {} for code in PEERS}  # why a peer has no ratio on a case
    unusable: list[str] = []  # exit status 2 (validation/run/exit_status.py)
    failed: list[str] = []  # exit status 1

    for bench in cases or BENCH_CASES:
        try:
            case = case_by_id(bench.case_id).case
        except CaseError as exc:
            skipped.append(f"{bench.case_id}: {exc.problem}")
            unusable.append(bench.case_id)
            continue
        if bench.single_level:
            case = _last_level_only(case)
        scale = characteristic_length(case)
        exact = _exact(case, bench.levels)
        fixed = _case_option_rows(case, bench, repeats, exact, skipped, failed)
        if not exact[0]:  # no exact solution (a mechanism): the finest extrapolated FEM is the reference
            sub = _at(case, bench, "fem", meshes[-1], own_richardson=True)
            exact = (run_method(sub, "fem").values, f"fem+richardson at {meshes[-1]} elements (finest)")
        for row, run in fixed:
            row["error"] = _reached_error(run, exact[0], scale)
            row["error_reference"] = exact[1]
            _log(row)
            rows.append(row)
        case_rows, why, notes = _sweep_codes(case, bench, meshes, repeats, exact, scale, peer_status)
        rows += case_rows
        skipped += why
        for code, note in notes.items():
            peer_notes[code][bench.label] = note
        without = {code: bench.label in peer_notes[code] for code in PEERS}
        confirmed |= _confirm_case(case, bench, case_rows, without, repeats)
        if bench == BENCH_CASES[0]:
            per_iteration = _per_iteration(case, bench, repeats, not peer_status, cap)
    if unusable and not rows:  # rejected: no case could run
        for s in skipped:
            print(f"skipped: {s}")
        return None
    frame = pd.DataFrame(rows)
    frame.to_csv(out / "bench.csv", index=False)
    headline = _headline(frame, quick, peer_notes[PEER], max(meshes), confirmed, peer_notes[SCRIPT])
    headline["per_iteration"] = per_iteration
    headline["blas"] = blas
    headline["configurations"] = CONFIGURATIONS
    headline["skipped"] = skipped
    (out / "headline.json").write_text(json.dumps(headline, indent=2, default=float))
    if plots:
        _plots(frame, out)
    _print_headline(headline)
    for s in skipped:
        print(f"skipped: {s}")
    for f in failed:
        print(f"did not converge: {f}")
    return int(decide(bad_input=bool(unusable), failed=bool(failed)))


def _sweep_codes(case, bench: BenchCase, meshes: list[int], repeats: int, exact, scale: float, peer_status: str):
    """Our FEM's and the peers' sweeps of the case (`_sweep`), taking turns mesh by mesh (`_interleaved`):
    their rows, the configurations skipped, and why a peer has no rows (peer -> note: not installed, not
    applicable to the case, or a case the plain script does not express)."""
    notes = {code: peer_status for code in PEERS} if peer_status else {}
    methods = ("fem",) + (() if peer_status else PEERS)
    swept = _interleaved({m: _sweep(case, bench, m, meshes, repeats, exact, scale, _log) for m in methods})
    rows, skipped = [], []
    for method in methods:
        got, why = swept[method]
        rows += got
        skipped += why
        if method in PEERS and not got:
            reason = why[0].split(": ", 1)[-1] if why else "no run"
            notes[method] = _no_rows(method, reason)
    return rows, skipped, notes


def _no_rows(peer: str, reason: str) -> str:
    """Why a peer has no rows on a case, as the headline says it: the adapter's "peer not applicable: ...",
    the plain script's "plain script unavailable: ..." (a case it does not express)."""
    if peer == SCRIPT:
        return "plain script " + (reason if reason.startswith("unavailable") else f"unavailable: {reason}")
    return "peer " + (reason if reason.startswith("not applicable") else f"not applicable: {reason}")


def _confirm_case(case, bench: BenchCase, case_rows: list[dict], without: dict[str, bool], repeats: int) -> dict:
    """The headline configurations of the case timed again for each target error (`_confirmed`): ours, the
    adapter's and the plain script's candidates, all in turn; none of a peer without rows (``without``:
    peer -> True), nothing when neither peer ran."""
    if not case_rows or all(without.values()):
        return {}
    part = pd.DataFrame(case_rows)
    confirmed = {}
    for target in TARGETS:
        ours, peer = _candidates(part, target)
        script = [] if without[SCRIPT] else _script_candidates(part, target)
        peer = [] if without[PEER] else peer
        if ours and (peer or script):
            confirmed[f"{bench.label} @ {target:g} L"] = _confirmed(case, bench, ours, peer, repeats, script)
    return confirmed


def _candidates(
    part: pd.DataFrame, target: float, count: int = CANDIDATES, spread: float = CANDIDATE_SPREAD, peer: str = PEER
) -> tuple[list[dict], list[dict]]:
    """The configurations of ours and of the peer's (``peer``: the adapter's, or the plain script's) that
    reach the target error that the headline times again (`_confirmed`): of each code the ``count`` fastest
    as the sweep timed them, and any other within ``spread`` times its fastest (at most CANDIDATES_MAX):
    one slow sweep time must not leave a code's fastest configuration out."""

    def chosen(methods: tuple[str, ...]) -> list[dict]:
        found = _fastest_at_error(part, methods, target, max(count, CANDIDATES_MAX))
        return [c for i, c in enumerate(found) if i < count or c["time_s"] <= spread * found[0]["time_s"]]

    return chosen((*OURS, paired_label("fem"))), chosen((peer, paired_label(peer)))


def _script_candidates(part: pd.DataFrame, target: float) -> list[dict]:
    """The plain script's configurations the headline times again: of its CANDIDATES fastest in the sweep,
    those within CANDIDATE_SPREAD times its fastest. Not its far slower ones, as for ours and the adapter's:
    the script runs the adapter's OpenSees model less a fixed cost per run, so one the sweep put more than
    CANDIDATE_SPREAD times slower is not its fastest re-timed, and re-timing it beside three codes' would
    cost ``--quick`` most of its time."""
    found = _candidates(part, target, peer=SCRIPT)[1]
    return [c for c in found[:CANDIDATES] if c["time_s"] <= CANDIDATE_SPREAD * found[0]["time_s"]]


def _choices(part: pd.DataFrame, target: float, peer: str = PEER) -> tuple[dict | None, dict | None]:
    """Our fastest configuration and the peer's (``peer``) that reach the target error, as the sweep timed
    them."""
    ours, theirs = _candidates(part, target, 1, spread=0.0, peer=peer)
    return (ours[0] if ours else None, theirs[0] if theirs else None)


@dataclass(frozen=True)
class ScriptRatio:
    """Our time over the plain script's (``opensees-script``) to reach one target error, beside the
    adapter's ratio of the same headline row: ``ratio`` as re-timed in turn with our and the adapter's
    candidates (`_confirmed`; else as the sweep measured them), ``ladder_ratio`` as the sweep measured them,
    the script's fastest configuration in the sweep (``script``) and as re-timed (``retimed``, with that
    time), the ratio in consecutive parts of the re-timing (``block_ratios``), and why there is no ratio
    (``note``: not installed, a case the script does not express, or the error not reached)."""

    ratio: float | None
    ladder_ratio: float | None
    script: dict | None
    retimed: dict | None
    block_ratios: tuple[float, ...]
    note: str


def _headline(
    frame: pd.DataFrame,
    quick: bool,
    peer_notes: dict,
    max_elements: int,
    confirmed: dict | None = None,
    script_notes: dict | None = None,
) -> dict:
    """The headline ratios: at each target, our fastest configuration's time over the peer's fastest, as
    the sweep measured them (``ladder_ratio``) and as re-timed with every run of both taking turns
    (``confirmed``, `_confirmed`: the ``ratio`` when present); beside it (``script``, `ScriptRatio`) our time
    over the plain script's, the same way."""
    headline: dict = {
        "fem_over_opensees_time_at_error": {},
        "per_iteration": {},
        "prbm_over_fem": {},
        "growth_exponent": {},
    }
    confirmed = confirmed or {}
    script_notes = script_notes or {}
    for case_id, part in frame.groupby("case", sort=False) if len(frame) else []:
        for target in TARGETS:
            key = f"{case_id} @ {target:g} L"
            entry = _adapter_ratio(part, target, confirmed.get(key), peer_notes.get(case_id), max_elements)
            script = _script_ratio(part, target, confirmed.get(key), script_notes.get(case_id), max_elements)
            headline["fem_over_opensees_time_at_error"][key] = entry | {"script": asdict(script)}
        prbm = part[part["method"] == "prbm"]
        fem_case = part[part["method"] == "fem (case options)"]
        if len(prbm) and len(fem_case):
            headline["prbm_over_fem"][case_id] = dict(
                prbm_time_s=float(prbm["time_s"].iloc[0]),
                fem_time_s=float(fem_case["time_s"].iloc[0]),
                ratio=float(prbm["time_s"].iloc[0] / fem_case["time_s"].iloc[0]),
            )
        fem = part[part["method"] == "fem"]
        big = fem[fem["elements"] >= 16]
        if len(big) >= 2:
            slope = np.polyfit(np.log(big["elements"].astype(float)), np.log(big["time_s"]), 1)[0]
            headline["growth_exponent"][case_id] = float(slope)
    if not quick:
        paths = find_case_files(None)
        start = time.perf_counter()
        cold = run_cases(paths, use_cache=False, jobs=2)
        headline["suite_cold_s"] = time.perf_counter() - start
        start = time.perf_counter()
        run_cases(paths, use_cache=True, jobs=2)
        headline["suite_warm_s"] = time.perf_counter() - start
        headline["suite_cases"] = len(cold.results)
    return headline


def _reach_note(ours: dict | None, peer: dict | None, peer_name: str, max_elements: int) -> str:
    """Why a headline ratio is missing when both codes ran: which of the two did not reach the error."""
    if ours is not None and peer is not None:
        return ""
    if ours is None and peer is None:
        return "neither reached it"
    who = "our FEM" if ours is None else peer_name
    return f"{who} did not reach this error (up to {max_elements} elements, or its error stopped falling)"


def _adapter_ratio(part: pd.DataFrame, target: float, again: dict | None, note: str | None, max_elements: int) -> dict:
    """Our time over the adapter's at the target: the sweep's fastest of each, their ratio (``ladder_ratio``)
    and the ratio as re-timed (``ratio``, ``confirmed``); ``note`` says why there is none."""
    ours, peer = _choices(part, target)
    ladder = ours["time_s"] / peer["time_s"] if ours and peer else None
    again = again if ours and peer else None
    return dict(
        ratio=again["ratio"] if again else ladder,
        ladder_ratio=ladder,
        confirmed=again,
        fem=ours,
        opensees=peer,
        note=note or _reach_note(ours, peer, "OpenSees", max_elements),
        reference=part["error_reference"].iloc[0],
    )


def _script_ratio(
    part: pd.DataFrame, target: float, again: dict | None, note: str | None, max_elements: int
) -> ScriptRatio:
    """Our time over the plain script's at the target (`ScriptRatio`)."""
    ours, script = _choices(part, target, SCRIPT)
    ladder = ours["time_s"] / script["time_s"] if ours and script else None
    again = again if ours and script and again and again.get("script") else None
    return ScriptRatio(
        ratio=again["script_ratio"] if again else ladder,
        ladder_ratio=ladder,
        script=script,
        retimed=again["script"] if again else None,
        block_ratios=tuple(again["script_block_ratios"]) if again else (),
        note=note or _reach_note(ours, script, "the plain script", max_elements),
    )


def _retimed(again: dict, code: str) -> str:
    """A code's fastest configuration as re-timed for the headline, and its time."""
    choice = again[code]
    return f"{choice['method']} n={choice['elements']} {again[f'{code}_s'] * 1e3:.2f} ms"


def _in_parts(ratios: list[float], timing: str) -> str:
    """A ratio in each consecutive part of its ``timing`` (`_block_ratios`, `_part_bests`), as printed;
    '' when there are none."""
    if not ratios:
        return ""
    return f"in {len(ratios)} consecutive parts of the {timing} {' '.join(f'{r:.2f}' for r in ratios)}"


def _noise(again: dict) -> str:
    """The re-timing's ratio in each of its consecutive parts, when there are any."""
    text = _in_parts(again.get("block_ratios") or [], "re-timing")
    return f"{text}; " if text else ""


def _config(c: dict | None) -> str:
    if c is None:
        return "-"
    return f"{c['method']} n={c['elements']} {c['time_s'] * 1e3:.2f} ms ({c['iterations']} it, error {c['error']:.1e})"


def _print_headline(headline: dict) -> None:
    print("\nconfigurations:")
    for code, text in CONFIGURATIONS.items():
        print(f"  {code}: {text}")
    print(
        "\nfem / OpenSees CPU time to reach the error, two ratios a row: over OpenSees through the harness's "
        "adapter (fem/opensees: both codes timed through run_method), and over OpenSees driven by a plain script "
        "(fem/script, the line below: the script's OpenSees calls alone timed); the fastest configuration of each "
        "beside; the ratio as re-timed with the runs of all three taking turns, and as the sweep measured them:"
    )
    for key, h in headline["fem_over_opensees_time_at_error"].items():
        print(_adapter_line(key, h))
        if "script" in h:
            print(_script_line(h["script"], h.get("confirmed")))
    if headline["per_iteration"]:
        print(
            "time of one Newton iteration, single-level cantilever (fem / OpenSees, through the adapter and by "
            "the plain script): the whole run over its iterations, and the load stepping alone (Newton "
            "iterations and step control, without model set-up and results) over its iterations; best of the "
            "repeats, the codes run by run in turn:"
        )
        for n, c in headline["per_iteration"].items():
            print(f"  n={n:>4}: " + _iteration_line(c, ("fem", PEER), ""))
            if SCRIPT in c:
                print(" " * 10 + _iteration_line(c, (SCRIPT,), "script_", "fem/script "))
    for key in ("suite_cold_s", "suite_warm_s"):
        if key in headline:
            print(f"{key}: {headline[key]:.1f}")


def _ratio_text(ratio: float | None) -> str:
    return "   -  " if ratio is None else f"{ratio:6.2f}"


def _adapter_line(key: str, h: dict) -> str:
    """A headline row's first line: our time over the adapter's, both configurations, the re-timing."""
    again = h.get("confirmed")
    ladder = (
        (
            f"   (re-timed in turn, {again['candidates']} candidates: of each code the sweep's "
            f"{CANDIDATES} fastest and any within {CANDIDATE_SPREAD:g}x its fastest; the fastest as re-timed: "
            f"fem {_retimed(again, 'fem')}, "
            f"opensees {_retimed(again, 'opensees')}; {_noise(again)}sweep {h['ladder_ratio']:.2f})"
        )
        if again and again.get("opensees")
        else ""
    )
    return (
        f"  {key:<52} fem/opensees {_ratio_text(h['ratio'])}   fem: {_config(h['fem'])}   "
        f"opensees: {_config(h['opensees'])}{ladder}" + (f"   [{h['note']}]" if h["note"] else "")
    )


def _script_line(script: dict, again: dict | None) -> str:
    """A headline row's second line: our time over the plain script's (the same fastest FEM configuration
    as the first line's), the script's configuration and its re-timing."""
    retimed = script.get("retimed")
    ladder = ""
    if retimed is not None and again is not None:
        parts = _in_parts(list(script.get("block_ratios") or []), "re-timing")
        ladder = (
            f"   (re-timed in the same turns, the fastest: opensees-script {_retimed(again, 'script')}; "
            + (f"{parts}; " if parts else "")
            + f"sweep {script['ladder_ratio']:.2f})"
        )
    return (
        f"  {'':<52} fem/script   {_ratio_text(script['ratio'])}   opensees-script: {_config(script['script'])}"
        + ladder
        + (f"   [{script['note']}]" if script["note"] else "")
    )


def _iteration_line(c: dict, codes: tuple[str, ...], prefix: str, label: str = "") -> str:
    """A per-iteration line: each code's time per Newton iteration (whole run, stepping alone) and our ratio
    over the peer (``prefix``: '' the adapter's ratios, 'script_' the plain script's)."""
    parts = [
        f"{m} {c[m]['per_iteration_s'] * 1e6:.1f} us run / {c[m]['loop_per_iteration_s'] * 1e6:.1f} us "
        f"stepping ({c[m]['iterations']:.0f} it)"
        for m in codes
        if m in c
    ]
    if f"{prefix}ratio" not in c:
        return ", ".join(parts)
    spread = _in_parts(c.get(f"{prefix}ratio_parts") or [], "timing")
    spread = f" ({spread})" if spread else ""
    return (
        ", ".join(parts) + f", {label}ratio {c[f'{prefix}ratio']:.2f} run{spread} / "
        f"{c[f'{prefix}loop_ratio']:.2f} stepping"
    )


def _plots(frame: pd.DataFrame, out: Path) -> None:
    if frame.empty:
        return
    for case_id, part in frame.groupby("case"):
        part = part[part["error"] > 0]
        if part.empty:
            continue
        fig, ax = plt.subplots(figsize=(6, 4.5))
        for method, rows in part.groupby("method"):
            rows = rows.sort_values("time_s")
            ax.loglog(rows["time_s"], rows["error"], "o-" if rows["elements"].notna().any() else "s", label=method)
        front = part[_pareto(part).astype(bool)].sort_values("time_s")
        ax.loglog(front["time_s"], front["error"], "k--", lw=1, label="Pareto front")
        ax.set_xlabel("CPU time, best of the repeats [s]")
        ax.set_ylabel("tip-position error / L")
        ax.set_title(case_id)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(out / f"{case_id}_error_vs_time.png", dpi=90)
        plt.close(fig)
    fem = frame[frame["method"].isin(["fem", *PEERS]) & frame["elements"].notna()]
    if len(fem):
        fig, ax = plt.subplots(figsize=(6, 4.5))
        for (case_id, method), rows in fem.groupby(["case", "method"]):
            rows = rows.sort_values("elements")
            big = rows[rows["elements"] >= 16]
            slope = np.polyfit(np.log(big["elements"]), np.log(big["time_s"]), 1)[0] if len(big) >= 2 else math.nan
            ax.loglog(rows["elements"], rows["time_s"], "o-", label=f"{case_id} {method} (slope {slope:.2f})")
        ax.set_xlabel("elements per member")
        ax.set_ylabel("CPU time, best of the repeats [s]")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / "time_vs_elements.png", dpi=90)
        plt.close(fig)
