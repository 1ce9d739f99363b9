"""The run cache cannot serve a wrong value or run code: an entry that is corrupt (random bytes, one
changed float with its checksum left as it was), truncated, of another schema version or not an entry
at all (a crafted pickle) is ignored with a one-line warning naming it, and the run is recomputed to the
value of a run without the cache; a cache folder that cannot be written is a warning naming the path,
never the bad-input exit status; orphan temporaries and old pickles are removed; and every run of the
representative cases comes back from its entry equal to itself, floats bit for bit
(`validation.run.cache_format`).
"""

from __future__ import annotations

import ast
import dataclasses
import errno
import math
import os
import pathlib
import pickle
import random
import re
import struct
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from validation.case.loader import case_by_id
from validation.cli.main import main
from validation.methods.base import Applicability, DeferredList, MethodRun, Request, RunStatus
from validation.run import cache
from validation.run.case_run import run_case

pytestmark = pytest.mark.xdist_group("cache_integrity")

CASE = "cantilever_tip_load"  # a segment: PRBM, FEM and elastica, each in well under a second
# a PRBM segment, a PRBM mechanism (inflection coupler), a PRBM network with the BCM, a four-bar
# (chapter 8 procedure in extras) and a segment's inverse (roots): every kind of extras the adapters write
ROUND_TRIP_CASES = (CASE, "bapat2015_ch5_ex1", "seed003_circular_guided", "bapat2015_test2", "bapat2015_table3_1")


def _as_stored(value):
    """A lazy value as what it stands for (the object its ``__reduce__`` rebuilds)."""
    kind = type(value)
    if (
        kind.__module__.startswith("validation.")
        and kind.__reduce__ is not object.__reduce__
        and not isinstance(value, (tuple, MethodRun))
    ):
        rebuild, args = value.__reduce__()[:2]
        return rebuild(*args)
    return value


def assert_same(a, b, where="run"):
    """Equal in type and value, floats and arrays bit for bit (NaN payloads and -0.0 included)."""
    a = _as_stored(a)
    assert type(a) is type(b), f"{where}: {type(a).__name__} became {type(b).__name__}"
    if isinstance(a, float):
        assert struct.pack("<d", a) == struct.pack("<d", b), f"{where}: {a!r} became {b!r}"
    elif isinstance(a, np.ndarray):
        assert (a.dtype, a.shape) == (b.dtype, b.shape) and a.tobytes() == b.tobytes(), where
    elif isinstance(a, np.generic):
        assert a.dtype == b.dtype and a.tobytes() == b.tobytes(), where
    elif isinstance(a, dict):
        assert list(a) == list(b), f"{where}: keys {list(a)} became {list(b)}"
        for k in a:
            assert_same(a[k], b[k], f"{where}[{k!r}]")
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b), f"{where}: length {len(a)} became {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{where}[{i}]")
    elif dataclasses.is_dataclass(a):
        for f in dataclasses.fields(a):
            assert_same(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}")
    else:
        assert a == b, f"{where}: {a!r} became {b!r}"


def _key(loaded, method: str) -> str:
    return cache.run_key(loaded.text, method, dict(loaded.case.methods[method] or {}))


def _entry(key: str) -> Path:
    """The one file the cache holds for ``key`` (whatever the format names it)."""
    found = [p for p in cache.cache_dir().glob(f"{key}*") if not p.name.endswith(".tmp")]
    assert len(found) == 1, found
    return found[0]


def _results(run: MethodRun) -> tuple:
    """What a run reports (not its timings)."""
    return (run.values, run.error_estimate, run.status, run.level_converged, run.level_messages)


@pytest.fixture(scope="module")
def clean():
    """The runs of ``CASE`` without the cache."""
    return run_case(case_by_id(CASE), use_cache=False)


def _run_twice_then(tamper, method: str, capsys) -> tuple:
    """Store the method's run, tamper with its entry, run again: (the second result, the entry's path,
    the warning lines)."""
    loaded = case_by_id(CASE)
    run_case(loaded, [method])
    path = _entry(_key(loaded, method))
    tamper(path)
    capsys.readouterr()
    again = run_case(loaded, [method])
    return again, path, [line for line in capsys.readouterr().err.splitlines() if "warning" in line]


