"""Benchmark: fem (this project) against OpenSeesPy (compiled C++, corotational).

Both codes solve the same models in one process:

* cantilever with a transverse tip load of fixed direction, P L^2/EI = 1, 5, 10
  (EA/EI = 1e9 L^2, so the axial strain, <= 1e-8, is below every target);
  error = |tip position - elastica (elliptic integrals)| / L;
* Lee's frame, first limit load P_max; error = |P_max - P_ref| / P_ref, with
  P_ref from a three-mesh Romberg extrapolation of fem's arc-length runs,
  cross-checked against OpenSees' own Richardson value (printed).

For each code and strategy the mesh is doubled until the error is below
1e-4 and 1e-6; reported is the wall time of the cheapest run (or run set)
that reaches the target, best of `REPEATS`.  fem strategies: a plain solve,
Richardson with n and 2n elements (time of both solves), Romberg with n, 2n,
4n (time of all three); `fem.solve_with_error_estimate` warm-starts each finer
load-control solve from the coarser result.  OpenSees: LoadControl (fewest steps that converge of
1, 2, 5, 10, 20) with Newton, NormDispIncr 1e-10, BandGeneral; Lee's frame by
DisplacementControl (dv = -0.25) and a parabola through the largest load.
Then the cost of one Newton iteration (wall time / linear solves) for 10, 40
and 160 elements.  OpenSees is skipped cleanly when it is not installed.

Run:  python validation/bench/fem_vs_opensees.py  [--quick]
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import fem  # noqa: E402
from elastica import cantilever_tip_load  # noqa: E402

try:
    import openseespy.opensees as ops
except Exception:  # pragma: no cover - optional peer
    ops = None

REPEATS = 3
TARGETS = (1e-4, 1e-6)
EI, EA, L = 1.0, 1e9, 1.0


# ---------------------------------------------------------------- references
def elastica_tip(alpha):
    """Exact tip position (x, y) of the tip-loaded cantilever, PL^2/EI = alpha (elliptic integrals)."""
    tip = cantilever_tip_load(alpha)
    return np.array([tip.a, tip.b]) * L


def best_time(fn):
    best, out = np.inf, None
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


# ---------------------------------------------------------------- fem models
def fem_cantilever(alpha, n):
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", L, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(EA, EI), n_elements=n)
    m.add_support("root", "fixed")
    m.add_force("tip", 0.0, alpha * EI / L**2)
    return m


def fem_lee(n):
    m = fem.Model()
    for name, x, y in (("A", 0, 0), ("B", 0, 120), ("P", 24, 120), ("C", 120, 120)):
        m.add_node(name, x, y)
    s = fem.Section.from_EI(720.0 * 6, 720.0 * 2)
    m.add_member("A", "B", s, n_elements=n)
    m.add_member("B", "P", s, n_elements=max(1, n // 5))
    m.add_member("P", "C", s, n_elements=n - max(1, n // 5))
    m.add_support("A", "pinned")
    m.add_support("C", "pinned")
    m.add_force("P", 0.0, -1.0)
    return m


def fem_lee_pmax(n):
    r = fem.solve(fem_lee(n), control="arclength", arc_length=5.0, max_arc_length=10.0,
                  max_limit_points=1)
    return r.critical_points[0]["load_factor"], r


# ---------------------------------------------------------------- OpenSees models
def ops_cantilever(alpha, n):
    """Tip position and Newton iterations; None if no step count converges."""
    for steps in (1, 2, 5, 10, 20):
        ops.wipe()
        ops.model("basic", "-ndm", 2, "-ndf", 3)
        for i in range(n + 1):
            ops.node(i + 1, i * L / n, 0.0)
        ops.fix(1, 1, 1, 1)
        ops.geomTransf("Corotational", 1)
        for e in range(n):
            ops.element("elasticBeamColumn", e + 1, e + 1, e + 2, EA, 1.0, EI, 1)
        ops.timeSeries("Linear", 1)
        ops.pattern("Plain", 1, 1)
        ops.load(n + 1, 0.0, alpha * EI / L**2, 0.0)
        ops.system("BandGeneral")
        ops.numberer("RCM")
        ops.constraints("Plain")
        ops.test("NormDispIncr", 1e-10, 50)
        ops.algorithm("Newton")
        ops.integrator("LoadControl", 1.0 / steps)
        ops.analysis("Static")
        its, ok = 0, 0
        for _ in range(steps):
            ok = ops.analyze(1)
            its += ops.testIter()
            if ok != 0:
                break
        if ok == 0:
            ux, uy = ops.nodeDisp(n + 1)[:2]
            return np.array([L + ux, uy]), its
    return None, 0


def ops_lee_pmax(n):
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    nb = max(1, n // 5)
    xs = [(0.0, 120.0 * i / n) for i in range(n + 1)]
    xs += [(24.0 * i / nb, 120.0) for i in range(1, nb + 1)]
    xs += [(24.0 + 96.0 * i / (n - nb), 120.0) for i in range(1, n - nb + 1)]
    for i, (x, y) in enumerate(xs):
        ops.node(i + 1, x, y)
    load_node = n + nb + 1
    ops.fix(1, 1, 1, 0)
    ops.fix(len(xs), 1, 1, 0)
    ops.geomTransf("Corotational", 1)
    for e in range(len(xs) - 1):
        ops.element("elasticBeamColumn", e + 1, e + 1, e + 2, 6.0, 720.0, 2.0, 1)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(load_node, 0.0, -1.0, 0.0)
    ops.system("BandGeneral")
    ops.numberer("RCM")
    ops.constraints("Plain")
    ops.test("NormDispIncr", 1e-10, 50)
    ops.algorithm("Newton")
    dv = -0.25
    ops.integrator("DisplacementControl", load_node, 2, dv)
    ops.analysis("Static")
    lams, its = [0.0], 0
    for _ in range(240):
        if ops.analyze(1) != 0:
            break
        its += ops.testIter()
        lams.append(ops.getLoadFactor(1))
        if len(lams) > 3 and lams[-1] < lams[-2]:
            break
    k = int(np.argmax(lams))
    y0, y1, y2 = lams[k - 1], lams[k], lams[min(k + 1, len(lams) - 1)]
    den = y0 - 2 * y1 + y2
    pmax = y1 - (y2 - y0) ** 2 / (8 * den) if den != 0 else y1
    return pmax, its


# ---------------------------------------------------------------- sweeps
def sweep(name, run, error, ns, targets=TARGETS):
    """Times to reach each target: dict target -> (time, n, error)."""
    reached, rows = {}, []
    for n in ns:
        t, out = best_time(lambda: run(n))
        err = error(out)
        rows.append((n, t, err))
        for tgt in targets:
            if tgt not in reached and err <= tgt:
                reached[tgt] = (t, n, err)
        if all(tgt in reached for tgt in targets):
            break
    print(f"  {name:<28s} " + "  ".join(f"n={n}:{t * 1e3:.1f}ms/{e:.1e}" for n, t, e in rows))
    return reached


def fem_strategies(model_fn, quantity, exact, ns, scale):
    """Plain, Richardson (n, 2n) and Romberg (n, 2n, 4n) sweeps for fem."""
    out = {}
    out["fem plain"] = sweep("fem plain", lambda n: quantity(fem.solve(model_fn(n))),
                             lambda q: np.max(np.abs(q - exact)) / scale, ns)

    def rich(n, levels):
        est = fem.solve_with_error_estimate(model_fn(n), levels=levels)
        return est
    for levels, label in ((2, "fem Richardson n,2n"), (3, "fem Romberg n,2n,4n")):
        out[label] = sweep(label, lambda n, lv=levels: rich(n, lv),
                           lambda est: np.max(np.abs(quantity_ext(est) - exact)) / scale, ns)
    return out


def quantity_ext(est):
    return est.extrapolated["positions"][-1, 1]


def report(title, results):
    print(f"\n  {title}: wall time to reach the error target")
    for tgt in TARGETS:
        line = [f"    error <= {tgt:.0e}:"]
        for name, reached in results.items():
            if tgt in reached:
                t, n, e = reached[tgt]
                line.append(f"{name} {t * 1e3:.1f} ms (n={n})")
            else:
                line.append(f"{name} not reached")
        print("  |  ".join(line))


def cantilever_benchmark(alpha, quick):
    exact = elastica_tip(alpha)
    print(f"\nCantilever P L^2/EI = {alpha:g}   exact tip (x, y)/L = {exact / L}")
    ns = [1, 2, 4, 8, 16, 32, 64] if quick else [1, 2, 4, 8, 16, 32, 64, 128]
    res = fem_strategies(lambda n: fem_cantilever(alpha, n), lambda r: r.position("tip"),
                         exact, ns, L)
    if ops is not None:
        ns_ops = [4, 8, 16, 32, 64, 128, 256, 512] if quick else [4, 8, 16, 32, 64, 128, 256, 512, 1024]
        res["OpenSees"] = sweep("OpenSees", lambda n: ops_cantilever(alpha, n)[0],
                                lambda p: np.inf if p is None else np.max(np.abs(p - exact)) / L,
                                ns_ops)
    report(f"cantilever alpha={alpha:g}", res)
    return res


def lee_benchmark(quick):
    print("\nLee's frame, first limit load")
    p = {n: fem_lee_pmax(n)[0] for n in (10, 20, 40)}
    r2a = p[20] + (p[20] - p[10]) / 3
    r2b = p[40] + (p[40] - p[20]) / 3
    p_ref = r2b + (r2b - r2a) / 15
    print(f"  fem P_max (10/20/40 per member) = {p[10]:.6f} / {p[20]:.6f} / {p[40]:.6f};"
          f" Romberg P_ref = {p_ref:.7f}  (P_max L^2/EI = {p_ref * 10:.5f})")
    res = {}
    ns = [5, 10, 20, 40, 80] if quick else [5, 10, 20, 40, 80, 160]
    res["fem plain"] = sweep("fem plain", lambda n: fem_lee_pmax(n)[0],
                             lambda q: abs(q - p_ref) / p_ref, ns)

    def rich(n):
        a, b = fem_lee_pmax(n)[0], fem_lee_pmax(2 * n)[0]
        return b + (b - a) / 3
    res["fem Richardson n,2n"] = sweep("fem Richardson n,2n", rich,
                                       lambda q: abs(q - p_ref) / p_ref, ns)
    if ops is not None:
        o = {n: ops_lee_pmax(n)[0] for n in (20, 40)}
        print(f"  OpenSees P_max 20/40 per member = {o[20]:.6f} / {o[40]:.6f}; "
              f"Richardson {o[40] + (o[40] - o[20]) / 3:.7f}")
        ns_ops = [5, 10, 20, 40, 80] if quick else [5, 10, 20, 40, 80, 160]
        res["OpenSees"] = sweep("OpenSees", lambda n: ops_lee_pmax(n)[0],
                                lambda q: abs(q - p_ref) / p_ref, ns_ops)
    report("Lee's frame P_max (relative error)", res)


def per_iteration_cost():
    print("\nCost of one Newton iteration (cantilever alpha = 5; wall time / linear solves)")
    for n in (10, 40, 160):
        t, r = best_time(lambda: fem.solve(fem_cantilever(5.0, n)))
        its = r.iterations + r.rejected_iterations
        line = f"  n={n:4d}: fem {t / its * 1e3:.3f} ms ({its} it, {t * 1e3:.1f} ms)"
        if ops is not None:
            t_o, (pos, its) = best_time(lambda: ops_cantilever(5.0, n))
            line += f"   OpenSees {t_o / max(its, 1) * 1e3:.3f} ms ({its} it, {t_o * 1e3:.1f} ms)"
        print(line)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller meshes, fewer repeats")
    args = parser.parse_args()
    global REPEATS
    if args.quick:
        REPEATS = 1
    if ops is None:
        print("openseespy is not installed: OpenSees runs are skipped")
    for alpha in (1.0, 5.0, 10.0):
        cantilever_benchmark(alpha, args.quick)
    lee_benchmark(args.quick)
    per_iteration_cost()


if __name__ == "__main__":
    main()
