"""pytest plugin (entry point ``pytest11``): case files are tests.

``pytest some_folder/`` collects every case file (a TOML file with a ``[case]`` table) under the
folder as test items, one per case and method: ``mine.toml::my_case[fem]``. The methods of a file run
once (shared by its items), and each item is judged by the same rule as the project's own suite
(``validation.run.compare.verdict_by_method``): every claimed limit of the method holds (printed
numbers with a tolerance, findings, limits between methods, FEM against the elastica); the method
ran, unless the case records its failure as expected (``case.expected_failure``); a method with
values has an enforced check at a loaded level, unless ``case.unchecked`` says why. A failing item's
message opens with the method's verdict (``validation.run.verdict``: outside the claimed limit,
refused, did not converge or failed) and its reason, then names quantity, point, load with its unit,
value, reference, error, tolerance and source; a method that gave no value is that one line, not a
row of NaN per reference. A case file with bad input is one failing item listing
every problem.

Options: ``--case-method NAME`` (repeatable) runs only those methods; ``--case-cache`` reuses the
on-disk cache of method runs (default: recompute).
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest

from validation.case.loader import CaseError, LoadedCase, load_case
from validation.run.api import Validation, validate
from validation.run.compare import verdict_by_method
from validation.run.verdict import MethodVerdict, Verdict, method_verdicts


def pytest_addoption(parser) -> None:
    group = parser.getgroup("prbm-validate", "case files as tests")
    group.addoption(
        "--case-method",
        action="append",
        default=None,
        metavar="NAME",
        help="run only this method of each case file (repeatable)",
    )
    group.addoption(
        "--case-cache",
        action="store_true",
        default=False,
        help="reuse cached method runs (.cache/runs or $PRBM_VALIDATE_CACHE)",
    )


def is_case_file(path: Path) -> bool:
    """A TOML file whose top level has a [case] table: what a case file looks like."""
    if path.suffix != ".toml":
        return False
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return False
    return isinstance(data.get("case"), dict)


def pytest_collect_file(file_path: Path, parent):
    if is_case_file(file_path):
        return CaseFile.from_parent(parent, path=file_path)
    return None


class CaseFile(pytest.File):
    """One case file: an item per method it asks for (or one item for its input errors)."""

    def collect(self):
        try:
            loaded = load_case(self.path)
        except CaseError as exc:
            yield BadCaseItem.from_parent(self, name="input", error=exc)
            return
        chosen = self.config.getoption("case_method")
        methods = [m for m in loaded.case.methods if not chosen or m in chosen]
        shared = SharedRun(loaded, methods, self.config.getoption("case_cache"))
        for method in methods:
            yield CaseItem.from_parent(self, name=f"{loaded.id}[{method}]", loaded=loaded, method=method, shared=shared)


class SharedRun:
    """The methods of one case file, run once for all its items, and the verdict per method."""

    def __init__(self, loaded: LoadedCase, methods: list[str], use_cache: bool):
        self.loaded, self.methods, self.use_cache = loaded, methods, use_cache
        self._result: Validation | None = None

    @property
    def result(self) -> Validation:
        if self._result is None:
            self._result = validate(self.loaded, methods=self.methods, use_cache=self.use_cache)
        return self._result

    def problems(self, method: str) -> list[str]:
        result = self.result
        verdict = verdict_by_method(self.loaded.case, result.result.runs, result.results)
        return verdict.get(method, [])

    def verdict(self, method: str) -> MethodVerdict:
        """The method's verdict in words, as the report and the tables give it."""
        result = self.result
        problems = verdict_by_method(self.loaded.case, result.result.runs, result.results)
        return method_verdicts(self.loaded.case, result.result.runs, result.results, problems)[method]


class CaseFailure(Exception):
    """A case item failed; the message is the readable account."""


class CaseItem(pytest.Item):
    def __init__(self, *, loaded, method: str, shared: SharedRun, **kwargs):
        super().__init__(**kwargs)
        self.loaded, self.method, self.shared = loaded, method, shared

    def runtest(self) -> None:
        readable = [line for line in comparison_failures(self.shared.result) if line.startswith(f"{self.method}:")]
        lines = self.shared.problems(self.method)
        if lines:
            verdict = self.shared.verdict(self.method)
            lines = without_the_run_verdict(lines + readable, self.method, verdict)
            raise CaseFailure(
                f"{self.loaded.id} ({self.loaded.path}), method {self.method}: {verdict.verdict.value}"
                f"{': ' + verdict.reason if verdict.reason else ''}" + "".join(f"\n  {line}" for line in lines)
            )

    def repr_failure(self, excinfo, style=None):
        if isinstance(excinfo.value, CaseFailure):
            return str(excinfo.value)
        return super().repr_failure(excinfo, style)

    def reportinfo(self):
        return self.path, None, f"case {self.loaded.id} with {self.method}"


RUN_VERDICTS = frozenset({Verdict.REFUSED, Verdict.FAILED, Verdict.NOT_CONVERGED, Verdict.EXPECTED})
NO_VALUE = re.compile(r": nan against ")


def without_the_run_verdict(lines: list[str], method: str, verdict: MethodVerdict) -> list[str]:
    """The failure's lines less what the first line (the method's verdict and its reason) already says:
    for a run that refused, failed or did not converge, its 'did not give every value' line and the
    rows it left without a value (NaN against each reference, NaN tolerances): one line, not rows of NaN."""
    if verdict.verdict not in RUN_VERDICTS:
        return lines
    return [
        line
        for line in lines
        if not line.startswith(f"{method} did not give every value:") and not NO_VALUE.search(line)
    ]


def comparison_failures(result) -> list[str]:
    """One readable line per comparison outside the claimed limit (no recorded finding) that has a
    value (a row without one is its run's verdict, said once)."""
    return [f"{row.method}: {describe_failure(row)}" for row in result.failures.itertuples() if row.value == row.value]


def describe_failure(row) -> str:
    """One line: quantity at point, level and load, value against reference, error and tolerance, source."""
    load = (
        f", {row.load} = {row.load_value:g} {row.load_unit}"
        if isinstance(row.load, str) and row.load_value == row.load_value
        else ""
    )
    tolerance = " or ".join(
        f"{kind} {value:g}"
        for kind, value in (("rel", row.tolerance_rel), ("abs", row.tolerance_abs))
        if value == value and value is not None
    )
    point = f" at {row.point}" if isinstance(row.point, str) else ""
    return (
        f"{row.quantity}{point}, level {row.level_label}{load}: {row.value:.6g} {row.unit} against "
        f"{row.reference_label} {row.reference_value:.6g}; error {row.abs_error:.3g} abs, "
        f"{row.rel_error:.3g} rel; tolerance {tolerance or 'none'}; source {row.source}"
    )


class BadCaseItem(pytest.Item):
    """A case file that cannot be used: fails with every problem, one per line."""

    def __init__(self, *, error: CaseError, **kwargs):
        super().__init__(**kwargs)
        self.error = error

    def runtest(self) -> None:
        raise CaseFailure(f"bad case file:\n{self.error}")

    def repr_failure(self, excinfo, style=None):
        return str(excinfo.value)

    def reportinfo(self):
        return self.path, None, "case file input"
