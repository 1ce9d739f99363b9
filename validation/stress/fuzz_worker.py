"""One mutated case file through the command line's own entry point, and what came of it.

``run_mutant`` writes the file, calls ``validation.cli.main.main`` in this process with ``solve <file>
--out <json>`` or ``run <file> --out <folder> --no-cache --quiet``, captures what it printed (file
descriptors 1 and 2, so C-level output is caught too) and judges the ending (``Outcome.problem``):

- it ends with exit 0, 1 or 2 (an exception escaping ``main`` is the traceback the installed command
  would print, exit 1);
- no traceback is printed or escapes;
- every message is one line: exit 2 prints at least one ``error: <file>: <field>: <problem>`` line,
  exit 1 says something, and no line on stderr continues another (an indented line: a traceback's
  frames, a warning's source line, a library's multi-line report) or is a Python warning;
- exit 0 gives finite numbers: every output and load of the ``solve`` JSON, every value of a method
  that ended ok in ``run``'s ``values.csv``.

Python's warnings are shown as in a fresh process (each once per place; the registries are reset
around every call). ``serve`` is the loop of a worker process (``validation.stress.fuzz_run``).
"""

from __future__ import annotations

import csv
import json
import math
import os
import re
import resource
import shutil
import sys
import tempfile
import threading
import time
import traceback
import warnings
from dataclasses import asdict, dataclass
from pathlib import Path

from threadpoolctl import threadpool_limits
from tqdm import tqdm

from validation.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
VERBS = ("solve", "run")
TRACEBACK = "Traceback (most recent call last)"
CONTINUED = re.compile(r"^\s+\S")  # a line that continues the one before
WARNING = re.compile(r"^\S.*:\d+: \w*Warning: ")  # warnings.formatwarning's first line
KEPT = 4000  # characters of stderr kept in an outcome


@dataclass(frozen=True)
class Outcome:
    """How one command ended. ``exit`` is None when it was stopped at its time bound."""

    exit: int | None
    seconds: float
    stderr: str = ""
    exception: str = ""  # 'Type at file:function' of a traceback (escaped from main, or printed)
    nonfinite: str = ""  # exit 0: the first number that is not finite
    silent: bool = False  # exit 1 or 2 and nothing said

    @property
    def timed_out(self) -> bool:
        return self.exit is None

    @property
    def problem(self) -> str:
        """'' when the ending keeps the contract, else the kind of failure (the shrinker keeps it)."""
        if self.timed_out:
            return "timed out"
        if self.exception:
            return f"traceback: {self.exception}"
        if self.exit not in (0, 1, 2):
            return f"exit {self.exit}"
        if self.silent:
            return f"exit {self.exit} without a message"
        lines = self.stderr.splitlines()
        if self.exit == 2 and not any(line.startswith("error: ") for line in lines):
            return "exit 2 without an error line"
        if any(CONTINUED.match(line) or WARNING.match(line) for line in lines):
            return "a message that is not one line"
        if self.exit == 0 and self.nonfinite:
            return "exit 0 with a number that is not finite"
        return ""

    @property
    def offending_line(self) -> str:
        """The first line on stderr that is not a whole message (its file's folder left out), else ''."""
        line = next((line for line in self.stderr.splitlines() if CONTINUED.match(line) or WARNING.match(line)), "")
        return re.sub(r"^/\S*/", "", line)

    def as_dict(self) -> dict:
        return asdict(self) | {"problem": self.problem}


def _where(exc: BaseException) -> str:
    """'Type at file:function' of the innermost frame of the project's code (else the innermost)."""
    frames = traceback.extract_tb(exc.__traceback__)
    ours = [f for f in frames if f.filename.startswith(str(ROOT)) and "site-packages" not in f.filename]
    frame = (ours or frames)[-1] if frames else None
    place = (
        f"{Path(frame.filename).relative_to(ROOT) if ours else Path(frame.filename).name}:{frame.name}"
        if frame
        else "?"
    )
    return f"{type(exc).__name__} at {place}"


def _printed_traceback(text: str) -> str:
    """'Type at file:function' of a traceback printed in ``text``, else ''."""
    if TRACEBACK not in text:
        return ""
    tail = text[text.rindex(TRACEBACK) :].splitlines()
    files = [line for line in tail if line.strip().startswith("File ")]
    last = next((line for line in tail[1:] if line and not line[0].isspace()), "?")
    place = re.search(r'File "([^"]+)", line \d+, in (\S+)', files[-1]) if files else None
    where = f"{Path(place.group(1)).name}:{place.group(2)}" if place else "?"
    return f"{last.split(':')[0]} at {where} (printed)"


