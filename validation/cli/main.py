"""``prbm-validate``: list, run, solve, report, bench, stress, audit, sweep and synthesize.

Exit status (every verb, defined in validation/run/exit_status.py): 0 everything asked for ran and every
comparison is inside its tolerance; 1 a comparison outside its tolerance, or a method that failed,
refused or did not converge on a case that asked for it; 2 bad input (a case, spec or option that
cannot be used, an unknown name, a missing optional dependency), found before any solve.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

from validation.case.capabilities import METHODS
from validation.run.exit_status import RULE, ExitStatus, combine, decide, of_run_status, print_error
from validation.case.loader import CaseError, find_case_files, load_case, search_roots
from validation.case.names import nearest

# optional dependency -> the extra that installs it
EXTRAS = {"distributed": "dask", "dask": "dask", "openseespy": "peer", "pytest": "test"}


def _paths(patterns: list[str]) -> tuple[list[Path], list[str]]:
    paths, errors = [], []
    if not patterns:
        return find_case_files(None), errors
    roots = search_roots(patterns)  # an id may name a file in a folder given alongside
    for pattern in patterns:
        try:
            paths.extend(find_case_files([pattern], roots=roots))
        except CaseError as exc:
            errors.append(str(exc))
    return list(dict.fromkeys(paths)), errors


def cmd_list(args) -> int:
    """One line per case; every file is loaded, so ``list FILE...`` checks files (exit 2 on a bad one)."""
    paths, errors = _paths(args.cases)
    for path in paths:
        try:
            case = load_case(path).case
        except CaseError as exc:
            errors.append(str(exc))
            continue
        kind = "segment" if case.segment is not None else "mechanism"
        print(f"{case.case.id:<40} {case.case.group:<12} {kind:<9} {','.join(case.methods):<24} "
              f"{case.case.title}")
    for error in errors:
        print_error(error)
    return decide(bad_input=bool(errors))


def _print_table(frame, file=sys.stdout) -> None:
    import pandas as pd

    with pd.option_context("display.max_rows", 500, "display.max_columns", 30, "display.width", 200,
                           "display.float_format", lambda v: f"{v:.4g}"):
        print(frame.to_string(index=False), file=file)


def unknown_methods(methods: list[str] | None) -> list[str]:
    """One error line per --method that names no method, with the nearest names."""
    return [f"--method {m}: unknown method{nearest(m, METHODS)}" for m in methods or [] if m not in METHODS]


def cmd_run(args) -> int:
    from validation.run import tables
    from validation.run.runner import run_cases, summary

    if unknown_methods(args.method):
        for line in unknown_methods(args.method):
            print_error(line)
        return ExitStatus.BAD_INPUT
    paths, errors = _paths(args.cases)
    started = time.perf_counter()
    outcome = run_cases(paths, methods=args.method, use_cache=not args.no_cache, jobs=args.jobs,
                        progress=not args.quiet)
    outcome.errors = sorted(errors + outcome.errors)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    results = outcome.table.astype({"within_tolerance": "boolean", "compare": "boolean", "converged": "boolean",
                                    "finding": "string", "message": "string", "source": "string"})
    results.to_csv(out / "results.csv", index=False)
    results.to_parquet(out / "results.parquet")
    tidy = tables.tables_of(outcome.results, outcome.table)
    tables.write(tidy, out)
    table = summary(outcome.table) if len(outcome.table) else None
    if table is not None:
        table.to_csv(out / "summary.csv", index=False)
        _print_table(table)
    failed = outcome.failed_comparisons
    if len(failed):
        print(f"\n{len(failed)} comparison(s) outside the claimed tolerance:")
        _print_table(failed[["case", "method", "quantity", "point", "level", "value", "reference_label",
                             "reference_value", "abs_error", "rel_error", "tolerance_rel", "tolerance_abs"]])
    problems = outcome.unexpected_problems
    if problems:
        print(f"\n{len(problems)} method run(s) did not end ok (and their case does not expect it):")
        for line in problems:
            print(f"  {line}")
    for error in outcome.errors:
        print_error(error)
    print(f"\n{len(outcome.results)} case(s) run, {len(outcome.errors)} rejected, in "
          f"{time.perf_counter() - started:.1f} s; results in {out / 'values.csv'} and "
          f"{out / 'comparisons.csv'}")
    return outcome.exit_status


def _clean(v):
    return None if v is None or (isinstance(v, float) and math.isnan(v)) else v


def solve_document(loaded, method: str, run) -> dict:
    """The JSON document of ``solve``: every requested output at every level, with the level's loads."""
    from validation.case.loads import level_labels, load_name, load_unit
    from validation.run.runner import requests_for

    case = loaded.case
    labels = level_labels(case)
    loads = [(load_name(load, i, case), load.levels(), load_unit(load, case))
             for i, load in enumerate(case.loads)]
    levels = []
    for level in range(case.n_levels()):
        outputs = {}
        for req in requests_for(case, method):
            if req.level != level:
                continue
            name = f"{req.quantity}@{req.point}" if req.point else req.quantity
            outputs[name] = _clean(run.values.get(req))
            if req in run.error_estimate:
                outputs[name + ":error_estimate"] = _clean(run.error_estimate[req])
        if outputs:
            levels.append({"level": level, "label": labels[level],
                           "loads": [{"name": n, "value": v[level], "unit": u} for n, v, u in loads],
                           "outputs": outputs})
    return {"case": case.case.id, "file": str(loaded.path), "method": method, "units": case.case.units,
            "status": run.status.value, "converged": run.converged, "message": run.message,
            "wall_time_s": run.wall_time, "levels": levels}


