"""On-disk cache of method runs, keyed by case content, method, options, package version and code.

A key changes whenever the case file text, the method's options, the package version, the version
of a numerical library, or any repository source file the method's run imports (found by following
the imports of its adapter and of the runner: schema, quantity contract, options, the library)
changes, so a cached result is never stale.

An entry is the file ``<key>.run`` in `cache_dir`, in the format of `validation.run.cache_format`:
plain data with a schema version and a SHA-256 of its payload, so reading one runs no code and a
corrupt, truncated, foreign or older entry is found. Such an entry is removed with a one-line
warning on stderr naming it, and the run is recomputed. An entry is written to a temporary file
``.<key>.<pid>.tmp`` and renamed into place, so a reader sees a whole entry or none (a write that
fails or is interrupted removes its temporary); a write that fails (a full disk, no permission) is
one warning naming the path, and the process goes on without writing to that folder. The first
use of a folder in a process removes what a run must not find there: temporaries whose writer is no
longer alive or that are older than ``ORPHAN_AGE`` seconds, and the pickles of an older format
(``*.pkl``, which can run code when read).
"""

from __future__ import annotations

import ast
import hashlib
import json
import os
import re
import sys
import time
from functools import lru_cache
from importlib import metadata
from pathlib import Path

from validation.methods.base import MethodRun
from validation.run import cache_format

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("validation", "prbm", "fem", "elastica", "bcm", "argcheck", "planar", "references")
# third-party libraries whose version can change a result
LIBRARY_VERSIONS = ("numpy", "scipy", "scikit-fem", "pydantic", "numba", "openseespy")
ENTRY_SUFFIX = ".run"
ORPHAN_AGE = 3600.0  # seconds: a temporary this old is an orphan whoever holds its pid now
_TEMPORARY = re.compile(r"^\.(?P<key>[0-9a-f]+)\.(?P<pid>[0-9]+)\.tmp$")
_tidied: set[Path] = set()  # folders this process has tidied (`tidy`)
_unwritable: set[Path] = set()  # folders a write failed in: this process writes no more entries there


def cache_dir() -> Path:
    return Path(os.environ.get("PRBM_VALIDATE_CACHE", ROOT / ".cache" / "runs"))


def package_version() -> str:
    """This package's installed version (`_version`: read once a process; every run key asks for it)."""
    return _version("prbm-validate") or "0+unknown"


@lru_cache(maxsize=None)
def _version(name: str) -> str | None:
    """The installed version of distribution ``name``, or None (read once a process: reading a
    distribution's metadata parses its METADATA file)."""
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return None


def _module_file(name: str, root: Path) -> Path | None:
    """The source file of a module of this repository (a package's ``__init__.py``), or None."""
    if name.split(".")[0] not in PACKAGES:
        return None
    base = root.joinpath(*name.split("."))
    for path in (base.with_suffix(".py"), base / "__init__.py"):
        if path.is_file():
            return path
    return None


def _imports(path: Path, root: Path) -> frozenset[Path]:
    """Repository source files a file imports (anywhere in it, also inside functions), with the
    ``__init__.py`` of every package on the way."""
    stat = path.stat()
    return _imports_of_version(path, root, stat.st_mtime_ns, stat.st_size)


@lru_cache(maxsize=None)
def _imports_of_version(path: Path, root: Path, mtime_ns: int, size: int) -> frozenset[Path]:
    """``_imports`` of one version of the file (its modification time and size key the memo: the
    report asks for the same files once per method)."""
    found = set()
    package = path.relative_to(root).with_suffix("").parts[:-1]
    for node in import_statements(path.read_text(encoding="utf-8")):
        names = []
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = ".".join(package[: len(package) - node.level + 1]) if node.level else ""
            module = ".".join(p for p in (base, node.module or "") if p)
            names = [module] + [f"{module}.{alias.name}" for alias in node.names]
        for name in names:
            parts = name.split(".")
            for i in range(1, len(parts) + 1):
                file = _module_file(".".join(parts[:i]), root)
                if file is not None:
                    found.add(file)
    return frozenset(found)


# where an import statement can begin: at the start of a line (after its indentation), or after the
# ';' or ':' of a simple statement or compound header on the same line ("try: import x")
_IMPORT_START = re.compile(r"(?:^[ \t]*|[;:][ \t]*)(?=(?:from|import)\b)", re.MULTILINE)


def import_statements(source: str) -> list[ast.Import | ast.ImportFrom]:
    """The import statements of a Python source, anywhere in it (module level, function and class
    bodies, branches): each place an import can begin (``_IMPORT_START``) is read to the end of its
    logical line and parsed alone, instead of parsing the whole file (a tenth of the time: the
    report hashes some 80 files before its first case). Text that only looks like an import (prose
    in a docstring that happens to parse as one) adds a dependency, never loses one."""
    found: list[ast.Import | ast.ImportFrom] = []
    for match in _IMPORT_START.finditer(source):
        try:
            tree = ast.parse(_logical_line(source, match.end()))
        except SyntaxError:
            continue
        found += [node for node in tree.body if isinstance(node, (ast.Import, ast.ImportFrom))]
    return found


def _logical_line(source: str, start: int) -> str:
    """The statement text from ``start`` to the end of its logical line: through brackets, comments
    and backslash continuations, up to a newline outside brackets or a ';'."""
    depth, i, n = 0, start, len(source)
    while i < n:
        ch = source[i]
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == "#":
            i = source.find("\n", i)
            if i < 0 or depth <= 0:
                break
            continue
        elif ch == "\\" and source.startswith("\n", i + 1):
            i += 2
            continue
        elif ch == ";" and depth <= 0:
            break
        elif ch == "\n" and depth <= 0:
            break
        i += 1
    return source[start : i if i >= 0 else n]


