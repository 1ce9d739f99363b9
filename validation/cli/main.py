"""``prbm-validate``: list, run, solve, report, bench, stress, audit, sweep, synthesize and atlas.

Exit status (every verb, defined in validation/run/exit_status.py): 0 everything asked for ran and every
comparison is inside its tolerance; 1 a comparison outside its tolerance, or a method that failed,
refused or did not converge on a case that asked for it, or results that could not be written (disk
full, no permission: the path is named); 2 bad input (a case, spec or option that cannot be used, an
unknown name, a missing optional dependency, an output folder that cannot be used or is in use by
another command), found before any solve.
"""

from __future__ import annotations

import time

STARTED = time.perf_counter()  # the command's clock starts before its imports (`timeline.command_age`)

import importlib  # noqa: E402
import math  # noqa: E402
import os  # noqa: E402
import sys  # noqa: E402

from validation.cli.arguments import build_parser  # noqa: E402
from validation.run.exit_status import ExitStatus, print_error  # noqa: E402
from validation.run.output_set import OutputFolderError  # noqa: E402
from validation.run.timeline import command_age, mark_command_start  # noqa: E402

# optional dependency -> the extra that installs it
EXTRAS = {"distributed": "dask", "dask": "dask", "openseespy": "peer", "pytest": "test"}
# verb -> the module that runs it (``run(args) -> int``), loaded only when the verb is asked for
COMMANDS = {
    "list": "validation.cli.list_cases",
    "run": "validation.cli.run",
    "solve": "validation.cli.solve",
    "report": "validation.cli.report",
    "bench": "validation.cli.bench",
    "stress": "validation.cli.stress",
    "audit": "validation.cli.audit",
    "sweep": "validation.cli.sweep",
    "synthesize": "validation.cli.synthesize",
    "atlas": "validation.cli.atlas",
}

__all__ = ["COMMANDS", "build_parser", "main"]


def main(argv: list[str] | None = None) -> int:
    # the process's first command counts its imports (its clock started at this module's first line); a
    # later one (main() called again from Python, long after the imports) starts at its own call
    mark_command_start(STARTED if math.isnan(command_age()) else time.perf_counter())
    # Start-up: before it builds its first validator pydantic looks for plugins in the entry points of
    # every installed distribution (a scan of every package's metadata); the harness uses none.
    # PYDANTIC_DISABLE_PLUGINS set by the user (e.g. empty, to load plugins) is kept.
    os.environ.setdefault("PYDANTIC_DISABLE_PLUGINS", "__all__")
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse: 0 for --help, 2 for a bad command line
        return int(exc.code or 0)
    try:
        return int(importlib.import_module(COMMANDS[args.command]).run(args))
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return ExitStatus.INTERRUPTED
    except ModuleNotFoundError as exc:
        top = (exc.name or "").split(".")[0]
        if top not in EXTRAS:
            raise
        print(
            f"error: '{args.command}' needs {top}, an optional dependency: pip install 'prbm-validate[{EXTRAS[top]}]'",
            file=sys.stderr,
        )
        return ExitStatus.BAD_INPUT
    except OutputFolderError as exc:  # an output folder in use, or results that could not be written
        print_error(exc.problem)
        print(exc.note, file=sys.stderr)
        return exc.status
    except OSError as exc:  # a file that cannot be read
        print_error(exc)
        return ExitStatus.BAD_INPUT


if __name__ == "__main__":
    sys.exit(main())
