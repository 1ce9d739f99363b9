"""pytest plugin (entry point ``pytest11``): case files are tests.

``pytest some_folder/`` collects every case file (a TOML file with a ``[case]`` table) under the
folder as test items, one per case and method: ``mine.toml::my_case[fem]``. An item passes when the
method ran (status ok) and every comparison the runner made for it with a claimed tolerance holds
(``within_tolerance`` of its rows, unless the reference records a ``finding``); it fails with a
message naming quantity, point, load with its unit, value, reference, error, tolerance and source.
A case file with bad input is one failing item listing every problem.

Options: ``--case-method NAME`` (repeatable) runs only those methods; ``--case-cache`` reuses the
on-disk cache of method runs (default: recompute).
"""
from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from validation.run.api import validate
from validation.case.loader import CaseError, load_case


def pytest_addoption(parser) -> None:
    group = parser.getgroup("prbm-validate", "case files as tests")
    group.addoption("--case-method", action="append", default=None, metavar="NAME",
                    help="run only this method of each case file (repeatable)")
    group.addoption("--case-cache", action="store_true", default=False,
                    help="reuse cached method runs (.cache/runs or $PRBM_VALIDATE_CACHE)")


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
        for method in loaded.case.methods:
            if chosen and method not in chosen:
                continue
            yield CaseItem.from_parent(self, name=f"{loaded.id}[{method}]", loaded=loaded, method=method)


class CaseFailure(Exception):
    """A case item failed; the message is the readable account."""


class CaseItem(pytest.Item):
    def __init__(self, *, loaded, method: str, **kwargs):
        super().__init__(**kwargs)
        self.loaded, self.method = loaded, method

    def runtest(self) -> None:
        result = validate(self.loaded, methods=[self.method],
                          use_cache=self.config.getoption("case_cache"))
        lines = run_problems(result) + comparison_failures(result)
        if lines:
            raise CaseFailure(f"{self.loaded.id} ({self.loaded.path}), method {self.method}:\n  "
                              + "\n  ".join(lines))

    def repr_failure(self, excinfo, style=None):
        if isinstance(excinfo.value, CaseFailure):
            return str(excinfo.value)
        return super().repr_failure(excinfo, style)

    def reportinfo(self):
        return self.path, None, f"case {self.loaded.id} with {self.method}"


def run_problems(result) -> list[str]:
    """One line per method run that did not end ok: method, status, message."""
    return [f"{method} {run.summary()}" for method, run in result.result.runs.items() if not run.ok]


def comparison_failures(result) -> list[str]:
    """One readable line per comparison outside its claimed tolerance (no recorded finding)."""
    return [f"{row.method}: {describe_failure(row)}" for row in result.failures.itertuples()]


def describe_failure(row) -> str:
    """One line: quantity at point, level and load, value against reference, error and tolerance, source."""
    load = (f", {row.load} = {row.load_value:g} {row.load_unit}"
            if isinstance(row.load, str) and row.load_value == row.load_value else "")
    tolerance = " or ".join(f"{kind} {value:g}" for kind, value in (("rel", row.tolerance_rel),
                                                                     ("abs", row.tolerance_abs))
                            if value == value and value is not None)
    point = f" at {row.point}" if isinstance(row.point, str) else ""
    return (f"{row.quantity}{point}, level {row.level_label}{load}: {row.value:.6g} {row.unit} against "
            f"{row.reference_label} {row.reference_value:.6g}; error {row.abs_error:.3g} abs, "
            f"{row.rel_error:.3g} rel; tolerance {tolerance or 'none'}; source {row.source}")


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