def _assert_recomputed(again, method: str, path: Path, warnings: list[str], clean) -> None:
    assert len(warnings) == 1 and str(path) in warnings[0], warnings
    assert not again.cached[method]
    assert _results(again.runs[method]) == _results(clean.runs[method])
    third = run_case(case_by_id(CASE), [method])  # the recomputed run is stored again, whole
    assert third.cached[method] and _results(third.runs[method]) == _results(clean.runs[method])


def test_random_bytes_in_an_elastica_entry_are_a_warning_and_a_recompute(clean, capsys):
    def scramble(path):
        data = bytearray(path.read_bytes())
        middle = len(data) // 2
        data[middle : middle + 64] = random.Random(45).randbytes(64)
        path.write_bytes(bytes(data))

    again, path, warnings = _run_twice_then(scramble, "elastica", capsys)
    _assert_recomputed(again, "elastica", path, warnings, clean)


def _change_one_float(path: Path, value: float) -> None:
    """Change ``value`` where the entry holds it (its JSON text, or a pickle's 8 big-endian bytes) by
    adding 0.01, leaving everything else (a checksum) as it was."""
    data = path.read_bytes()
    text, changed = repr(value).encode(), repr(value + 0.01).encode()
    if text in data:
        data = data.replace(text, changed, 1)
    else:
        data = data.replace(struct.pack(">d", value), struct.pack(">d", value + 0.01), 1)
    assert data != path.read_bytes()
    path.write_bytes(data)


def test_one_changed_float_under_a_stale_checksum_is_a_warning_and_a_recompute(clean, capsys):
    x = clean.runs["prbm"].values[Request("x", "tip", 3)]
    again, path, warnings = _run_twice_then(lambda p: _change_one_float(p, x), "prbm", capsys)
    assert again.runs["prbm"].values[Request("x", "tip", 3)] == x
    _assert_recomputed(again, "prbm", path, warnings, clean)


class _Touch:
    """Unpickling this creates the file ``marker`` (what a crafted entry can do)."""

    def __init__(self, marker: Path):
        self.marker = marker

    def __reduce__(self):
        return pathlib.Path.touch, (pathlib.Path(self.marker),)


def test_a_crafted_pickle_in_the_cache_runs_no_code_and_is_recomputed(clean, capsys, tmp_path):
    """A crafted pickle under the entry's name, and under the name of the older pickle format (found
    when the process first uses the folder): no code runs, both are removed, the run is recomputed."""
    marker = tmp_path / "code ran"
    crafted = pickle.dumps(_Touch(marker))
    loaded = case_by_id(CASE)
    old_name = cache.cache_dir() / f"{_key(loaded, 'prbm')}.pkl"
    old_name.parent.mkdir(parents=True)
    old_name.write_bytes(crafted)
    again, path, warnings = _run_twice_then(lambda p: p.write_bytes(crafted), "prbm", capsys)
    assert not marker.exists()
    assert len(warnings) == 1 and str(path) in warnings[0], warnings
    assert not again.cached["prbm"] and _results(again.runs["prbm"]) == _results(clean.runs["prbm"])
    assert not list(cache.cache_dir().glob("*.pkl*"))


@pytest.mark.parametrize(
    "keep", [0, 10, 60, 0.5, -1], ids=["empty", "in the first line", "in the header", "half", "all but the last byte"]
)
def test_a_truncated_entry_is_a_warning_and_a_recompute(keep, clean, capsys):
    def truncate(path):
        data = path.read_bytes()
        path.write_bytes(data[: int(len(data) * keep) if isinstance(keep, float) else keep])

    again, path, warnings = _run_twice_then(truncate, "prbm", capsys)
    assert warnings and "truncated" in warnings[0], warnings
    _assert_recomputed(again, "prbm", path, warnings, clean)


