"""Every output folder is one set: whoever reads it finds the previous set or the new one, never a mix
(validation/run/output_set.py).

The run's tables under a rejected run, a SIGKILL at many instants of the writing, two runs at once on
one folder and a full disk; every verb refused while its folder is in use; the report carrying the
other commands' folders without writing through the links to the previous report; an interrupted
sweep still resuming from its finished points; the module's own steps (the swap without the exchange
system call, an old set put back, a killed sweep's parts taken over).

The harness runs on the fake PRBM adapter of tests/validation/test_exit_status.py (the solvers are not under test).
The killed runs are forked children of the test process (no start-up: a run is a fraction of a
second), their table writes slowed so that the kills fall inside the writing.
"""

from __future__ import annotations

import errno
import fcntl
import hashlib
import os
import shutil
import signal
import sys
import time
import types
from contextlib import contextmanager
from pathlib import Path

import pandas as pd
import pytest

from validation.cli.main import main

from tests.validation.test_exit_status import fake, write  # noqa: F401  (the fake prbm adapter fixture)
from tests.validation.test_foundation import GOOD

TABLES = ("runs", "values", "loads", "comparisons", "results")


def case_ids(folder: Path) -> set[str]:
    """The case ids of a run's folder, the same in every table; fails when a table is missing, cut or
    belongs to another run than the others."""
    ids = [frozenset(pd.read_csv(folder / f"{name}.csv", usecols=["case"])["case"]) for name in TABLES]
    ids += [frozenset(pd.read_parquet(folder / f"{name}.parquet", columns=["case"])["case"]) for name in TABLES]
    ids += [frozenset(pd.read_csv(folder / "summary.csv", usecols=["case"])["case"])]
    assert len(set(ids)) == 1, f"tables of different runs in {folder}: {ids}"
    return set(ids[0])


def snapshot(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def leftovers(folder: Path) -> list[str]:
    """Stages and set-aside sets of ``folder`` still beside it."""
    return sorted(
        p.name for p in folder.parent.iterdir() if p.name.startswith(f"{folder.name}.") and not p.name.endswith(".lock")
    )


def two_cases(tmp_path: Path) -> tuple[Path, Path]:
    """The toy cantilever as case 'toy' and as case 'toy_new'."""
    return write(tmp_path, "old.toml", GOOD), write(tmp_path, "new.toml", GOOD.replace('id = "toy"', 'id = "toy_new"'))


def run_argv(case: Path, out: Path) -> list[str]:
    return ["run", str(case), "--out", str(out), "--quiet", "--no-cache"]


def forked_run(argv: list[str], marker: Path, pause: float) -> int:
    """``main(argv)`` in a forked child whose every table write first waits ``pause`` seconds, the
    first one leaving ``marker``; returns the child's pid."""
    pid = os.fork()
    if pid:
        return pid
    code = 70
    try:
        for name in ("to_csv", "to_parquet"):

            def slow(self, *args, _write=getattr(pd.DataFrame, name), **kwargs):
                marker.touch()
                time.sleep(pause)
                return _write(self, *args, **kwargs)

            setattr(pd.DataFrame, name, slow)
        code = main(argv)
    finally:
        os._exit(code)


def wait_for(marker: Path, pid: int, timeout: float = 60.0) -> float:
    """The moment ``marker`` appears (the child has begun to write)."""
    end = time.monotonic() + timeout
    while not marker.exists():
        done, status = os.waitpid(pid, os.WNOHANG)
        assert not done, f"the run ended before it wrote anything (status {status})"
        assert time.monotonic() < end, "the run wrote nothing in time"
        time.sleep(0.001)
    return time.monotonic()


def exit_code(pid: int) -> int:
    return os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1])


def test_a_rejected_run_leaves_the_previous_tables_byte_identical_and_says_so(tmp_path, fake, capsys):  # noqa: F811
    old, _ = two_cases(tmp_path)
    out = tmp_path / "latest"
    assert main(run_argv(old, out)) == 0
    before = snapshot(out)
    capsys.readouterr()
    bad = write(tmp_path, "bad.toml", GOOD.replace("length = 10.0", "length = -10.0"))
    assert main(run_argv(bad, out)) == 2
    said = capsys.readouterr()
    assert snapshot(out) == before
    assert f"nothing written; the previous results in {out} are unchanged" in said.err
    assert "results in" not in said.out and not leftovers(out)
    assert main(["run", "no_such_case_anywhere", "--out", str(out), "--quiet"]) == 2
    assert snapshot(out) == before and "nothing written" in capsys.readouterr().err


