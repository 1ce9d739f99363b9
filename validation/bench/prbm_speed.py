"""Speed of the PRBM library: one segment solve at one load level, a 10,000-level sweep, the
chapter-3 inflection solves, a four-bar torque sweep; one load level of four-link PRB networks
(``network_rows``: the parallel-guided mechanism built from its geometry and the chapter-9 Test 2
four-bar, beside the FEM's time for the same case, target <= 0.5 ms); the CPU time per load level of
each segment model, called for one level and for a case's ten (``segment_level_rows``, target 20 us a
level); then the whole adapter call
``validation.run.runner.run_method(case, "prbm")`` (what ``prbm-validate bench`` times against the FEM)
for every case under cases/ with a prbm method, per case and per kind of case (target: 50 us a case),
in CPU time (the machine is shared: wall time also counts waiting for a core) with the
load average printed beside.  Run: ``.venv/bin/python validation/bench/prbm_speed.py``
(``--cases-only`` skips the library rows, ``--fast`` leaves out the cases slower than 50 ms a call,
``--case=ID`` (repeatable) times only those cases).  (Timing lives here, never in the tests.)"""

from __future__ import annotations

import math
import os
import statistics
import sys
import time
import timeit
from dataclasses import dataclass

import numpy as np

import prbm
from prbm.theta_dependent import theta_dependent_tip
from validation.case.loader import case_by_id, find_case_files, load_case
from validation.methods import prbm_network
from validation.methods.geometry import geometry
from validation.run.runner import run_method


def best(stmt, number: int, repeat: int = 5) -> float:
    """Best time per call, seconds."""
    return min(timeit.repeat(stmt, number=number, repeat=repeat)) / number


def best_cpu(stmt, number: int, repeat: int = 5) -> float:
    """Best CPU time per call, seconds (``time.process_time``: on a machine shared by other jobs the
    wall time also counts the time this process waits for a core)."""
    timer = timeit.Timer(stmt, timer=time.process_time)
    return min(timer.repeat(number=number, repeat=repeat)) / number


@dataclass(frozen=True)
class AdapterRow:
    """One case's whole PRBM adapter call as the runner makes it (``run_method(case, "prbm")``: the
    requests, the adapter with its load-level loop and bookkeeping, the runner's checks), after a first
    call that pays the one-time imports and caches: best CPU and wall seconds per call."""

    case_id: str
    kind: str
    cpu: float
    wall: float
    calls: int
    message: str


def case_kind(case) -> str:
    """The kind of PRBM case, from its description alone: the segment's boundary, straight or curved,
    its ``model``, the load kinds at the tip; or the mechanism's supports and the adapter's ``links`` or
    ``model`` option."""
    options = case.methods.get("prbm") or {}
    if case.segment is not None:
        seg = case.segment
        shape = "curved" if seg.initial_curvature() != 0.0 else "straight"
        loads = sorted({("follower " if ld.follower else "") + ld.kind for ld in case.loads})
        model = options.get("model") or seg.model
        return f"segment {seg.boundary} {shape}" + (f" {model}" if model else "") + f" ({', '.join(loads)})"
    mech = case.mechanism
    if options.get("links"):
        return "mechanism, hand-given " + ("slider-crank" if "r11" in options["links"] else "four-bar")
    return f"mechanism, {len(mech.beams)} beam(s), {len(mech.links)} link(s)" + (
        f", model {options['model']}" if options.get("model") else ""
    )


def time_adapter(case, budget: float = 0.05) -> AdapterRow:
    """Best of 5 repeats of ``number`` calls (as many as fit in ``budget`` seconds, at most 2000) after
    one warm-up call; a case slower than 0.1 s a call is timed on 2 single calls."""
    run = run_method(case, "prbm")  # warm: imports, first-call caches (a one-time cost)
    cpu_once = best_cpu(lambda: run_method(case, "prbm"), 1, 1)
    if cpu_once > 0.1:
        number, repeat = 1, 2
    else:
        number, repeat = max(1, min(2000, int(budget / max(cpu_once, 1e-7)))), 5
    cpu = best_cpu(lambda: run_method(case, "prbm"), number, repeat)
    wall = best(lambda: run_method(case, "prbm"), number, repeat)
    return AdapterRow(case.case.id, case_kind(case), cpu, wall, number, run.message)


