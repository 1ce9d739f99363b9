"""Speed of the PRBM library: one segment solve at one load level, a 10,000-level sweep, the
chapter-3 inflection solves, a four-bar torque sweep; one load level of four-link PRB networks
(``network_rows``: the parallel-guided mechanism built from its geometry and the chapter-9 Test 2
four-bar, beside the FEM's time for the same case, target <= 0.5 ms); then the whole adapter call
``validation.run.runner.run_method(case, "prbm")`` (what ``prbm-validate bench`` times against the FEM)
for every case under cases/ with a prbm method.  Run: ``.venv/bin/python validation/bench/prbm_speed.py``
(``--cases-only`` skips the library rows).  (Timing lives here, never in the tests.)"""
from __future__ import annotations

import math
import sys
import time
import timeit

import numpy as np

import prbm
from validation.case.loader import case_by_id, find_case_files, load_case
from validation.methods import prbm_network
from validation.run.runner import run_method


def best(stmt, number: int, repeat: int = 5) -> float:
    """Best time per call, seconds."""
    return min(timeit.repeat(stmt, number=number, repeat=repeat)) / number


def best_cpu(stmt, number: int, repeat: int = 5) -> float:
    """Best CPU time per call, seconds (``time.process_time``: on a machine shared by other jobs the
    wall time also counts the time this process waits for a core)."""
    timer = timeit.Timer(stmt, timer=time.process_time)
    return min(timer.repeat(number=number, repeat=repeat)) / number


def adapter_rows() -> list[tuple[str, float, str]]:
    """(case id, best seconds per whole PRBM adapter call, the run's message) for every prbm case."""
    rows = []
    for path in find_case_files():
        case = load_case(path).case
        if "prbm" not in case.methods:
            continue
        run = run_method(case, "prbm")  # warm: imports, first-call caches
        once = min(timeit.repeat(lambda: run_method(case, "prbm"), number=1, repeat=3))
        number = max(1, min(200, int(0.02 / max(once, 1e-7))))
        rows.append((case.case.id, best(lambda: run_method(case, "prbm"), number, 5), run.message))
    return rows


def library_rows() -> list[tuple[str, float]]:
    rows = []
    rows.append(("fixed_pinned_tip, 1 level", best(lambda: prbm.fixed_pinned_tip(2.0, 0.5, length=1.0, EI=1.0), 2000)))
    P = np.linspace(0.0, 5.0, 10_000)
    rows.append(("fixed_pinned_tip, 10,000 levels", best(lambda: prbm.fixed_pinned_tip(P, 0.5, length=1.0, EI=1.0), 20)))
    n = np.linspace(-3.9, 9.9, 10_000)
    rows.append(("fixed_pinned_tip, 10,000 (P, n) pairs", best(lambda: prbm.fixed_pinned_tip(P, n, length=1.0, EI=1.0), 20)))
    rows.append(("fixed_pinned_from_tip, 10,000 levels", best(lambda: prbm.fixed_pinned_from_tip(n=0.5, b=0.5 * P / 5.0, length=1.0, EI=1.0), 20)))
    rows.append(("pure_moment_tip, 10,000 levels", best(lambda: prbm.pure_moment_tip(P, length=1.0, EI=1.0), 50)))
    rows.append(("curved_fixed_pinned_tip, 10,000 levels", best(lambda: prbm.curved_fixed_pinned_tip(P, 0.5, length=1.0, EI=1.0, curvature=0.5), 20)))
    rows.append(("fixed_guided_tip, 10,000 levels", best(lambda: prbm.fixed_guided_tip(P, 0.5, length=1.0, EI=1.0), 20)))
    rows.append(("slfp_tip, 10,000 levels", best(lambda: prbm.slfp_tip(P, 0.5, flexure_length=0.1, rigid_length=1.0, EI=1.0), 20)))
    beam = prbm.InflectionBeam(20.0, 30e6 * 1.02e-5)
    rows.append(("inflection solve_loads (Table 3.2 Ex. 1, all roots)", best(lambda: prbm.solve_loads(beam, 3.5, 1.5, 15.0), 3, 3)))
    rows.append(("inflection case 1 (Table 3.3 Ex. 3, all roots)",
                 best(lambda: prbm.solve_displacements(beam, a=18.5, b=5.0, theta0=math.radians(-45)), 3, 3)))
    rows.append(("inflection case 2c (Table 3.6 Ex. 3, all roots)",
                 best(lambda: prbm.solve_displacements(beam, b=5.0, theta0=math.radians(-30), l1=9.0), 3, 3)))
    fb = prbm.FourBar(3.902 - 0.8802j, 4.754 + 2.767j, 6.249 - 2.176j, 7.099 + 1.471j, 7.929 - 0.148j,
                      springs=(38.356, 0, 0, 0), theta_free=(math.radians(15.86), -0.4958, -0.1057))
    th = np.linspace(0.3, 0.9, 100)
    rows.append(("FourBar.input_torque (network virtual work), 100 angles", best(lambda: fb.input_torque(th), 5)))
    rows.append(("FourBar.positions_under_torque, 1 level", best(lambda: fb.positions_under_torque([9.75]), 20)))
    return rows


