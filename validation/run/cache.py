"""On-disk cache of method runs, keyed by case content, method, options, package version and code.

A key changes whenever the case file text, the method's options, the package version, the version
of a numerical library, or any repository source file the method's run imports (found by following
the imports of its adapter and of the runner: schema, quantity contract, options, the library)
changes, so a cached result is never stale.
"""
from __future__ import annotations

import ast
import hashlib
import json
import os
import pickle
import re
from functools import lru_cache
from importlib import metadata
from pathlib import Path

from validation.methods.base import MethodRun

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("validation", "prbm", "fem", "elastica", "bcm", "argcheck")
# third-party libraries whose version can change a result
LIBRARY_VERSIONS = ("numpy", "scipy", "scikit-fem", "pydantic", "numba", "openseespy")


def cache_dir() -> Path:
    return Path(os.environ.get("PRBM_VALIDATE_CACHE", ROOT / ".cache" / "runs"))


def package_version() -> str:
    """This package's installed version (`_version`: read once a process; every run key asks for it)."""
    return _version("prbm-validate") or "0+unknown"


@lru_cache(maxsize=None)
def _version(name: str) -> str | None:
    """The installed version of distribution ``name``, or None (read once a process: reading a
    distribution's metadata parses its METADATA file, ~2 ms)."""
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


def _imports(path: Path, root: Path) -> set[Path]:
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
            base = ".".join(package[:len(package) - node.level + 1]) if node.level else ""
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


def import_statements(source: str) -> list[ast.stmt]:
    """The import statements of a Python source, anywhere in it (module level, function and class
    bodies, branches): each place an import can begin (``_IMPORT_START``) is read to the end of its
    logical line and parsed alone, instead of parsing the whole file (a tenth of the time: the
    report hashes some 80 files before its first case). Text that only looks like an import (prose
    in a docstring that happens to parse as one) adds a dependency, never loses one."""
    found = []
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
    return source[start:i if i >= 0 else n]


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
    return sources_of([root / "validation" / "methods" / f"{method}.py", root / "validation" / "run" / "runner.py"],
                      root)


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
    payload = json.dumps([case_text, method, options, package_version(), code_hash(method)],
                         sort_keys=True, default=str)
    return hashlib.sha256(payload.encode()).hexdigest()[:32]


def load(key: str) -> MethodRun | None:
    path = cache_dir() / f"{key}.pkl"
    if not path.is_file():
        return None
    try:
        with path.open("rb") as handle:
            return pickle.load(handle)
    except Exception:  # a corrupt or incompatible entry is simply recomputed
        return None


def has(key: str) -> bool:
    """Whether a run is stored under ``key`` (without reading it)."""
    return (cache_dir() / f"{key}.pkl").is_file()


def store(key: str, run: MethodRun) -> None:
    folder = cache_dir()
    folder.mkdir(parents=True, exist_ok=True)
    tmp = folder / f"{key}.pkl.tmp{os.getpid()}"
    with tmp.open("wb") as handle:
        pickle.dump(run, handle)
    tmp.replace(folder / f"{key}.pkl")