def test_an_entry_of_another_schema_version_is_a_warning_and_a_recompute(clean, capsys):
    from validation.run import cache_format

    def restamp(path):
        header = b'{"schema":%d,' % cache_format.SCHEMA_VERSION
        data = path.read_bytes()
        assert header in data
        path.write_bytes(data.replace(header, b'{"schema":%d,' % (cache_format.SCHEMA_VERSION + 1), 1))

    again, path, warnings = _run_twice_then(restamp, "prbm", capsys)
    assert warnings and "schema version" in warnings[0], warnings
    _assert_recomputed(again, "prbm", path, warnings, clean)


def test_an_entry_under_another_key_is_not_served(clean, capsys):
    """A whole, valid entry copied under another key's name holds another run: ignored."""
    loaded = case_by_id(CASE)
    run_case(loaded, ["prbm", "elastica"])
    elastica, prbm = _entry(_key(loaded, "elastica")), _entry(_key(loaded, "prbm"))
    prbm.write_bytes(elastica.read_bytes())
    capsys.readouterr()
    again = run_case(loaded, ["prbm"])
    warnings = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    _assert_recomputed(again, "prbm", prbm, warnings, clean)


class _FullDisk:
    """A file opened for writing whose every write fails as on a full disk."""

    def __init__(self, handle):
        self.handle = handle

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.handle.close()

    def write(self, data):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


@pytest.mark.parametrize("failure", ["disk full", "no permission"])
def test_a_cache_that_cannot_be_written_is_a_warning_naming_the_path(failure, tmp_path, monkeypatch, capsys):
    folder = cache.cache_dir()
    real_open = pathlib.Path.open

    def failing_open(self, mode="r", *args, **kwargs):
        if "w" in mode and folder in self.parents:
            if failure == "no permission":
                raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(self))
            return _FullDisk(real_open(self, mode, *args, **kwargs))
        return real_open(self, mode, *args, **kwargs)

    with monkeypatch.context() as patch:
        patch.setattr(pathlib.Path, "open", failing_open)
        status = main(["run", CASE, "--out", str(tmp_path / "uncached"), "--quiet"])
    warnings = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert status == 0  # not 2, not an abort
    assert len(warnings) == 1, warnings  # one line, however many runs were not stored
    assert re.search(rf"{re.escape(str(folder))}/[0-9a-f]+\.\w+", warnings[0]), warnings  # the entry's path
    assert os.strerror(errno.ENOSPC if failure == "disk full" else errno.EACCES) in warnings[0]
    assert not list(folder.iterdir()) if folder.is_dir() else True  # no entry, no temporary left
    assert main(["run", CASE, "--out", str(tmp_path / "clean"), "--quiet", "--no-cache"]) == 0
    assert (tmp_path / "uncached" / "values.csv").read_text() == (tmp_path / "clean" / "values.csv").read_text()


def test_orphan_temporaries_and_old_pickles_are_removed(tmp_path):
    folder = cache.cache_dir()
    folder.mkdir(parents=True)
    finished = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    dead = int(finished.stdout)
    me = os.getpid()
    names = {
        "of a dead writer": f".{'a' * 32}.{dead}.tmp",
        "an hour old": f".{'b' * 32}.{me}.tmp",
        "old pickle": f"{'c' * 32}.pkl",
        "old temporary": f"{'d' * 32}.pkl.tmp{dead}",
        "being written": f".{'e' * 32}.{me}.tmp",
    }
    for name in names.values():
        (folder / name).write_bytes(b"x")
    two_hours_ago = time.time() - 7200
    os.utime(folder / names["an hour old"], (two_hours_ago, two_hours_ago))
    run_case(case_by_id(CASE), ["prbm"])
    left = {p.name for p in folder.iterdir()}
    assert names["being written"] in left  # a live writer's young temporary stays
    assert not left & {names[k] for k in ("of a dead writer", "an hour old", "old pickle", "old temporary")}
    assert not [n for n in left if "pkl" in n]