def sources_of(start: list[Path], root: Path | None = None) -> list[Path]:
    """Every repository source file the files ``start`` depend on: themselves and everything they
    import, transitively."""
    root = root or ROOT
    seen: set[Path] = set()
    todo = [p for p in start if p.is_file()]
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        seen.add(path)
        todo.extend(_imports(path, root) - seen)
    return sorted(seen)


def source_files(method: str, root: Path | None = None) -> list[Path]:
    """Every repository source file a method's results can depend on: its adapter, the runner that
    calls it, and everything they import, transitively (schema, quantity contract, options, the library)."""
    root = root or ROOT
    sources = sources_of(
        [root / "validation" / "methods" / f"{method}.py", root / "validation" / "run" / "runner.py"], root
    )
    # data files beside the code are code too (the PRBM's error maps decide its flags)
    data = sorted({p for folder in {s.parent for s in sources} for p in folder.glob("*.json")})
    return sources + [p for p in data if p not in sources]


def digest_of(paths: list[Path]) -> str:
    """Hash of the files (names and contents) and of the third-party versions that can change a result."""
    digest = hashlib.sha256()
    for path in paths:
        digest.update(path.relative_to(ROOT).as_posix().encode())
        digest.update(path.read_bytes())
    for name in LIBRARY_VERSIONS:
        version = _version(name)
        if version is not None:
            digest.update(f"{name}=={version}".encode())
    return digest.hexdigest()


@lru_cache(maxsize=None)
def code_hash(method: str) -> str:
    """Hash of every source file the method's results depend on, and of the third-party versions."""
    return digest_of(source_files(method))


def run_key(case_text: str, method: str, options: dict) -> str:
    payload = json.dumps(
        [case_text, method, options, package_version(), code_hash(method)], sort_keys=True, default=str
    )
    return hashlib.sha256(payload.encode()).hexdigest()[:32]


def entry_path(key: str) -> Path:
    """Where the run of ``key`` is stored."""
    return cache_dir() / f"{key}{ENTRY_SUFFIX}"


def load(key: str) -> MethodRun | None:
    """The run stored under ``key``, or None: none stored, or an entry that cannot be used (removed,
    with a warning naming it and why)."""
    path = entry_path(key)
    tidy(path.parent)
    try:
        entry = path.read_bytes()
    except FileNotFoundError:
        return None
    except OSError as exc:
        warn(f"cannot read {path} ({_strerror(exc)}); recomputing the run")
        return None
    try:
        return cache_format.decode(entry, key)
    except cache_format.EntryError as exc:
        removed = "removed" if _remove(path) else "left in place"
        warn(f"ignored {path}: {exc}; {removed}, recomputing the run")
        return None


def has(key: str) -> bool:
    """Whether a run is stored under ``key`` (without reading it)."""
    return entry_path(key).is_file()


def store(key: str, run: MethodRun) -> None:
    """Store ``run`` under ``key``: written to a temporary file, then renamed into place. A run the
    format cannot write, or a folder that cannot be written, leaves the run uncached with a warning."""
    path = entry_path(key)
    folder = path.parent
    if folder in _unwritable:
        return
    try:
        entry = cache_format.encode(run, key)
    except TypeError as exc:
        warn(f"not cached, {path}: {exc}")
        return
    tmp = folder / f".{key}.{os.getpid()}.tmp"
    try:
        folder.mkdir(parents=True, exist_ok=True)
        tidy(folder)
        tmp.write_bytes(entry)
        os.replace(tmp, path)
    except OSError as exc:
        _remove(tmp)
        _unwritable.add(folder)
        where = f"{path}" if exc.filename in (None, str(tmp), str(path)) else f"{path} ({exc.filename})"
        warn(f"cannot write {where}: {_strerror(exc)}; going on without caching runs in {folder}")
    except BaseException:  # an interruption (Ctrl-C, a case's deadline) leaves no temporary behind
        _remove(tmp)
        raise


def tidy(folder: Path) -> None:
    """Remove, once a process, the files of ``folder`` no run may find: orphan temporaries (of a
    writer no longer alive, or older than ``ORPHAN_AGE`` seconds) and pickled entries of an older
    format, with a warning for the pickles."""
    if folder in _tidied:
        return
    _tidied.add(folder)
    try:
        names = os.listdir(folder)
    except OSError:
        return
    now = time.time()
    pickles = 0
    for name in names:
        path = folder / name
        if name.endswith(".pkl") or ".pkl.tmp" in name:
            pickles += _remove(path)
            continue
        match = _TEMPORARY.match(name)
        if match is None:
            continue
        try:
            age = now - path.stat().st_mtime
        except OSError:
            continue
        if age > ORPHAN_AGE or not _alive(int(match["pid"])):
            _remove(path)
    if pickles:
        warn(f"removed {pickles} pickled entries of an older format from {folder}")


def warn(message: str) -> None:
    """One line on stderr."""
    print(f"warning: run cache: {message}".replace("\n", " "), file=sys.stderr)


def _alive(pid: int) -> bool:
    """Whether a process ``pid`` exists (one of another user's counts)."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    except (OSError, OverflowError):
        return False
    return True


def _remove(path: Path) -> bool:
    """Remove a file if it is there; whether it was removed."""
    try:
        path.unlink()
    except OSError:
        return False
    return True


def _strerror(exc: OSError) -> str:
    return f"[Errno {exc.errno}] {exc.strerror}" if exc.strerror else str(exc)
