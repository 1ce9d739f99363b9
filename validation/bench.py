"""``prbm-validate bench``: run time against error for every method, on the same cases, in one run.

For each benchmark case the FEM runs at 2, 4, 8, ... 256 elements per member, with and without
Richardson extrapolation, beside the PRBM, the exact elastica and (if installed) OpenSeesPy on the
same mesh and load steps. Each configuration is timed in this process with ``time.perf_counter``:
one warm-up, then the median of ``repeats`` runs; its error is the largest tip-position error over
the benchmarked load levels, over the characteristic length, against the exact solution (the elastica
method on the same case, or the case's 'exact' references). Peak Python memory is measured in a
separate run with ``tracemalloc``. BLAS threads are pinned to one and recorded.

Writes ``bench.csv``, ``headline.json`` and plots (error against time with the Pareto front; time
against elements with the fitted growth exponent) under the output folder.
"""
from __future__ import annotations

import json
import math
import os
import statistics
import time
import tracemalloc
from pathlib import Path

import numpy as np
import pandas as pd

from validation.exit_status import decide
from validation.loader import CaseError, case_by_id, find_case_files
from validation.methods.base import Request
from validation.runner import characteristic_length, requests_for, run_cases, run_method

# case id -> levels benchmarked (None = all)
BENCH_CASES: dict[str, list[int] | None] = {
    "cantilever_tip_load": [0, 4, 9],    # PL^2/EI = 1, 5, 10
    "pure_moment_roll_up": None,
    "lee_frame": None,
    "bapat2015_test1a": None,
    "bapat2015_test2": None,
}
POSITION = ("x", "y", "dx", "dy")


def _pin_blas() -> dict[str, str]:
    try:
        from threadpoolctl import threadpool_limits

        threadpool_limits(1)
    except ImportError:
        pass
    return {k: os.environ.get(k, "") for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                                               "OPENBLAS_CORETYPE")}


def _restrict(case, method: str, options: dict, levels: list[int] | None):
    outputs = []
    for out in case.outputs:
        if out.quantity in POSITION + ("limit_load",):
            update = {"methods": None}
            if levels is not None and out.quantity != "limit_load":
                update["levels"] = levels
            outputs.append(out.model_copy(update=update))
    return case.model_copy(update={"methods": {method: options}, "outputs": outputs})


def _timed(case, method: str, repeats: int):
    run_method(case, method)  # warm-up (imports, caches)
    times, run = [], None
    for _ in range(repeats):
        run = run_method(case, method)
        times.append(run.wall_time)
    tracemalloc.start()
    run_method(case, method)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return run, statistics.median(times), peak


def _exact(case, levels) -> tuple[dict, str]:
    """Exact tip positions: the elastica on this case, else the case's 'exact' references."""
    if "elastica" in case.methods:
        run = run_method(_restrict(case, "elastica", dict(case.methods["elastica"] or {}), levels), "elastica")
        if run.converged and run.values:
            return run.values, "elastica"
    refs = {Request(r.quantity, r.point if r.quantity != "limit_load" else "", r.level): r.value
            for r in case.references
            if r.label in ("exact", "elliptic") or (r.quantity == "limit_load" and r.label == "published")}
    return refs, "references"


def _error(values: dict, exact: dict, scale: float) -> float:
    """Largest tip-position (or limit-load) error over the levels, relative to the scale."""
    worst = 0.0
    found = False
    by_point = {}
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


def _pareto(frame: pd.DataFrame) -> pd.Series:
    order = frame.sort_values("time_s")
    best, flags = math.inf, {}
    for idx, row in order.iterrows():
        flags[idx] = row["error"] < best
        best = min(best, row["error"]) if not math.isnan(row["error"]) else best
    return pd.Series(flags).reindex(frame.index)


def _time_to_error(frame: pd.DataFrame, method: str, target: float) -> float:
    rows = frame[(frame["method"] == method) & (frame["error"] <= target)]
    return float(rows["time_s"].min()) if len(rows) else math.nan


