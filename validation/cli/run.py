"""``prbm-validate run``: run cases, compare with the published numbers, write the result tables, and
print the summary (one row per case with its verdict, then the cases counted per verdict).

The tables are one output set (``validation.run.output_set``): written beside ``--out`` and put in place
whole once all of them are written. A run in which no case could run (every case file bad, no case
named) is rejected: nothing is written and the previous tables stay as they were; bad files beside good
ones are reported and the good cases are written (exit 2 all the same).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import pandas as pd

from validation.cli.common import case_paths, unknown_methods
from validation.run import tables
from validation.run.exit_status import ExitStatus, print_error
from validation.run.outcome import RunOutcome, run_cases, summary
from validation.run.output_set import OutputSet
from validation.run.verdict import Verdict, counts_sentence

TABLES = ("runs", "values", "loads", "comparisons", "results")
OWNED = tuple(f"{name}.{kind}" for name in TABLES for kind in ("csv", "parquet")) + ("summary.csv",)


def _print_table(frame, file=None) -> None:
    with pd.option_context(
        "display.max_rows",
        500,
        "display.max_columns",
        30,
        "display.width",
        200,
        "display.max_colwidth",
        48,
        "display.float_format",
        lambda v: f"{v:.4g}",
    ):
        print(frame.to_string(index=False), file=file or sys.stdout)


def write_tables(outcome: RunOutcome, out: Path) -> pd.DataFrame | None:
    """Every table of the run under ``out``; returns the summary (None when no case has a row)."""
    results = outcome.table.astype(
        {
            "within_tolerance": "boolean",
            "compare": "boolean",
            "converged": "boolean",
            "finding": "string",
            "message": "string",
            "source": "string",
            "verdict": "string",
            "applicability": "string",
        }
    )
    results.to_csv(out / "results.csv", index=False)
    results.to_parquet(out / "results.parquet")
    tables.write(tables.tables_of(outcome.results, outcome.table), out)
    table = summary(outcome.table, outcome.results) if len(outcome.table) else None
    if table is not None:
        table.to_csv(out / "summary.csv", index=False)
    return table


def run(args) -> int:
    out = Path(args.out)
    problems = unknown_methods(args.method)
    paths, errors = case_paths(args.cases)
    if problems or not paths:
        for line in problems or errors:
            print_error(line)
        print(OutputSet(out).note, file=sys.stderr)
        return ExitStatus.BAD_INPUT
    started = time.perf_counter()
    with OutputSet(out, owned=OWNED) as output:
        outcome = run_cases(
            paths, methods=args.method, use_cache=not args.no_cache, jobs=args.jobs, progress=not args.quiet
        )
        outcome.errors = sorted(errors + outcome.errors)
        if not outcome.results:  # rejected: no case could run
            for error in outcome.errors:
                print_error(error)
            return ExitStatus.BAD_INPUT
        table = write_tables(outcome, output.path)
        output.commit()
    if table is not None:
        _print_table(table)
    print_findings(outcome)
    verdicts = [Verdict(v) for v in table["verdict"]] if table is not None else []
    print(
        f"\n{counts_sentence(verdicts)} ({len(outcome.errors)} file(s) rejected; verdicts: validation/run/verdict.py)"
    )
    print(
        f"results: {out} (values.csv, comparisons.csv, summary.csv, ...; as Parquet too), in "
        f"{time.perf_counter() - started:.1f} s"
    )
    return outcome.exit_status


def print_findings(outcome: RunOutcome) -> None:
    """What is wrong, before the counts: the rows outside their claimed limit (with a value: a method
    that gave none is its run's one line), each run that refused, failed or did not converge with its
    reason, one line each, and the files that could not be used."""
    failed = outcome.outside_limit
    if len(failed):
        print(f"\n{len(failed)} row(s) outside the claimed limit:")
        _print_table(
            failed[
                [
                    "case",
                    "method",
                    "quantity",
                    "point",
                    "level",
                    "value",
                    "reference_label",
                    "reference_value",
                    "abs_error",
                    "rel_error",
                    "tolerance_rel",
                    "tolerance_abs",
                ]
            ]
        )
    problems = outcome.unexpected_verdicts
    if problems:
        print(
            f"\n{len(problems)} method run(s) refused, failed or did not converge (and their case does not "
            f"record an expected failure):"
        )
        for line in problems:
            print(f"  {line}")
    for error in outcome.errors + outcome.misconfigured:
        print_error(error)
