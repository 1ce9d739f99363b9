"""An output folder written as one set: whoever reads it finds the previous set or the new one, never a mix.

Every command that writes an output folder (``run``, ``report``, ``sweep``, ``stress``, ``bench``,
``audit``) does it through ``OutputSet``:

1. **Lock.** ``flock`` on ``<out>.lock`` beside the folder, held for the whole command, the holder's pid
   written in it. A second command on the folder is refused at once, before any work:
   ``output folder <out> is in use by pid N`` (exit 2). The lock file is never deleted (a deleted lock
   file could be locked by two commands at once, each through its own file).
2. **Stage.** The command writes into ``<out>.tmp-<pid>`` beside the folder (the same parent, so the same
   filesystem). ``seed`` entries of the previous set are copied into it first (what a command reuses:
   the report's case pages, a sweep's finished points; ``link``: files that are never rewritten in
   place, hard-linked instead of copied).
3. **Commit**, only once every file is written: every entry of the previous set the command does not
   write (``owned``: the patterns of what it writes; another command's folder inside this one, e.g.
   ``reports/latest`` inside the report's ``reports``) is carried into the stage as a hard link (an output
   folder carried so is locked meanwhile, waiting for a command that writes it); the stage is flushed to
   disk (``syncfs``); then on Linux ``renameat2(RENAME_EXCHANGE)`` swaps the stage and the folder in one
   system call: the path names the old set up to that instant and the new one after it. The old set,
   now at the stage's path, is deleted. Where the exchange is missing (another OS, a filesystem without
   it) the folder is renamed aside to ``<out>.old-<pid>`` and the stage into place; a kill between the
   two renames leaves the old set there, and the next command on the folder renames it back first.

A command that is rejected, fails or is interrupted deletes its stage and says, in one line,
``nothing written; the previous results in <out> are unchanged``: the previous set is never opened for
writing. A stage a killed command left is deleted by the next command on the folder (after taking
the ``adopt`` files from it: whole files written by rename, e.g. a sweep's finished parts).

Exit status: an output folder that cannot be a folder (a file in the way), is in use, or holds the
current folder is refused before any work, status 2 (bad input); an operating-system error while the
set is staged, written or put in place (disk full, no permission) names the folder and the file,
status 1: the results could not be kept (``OutputFolderError``).

Why this scheme: the output stays a real folder at the path it always had (a ``latest -> set-N``
symlink would be one atomic rename too, but changes what users, scripts and CI artifact uploads find
there), and one system call is the whole switch, so there is no instant at which the path names a
mix or nothing. Hard links make carrying other commands' folders, and reusing the unchanged part of
a large previous set, cost no copy; no command writes into a file of a set in place, so a linked file
never changes under the set that shares it.
"""

from __future__ import annotations

import ctypes
import errno
import fcntl
import fnmatch
import glob
import os
import re
import shutil
import sys
import weakref
from collections.abc import Iterator
from pathlib import Path
from typing import Literal

from validation.run.exit_status import ExitStatus

LEFTOVER = re.compile(r"\.(tmp|old)-\d+$")  # a stage or an old set of some output folder
# errors that say the path given cannot be a folder (bad input); any other (no space, no permission, a
# read-only or failing disk) is the system refusing to write
NOT_A_FOLDER = {errno.ENOTDIR, errno.EEXIST, errno.EISDIR, errno.ENAMETOOLONG, errno.ELOOP}


class OutputFolderError(Exception):
    """An output folder that cannot be used or written: ``problem`` (one line naming the folder and the
    file), the exit status, and the note on what was left as it was."""

    def __init__(self, problem: str, status: ExitStatus, note: str):
        super().__init__(problem)
        self.problem, self.status, self.note = problem, status, note


def is_leftover(path: Path | str) -> bool:
    """True for the stage or the set-aside old set of some output folder (``<out>.tmp-N``, ``<out>.old-N``)."""
    return bool(LEFTOVER.search(Path(path).name))


def _matches(relative: str, patterns: tuple[str, ...]) -> bool:
    """``relative`` (a POSIX path inside the folder) or one of its parent folders matches a pattern."""
    parts = relative.split("/")
    return any(fnmatch.fnmatch("/".join(parts[:i]), p) for i in range(1, len(parts) + 1) for p in patterns)


def _files(root: Path) -> Iterator[tuple[str, Path]]:
    """(relative POSIX path, path) of every file and symlink under ``root``, and of every empty folder."""
    for folder, dirs, files in os.walk(root):
        here = Path(folder)
        for name in files + [d for d in dirs if (here / d).is_symlink()]:
            yield (here / name).relative_to(root).as_posix(), here / name
        if not dirs and not files and here != root:
            yield here.relative_to(root).as_posix(), here


def _place(source: Path, target: Path, link: bool) -> None:
    """``source`` (a file, a symlink or an empty folder) at ``target``: hard-linked with ``link``, else copied."""
    target.parent.mkdir(parents=True, exist_ok=True)
    if source.is_dir() and not source.is_symlink():
        target.mkdir(exist_ok=True)
    elif source.is_symlink():
        os.symlink(os.readlink(source), target)
    elif link:
        os.link(source, target)
    else:
        shutil.copyfile(source, target)


