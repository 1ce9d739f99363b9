"""``prbm-validate stress``: numerical stability, invariances, bad input, and (--long) the quantity contract at scale."""
from __future__ import annotations

from pathlib import Path

from validation.stress.checks import run_stress


def run(args) -> int:
    return run_stress(Path(args.out), long=args.long, seed=args.seed, configurations=args.configurations,
                      executor="dask" if args.dask else "process", workers=args.workers, scheduler=args.scheduler)
