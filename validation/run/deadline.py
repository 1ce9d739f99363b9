"""A wall-time limit on a piece of work in this process: ``deadline(seconds)`` raises ``TimedOut`` in the
work once that much wall time has passed, so that one case over its ``[limits] seconds`` stops and the
others of a run go on.

The limit is a one-shot ``SIGALRM`` timer (``signal.setitimer``) whose handler raises ``TimedOut``.
``TimedOut`` derives from ``BaseException``, not ``Exception``, so the ``except Exception`` of an adapter or
a solver loop (which turns a failed level into a message and goes on) does not swallow it. Python runs a
signal handler between bytecodes of its main thread: the limit is enforced in the main thread of a
process (the command's, or a ``--jobs`` worker's), and only where a long computation returns to the
interpreter (a compiled numba kernel is interrupted when it returns, so a single call that never
returns is not). Elsewhere (another thread, a platform without ``setitimer``) ``deadline`` enforces
nothing and says so (``Deadline.enforced``). Deadlines do not nest.
"""

from __future__ import annotations

import signal
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Iterator


class TimedOut(BaseException):
    """The wall-time limit of the work passed (raised by the ``deadline`` timer)."""


@dataclass
class Deadline:
    """The limit in seconds, when it started (``time.perf_counter``), whether it is enforced here and
    whether it has fired."""

    seconds: float
    started: float = field(default_factory=time.perf_counter)
    enforced: bool = True
    fired: bool = False

    def _alarm(self, signum, frame) -> None:
        if not self.fired:  # one TimedOut per deadline, however late the work notices it
            self.fired = True
            raise TimedOut(f"over the wall-time limit of {self.seconds:g} s")


@contextmanager
def deadline(seconds: float) -> Iterator[Deadline]:
    """Raise ``TimedOut`` in the enclosed work once ``seconds`` of wall time have passed (module docstring)."""
    limit = Deadline(seconds)
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "setitimer"):
        limit.enforced = False
        yield limit
        return
    previous = signal.signal(signal.SIGALRM, limit._alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield limit
    finally:
        try:
            signal.setitimer(signal.ITIMER_REAL, 0.0)
        finally:  # restored even when the timer fires on the way out
            signal.signal(signal.SIGALRM, previous)
