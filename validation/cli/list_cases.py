"""``prbm-validate list``: one line per case; every file is loaded, so it checks files. ``list --methods``:
what each method can do instead (``validation.run.coverage``), ``--markdown`` as a Markdown table."""

from __future__ import annotations

from validation.run import coverage
from validation.case.loader import CaseError, load_case
from validation.cli.common import case_paths
from validation.run.exit_status import decide, print_error


def run(args) -> int:
    """One line per case; every file is loaded, so ``list FILE...`` checks files (exit 2 on a bad one)."""
    if args.methods or args.markdown:
        return _methods(args)
    paths, errors = case_paths(args.cases)
    for path in paths:
        try:
            case = load_case(path).case
        except CaseError as exc:
            errors.append(str(exc))
            continue
        kind = "segment" if case.segment is not None else "mechanism"
        print(f"{case.case.id:<40} {case.case.group:<12} {kind:<9} {','.join(case.methods):<24} {case.case.title}")
    for error in errors:
        print_error(error)
    return decide(bad_input=bool(errors))


def _methods(args) -> int:
    """The coverage matrix: a row per (load kind, boundary), a column per method."""
    if not args.methods or args.cases:
        print_error(
            "--markdown needs --methods"
            if not args.methods
            else "--methods lists what each method can do, on generated cases: give no case"
        )
        return decide(bad_input=True)
    cells = coverage.matrix()
    print(coverage.markdown(cells) if args.markdown else coverage.text(cells))
    return decide()