def adapter_rows(only: list[str] | None = None, slower_than: float = math.inf) -> list[AdapterRow]:
    """Every case under cases/ with a prbm method (or the ids in ``only``); cases whose one call costs
    more than ``slower_than`` CPU seconds are left out (``--fast``: the chapter-5 couplers take seconds)."""
    rows = []
    for path in find_case_files():
        case = load_case(path).case
        if "prbm" not in case.methods or (only and case.case.id not in only):
            continue
        if slower_than < math.inf:
            run_method(case, "prbm")
            if best_cpu(lambda: run_method(case, "prbm"), 1, 1) > slower_than:
                continue
        rows.append(time_adapter(case))
    return rows


def print_adapter_rows(rows: list[AdapterRow]) -> None:
    """One line per case, then per kind of case the median and the largest CPU time per call."""
    width = max(len(r.case_id) for r in rows)
    print(
        f"{'case':<{width}}  {'CPU/call':>12}  {'wall/call':>12}  kind; message (whole adapter call, "
        f"run_method(case, 'prbm'), first call excluded)"
    )
    for r in sorted(rows, key=lambda r: (r.kind, r.case_id)):
        print(f"{r.case_id:<{width}}  {r.cpu * 1e6:9.1f} us  {r.wall * 1e6:9.1f} us  {r.kind}; {r.message[:50]}")
    print()
    kinds: dict[str, list[float]] = {}
    for r in rows:
        kinds.setdefault(r.kind, []).append(r.cpu)
    width = max(len(k) for k in kinds)
    print(f"{'kind of case':<{width}}  cases  {'median CPU':>12}  {'max CPU':>12}")
    for kind, cpus in sorted(kinds.items()):
        print(f"{kind:<{width}}  {len(cpus):5d}  {statistics.median(cpus) * 1e6:9.1f} us  {max(cpus) * 1e6:9.1f} us")


def library_rows() -> list[tuple[str, float]]:
    rows = []
    rows.append(("fixed_pinned_tip, 1 level", best(lambda: prbm.fixed_pinned_tip(2.0, 0.5, length=1.0, EI=1.0), 2000)))
    P = np.linspace(0.0, 5.0, 10_000)
    rows.append(
        ("fixed_pinned_tip, 10,000 levels", best(lambda: prbm.fixed_pinned_tip(P, 0.5, length=1.0, EI=1.0), 20))
    )
    n = np.linspace(-3.9, 9.9, 10_000)
    rows.append(
        ("fixed_pinned_tip, 10,000 (P, n) pairs", best(lambda: prbm.fixed_pinned_tip(P, n, length=1.0, EI=1.0), 20))
    )
    rows.append(
        (
            "fixed_pinned_from_tip, 10,000 levels",
            best(lambda: prbm.fixed_pinned_from_tip(n=0.5, b=0.5 * P / 5.0, length=1.0, EI=1.0), 20),
        )
    )
    rows.append(("pure_moment_tip, 10,000 levels", best(lambda: prbm.pure_moment_tip(P, length=1.0, EI=1.0), 50)))
    rows.append(
        (
            "curved_fixed_pinned_tip, 10,000 levels",
            best(lambda: prbm.curved_fixed_pinned_tip(P, 0.5, length=1.0, EI=1.0, curvature=0.5), 20),
        )
    )
    rows.append(
        ("fixed_guided_tip, 10,000 levels", best(lambda: prbm.fixed_guided_tip(P, 0.5, length=1.0, EI=1.0), 20))
    )
    rows.append(
        (
            "slfp_tip, 10,000 levels",
            best(lambda: prbm.slfp_tip(P, 0.5, flexure_length=0.1, rigid_length=1.0, EI=1.0), 20),
        )
    )
    beam = prbm.InflectionBeam(20.0, 30e6 * 1.02e-5)
    rows.append(
        (
            "inflection solve_loads (Table 3.2 Ex. 1, all roots)",
            best(lambda: prbm.solve_loads(beam, 3.5, 1.5, 15.0), 3, 3),
        )
    )
    rows.append(
        (
            "inflection case 1 (Table 3.3 Ex. 3, all roots)",
            best(lambda: prbm.solve_displacements(beam, a=18.5, b=5.0, theta0=math.radians(-45)), 3, 3),
        )
    )
    rows.append(
        (
            "inflection case 2c (Table 3.6 Ex. 3, all roots)",
            best(lambda: prbm.solve_displacements(beam, b=5.0, theta0=math.radians(-30), l1=9.0), 3, 3),
        )
    )
    fb = prbm.FourBar(
        3.902 - 0.8802j,
        4.754 + 2.767j,
        6.249 - 2.176j,
        7.099 + 1.471j,
        7.929 - 0.148j,
        springs=(38.356, 0, 0, 0),
        theta_free=(math.radians(15.86), -0.4958, -0.1057),
    )
    th = np.linspace(0.3, 0.9, 100)
    rows.append(("FourBar.input_torque (network virtual work), 100 angles", best(lambda: fb.input_torque(th), 5)))
    rows.append(("FourBar.positions_under_torque, 1 level", best(lambda: fb.positions_under_torque([9.75]), 20)))
    return rows


