"""On-disk cache of method runs, keyed by case content, method, options, package version and code.

A key changes whenever the case file text, the method's options, the package version or the
source of the method's library changes, so a cached result is never stale.
"""
from __future__ import annotations

import hashlib
import json
import os
import pickle
from functools import lru_cache
from importlib import metadata
from pathlib import Path

from validation.methods.base import MethodRun

ROOT = Path(__file__).resolve().parent.parent
LIBRARIES = {"fem": ["fem", "argcheck"], "prbm": ["prbm", "argcheck"], "elastica": ["elastica", "argcheck"],
             "bcm": ["bcm", "argcheck"]}


def cache_dir() -> Path:
    return Path(os.environ.get("PRBM_VALIDATE_CACHE", ROOT / ".cache" / "runs"))


def package_version() -> str:
    try:
        return metadata.version("prbm-validate")
    except metadata.PackageNotFoundError:
        return "0+unknown"


@lru_cache(maxsize=None)
def code_hash(method: str) -> str:
    """Hash of every source file the method's results depend on."""
    digest = hashlib.sha256()
    folders = [ROOT / name for name in LIBRARIES.get(method, [])]
    files = [ROOT / "validation" / "methods" / f"{method}.py", ROOT / "validation" / "methods" / "base.py"]
    for folder in folders:
        files.extend(sorted(folder.rglob("*.py")))
    for path in files:
        if path.is_file():
            digest.update(path.relative_to(ROOT).as_posix().encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()


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


def store(key: str, run: MethodRun) -> None:
    folder = cache_dir()
    folder.mkdir(parents=True, exist_ok=True)
    tmp = folder / f"{key}.pkl.tmp{os.getpid()}"
    with tmp.open("wb") as handle:
        pickle.dump(run, handle)
    tmp.replace(folder / f"{key}.pkl")
