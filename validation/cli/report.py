"""``prbm-validate report``: run (or reuse) every case and write the HTML/Markdown report."""

from __future__ import annotations

from pathlib import Path

from validation.report.build import build_report


def run(args) -> int:
    return build_report(Path(args.out), use_cache=not args.no_cache, jobs=args.jobs, cases=args.cases)
