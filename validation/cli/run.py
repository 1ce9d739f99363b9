"""``prbm-validate run``: run cases, compare with the published numbers, write the result tables."""
from __future__ import annotations

import sys
import time
from pathlib import Path

import pandas as pd

from validation.cli.common import case_paths, unknown_methods
from validation.run import tables
from validation.run.exit_status import ExitStatus, print_error
from validation.run.outcome import run_cases, summary


def _print_table(frame, file=None) -> None:
    with pd.option_context("display.max_rows", 500, "display.max_columns", 30, "display.width", 200,
                           "display.float_format", lambda v: f"{v:.4g}"):
        print(frame.to_string(index=False), file=file or sys.stdout)


def run(args) -> int:
    if unknown_methods(args.method):
        for line in unknown_methods(args.method):
            print_error(line)
        return ExitStatus.BAD_INPUT
    paths, errors = case_paths(args.cases)
    started = time.perf_counter()
    outcome = run_cases(paths, methods=args.method, use_cache=not args.no_cache, jobs=args.jobs,
                        progress=not args.quiet)
    outcome.errors = sorted(errors + outcome.errors)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    results = outcome.table.astype({"within_tolerance": "boolean", "compare": "boolean", "converged": "boolean",
                                    "finding": "string", "message": "string", "source": "string",
                                    "applicability": "string"})
    results.to_csv(out / "results.csv", index=False)
    results.to_parquet(out / "results.parquet")
    tidy = tables.tables_of(outcome.results, outcome.table)
    tables.write(tidy, out)
    table = summary(outcome.table, outcome.results) if len(outcome.table) else None
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