def network_rows() -> list[tuple[str, float, float, float | None]]:
    """(what, best wall and CPU seconds per load level of the PRB network after warm-up, FEM wall
    seconds per level of the same case or None): the network built by rule for seed004_parallel_guided (ground, two middle
    links, coupler: four links), solved one level at a time and over its 8 levels; the chapter-9
    Test 2 four-bar under one design torque."""
    rows = []
    case = case_by_id("seed004_parallel_guided").case
    model = prbm.build(prbm_network.geometry(case.mechanism), prbm_network.rules({}, case.mechanism))
    net = model.network
    all_loads = prbm_network.network_loads(case, model)
    n = case.n_levels()
    one = [prbm.Force("M", (0.0,), (8.0,))]
    prbm.solve(net, one, 1)  # warm-up: the network's mobility analysis is done once
    run_method(case, "fem")
    fem = min(timeit.repeat(lambda: run_method(case, "fem"), number=1, repeat=3)) / n
    rows.append(("parallel-guided network, 1 level from the unloaded pose",
                 best(lambda: prbm.solve(net, one, 1), 50), best_cpu(lambda: prbm.solve(net, one, 1), 50), fem))
    rows.append(("parallel-guided network, per level of 8 (stability on)",
                 best(lambda: prbm.solve(net, all_loads, n), 20) / n,
                 best_cpu(lambda: prbm.solve(net, all_loads, n), 20) / n, fem))
    rows.append(("parallel-guided network, per level of 8 (stability off)",
                 best(lambda: prbm.solve(net, all_loads, n, stability=False), 20) / n,
                 best_cpu(lambda: prbm.solve(net, all_loads, n, stability=False), 20) / n, fem))
    fb = prbm.FourBar(3.902 - 0.8802j, 4.754 + 2.767j, 6.249 - 2.176j, 7.099 + 1.471j, 7.929 - 0.148j,
                      springs=(38.356, 0, 0, 0), theta_free=(math.radians(15.86), -0.4958, -0.1057))
    net4 = fb.network()
    torque = [prbm.Couple("link2", (9.75,))]
    prbm.solve(net4, torque, 1)
    rows.append(("Test 2 four-bar network, 1 design torque", best(lambda: prbm.solve(net4, torque, 1), 50),
                 best_cpu(lambda: prbm.solve(net4, torque, 1), 50), None))
    return rows


def main() -> None:
    if "--cases-only" not in sys.argv:
        rows = network_rows()
        width = max(len(r[0]) for r in rows)
        print(f"{'PRB network (one load level, after warm-up)':<{width}}  {'PRBM wall':>10}  {'PRBM CPU':>10}  "
              f"{'FEM same case':>14}")
        for name, t, cpu, fem in rows:
            fem_text = f"{fem * 1e3:11.1f} ms" if fem is not None else ""
            print(f"{name:<{width}}  {t * 1e3:7.3f} ms  {cpu * 1e3:7.3f} ms  {fem_text:>14}")
        print()
        rows = library_rows()
        width = max(len(r[0]) for r in rows)
        for name, t in rows:
            print(f"{name:<{width}}  {t * 1e6:12.1f} us")
        print()
    rows = adapter_rows()
    width = max(len(r[0]) for r in rows)
    print(f"{'case':<{width}}  {'per call':>12}  message (whole adapter call, run_method(case, 'prbm'))")
    for name, t, message in rows:
        print(f"{name:<{width}}  {t * 1e6:12.1f} us  {message[:70]}")


if __name__ == "__main__":
    main()