_LIBC = ctypes.CDLL(None, use_errno=True)
AT_FDCWD, RENAME_EXCHANGE, RENAME_SWAP = -100, 2, 2  # <fcntl.h>, <linux/fs.h>, macOS <stdio.h>


def _exchange(a: Path, b: Path) -> bool:
    """Swap two paths in one system call (Linux ``renameat2``, macOS ``renamex_np``); False where the
    system or the filesystem cannot."""
    if hasattr(_LIBC, "renameat2"):
        result = _LIBC.renameat2(AT_FDCWD, os.fsencode(a), AT_FDCWD, os.fsencode(b), RENAME_EXCHANGE)
    elif hasattr(_LIBC, "renamex_np"):
        result = _LIBC.renamex_np(os.fsencode(a), os.fsencode(b), RENAME_SWAP)
    else:
        return False
    if result == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.EINVAL, errno.ENOSYS, errno.ENOTSUP, errno.EOPNOTSUPP):
        return False
    raise OSError(code, os.strerror(code), str(b))


def _flush(folder: Path) -> None:
    """Everything written under ``folder`` on disk: ``syncfs`` of its filesystem where there is one,
    else every file and folder fsynced."""
    fd = os.open(folder, os.O_RDONLY)
    try:
        if hasattr(_LIBC, "syncfs") and _LIBC.syncfs(fd) == 0:
            return
    finally:
        os.close(fd)
    for here, _, files in os.walk(folder):
        for name in [*files, "."]:
            path = Path(here) / name
            if path.is_symlink():
                continue
            handle = os.open(path, os.O_RDONLY)
            try:
                os.fsync(handle)
            finally:
                os.close(handle)


def _fsync_folder(folder: Path) -> None:
    fd = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _current_folder() -> Path | None:
    try:
        return Path(os.path.realpath(os.getcwd()))
    except OSError:  # deleted under the process
        return None


class Lock:
    """``flock`` on a lock file, the holder's pid written in it.

    A forked child (a worker of a process pool) closes its copy of the lock's file descriptor at once
    (``os.register_at_fork``): a flock lasts while any copy is open, so a worker left running after its
    parent was killed would otherwise keep the folder locked."""

    held: weakref.WeakSet[Lock] = weakref.WeakSet()

    def __init__(self, path: Path):
        self.path = path
        self.fd: int | None = None

    @classmethod
    def forget_in_child(cls) -> None:
        for lock in list(cls.held):
            if lock.fd is not None:
                try:
                    os.close(lock.fd)  # not flock(LOCK_UN): that would unlock the parent's lock too
                except OSError:
                    pass
                lock.fd = None
        cls.held = weakref.WeakSet()

    def holder(self) -> str:
        try:
            pid = self.path.read_text().strip()
        except OSError:
            pid = ""
        return f"pid {pid}" if pid.isdigit() else "another process"

    def take(self, wait: bool = False) -> bool:
        """Lock; False when another process holds it and ``wait`` is False."""
        fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | (0 if wait else fcntl.LOCK_NB))
        except BlockingIOError:
            os.close(fd)
            return False
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        self.fd = fd
        Lock.held.add(self)
        return True

    def release(self) -> None:
        if self.fd is not None:
            fcntl.flock(self.fd, fcntl.LOCK_UN)
            os.close(self.fd)
            self.fd = None
        Lock.held.discard(self)


os.register_at_fork(after_in_child=Lock.forget_in_child)


