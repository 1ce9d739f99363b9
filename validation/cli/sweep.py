"""``prbm-validate sweep``: a parameter sweep over a case, resumable, with its plots and what varies.

The sweep's folder is one output set (``validation.run.output_set``): the sweep runs in a copy of the
folder beside it (its finished parts hard-linked: a part is written once, by rename, and never
rewritten), put in place whole when the sweep ends, interrupted (Ctrl-C) included, so that the next
run resumes from every finished point. A sweep killed outright leaves the folder as it was; the next
run on it takes over the parts the killed one had finished.
"""

from __future__ import annotations

import contextlib
import sys
from pathlib import Path
from typing import TextIO

from validation.case.loader import CaseError
from validation.run.exit_status import ExitStatus, print_error
from validation.run.output_set import OutputSet
from validation.sweep.plot import plot_sweep, sensitivity_summary
from validation.sweep.run import EXIT_FAILED_POINTS, EXIT_INTERRUPTED, EXIT_OK, find_spec, load_spec, run_sweep

PARTS = "parts/part-*.parquet"  # a finished part: whole, or not there


class _Named:
    """A text stream on which the sweep, writing in the stage, names the output folder instead."""

    def __init__(self, stream: TextIO, stage: Path, folder: Path):
        self.stream, self.stage, self.folder = stream, str(stage), str(folder)

    def write(self, text: str) -> int:
        return self.stream.write(text.replace(self.stage, self.folder))

    def __getattr__(self, name: str):
        return getattr(self.stream, name)


def run(args) -> int:
    try:
        spec = load_spec(find_spec(args.spec)).spec
    except (CaseError, ValueError) as exc:
        print_error(exc)
        return ExitStatus.BAD_INPUT
    out = Path(args.out) if args.out else Path("reports") / "sweeps" / spec.sweep.id
    executor = "serial" if args.serial else ("dask" if args.dask else "process")
    with OutputSet(out, seed=("*",), link=("parts",), adopt=(PARTS,)) as output:
        with (
            contextlib.redirect_stdout(_Named(sys.stdout, output.path, out)),
            contextlib.redirect_stderr(_Named(sys.stderr, output.path, out)),
        ):
            status = run_sweep(
                args.spec,
                output.path,
                executor=executor,
                scheduler=args.scheduler,
                workers=args.workers,
                resume=not args.restart,
                progress=not args.quiet,
                chunk=args.chunk,
                limit=args.limit,
            )
            if status not in (EXIT_OK, EXIT_FAILED_POINTS, EXIT_INTERRUPTED):
                return status
            ended = status in (EXIT_OK, EXIT_FAILED_POINTS)
            plots = plot_sweep(output.path) if ended and not args.no_plot else []
            notes = sensitivity_summary(output.path) if ended else []
        output.commit()
    for path in plots:
        print(f"plot: {out / Path(path).relative_to(output.path)}")
    for line in notes:
        print(f"note: {line}")
    return status