def cmd_solve(args) -> int:
    from validation.run.runner import run_method

    try:
        paths = find_case_files([args.case])
        if len(paths) != 1:
            raise CaseError(args.case, "", f"names {len(paths)} case files; solve takes one")
        loaded = load_case(paths[0])
    except CaseError as exc:
        print_error(exc)
        return ExitStatus.BAD_INPUT
    case = loaded.case
    methods = args.method or list(case.methods)
    unknown = [m for m in methods if m not in case.methods]
    if unknown:
        print(f"error: {loaded.path}: methods: the case does not ask for method '{unknown[0]}' "
              f"(it has {', '.join(case.methods)})", file=sys.stderr)
        return ExitStatus.BAD_INPUT
    documents, statuses = [], []
    for method in methods:
        run = run_method(case, method)
        statuses.append(of_run_status(run.status))
        if not run.ok:
            print(f"{case.case.id} {method}: {run.summary()}", file=sys.stderr)
        documents.append(solve_document(loaded, method, run))
    document = documents[0] if len(documents) == 1 else {"case": case.case.id, "runs": documents}
    text = json.dumps(document, indent=None if args.compact else 2)
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(text + "\n", encoding="utf-8")
    else:
        print(text)
    return combine(statuses)


def cmd_report(args) -> int:
    from validation.report.build import build_report

    return build_report(Path(args.out), use_cache=not args.no_cache, jobs=args.jobs, cases=args.cases)


def cmd_bench(args) -> int:
    from validation.bench.headline import run_bench

    return run_bench(Path(args.out), quick=args.quick)


def cmd_audit(args) -> int:
    from validation.stress.audit import cmd_audit as run_audit

    return run_audit(args)


