"""What several verbs share: the case files named on the command line, and --method checks."""

from __future__ import annotations

from pathlib import Path

from validation.case.capabilities import METHODS
from validation.case.loader import CaseError, find_case_files, search_roots
from validation.case.names import nearest


def case_paths(patterns: list[str]) -> tuple[list[Path], list[str]]:
    paths: list[Path] = []
    errors: list[str] = []
    if not patterns:
        return find_case_files(None), errors
    roots = search_roots(patterns)  # an id may name a file in a folder given alongside
    for pattern in patterns:
        try:
            paths.extend(find_case_files([pattern], roots=roots))
        except CaseError as exc:
            errors.append(str(exc))
    return list(dict.fromkeys(paths)), errors


def unknown_methods(methods: list[str] | None) -> list[str]:
    """One error line per --method that names no method, with the nearest names."""
    return [f"--method {m}: unknown method{nearest(m, METHODS)}" for m in methods or [] if m not in METHODS]
