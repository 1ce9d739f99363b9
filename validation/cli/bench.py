"""``prbm-validate bench``: run time against error for every method."""

from __future__ import annotations

from pathlib import Path

from validation.bench.headline import run_bench


def run(args) -> int:
    return run_bench(Path(args.out), quick=args.quick)