def cmd_stress(args) -> int:
    from validation.stress.checks import run_stress

    return run_stress(Path(args.out), long=args.long, seed=args.seed, configurations=args.configurations,
                      executor="dask" if args.dask else "process", workers=args.workers, scheduler=args.scheduler)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="prbm-validate", description=__doc__.splitlines()[0], epilog=RULE)
    sub = parser.add_subparsers(dest="command", required=True)

    def add(name: str, help: str) -> argparse.ArgumentParser:
        return sub.add_parser(name, help=help, description=help, epilog=RULE)

    listing = add("list", "every case (or the given ids, files, folders), one line each; checks every file")
    listing.add_argument("cases", nargs="*", help="case ids, files, folders or globs (default: all)")
    listing.set_defaults(func=cmd_list)

    run = add("run", "run cases and compare with the published numbers")
    run.add_argument("cases", nargs="*", help="case ids, files, folders or globs (default: all)")
    run.add_argument("--method", action="append", help="only this method (repeatable)")
    run.add_argument("--out", default="reports/latest", help="folder for the result tables (default %(default)s)")
    run.add_argument("--jobs", type=int, default=1, help="parallel processes")
    run.add_argument("--no-cache", action="store_true", help="recompute even unchanged cases")
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    run.set_defaults(func=cmd_run)

    solve = add("solve", "one case, every requested output at every level with its loads, as JSON")
    solve.add_argument("case", help="a case id, or a case file anywhere")
    solve.add_argument("--method", action="append", help="this method (repeatable; default: every method of the case)")
    solve.add_argument("--json", action="store_true", help="JSON (the only format)")
    solve.add_argument("--out", help="write the JSON to this file instead of stdout")
    solve.add_argument("--compact", action="store_true")
    solve.set_defaults(func=cmd_solve)

    report = add("report", "run (or reuse) every case and write the report")
    report.add_argument("cases", nargs="*")
    report.add_argument("--out", default="reports")
    report.add_argument("--jobs", type=int, default=2)
    report.add_argument("--no-cache", action="store_true")
    report.set_defaults(func=cmd_report)

    bench = add("bench", "run time against error for every method")
    bench.add_argument("--out", default="reports/bench")
    bench.add_argument("--quick", action="store_true", help="fewer meshes and repeats")
    bench.set_defaults(func=cmd_bench)
    stress = add("stress", "numerical stability, invariances and bad input")
    stress.add_argument("--out", default="reports/stress")
    stress.add_argument("--long", action="store_true", help="many more random cases")
    stress.add_argument("--seed", type=int, default=20261122)
    stress.add_argument("--configurations", type=int, default=10_000,
                        help="generated configurations of the quantity contract with --long (default %(default)s)")
    stress.add_argument("--workers", type=int, default=None, help="worker processes (default 2)")
    stress.add_argument("--dask", action="store_true", help="run --long on a local Dask cluster")
    stress.add_argument("--scheduler", default=None, help="run --long on the Dask cluster at this address")
    stress.set_defaults(func=cmd_stress)

    from validation.synthesis.cli import add_parser as add_synthesize_parser
    from validation.sweep.run import add_parser as add_sweep_parser

    audit = sub.add_parser("audit", help="plant errors in each method and count the cases that catch them")
    audit.add_argument("cases", nargs="*", help="case ids, files or globs (default: all)")
    audit.add_argument("--plant", action="append",
                       help="only this planted error (repeatable; default: all; names in validation/stress/plants.py)")
    audit.add_argument("--jobs", type=int, default=2, help="worker processes")
    audit.add_argument("--out", default="reports/audit", help="folder for audit.csv (default %(default)s)")
    audit.set_defaults(func=cmd_audit)
    add_sweep_parser(sub)
    add_synthesize_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse: 0 for --help, 2 for a bad command line
        return int(exc.code or 0)
    try:
        return int(args.func(args))
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return ExitStatus.INTERRUPTED
    except ModuleNotFoundError as exc:
        top = (exc.name or "").split(".")[0]
        if top not in EXTRAS:
            raise
        print(f"error: '{args.command}' needs {top}, an optional dependency: "
              f"pip install 'prbm-validate[{EXTRAS[top]}]'", file=sys.stderr)
        return ExitStatus.BAD_INPUT
    except OSError as exc:  # an output folder that cannot be written, a file that cannot be read
        print_error(exc)
        return ExitStatus.BAD_INPUT


if __name__ == "__main__":
    sys.exit(main())
