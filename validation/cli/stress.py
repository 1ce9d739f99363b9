"""``prbm-validate stress``: numerical stability, invariances, bad input, mutated case files through the
command line, and (--long) the quantity contract and the fuzzing at scale."""

from __future__ import annotations

from pathlib import Path

from validation.stress.checks import run_stress

MUTANTS = {False: 300, True: 10_000}  # mutated case files fuzzed, without and with --long


def run(args) -> int:
    return run_stress(
        Path(args.out),
        long=args.long,
        seed=args.seed,
        configurations=args.configurations,
        executor="dask" if args.dask else "process",
        workers=args.workers,
        scheduler=args.scheduler,
        mutants=args.mutants if args.mutants is not None else MUTANTS[args.long],
        mutant_timeout=args.mutant_timeout,
    )