def run_bench(out: Path, quick: bool = False, cases: dict[str, list[int] | None] | None = None) -> int:
    out.mkdir(parents=True, exist_ok=True)
    blas = _pin_blas()
    meshes = [2, 4, 8, 16, 32] if quick else [2, 4, 8, 16, 32, 64, 128, 256]
    repeats = 1 if quick else 5
    rows, skipped = [], []
    unusable, failed = [], []  # exit status 1 and 2 (validation/exit_status.py)
    for case_id, levels in (cases or BENCH_CASES).items():
        try:
            loaded = case_by_id(case_id)
        except CaseError as exc:
            skipped.append(f"{case_id}: {exc.problem}")
            unusable.append(case_id)
            continue
        case = loaded.case
        scale = characteristic_length(case)
        exact, exact_from = _exact(case, levels)
        configs = [("prbm", {}, None), ("elastica", {}, None), ("fem (case options)", {}, None)]
        runs = []
        for n in meshes:
            configs += [("fem", {"elements": n, "error_estimate": False}, n),
                        ("fem+richardson", {"elements": n, "error_estimate": True, "richardson": True}, n),
                        ("opensees", {"elements": n}, n)]
        for label, extra, n in configs:
            method = label.split("+")[0].split(" ")[0]
            if method != "opensees" and method not in case.methods:
                continue
            options = dict(case.methods.get(method) or {}) | extra
            sub = _restrict(case, method, options, levels)
            if not requests_for(sub, method):
                skipped.append(f"{case_id}/{label}: no tip-position or limit-load output to time")
                continue
            run, median, peak = _timed(sub, method, repeats)
            if not run.converged and method in case.methods:
                failed.append(f"{case_id}/{label} n={n}: {run.message}")
            if not run.values:
                skipped.append(f"{case_id}/{label} n={n}: {run.message}")
                continue
            runs.append((label, n, run))
            rows.append(dict(case=case_id, method=label, elements=n, time_s=median, repeats=repeats,
                             error=math.nan, error_reference=exact_from,
                             iterations=run.extras.get("iterations", math.nan), peak_memory_mb=peak / 2**20,
                             converged=run.converged, message=run.message[:200]))
        if not exact:  # no exact solution (a mechanism): the finest extrapolated FEM is the reference
            finest = [r for label, n, r in runs if label == "fem+richardson"]
            if finest:
                exact, exact_from = finest[-1].values, f"fem+richardson at {max(meshes)} elements (finest)"
        for row, (label, n, run) in zip(rows[len(rows) - len(runs):], runs):
            row["error"] = _error(run.values, exact, scale)
            row["error_reference"] = exact_from
            print(f"  {case_id:<28} {label:<16} n={n!s:<4} {row['time_s'] * 1e3:9.2f} ms  "
                  f"error={row['error']:.2e}", flush=True)
    frame = pd.DataFrame(rows)
    frame.to_csv(out / "bench.csv", index=False)
    headline = _headline(frame, quick)
    headline["blas"] = blas
    headline["skipped"] = skipped
    (out / "headline.json").write_text(json.dumps(headline, indent=2, default=float))
    _plots(frame, out)
    print(json.dumps({k: v for k, v in headline.items() if k != "skipped"}, indent=2, default=float))
    for s in skipped:
        print(f"skipped: {s}")
    for f in failed:
        print(f"did not converge: {f}")
    return int(decide(bad_input=bool(unusable), failed=bool(failed)))


def _headline(frame: pd.DataFrame, quick: bool) -> dict:
    headline: dict = {"fem_over_opensees_time_at_error": {}, "prbm_over_fem": {}, "growth_exponent": {}}
    for case_id, part in frame.groupby("case") if len(frame) else []:
        for target in (1e-4, 1e-6):
            ours = float(np.nanmin([_time_to_error(part, "fem", target),
                                    _time_to_error(part, "fem+richardson", target), math.inf]))
            ours = math.nan if math.isinf(ours) else ours
            peer = _time_to_error(part, "opensees", target)
            reached = (not math.isnan(ours), not math.isnan(peer))
            headline["fem_over_opensees_time_at_error"][f"{case_id} @ {target:g} L"] = dict(
                fem_s=None if math.isnan(ours) else ours, opensees_s=None if math.isnan(peer) else peer,
                ratio=ours / peer if all(reached) else None,
                note={(True, True): "", (True, False): "OpenSees did not reach this error (up to 256 elements)",
                      (False, True): "our FEM did not reach this error", (False, False): "neither reached it"}[reached]
                + ("" if part["error_reference"].iloc[0] in ("elastica",) else
                   f"; reference: {part['error_reference'].iloc[0]}"))
        prbm = part[part["method"] == "prbm"]
        fem = part[(part["method"] == "fem")]
        fem_case = part[part["method"] == "fem (case options)"]
        if len(prbm) and len(fem_case):
            headline["prbm_over_fem"][case_id] = dict(
                prbm_time_s=float(prbm["time_s"].iloc[0]), fem_time_s=float(fem_case["time_s"].iloc[0]),
                ratio=float(prbm["time_s"].iloc[0] / fem_case["time_s"].iloc[0]),
                prbm_error=float(prbm["error"].iloc[0]), fem_error=float(fem_case["error"].iloc[0]))
        big = fem[fem["elements"] >= 16]
        if len(big) >= 2:
            slope = np.polyfit(np.log(big["elements"]), np.log(big["time_s"]), 1)[0]
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


def _plots(frame: pd.DataFrame, out: Path) -> None:
    if frame.empty:
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    for case_id, part in frame.groupby("case"):
        part = part[part["error"] > 0]
        if part.empty:
            continue
        fig, ax = plt.subplots(figsize=(6, 4.5))
        for method, rows in part.groupby("method"):
            rows = rows.sort_values("time_s")
            ax.loglog(rows["time_s"], rows["error"], "o-" if rows["elements"].notna().any() else "s",
                      label=method)
        front = part[_pareto(part).astype(bool)].sort_values("time_s")
        ax.loglog(front["time_s"], front["error"], "k--", lw=1, label="Pareto front")
        ax.set_xlabel("median wall time [s]")
        ax.set_ylabel("tip-position error / L")
        ax.set_title(case_id)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(out / f"{case_id}_error_vs_time.png", dpi=90)
        plt.close(fig)
    fem = frame[frame["method"].isin(["fem", "opensees"]) & frame["elements"].notna()]
    if len(fem):
        fig, ax = plt.subplots(figsize=(6, 4.5))
        for (case_id, method), rows in fem.groupby(["case", "method"]):
            rows = rows.sort_values("elements")
            big = rows[rows["elements"] >= 16]
            slope = np.polyfit(np.log(big["elements"]), np.log(big["time_s"]), 1)[0] if len(big) >= 2 else math.nan
            ax.loglog(rows["elements"], rows["time_s"], "o-", label=f"{case_id} {method} (slope {slope:.2f})")
        ax.set_xlabel("elements per member")
        ax.set_ylabel("median wall time [s]")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / "time_vs_elements.png", dpi=90)
        plt.close(fig)