def test_a_run_killed_at_any_instant_leaves_the_old_set_or_the_new_one(tmp_path, fake):  # noqa: F811
    old, new = two_cases(tmp_path)
    out, pristine, marker = tmp_path / "latest", tmp_path / "pristine", tmp_path / "writing"
    assert main(run_argv(old, out)) == 0
    shutil.copytree(out, pristine)
    pid = forked_run(run_argv(new, out), marker, pause=0.01)  # one run to its end: how long it writes
    began = wait_for(marker, pid)
    assert exit_code(pid) == 0 and case_ids(out) == {"toy_new"}
    span = time.monotonic() - began
    seen = []
    for instant in range(15):  # 14 kills spread over the writing, then one run left to finish
        shutil.rmtree(out)
        shutil.copytree(pristine, out)
        marker.unlink()
        pid = forked_run(run_argv(new, out), marker, pause=0.01)
        wait_for(marker, pid)
        if instant < 14:
            time.sleep(span * instant / 14)
            os.kill(pid, signal.SIGKILL)
            exit_code(pid)
        else:
            assert exit_code(pid) == 0
        seen.append(case_ids(out))
    assert seen[0] == {"toy"} and seen[-1] == {"toy_new"}
    assert all(ids in ({"toy"}, {"toy_new"}) for ids in seen)
    assert not leftovers(out)  # the finished run deleted the stages the killed ones left


def test_two_runs_on_one_folder_do_not_interleave(tmp_path, fake, capsys):  # noqa: F811
    old, new = two_cases(tmp_path)
    out, marker = tmp_path / "latest", tmp_path / "writing"
    pid = forked_run(run_argv(old, out), marker, pause=0.2)  # writes for over 2 s
    wait_for(marker, pid)
    status = main(run_argv(new, out))
    err = capsys.readouterr().err
    assert status == 2, err
    assert f"error: output folder {out} is in use by pid {pid}" in err and "nothing written" in err
    assert exit_code(pid) == 0
    assert case_ids(out) == {"toy"}
    assert main(run_argv(new, out)) == 0 and case_ids(out) == {"toy_new"}  # free again


def test_a_full_disk_while_writing_exits_1_naming_the_folder_and_keeps_the_old_set(tmp_path, fake, monkeypatch, capsys):  # noqa: F811
    old, new = two_cases(tmp_path)
    out = tmp_path / "latest"
    assert main(run_argv(old, out)) == 0
    before = snapshot(out)
    capsys.readouterr()
    write_parquet, calls = pd.DataFrame.to_parquet, []

    def full(self, path, *args, **kwargs):
        calls.append(path)
        if len(calls) == 3:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
        return write_parquet(self, path, *args, **kwargs)

    monkeypatch.setattr(pd.DataFrame, "to_parquet", full)
    assert main(run_argv(new, out)) == 1
    err = capsys.readouterr().err
    assert f"error: the results could not be written to {out}: [Errno {errno.ENOSPC}]" in err
    assert f"nothing written; the previous results in {out} are unchanged" in err
    assert snapshot(out) == before and not leftovers(out)