def segment_level_rows() -> list[tuple[str, float, float | None]]:
    """(model, best CPU seconds per load level of a one-level call, of a ten-level call or None): each
    segment model of the library called as the error atlas calls it point by point (one level) and as the
    adapter calls it for a case (its few levels at once); target: 20 us a level."""
    P = [0.5 * i for i in range(10)]
    n = [0.5] * 10
    M = [0.1 * i for i in range(10)]
    L, EI = 1.0, 1.0
    calls = {
        "fixed_pinned_tip": (
            lambda: prbm.fixed_pinned_tip(2.0, 0.5, length=L, EI=EI),
            lambda: prbm.fixed_pinned_tip(P, n, length=L, EI=EI),
        ),
        "pure_moment_tip": (
            lambda: prbm.pure_moment_tip(0.5, length=L, EI=EI),
            lambda: prbm.pure_moment_tip(M, length=L, EI=EI),
        ),
        "curved_fixed_pinned_tip": (
            lambda: prbm.curved_fixed_pinned_tip(2.0, 0.5, length=L, EI=EI, curvature=0.5),
            lambda: prbm.curved_fixed_pinned_tip(P, n, length=L, EI=EI, curvature=0.5),
        ),
        "fixed_guided_tip": (
            lambda: prbm.fixed_guided_tip(2.0, 0.5, length=L, EI=EI),
            lambda: prbm.fixed_guided_tip(P, n, length=L, EI=EI),
        ),
        "fixed_guided_monotonic_tip": (
            lambda: prbm.fixed_guided_monotonic_tip(2.0, 0.5, 0.5, length=L, EI=EI),
            lambda: prbm.fixed_guided_monotonic_tip(P, n, M, length=L, EI=EI),
        ),
        "composite_beam_tip (follower)": (
            lambda: prbm.composite_beam_tip(2.0, 0.5, length=L, EI=EI, follower=True),
            lambda: prbm.composite_beam_tip(P, 0.5, length=L, EI=EI, follower=True),
        ),
        "slfp_tip": (
            lambda: prbm.slfp_tip(2.0, 0.5, flexure_length=0.1, rigid_length=L, EI=EI),
            lambda: prbm.slfp_tip(P, n, flexure_length=0.1, rigid_length=L, EI=EI),
        ),
        "fixed_guided_displaced_tip": (
            lambda: prbm.fixed_guided_displaced_tip(0.2, length=L, EI=EI),
            lambda: prbm.fixed_guided_displaced_tip(M, length=L, EI=EI),
        ),
        "theta_dependent_tip (eq 51)": (lambda: theta_dependent_tip(2.0, 0.5, length=L, EI=EI, fit="51"), None),
    }
    rows: list[tuple[str, float, float | None]] = []
    for name, (one, ten) in calls.items():
        rows.append((name, best_cpu(one, 500), best_cpu(ten, 100) / 10 if ten is not None else None))
    return rows