def _call(argv: list[str]) -> tuple[int, str]:
    """main(argv): its exit status, and the traceback of an exception that escaped it ('')."""
    try:
        with warnings.catch_warnings():  # entering resets the once-per-place registries
            return int(main(argv)), ""
    except SystemExit as exc:
        return (0 if exc.code is None else exc.code if isinstance(exc.code, int) else 1), ""
    except BaseException as exc:  # noqa: BLE001 - the installed command would print this traceback
        return 1, _where(exc)


def _captured(argv: list[str]) -> tuple[int, str, str, str]:
    """(exit status, escaped exception, stdout, stderr) of main(argv), with file descriptors 1 and 2
    sent to temporary files while it runs."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        sys.stdout.flush()
        sys.stderr.flush()
        saved = os.dup(1), os.dup(2)
        os.dup2(out.fileno(), 1)
        os.dup2(err.fileno(), 2)
        try:
            status, exception = _call(argv)
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])
        out.seek(0)
        err.seek(0)
        return status, exception, out.read().decode(errors="replace"), err.read().decode(errors="replace")


def _not_finite(value) -> bool:
    return value is None or isinstance(value, float) and not math.isfinite(value)


def solve_nonfinite(path: Path) -> str:
    """The first output or load of a ``solve`` JSON document that is missing or not finite ('')."""
    if not path.exists():
        return "no JSON written"
    document = json.loads(path.read_text(encoding="utf-8"))
    for run in document.get("runs", [document]):
        for level in run["levels"]:
            for name, value in level["outputs"].items():
                if _not_finite(value) and not name.endswith(":error_estimate"):
                    return f"{run['method']} {name} at level {level['level']} = {value}"
            for load in level["loads"]:
                if _not_finite(load["value"]):
                    return f"load {load['name']} at level {level['level']} = {load['value']}"
    return ""


def run_nonfinite(folder: Path) -> str:
    """The first value in ``values.csv`` of a method that ended ok that is not finite ('')."""
    if not (folder / "runs.csv").exists():
        return "no runs.csv written"
    with open(folder / "runs.csv", newline="", encoding="utf-8") as f:
        ok = {(r["case"], r["method"]) for r in csv.DictReader(f) if r["status"] == "ok"}
    with open(folder / "values.csv", newline="", encoding="utf-8") as f:
        for row in csv.DictReader(f):
            if (row["case"], row["method"]) in ok and not math.isfinite(float(row["value"] or "nan")):
                return f"{row['method']} {row['quantity']}@{row['point']} at level {row['level']} = {row['value']}"
    return ""


def run_mutant(data: bytes, verb: str, workdir: Path) -> Outcome:
    """The mutated file ``data`` through ``prbm-validate <verb>``, judged (module docstring)."""
    for old in workdir.iterdir():  # the previous mutant's file and outputs
        shutil.rmtree(old) if old.is_dir() else old.unlink()
    path = workdir / "mutant.toml"
    path.write_bytes(data)
    out = workdir / ("solve.json" if verb == "solve" else "run")
    argv = (
        ["solve", str(path), "--out", str(out)]
        if verb == "solve"
        else ["run", str(path), "--out", str(out), "--no-cache", "--quiet"]
    )
    started = time.perf_counter()
    status, exception, stdout, stderr = _captured(argv)
    seconds = time.perf_counter() - started
    exception = exception or _printed_traceback(stderr) or _printed_traceback(stdout)
    nonfinite = ""
    if status == 0 and not exception:
        nonfinite = solve_nonfinite(out) if verb == "solve" else run_nonfinite(out)
    said = stderr.strip() or (verb == "run" and status == 1 and stdout.strip())
    return Outcome(
        exit=status,
        seconds=seconds,
        stderr=stderr[:KEPT],
        exception=exception,
        nonfinite=nonfinite,
        silent=status in (1, 2) and not said,
    )


def serve(conn, memory_bytes: int, warm_up: list[str]) -> None:
    """A worker's loop: receive (verb, bytes), send back its ``Outcome``; None ends it. The
    address space is limited to ``memory_bytes`` (a huge count is a MemoryError, not a machine out
    of memory); BLAS runs on one thread; progress bars lock with a thread lock (a worker killed at its
    time bound leaves no semaphore behind); the warm-up files are solved first, and the first is also
    run, then 'ready' is sent."""
    if memory_bytes:
        resource.setrlimit(resource.RLIMIT_AS, (memory_bytes, memory_bytes))
    tqdm.set_lock(threading.RLock())
    with threadpool_limits(1), tempfile.TemporaryDirectory(prefix="prbm-fuzz-") as folder:
        workdir = Path(folder)
        for i, path in enumerate(warm_up):
            for verb in VERBS if i == 0 else ("solve",):
                run_mutant(Path(path).read_bytes(), verb, workdir)
        conn.send("ready")
        while (task := conn.recv()) is not None:
            verb, data = task
            conn.send(run_mutant(data, verb, workdir))