@contextmanager
def held(out: Path):
    """``out`` in use, as another command holds it: ``flock`` on ``<out>.lock``, the pid written in it."""
    out.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(f"{out}.lock", os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        yield
    finally:
        os.close(fd)


@pytest.mark.parametrize(
    "argv",
    [
        ["run", "cantilever_tip_load", "--quiet"],
        ["report", "cantilever_tip_load"],
        ["sweep", "mesh_convergence", "--quiet"],
        ["stress"],
        ["bench", "--quick"],
        ["audit", "cantilever_tip_load", "--plant", "fem-EI-x1.10"],
    ],
    ids=lambda argv: argv[0],
)
def test_every_verb_is_refused_while_its_folder_is_in_use(tmp_path, capsys, argv):
    out = tmp_path / "out"
    out.mkdir()
    (out / "earlier.txt").write_text("an earlier result")
    with held(out):
        status = main([*argv, "--out", str(out)])
    err = capsys.readouterr().err
    assert status == 2
    assert f"error: output folder {out} is in use by pid {os.getpid()}" in err
    assert f"nothing written; the previous results in {out} are unchanged" in err
    assert snapshot(out) == {"earlier.txt": b"an earlier result"} and not leftovers(out)


def test_the_report_carries_other_folders_and_never_writes_into_the_previous_report(
    tmp_path,
    fake,  # noqa: F811
    monkeypatch,
):
    from validation.report import build

    good = write(tmp_path, "toy.toml", GOOD)
    out = tmp_path / "reports"
    assert build.build_report(out, use_cache=False, jobs=1, cases=[str(good)]) == 0
    (out / "latest").mkdir()
    (out / "latest" / "values.csv").write_text("case\ntoy\n")  # another command's folder, with its lock
    (out / "latest.lock").write_text("")
    (out / "notes.txt").write_text("the user's own file")
    backup, before = tmp_path / "backup", {}
    for path in (p for p in out.rglob("*") if p.is_file() and p.suffix != ".lock"):  # a second name for each file
        relative = path.relative_to(out)
        (backup / relative).parent.mkdir(parents=True, exist_ok=True)
        os.link(path, backup / relative)
        before[relative] = (path.stat().st_mtime_ns, hashlib.sha256(path.read_bytes()).hexdigest())
    assert any(r.parts[0] == "cases" for r in before)
    monkeypatch.setattr(build, "_code_digest", lambda: "other page code")  # every page drawn again
    assert build.build_report(out, use_cache=False, jobs=1, cases=[str(good)]) == 0
    for relative, (mtime, digest) in before.items():  # no file of the previous report was written to
        kept = backup / relative
        assert (kept.stat().st_mtime_ns, hashlib.sha256(kept.read_bytes()).hexdigest()) == (mtime, digest), relative
    assert (out / "latest" / "values.csv").samefile(backup / "latest" / "values.csv")  # carried as it was
    assert (out / "notes.txt").read_text() == "the user's own file" and (out / "latest.lock").exists()
    assert (out / "index.html").is_file() and (out / "cases" / "toy.html").is_file() and not leftovers(out)


def test_an_interrupted_sweep_keeps_its_finished_points_and_names_its_own_folder(tmp_path, monkeypatch, capsys):
    from tests.validation.test_sweep import CASE, SPEC

    from validation.methods.base import MethodRun
    from validation.sweep.run import load_results

    calls, interrupt_at = [], [12]

    def run(case, requests, options):  # y = 1 everywhere; Ctrl-C in the 12th point of the first run
        calls.append(case.segment.E)
        if len(calls) in interrupt_at:
            raise KeyboardInterrupt
        return MethodRun(values={r: 1.0 for r in requests}, converged=True)

    module = types.ModuleType("validation.methods.elastica")
    module.run = run
    monkeypatch.setitem(sys.modules, "validation.methods.elastica", module)
    (tmp_path / "toy.toml").write_text(CASE)
    spec = write(tmp_path, "toy_sweep.toml", SPEC.replace("samples = 100", "samples = 3"))  # 30 points
    out = tmp_path / "sweep"
    argv = ["sweep", str(spec), "--out", str(out), "--serial", "--quiet", "--no-plot", "--chunk", "5"]
    assert main(argv) == 130
    said = capsys.readouterr()
    assert f"are in {out};" in said.err and ".tmp-" not in said.err + said.out  # the folder, not the stage
    assert load_results(out)["point_id"].nunique() == 10  # the two finished chunks, put in place
    calls.clear()
    interrupt_at.clear()
    assert main(argv) == 0
    assert len(calls) == 20 and load_results(out)["point_id"].nunique() == 30 and not leftovers(out)
    assert "10 already done" in capsys.readouterr().out


def test_without_the_exchange_the_set_is_renamed_aside_and_a_killed_swap_is_put_back(tmp_path, monkeypatch, capsys):
    from validation.run import output_set

    monkeypatch.setattr(output_set, "_exchange", lambda a, b: False)  # a system without renameat2
    out = tmp_path / "set"
    for text in ("first", "second"):
        with output_set.OutputSet(out, owned=("a.txt",)) as output:
            (output.path / "a.txt").write_text(text)
            output.commit()
        assert (out / "a.txt").read_text() == text and not leftovers(out)
    out.rename(tmp_path / "set.old-999999")  # killed between the two renames: no folder, the old set
    (tmp_path / "set.tmp-999999").mkdir()  # aside, the new one staged
    (tmp_path / "set.tmp-999999" / "a.txt").write_text("third")
    with output_set.OutputSet(out, owned=("a.txt",)):
        assert (out / "a.txt").read_text() == "second"  # put back before anything else
    assert capsys.readouterr().err.strip() == f"nothing written; the previous results in {out} are unchanged"
    assert (out / "a.txt").read_text() == "second" and not leftovers(out)


def test_a_killed_sweeps_finished_parts_are_taken_over(tmp_path):
    from validation.run.output_set import OutputSet

    out, stale = tmp_path / "sweep", tmp_path / "sweep.tmp-999999"
    (out / "parts").mkdir(parents=True)
    (out / "sweep.json").write_text("{}")
    (out / "parts" / "part-a-00000.parquet").write_text("finished before")
    (stale / "parts").mkdir(parents=True)
    (stale / "parts" / "part-b-00000.parquet").write_text("finished by the killed run")
    (stale / "parts" / ".part-b-00001.parquet.tmp").write_text("cut")
    (stale / "sweep.json").write_text("{half")
    with OutputSet(out, seed=("*",), link=("parts",), adopt=("parts/part-*.parquet",)) as output:
        stage = output.path
        assert sorted(p.name for p in (stage / "parts").iterdir()) == ["part-a-00000.parquet", "part-b-00000.parquet"]
        assert (stage / "parts" / "part-a-00000.parquet").samefile(out / "parts" / "part-a-00000.parquet")
        assert (stage / "sweep.json").read_text() == "{}" and not (stage / "sweep.json").samefile(out / "sweep.json")
        assert not stale.exists()
        output.commit()
    assert (out / "parts" / "part-b-00000.parquet").read_text() == "finished by the killed run"
    assert not leftovers(out)