def network_rows() -> list[tuple[str, float, float, float | None]]:
    """(what, best wall and CPU seconds per load level of the PRB network after warm-up, FEM wall
    seconds per level of the same case or None): the network built by rule for seed004_parallel_guided (ground, two middle
    links, coupler: four links), solved one level at a time and over its 8 levels; the chapter-9
    Test 2 four-bar under one design torque."""
    rows: list[tuple[str, float, float, float | None]] = []
    case = case_by_id("seed004_parallel_guided").case
    model = prbm.build(geometry(case.mechanism), prbm_network.rules(None, case.mechanism))
    net = model.network
    all_loads = prbm_network.network_loads(case, model)
    n = case.n_levels()
    one = [prbm.Force("M", (0.0,), (8.0,))]
    prbm.solve(net, one, 1)  # warm-up: the network's mobility analysis is done once
    run_method(case, "fem")
    fem = min(timeit.repeat(lambda: run_method(case, "fem"), number=1, repeat=3)) / n
    rows.append(
        (
            "parallel-guided network, 1 level from the unloaded pose",
            best(lambda: prbm.solve(net, one, 1), 50),
            best_cpu(lambda: prbm.solve(net, one, 1), 50),
            fem,
        )
    )
    rows.append(
        (
            "parallel-guided network, per level of 8 (stability on)",
            best(lambda: prbm.solve(net, all_loads, n), 20) / n,
            best_cpu(lambda: prbm.solve(net, all_loads, n), 20) / n,
            fem,
        )
    )
    rows.append(
        (
            "parallel-guided network, per level of 8 (stability off)",
            best(lambda: prbm.solve(net, all_loads, n, stability=False), 20) / n,
            best_cpu(lambda: prbm.solve(net, all_loads, n, stability=False), 20) / n,
            fem,
        )
    )
    fb = prbm.FourBar(
        3.902 - 0.8802j,
        4.754 + 2.767j,
        6.249 - 2.176j,
        7.099 + 1.471j,
        7.929 - 0.148j,
        springs=(38.356, 0, 0, 0),
        theta_free=(math.radians(15.86), -0.4958, -0.1057),
    )
    net4 = fb.network()
    torque = [prbm.Couple("link2", (9.75,))]
    prbm.solve(net4, torque, 1)
    rows.append(
        (
            "Test 2 four-bar network, 1 design torque",
            best(lambda: prbm.solve(net4, torque, 1), 50),
            best_cpu(lambda: prbm.solve(net4, torque, 1), 50),
            None,
        )
    )
    return rows


def main() -> None:
    if "--cases-only" not in sys.argv:
        rows = network_rows()
        width = max(len(r[0]) for r in rows)
        print(
            f"{'PRB network (one load level, after warm-up)':<{width}}  {'PRBM wall':>10}  {'PRBM CPU':>10}  "
            f"{'FEM same case':>14}"
        )
        for name, t, cpu, fem in rows:
            fem_text = f"{fem * 1e3:11.1f} ms" if fem is not None else ""
            print(f"{name:<{width}}  {t * 1e3:7.3f} ms  {cpu * 1e3:7.3f} ms  {fem_text:>14}")
        print()
        library = library_rows()
        width = max(len(r[0]) for r in library)
        for name, t in library:
            print(f"{name:<{width}}  {t * 1e6:12.1f} us")
        print()
        levels = segment_level_rows()
        header = "segment model, CPU per load level"
        width = max(len(header), *(len(r[0]) for r in levels))
        print(f"{header:<{width}}  {'1 level':>10}  {'10 levels':>10}")
        for name, one, ten in levels:
            ten_text = f"{ten * 1e6:7.1f} us" if ten is not None else ""
            print(f"{name:<{width}}  {one * 1e6:7.1f} us  {ten_text:>10}")
        print()
    only = [a.split("=", 1)[1] for a in sys.argv if a.startswith("--case=")]
    slower_than = 0.05 if "--fast" in sys.argv else math.inf
    print(f"load average before the adapter rows: {os.getloadavg()[0]:.1f}")
    print_adapter_rows(adapter_rows(only or None, slower_than))
    print(f"load average after: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