class OutputSet:
    """The output folder ``target`` written as one set (module docstring); a context manager.

    Write into ``path`` (the stage), then call ``commit()``; leaving the block without it keeps the
    previous set as it was. ``owned``: patterns (POSIX paths inside the folder) of every entry the
    command writes (None: the whole folder); the previous set's other entries are carried over.
    ``seed``: patterns of the previous set's entries copied into the stage first; ``link``: those of them
    hard-linked instead; ``adopt``: whole files a killed command's stage left, hard-linked into the stage.
    """

    def __init__(
        self,
        target: Path | str,
        *,
        owned: tuple[str, ...] | None = None,
        seed: tuple[str, ...] = (),
        link: tuple[str, ...] = (),
        adopt: tuple[str, ...] = (),
    ):
        self.target = Path(target)  # as the user named it, for the messages
        self.folder = Path(os.path.realpath(self.target))
        self.owned, self.seed, self.link, self.adopt = owned, seed, link, adopt
        self.path = self.folder.parent / f"{self.folder.name}.tmp-{os.getpid()}"
        self.lock = Lock(self.folder.parent / f"{self.folder.name}.lock")
        self.committed = False

    @property
    def note(self) -> str:
        """The one line a command that wrote nothing says."""
        if self.folder.is_dir():
            return f"nothing written; the previous results in {self.target} are unchanged"
        return f"nothing written; {self.target} was not created"

    def __enter__(self) -> OutputSet:
        try:
            here = _current_folder()
            if here is not None and (self.folder == here or self.folder in here.parents):
                raise OutputFolderError(
                    f"output folder {self.target} holds the current folder; give the results a folder of their own",
                    ExitStatus.BAD_INPUT,
                    self.note,
                )
            if self.folder.exists() and not self.folder.is_dir():
                raise OSError(errno.ENOTDIR, "not a folder", str(self.target))
            self.folder.parent.mkdir(parents=True, exist_ok=True)
            if not self.lock.take():
                raise OutputFolderError(
                    f"output folder {self.target} is in use by {self.lock.holder()}", ExitStatus.BAD_INPUT, self.note
                )
        except OSError as exc:
            raise self._unusable(exc) from exc
        try:
            self._stage()
        except BaseException as exc:
            shutil.rmtree(self.path, ignore_errors=True)
            self.lock.release()
            if isinstance(exc, OSError):
                raise self._unusable(exc) from exc
            raise
        return self

    def _unusable(self, exc: OSError) -> OutputFolderError:
        """The folder refused before any work: status 2 where the path cannot be a folder, else 1."""
        status = ExitStatus.BAD_INPUT if exc.errno in NOT_A_FOLDER else ExitStatus.FAILED
        return OutputFolderError(f"output folder {self.target} cannot be used: {exc}", status, self.note)

    def _stage(self) -> None:
        """Put back an old set a killed command left aside; make the stage with the ``adopt`` files of
        killed commands' stages and the ``seed`` of the previous set; delete the leftovers."""
        name = self.folder.name
        leftovers = sorted(
            p
            for p in self.folder.parent.glob(f"{glob.escape(name)}.*")
            if is_leftover(p) and LEFTOVER.sub("", p.name) == name
        )
        olds = [p for p in leftovers if ".old-" in p.name]
        if olds and not self.folder.exists():
            olds[-1].rename(self.folder)
        shutil.rmtree(self.path, ignore_errors=True)  # a stage of a killed command that had this pid
        self.path.mkdir()
        for stage in (p for p in leftovers if ".tmp-" in p.name and p != self.path and self.adopt):
            for relative, source in _files(stage):
                if _matches(relative, self.adopt) and source.is_file() and not (self.path / relative).exists():
                    _place(source, self.path / relative, link=True)
        for leftover in leftovers:
            if leftover != self.path:
                shutil.rmtree(leftover, ignore_errors=True)
        if self.folder.is_dir() and self.seed:
            for relative, source in _files(self.folder):
                if _matches(relative, self.seed) and not (self.path / relative).exists():
                    _place(source, self.path / relative, link=_matches(relative, self.link))

    def commit(self) -> None:
        """Put the stage in place of the folder (module docstring, step 3)."""
        carried = self._carry(self.owned) if self.owned is not None and self.folder.is_dir() else []
        try:
            if self.folder.exists():
                shutil.copymode(self.folder, self.path)  # the folder keeps its permissions
            _flush(self.path)
            if not self.folder.exists():
                os.rename(self.path, self.folder)
            elif not _exchange(self.path, self.folder):
                aside = self.folder.parent / f"{self.folder.name}.old-{os.getpid()}"
                os.rename(self.folder, aside)
                try:
                    os.rename(self.path, self.folder)
                except OSError:
                    os.rename(aside, self.folder)
                    raise
                os.rename(aside, self.path)
            self.committed = True
        finally:
            for lock in carried:
                lock.release()
        try:
            _fsync_folder(self.folder.parent)  # the swap itself on disk
        except OSError:
            pass
        shutil.rmtree(self.path, ignore_errors=True)  # the old set

    def _carry(self, owned: tuple[str, ...]) -> list[Lock]:
        """Hard links in the stage to every entry of the previous set the command does not own (an output
        folder among them locked first, waiting for its command); returns the locks held."""
        held: list[Lock] = []
        try:
            for lock_file in sorted(self.folder.rglob("*.lock")):
                inner = lock_file.with_suffix("")
                relative = inner.relative_to(self.folder).as_posix()
                if inner.is_dir() and not _matches(relative, owned):
                    held.append(Lock(lock_file))
                    if not held[-1].take():
                        print(
                            f"waiting: output folder {self.target / relative} is in use by {held[-1].holder()}",
                            file=sys.stderr,
                            flush=True,
                        )
                        held[-1].take(wait=True)
            for relative, source in _files(self.folder):
                if _matches(relative, owned) or any(is_leftover(p) for p in relative.split("/")):
                    continue
                if not (self.path / relative).exists():
                    _place(source, self.path / relative, link=True)
        except BaseException:
            for lock in held:
                lock.release()
            raise
        return held

    def __exit__(self, kind, exc, traceback) -> Literal[False]:
        try:
            if not self.committed:
                shutil.rmtree(self.path, ignore_errors=True)
                if isinstance(exc, OSError):
                    raise OutputFolderError(
                        f"the results could not be written to {self.target}: {exc}", ExitStatus.FAILED, self.note
                    ) from exc
                if not isinstance(exc, OutputFolderError):
                    print(self.note, file=sys.stderr)
        finally:
            self.lock.release()
        return False
