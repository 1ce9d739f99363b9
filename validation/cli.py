"""``prbm-validate``: list, run, solve, report, bench, stress, audit, sweep and synthesize.

Exit status: 0 all good, 1 a comparison outside its claimed tolerance, 2 bad input.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

from validation.loader import CaseError, find_case_files, load_case

EXIT_OK, EXIT_TOLERANCE, EXIT_BAD_INPUT = 0, 1, 2


def _paths(patterns: list[str]) -> tuple[list[Path], list[str]]:
    paths, errors = [], []
    if not patterns:
        return find_case_files(None), errors
    for pattern in patterns:
        try:
            paths.extend(find_case_files([pattern]))
        except CaseError as exc:
            errors.append(str(exc))
    return list(dict.fromkeys(paths)), errors


def cmd_list(args) -> int:
    status = EXIT_OK
    for path in find_case_files(None):
        try:
            case = load_case(path).case
        except CaseError as exc:
            print(f"error: {exc}", file=sys.stderr)
            status = EXIT_BAD_INPUT
            continue
        kind = "segment" if case.segment is not None else "mechanism"
        print(f"{case.case.id:<40} {case.case.group:<12} {kind:<9} {','.join(case.methods):<24} "
              f"{case.case.title}")
    return status


def _print_table(frame, file=sys.stdout) -> None:
    import pandas as pd

    with pd.option_context("display.max_rows", 500, "display.max_columns", 30, "display.width", 200,
                           "display.float_format", lambda v: f"{v:.4g}"):
        print(frame.to_string(index=False), file=file)


def cmd_run(args) -> int:
    from validation.runner import run_cases, summary

    paths, errors = _paths(args.cases)
    started = time.perf_counter()
    outcome = run_cases(paths, methods=args.method, use_cache=not args.no_cache, jobs=args.jobs,
                        progress=not args.quiet)
    outcome.errors = sorted(errors + outcome.errors)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    outcome.table.to_csv(out / "results.csv", index=False)
    try:
        outcome.table.astype({"finding": "string", "message": "string"}).to_parquet(out / "results.parquet")
    except ImportError:
        pass
    table = summary(outcome.table) if len(outcome.table) else None
    if table is not None:
        table.to_csv(out / "summary.csv", index=False)
        _print_table(table)
    failed = outcome.failed_comparisons
    if len(failed):
        print(f"\n{len(failed)} comparison(s) outside the claimed tolerance:")
        _print_table(failed[["case", "method", "quantity", "point", "level", "value", "reference_label",
                             "reference_value", "abs_error", "rel_error", "tolerance_rel", "tolerance_abs"]])
    for error in outcome.errors:
        print(f"error: {error}", file=sys.stderr)
    print(f"\n{len(paths) - len(outcome.errors)} case(s) run in {time.perf_counter() - started:.1f} s; "
          f"results in {out / 'results.csv'}")
    return outcome.exit_status


def cmd_solve(args) -> int:
    from validation.runner import requests_for, run_method

    try:
        [path] = find_case_files([args.case])[:1]
        case = load_case(path).case
    except CaseError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    if args.method not in case.methods:
        print(f"error: {path}: methods: the case does not ask for method '{args.method}' "
              f"(it has {', '.join(case.methods)})", file=sys.stderr)
        return EXIT_BAD_INPUT
    run = run_method(case, args.method)
    labels = case.level_labels or [str(i) for i in range(case.n_levels())]

    def clean(v):
        return None if v is None or (isinstance(v, float) and math.isnan(v)) else v

    levels = []
    for level in range(case.n_levels()):
        outputs = {}
        for req in requests_for(case, args.method):
            if req.level != level:
                continue
            name = f"{req.quantity}@{req.point}" if req.point else req.quantity
            outputs[name] = clean(run.values.get(req))
            if req in run.error_estimate:
                outputs[name + ":error_estimate"] = clean(run.error_estimate[req])
        if outputs:
            levels.append({"level": level, "label": labels[level], "outputs": outputs})
    document = {"case": case.case.id, "method": args.method, "units": case.case.units,
                "converged": run.converged, "message": run.message, "wall_time_s": run.wall_time,
                "levels": levels}
    json.dump(document, sys.stdout, indent=2 if not args.compact else None)
    print()
    return EXIT_OK if run.converged else EXIT_TOLERANCE


def cmd_report(args) -> int:
    from validation.report import build_report

    return build_report(Path(args.out), use_cache=not args.no_cache, jobs=args.jobs, cases=args.cases)


def cmd_bench(args) -> int:
    from validation.bench import run_bench

    return run_bench(Path(args.out), quick=args.quick)


def cmd_audit(args) -> int:
    from validation.audit import cmd_audit as run_audit

    return run_audit(args)


def cmd_stress(args) -> int:
    from validation.stress import run_stress

    return run_stress(Path(args.out), long=args.long, seed=args.seed, configurations=args.configurations,
                      executor="dask" if args.dask else "process", workers=args.workers, scheduler=args.scheduler)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="prbm-validate", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("list", help="every case, one line each").set_defaults(func=cmd_list)

    run = sub.add_parser("run", help="run cases and compare with the published numbers")
    run.add_argument("cases", nargs="*", help="case ids, files or globs (default: all)")
    run.add_argument("--method", action="append", help="only this method (repeatable)")
    run.add_argument("--out", default="reports/latest", help="folder for results.csv (default %(default)s)")
    run.add_argument("--jobs", type=int, default=1, help="parallel processes")
    run.add_argument("--no-cache", action="store_true", help="recompute even unchanged cases")
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    run.set_defaults(func=cmd_run)

    solve = sub.add_parser("solve", help="one case, one method, every requested output as JSON")
    solve.add_argument("case")
    solve.add_argument("--method", required=True)
    solve.add_argument("--json", action="store_true", help="JSON on stdout (the only format)")
    solve.add_argument("--compact", action="store_true")
    solve.set_defaults(func=cmd_solve)

    report = sub.add_parser("report", help="run (or reuse) every case and write the report")
    report.add_argument("cases", nargs="*")
    report.add_argument("--out", default="reports")
    report.add_argument("--jobs", type=int, default=2)
    report.add_argument("--no-cache", action="store_true")
    report.set_defaults(func=cmd_report)

    bench = sub.add_parser("bench", help="run time against error for every method")
    bench.add_argument("--out", default="reports/bench")
    bench.add_argument("--quick", action="store_true", help="fewer meshes and repeats")
    bench.set_defaults(func=cmd_bench)
    stress = sub.add_parser("stress", help="numerical stability, invariances and bad input")
    stress.add_argument("--out", default="reports/stress")
    stress.add_argument("--long", action="store_true", help="many more random cases")
    stress.add_argument("--seed", type=int, default=20261122)
    stress.add_argument("--configurations", type=int, default=10_000,
                        help="generated configurations of the quantity contract with --long (default %(default)s)")
    stress.add_argument("--workers", type=int, default=None, help="worker processes (default 2)")
    stress.add_argument("--dask", action="store_true", help="run --long on a local Dask cluster")
    stress.add_argument("--scheduler", default=None, help="run --long on the Dask cluster at this address")
    stress.set_defaults(func=cmd_stress)

    from synthesis.cli import add_parser as add_synthesize_parser
    from validation.sweep import add_parser as add_sweep_parser

    audit = sub.add_parser("audit", help="plant errors in each method and count the cases that catch them")
    audit.add_argument("cases", nargs="*", help="case ids, files or globs (default: all)")
    audit.add_argument("--plant", action="append",
                       help="only this planted error (repeatable; default: all; names in validation/plants.py)")
    audit.add_argument("--jobs", type=int, default=2, help="worker processes")
    audit.add_argument("--out", default="reports/audit", help="folder for audit.csv (default %(default)s)")
    audit.set_defaults(func=cmd_audit)
    add_sweep_parser(sub)
    add_synthesize_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
