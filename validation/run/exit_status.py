"""The exit status of every ``prbm-validate`` verb, defined once.

Every verb (``list``, ``run``, ``solve``, ``report``, ``bench``, ``stress``, ``sweep``,
``synthesize``) ends with one of these codes, so a CI job can gate on any of them:

- ``0`` everything asked for ran and no row is 'outside the claimed limit' (the verdicts of
  ``validation.run.verdict``);
- ``1`` a row is 'outside the claimed limit', or a method 'failed', was 'refused' or 'did not
  converge' on a case that does not record it as an 'expected failure' (the summary says which, in
  words); or the results could not be written
  (disk full, no permission; the line names the folder and the file, and the previous results stay);
- ``2`` bad input: a case, spec or option that cannot be used, an unknown name, a missing extra, an
  output folder that cannot be used or is in use by another command ("output folder X is in use by
  pid N"); found before any solve and reported in one line naming the file, the field and what is wrong;
- ``130`` interrupted (Ctrl-C).

When several apply, the largest of 0, 1, 2 wins: bad input is never hidden by a failed comparison.
"""

from __future__ import annotations

import sys
from enum import IntEnum
from typing import Iterable

from validation.methods.base import RunStatus


class ExitStatus(IntEnum):
    OK = 0
    FAILED = 1
    BAD_INPUT = 2
    INTERRUPTED = 130


RULE = (
    "exit status (every verb): 0 everything asked for ran and no row is 'outside the claimed limit'; "
    "1 a row 'outside the claimed limit', or a method that 'failed', was 'refused' or 'did not converge' "
    "on a case that does not record it as an 'expected failure', or results that could not be written (disk full, "
    "permission); 2 bad input (case, spec, option or name, or an output folder that cannot be used "
    "or is in use by another command), found before any solve; 130 interrupted. A command that "
    "ends with nothing written leaves the previous results in its output folder unchanged"
)


def of_run_status(status: RunStatus) -> ExitStatus:
    """The exit status one method run contributes: a misconfigured method is bad input (2), one
    that did not converge, refused the case or failed is 1."""
    if status is RunStatus.OK:
        return ExitStatus.OK
    if status is RunStatus.MISCONFIGURED:
        return ExitStatus.BAD_INPUT
    return ExitStatus.FAILED


def combine(statuses: Iterable[int]) -> ExitStatus:
    """The status of several outcomes: interrupted if any was, else the largest of 0, 1, 2."""
    outcomes = [ExitStatus(int(s)) for s in statuses]
    if ExitStatus.INTERRUPTED in outcomes:
        return ExitStatus.INTERRUPTED
    return max(outcomes, default=ExitStatus.OK)


def decide(bad_input: bool = False, failed: bool = False) -> ExitStatus:
    """The status from the two questions every verb answers: was any input bad, did anything fail."""
    if bad_input:
        return ExitStatus.BAD_INPUT
    return ExitStatus.FAILED if failed else ExitStatus.OK


def misconfigured_line(path, run) -> str:
    """The error line of a method run that found its case misconfigured while it solved: the case file,
    then the run's own 'methods.<method>: <problem>' (its message without the status word)."""
    message = run.message.removeprefix("misconfigured: ")
    return " ".join(f"{path}: {message}".split())


def print_error(message: object) -> None:
    """Print an error to stderr, every line of it prefixed 'error: ' (a case file with three problems
    is three lines, each naming the file and the field)."""
    for line in str(message).splitlines() or [""]:
        print(f"error: {line}", file=sys.stderr)