def test_the_cache_modules_do_not_use_pickle():
    for path in sorted((Path(cache.__file__).parent).glob("cache*.py")):
        source = path.read_text(encoding="utf-8")
        imported = {
            alias.name.split(".")[0]
            for node in ast.walk(ast.parse(source))
            if isinstance(node, (ast.Import, ast.ImportFrom))
            for alias in (node.names if isinstance(node, ast.Import) else [ast.alias(node.module or "")])
        }
        assert not imported & {"pickle", "cPickle", "_pickle", "dill", "shelve", "marshal", "joblib"}, path
        assert not re.search(r"^\s*import\s+pickle\b", source, re.MULTILINE), path


@pytest.mark.parametrize("case_id", ROUND_TRIP_CASES)
def test_every_run_of_a_case_comes_back_from_its_entry_equal(case_id):
    from validation.run import cache_format

    loaded = case_by_id(case_id)
    result = run_case(loaded, use_cache=False)
    stored = [m for m, run in result.runs.items() if run.status in (RunStatus.OK, RunStatus.NOT_CONVERGED)]
    assert stored
    for method in stored:
        run, key = result.runs[method], _key(loaded, method)
        back = cache_format.decode(cache_format.encode(run, key), key)
        assert_same(run, back, f"{case_id}:{method}")
        fields = _as_stored(run.extras.get("fields"))
        if fields is not None:  # elements that shared a section share it again
            count = len({id(s) for s in fields.forces.sections})
            assert len({id(s) for s in back.extras["fields"].forces.sections}) == count
        cache.store(key, run)
        assert_same(run, cache.load(key), f"{case_id}:{method} through the cache")


def test_floats_arrays_and_classes_come_back_bit_for_bit():
    from validation.run import cache_format

    quiet_nan = struct.unpack("<d", bytes.fromhex("0100000000f8ff7f"))[0]  # a NaN with a payload
    shared = np.arange(6.0).reshape(2, 3)
    run = MethodRun(
        values={
            Request("x", "tip", 0): -0.0,
            Request("y", "tip", 1): math.nan,
            Request("F", "", 2): math.inf,
            Request("theta", "tip", 3): 5e-324,
        },
        error_estimate={Request("x", "tip", 0): quiet_nan},
        level_converged={0: True, 1: False},
        level_messages={1: "stalled"},
        applicability={1: [Applicability.INFLECTION]},
        status=RunStatus.NOT_CONVERGED,
        extras={
            "shapes": DeferredList(lambda: [[shared]]),
            "same": shared,
            "fortran": np.asfortranarray(np.arange(12, dtype=np.int32).reshape(3, 4)),
            "flags": np.array([True, False]),
            "scalar": np.float64(-math.inf),
            "tuple": (1, "a", None, (2.5,)),
            "$": {"nested": [1.0, -math.inf]},
            "empty": np.zeros((0, 2)),
            "complex": np.array([1 + 2j]),
            "big": 2**70,
        },
    )
    back = cache_format.decode(cache_format.encode(run, "k"), "k")
    assert_same(run, back)
    assert back.extras["shapes"][0][0] is not None and back.extras["fortran"].flags.f_contiguous
    with pytest.raises(cache_format.EntryError, match="another key"):
        cache_format.decode(cache_format.encode(run, "k"), "other")


def test_a_run_holding_what_the_format_cannot_write_is_not_cached(capsys):
    run = MethodRun(values={Request("x", "tip", 0): 1.0}, extras={"odd": {1, 2}})
    cache.store("0" * 32, run)
    assert cache.load("0" * 32) is None
    assert "set" in capsys.readouterr().err


def test_an_interrupted_write_leaves_no_temporary(monkeypatch):
    """A write stopped between the temporary and its rename (Ctrl-C, a case's deadline) removes it."""

    def interrupted(src, dst):
        raise KeyboardInterrupt

    run = MethodRun(values={Request("x", "tip", 0): 1.0})
    monkeypatch.setattr(cache.os, "replace", interrupted)
    with pytest.raises(KeyboardInterrupt):
        cache.store("0" * 32, run)
    assert not list(cache.cache_dir().iterdir())
