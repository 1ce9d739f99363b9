"""The harness as a library: validate a case (by path, id or object) and get typed tables back.

>>> from validation.run.api import validate
>>> result = validate("cantilever_tip_load", methods=["prbm", "elastica"])
>>> result.passed                                  # every method ran and every claimed tolerance holds
True
>>> sorted(result.runs["status"])
['ok', 'ok']
>>> tip = result.values.query("quantity == 'y' and point == 'tip'")
>>> by_load = tip.pivot(index="load_value", columns="method", values="value")
>>> round(float(by_load.loc[10.0, "elastica"]), 5)   # exact elastica, PL^2/EI = 10
0.81061
>>> diff = result.method_differences("prbm", "elastica").query("quantity == 'y'")
>>> bool(diff["rel_error"].max() < 0.05)           # the PRBM within 5 % of the elastica on y
True

``validate`` returns a ``Validation``: the case, the four tidy tables of ``validation/run/tables.py``
(``runs``, ``values``, ``loads``, ``comparisons``), the runner's combined ``results`` rows, the
exit status of the rule in ``validation/run/exit_status.py`` and ``passed``. Bad input raises
``CaseError`` (every problem of the file, one per line) before anything runs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from validation.run import tables
from validation.run.exit_status import ExitStatus
from validation.case.loader import CaseError, LoadedCase, check_case, find_case_files, load_case
from validation.methods.base import RunStatus
from validation.run.case_run import run_case
from validation.run.runner import CaseResult
from validation.run.outcome import RunOutcome, tabulate
from validation.case.schema import Case


@dataclass(frozen=True)
class Validation:
    """What one case gave: tidy tables, the failures, and pass/fail."""

    case: Case
    path: Path | None
    result: CaseResult
    results: pd.DataFrame  # the runner's combined rows (values x references)
    runs: pd.DataFrame
    values: pd.DataFrame
    loads: pd.DataFrame
    comparisons: pd.DataFrame

    @property
    def outcome(self) -> RunOutcome:
        """The runner's outcome of this one case: what ``prbm-validate run`` judges."""
        return RunOutcome(table=self.results, errors=[], results=[self.result])

    @property
    def failures(self) -> pd.DataFrame:
        """Comparisons the runner judges failed (outside their claimed tolerance), with the load."""
        return tables.comparisons_table(self.outcome.failed_comparisons, tables.driving_loads([self.result]))

    @property
    def method_problems(self) -> pd.DataFrame:
        """Runs that did not end ok (not converged, not applicable, failed, misconfigured)."""
        return self.runs[self.runs["status"] != RunStatus.OK.value]

    @property
    def status(self) -> ExitStatus:
        """The exit status ``prbm-validate run`` would give on this case alone."""
        return ExitStatus(self.outcome.exit_status)

    @property
    def passed(self) -> bool:
        return self.status is ExitStatus.OK

    @property
    def values_with_loads(self) -> pd.DataFrame:
        """``values`` with one column per named load of the case, ``"<name> [<unit>]"``."""
        return tables.with_loads(self.values, self.loads)

    def method_differences(self, method: str, against: str) -> pd.DataFrame:
        """``method`` against ``against`` at every quantity, point and level both gave: the values,
        the absolute error and the relative error |a - b| / |b| (NaN where b is 0)."""
        return method_differences(self.values, method, against)


def method_differences(values: pd.DataFrame, method: str, against: str) -> pd.DataFrame:
    """Rows of a values table of ``method`` joined with ``against`` on case, quantity, point, level."""
    key = ["case", "quantity", "point", "level"]
    a = values[values["method"] == method]
    b = values[values["method"] == against][key + ["value"]].rename(columns={"value": "reference_value"})
    both = a.merge(b, on=key, how="inner").assign(against=against)
    both["abs_error"] = (both["value"] - both["reference_value"]).abs()
    denom = both["reference_value"].abs().to_numpy(dtype=float)
    both["rel_error"] = np.where(
        denom > 0, both["abs_error"].to_numpy(dtype=float) / np.where(denom > 0, denom, 1.0), math.nan
    )
    return both.reset_index(drop=True)


def _loaded(case: str | Path | Case | LoadedCase) -> LoadedCase:
    if isinstance(case, LoadedCase):
        return case
    if isinstance(case, Case):
        problems = check_case(case)
        if problems:
            (field, message), more = problems[0], problems[1:]
            raise CaseError(f"<case {case.case.id}>", field, message, more)
        return LoadedCase(path=Path(f"<case {case.case.id}>"), text=case.model_dump_json(), case=case)
    paths = find_case_files([str(case)])
    if len(paths) != 1:
        raise CaseError(str(case), "", f"names {len(paths)} case files; validate takes one")
    return load_case(paths[0])


def validate(
    case: str | Path | Case | LoadedCase, methods: list[str] | None = None, use_cache: bool = False
) -> Validation:
    """Run a case (a file path, a case id, or a ``Case``) with its methods (or only ``methods``)
    and compare; raises ``CaseError`` on bad input before anything runs."""
    loaded = _loaded(case)
    unknown = [m for m in methods or [] if m not in loaded.case.methods]
    if unknown:
        raise CaseError(
            loaded.path,
            "methods",
            f"the case does not ask for method '{unknown[0]}' (it has {', '.join(loaded.case.methods)})",
        )
    result = run_case(loaded, methods, use_cache=use_cache)
    rows = tabulate(result)
    tidy = tables.tables_of([result], rows)
    path = loaded.path if loaded.path.exists() else None
    return Validation(case=loaded.case, path=path, result=result, results=rows, **tidy)
