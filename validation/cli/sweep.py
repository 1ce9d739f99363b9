"""``prbm-validate sweep``: a parameter sweep over a case, resumable, with its plots and what varies."""
from __future__ import annotations

from pathlib import Path

from validation.sweep.plot import plot_sweep, sensitivity_summary
from validation.sweep.run import EXIT_FAILED_POINTS, EXIT_OK, find_spec, load_spec, run_sweep


def run(args) -> int:
    executor = "serial" if args.serial else ("dask" if args.dask else "process")
    status = run_sweep(args.spec, args.out, executor=executor, scheduler=args.scheduler, workers=args.workers,
                       resume=not args.restart, progress=not args.quiet, chunk=args.chunk, limit=args.limit)
    if status in (EXIT_OK, EXIT_FAILED_POINTS) and not args.no_plot:
        out = args.out or Path("reports") / "sweeps" / load_spec(find_spec(args.spec)).spec.sweep.id
        for path in plot_sweep(out):
            print(f"plot: {path}")
    if status in (EXIT_OK, EXIT_FAILED_POINTS):
        out = args.out or Path("reports") / "sweeps" / load_spec(find_spec(args.spec)).spec.sweep.id
        for line in sensitivity_summary(out):
            print(f"note: {line}")
    return status
