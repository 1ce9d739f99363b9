"""``prbm-validate audit``: plant errors in one method at a time and count the cases that catch them.

For each plant of ``validation.stress.plants`` (adapter outputs x 1.10, sign flips, library constants
x 1.10) every case that lists the planted method is run in a fresh worker process with the error in
place and judged by the suite's own rule (``validation.run.compare.case_verdict``). The table has one row
per plant and one column per case group: caught / cases of the group that run the method. A planted
error that changes some value in a group but fails no case there is a hole in the suite; one that
changes no value (the planted constant is not on the group's code path) is marked 'not exercised'.
The unplanted baseline runs first; a case failing there is reported, since it cannot catch anything.
"""

from __future__ import annotations

import hashlib
import os
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import pandas as pd
from threadpoolctl import threadpool_limits

from validation.case.loader import CaseError, find_case_files, load_case
from validation.run.compare import case_verdict
from validation.run.exit_status import ExitStatus, decide
from validation.run.output_set import OutputSet
from validation.run.outcome import tabulate
from validation.run.case_run import run_case
from validation.stress import plants

BASELINE = "none"


@dataclass(frozen=True)
class Verdict:
    """One case under one plant."""

    plant: str
    case: str
    group: str
    failed: bool
    first_problem: str
    fingerprints: dict[str, str]  # method -> digest of its values, to tell whether a plant changed anything


def _fingerprint(run) -> str:
    values = sorted((tuple(req), round(float(v), 9)) for req, v in run.values.items())
    return hashlib.sha1(repr(values).encode()).hexdigest()


def _judge(plant: str, path: Path) -> Verdict:
    loaded = load_case(path)
    result = run_case(loaded, use_cache=False)
    problems = case_verdict(loaded.case, result.runs, tabulate(result))
    return Verdict(
        plant,
        loaded.id,
        loaded.case.case.group,
        bool(problems),
        problems[0][:200] if problems else "",
        {method: _fingerprint(run) for method, run in result.runs.items()},
    )


def _initialise(plant: str, cache: str) -> None:
    # planted runs must never reach the project's run cache (the runner stores every fresh run)
    os.environ["PRBM_VALIDATE_CACHE"] = cache
    threadpool_limits(1)  # one BLAS thread per worker: the FEM's systems are small and the workers share the cores
    if plant != BASELINE:
        plants.apply(plant)


def run_plant(plant: str, paths: list[Path], jobs: int) -> list[Verdict]:
    """Every case of ``paths`` in worker processes that carry the planted error."""
    with (
        tempfile.TemporaryDirectory(prefix="prbm-audit-") as cache,
        ProcessPoolExecutor(max_workers=jobs, initializer=_initialise, initargs=(plant, cache)) as pool,
    ):
        return list(pool.map(_judge, [plant] * len(paths), paths))


def audit(paths: list[Path], names: list[str], jobs: int = 2) -> pd.DataFrame:
    """Verdicts of the baseline and of each named plant, one row per (plant, case)."""
    methods = {}
    for path in paths:
        try:
            methods[path] = set(load_case(path).case.methods)
        except CaseError as exc:
            raise SystemExit(f"error: {exc}")
    baseline = run_plant(BASELINE, paths, jobs)
    before = {v.case: v.fingerprints for v in baseline}
    rows = [_row(v, exercised=True) for v in baseline]
    for name in names:
        method = plants.PLANTS[name].method
        wanted = [p for p in paths if method in methods[p]]
        if wanted:
            rows += [
                _row(v, exercised=v.fingerprints.get(method) != before[v.case].get(method))
                for v in run_plant(name, wanted, jobs)
            ]
    return pd.DataFrame(rows)


def _row(verdict: Verdict, exercised: bool) -> dict:
    return dict(
        plant=verdict.plant,
        case=verdict.case,
        group=verdict.group,
        failed=verdict.failed,
        exercised=exercised,
        first_problem=verdict.first_problem,
    )


def by_group(verdicts: pd.DataFrame) -> pd.DataFrame:
    """'failing/running' per (plant, group), the baseline row counting failures that need no plant;
    '(not exercised)' where the plant changed no value of any case of the group (the planted constant
    is not on that group's code path)."""
    grouped = verdicts.groupby(["plant", "group"])
    table = grouped["failed"].agg(["sum", "count"]).join(grouped["exercised"].any())

    def cell(r) -> str:
        text = f"{int(r['sum'])}/{int(r['count'])}"
        return text if r["exercised"] else text + " (not exercised)"

    cells = table.apply(cell, axis=1).unstack("group").fillna("-")
    order = [BASELINE] + [p for p in plants.PLANTS if p in cells.index]
    return cells.reindex(order)


def holes(verdicts: pd.DataFrame) -> list[str]:
    """(plant, group) pairs where the plant changed some value and no case fails."""
    planted = verdicts[(verdicts["plant"] != BASELINE) & verdicts["exercised"]]
    caught = planted.groupby(["plant", "group"])["failed"].any()
    return [f"{plant} in {group}" for (plant, group), hit in caught.items() if not hit]


def cmd_audit(args) -> int:
    """The ``prbm-validate audit`` command (its arguments are declared in validation/cli/main.py)."""
    names = args.plant or list(plants.PLANTS)
    unknown = [name for name in names if name not in plants.PLANTS]
    if unknown:
        print(
            f"error: --plant: unknown planted error {', '.join(unknown)}; known: {', '.join(plants.PLANTS)}",
            file=sys.stderr,
        )
        return ExitStatus.BAD_INPUT
    try:
        paths = find_case_files(args.cases or None)
    except CaseError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return ExitStatus.BAD_INPUT
    started = time.perf_counter()
    out = Path(args.out)
    with OutputSet(out, owned=("audit.csv",)) as output:  # one output set (validation.run.output_set)
        verdicts = audit(paths, names, jobs=args.jobs)
        verdicts.to_csv(output.path / "audit.csv", index=False)
        output.commit()
    table = by_group(verdicts)
    print("cases failing under each planted error, by group (failing / running the method):")
    print(table.to_string())
    baseline = verdicts[(verdicts["plant"] == BASELINE) & verdicts["failed"]]
    for _, row in baseline.iterrows():
        print(f"baseline failure (catches nothing): {row['case']}: {row['first_problem']}", file=sys.stderr)
    missed = holes(verdicts)
    for hole in missed:
        print(f"not caught: {hole}")
    print(
        f"\n{len(names)} plant(s) over {len(paths)} case(s) in {time.perf_counter() - started:.0f} s; "
        f"verdicts in {out / 'audit.csv'}"
    )
    return decide(failed=bool(missed) or len(baseline) > 0)
