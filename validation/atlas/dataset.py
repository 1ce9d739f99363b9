"""Build, resume and load the atlas dataset: every line of every model, on the sweep executors.

A build is named by its grid (``full``: at least 10^4 points a model; ``coarse``: a few hundred, for CI
and a first report) and the *code version*: a hash of the sources that decide its numbers (the atlas's
models and lines, ``prbm/`` and ``elastica/``).  It lives in ``OUT/<grid>-<version>/``:

* ``parts/*.parquet``: finished lines, written every few seconds, so an interrupted build is resumed by
  running the same command again (a line whose id is in a part is not run again);
* ``atlas.json``: the spec (grid, models, their axes), the version, and one record per run (lines run,
  points, wall time, points per second, executor, workers);
* ``atlas.parquet``: once every line is in, all rows in one file with the spec and the code version in
  its schema metadata.

Lines run on local processes (default), a local Dask cluster or an existing one, through
``validation.sweep.run.completed``; each task is a batch of lines.  A different code version is a new
folder: an old build is never overwritten, and a build of the current code never reads an old one.
"""

from __future__ import annotations

import hashlib
import json
import time
import uuid
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Callable

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from validation.atlas.lines import solve_line
from validation.atlas.models import MODELS, model as model_named
from validation.sweep.run import completed

ROOT = Path(__file__).resolve().parents[2]
DEFAULT_OUT = Path("reports") / "atlas"
GRIDS = ("full", "coarse")
_VERSION_SOURCES = ("validation/atlas/models.py", "validation/atlas/lines.py", "prbm", "elastica", "planar")
_FLUSH_SECONDS = 3.0


@lru_cache(maxsize=1)
def code_version() -> str:
    """A short hash of the sources that decide the atlas's numbers (read once a process, as the run
    cache's code hash is)."""
    digest = hashlib.sha256()
    for rel in _VERSION_SOURCES:
        path = ROOT / rel
        files = sorted(path.rglob("*.py")) if path.is_dir() else [path]
        for f in files:
            digest.update(f.relative_to(ROOT).as_posix().encode())
            digest.update(f.read_bytes())
    return digest.hexdigest()[:12]


def line_id(model: str, shape: dict, grid: str) -> str:
    text = json.dumps([model, grid, sorted(shape.items())])
    return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class LineTask:
    """One line to solve: the model, its shape inputs, the grid (which load levels) and its id."""

    model: str
    shape: tuple[tuple[str, float], ...]
    grid: str
    id: str


def tasks(models: list[str], grid: str) -> list[LineTask]:
    out = []
    for name in models:
        m = model_named(name)
        for shape in m.shapes(grid == "coarse"):
            out.append(LineTask(name, tuple(shape.items()), grid, line_id(name, shape, grid)))
    return out


def run_lines(context: dict, chunk: list[LineTask]) -> list[dict]:
    """A worker's task: every line of the chunk, as rows (``validation.atlas.lines.solve_line``); ``context``
    names the grid (a Dask scatter needs a non-empty one)."""
    rows = []
    for task in chunk:
        m = MODELS[task.model]
        shape = dict(task.shape)
        for row in solve_line(m, shape, m.load.values(task.grid == "coarse")):
            rows.append({"model": task.model, "line_id": task.id, **row})
    return rows


def folder(out: Path | str, grid: str, version: str | None = None) -> Path:
    return Path(out) / f"{grid}-{version or code_version()}"


def _done(parts: Path) -> set[str]:
    done: set[str] = set()
    for part in sorted(parts.glob("*.parquet")):
        done.update(pd.read_parquet(part, columns=["line_id"])["line_id"].unique())
    return done


def _write_part(parts: Path, rows: list[dict]) -> None:
    """One part file, written to a temporary name and renamed (a reader never sees half a file)."""
    if not rows:
        return
    name = parts / f"part-{uuid.uuid4().hex[:12]}.parquet"
    tmp = name.with_suffix(".tmp")
    pd.DataFrame(rows).to_parquet(tmp, index=False)
    tmp.replace(name)


@dataclass(frozen=True)
class BuildRecord:
    """What one build run did."""

    grid: str
    version: str
    lines_run: int
    lines_skipped: int
    points: int
    seconds: float
    points_per_second: float
    executor: str
    workers: int | None
    folder: str


def _spec(models: list[str], grid: str) -> dict:
    coarse = grid == "coarse"
    return {
        name: {
            "title": MODELS[name].title,
            "source": MODELS[name].source,
            "inputs": {
                a.name: {"label": a.label, "values": [float(v) for v in a.values(coarse)]}
                for a in (*MODELS[name].shape_axes, MODELS[name].load)
            },
            "points": MODELS[name].points(coarse),
        }
        for name in models
    }


def build(
    grid: str = "full",
    models: list[str] | None = None,
    out: Path | str = DEFAULT_OUT,
    executor: str = "process",
    workers: int | None = None,
    scheduler: str | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> BuildRecord:
    """Build (or resume) the atlas of ``models`` (default: all) on ``grid``; returns what was run."""
    if grid not in GRIDS:
        raise ValueError(f"atlas grid must be one of {', '.join(GRIDS)}, not {grid!r}")
    models = list(models or MODELS)
    for name in models:
        model_named(name)
    version = code_version()
    where = folder(out, grid, version)
    parts = where / "parts"
    parts.mkdir(parents=True, exist_ok=True)
    manifest = where / "atlas.json"
    record_list = json.loads(manifest.read_text())["runs"] if manifest.exists() else []
    todo_all = tasks(models, grid)
    done = _done(parts)
    todo = [t for t in todo_all if t.id not in done]
    per_chunk = max(1, min(8, len(todo) // (16 * max(workers or 2, 1)) or 1))
    chunks = [todo[i : i + per_chunk] for i in range(0, len(todo), per_chunk)]
    t0 = time.perf_counter()
    buffer: list[dict] = []
    points, lines, last = 0, 0, time.perf_counter()
    if progress:
        progress(0, len(todo))
    try:
        if chunks:
            for chunk, rows in completed(executor, {"grid": grid}, chunks, workers, scheduler, task=run_lines):
                if isinstance(rows, BaseException):
                    raise RuntimeError(f"atlas lines of {chunk[0].model} failed: {rows}") from rows
                buffer.extend(rows)
                points += len(rows)
                lines += len(chunk)
                if progress:
                    progress(lines, len(todo))
                if time.perf_counter() - last > _FLUSH_SECONDS:
                    _write_part(parts, buffer)
                    buffer, last = [], time.perf_counter()
    finally:
        _write_part(parts, buffer)
    seconds = time.perf_counter() - t0
    record = BuildRecord(
        grid,
        version,
        lines,
        len(todo_all) - len(todo),
        points,
        round(seconds, 3),
        round(points / seconds, 1) if seconds > 0 and points else 0.0,
        executor if scheduler is None else f"dask at {scheduler}",
        workers,
        str(where),
    )
    record_list.append(record.__dict__)
    spec = {"grid": grid, "version": version, "models": _spec(models, grid)}
    tmp = manifest.with_suffix(".tmp")
    tmp.write_text(json.dumps({**spec, "runs": record_list}, indent=1))
    tmp.replace(manifest)
    if complete(out, grid, models):
        _write_whole(where, grid, spec)
    return record


def _write_whole(where: Path, grid: str, spec: dict) -> None:
    """``atlas.parquet``: every row of the dataset in one file, the spec that generated it and the code
    version in its schema metadata (``atlas_spec``, ``code_version``), for use outside the harness."""
    frame = load(where.parent, grid, spec["version"])
    if frame is None:
        return
    table = pa.Table.from_pandas(frame, preserve_index=False)
    metadata = {
        **(table.schema.metadata or {}),
        b"atlas_spec": json.dumps(spec).encode(),
        b"code_version": spec["version"].encode(),
    }
    tmp = where / "atlas.parquet.tmp"
    pq.write_table(table.replace_schema_metadata(metadata), tmp)
    tmp.replace(where / "atlas.parquet")


def load(out: Path | str = DEFAULT_OUT, grid: str = "full", version: str | None = None) -> pd.DataFrame | None:
    """The atlas of the current code on ``grid`` (None when it has not been built)."""
    parts = folder(out, grid, version) / "parts"
    files = sorted(parts.glob("*.parquet")) if parts.exists() else []
    if not files:
        return None
    frame = pd.concat([pd.read_parquet(f) for f in files], ignore_index=True)
    return frame.drop_duplicates(subset=["line_id", "load"], keep="last").reset_index(drop=True)


def complete(out: Path | str = DEFAULT_OUT, grid: str = "full", models: list[str] | None = None) -> bool:
    """Whether every line of ``models`` on ``grid`` is in the current code's dataset."""
    parts = folder(out, grid) / "parts"
    if not parts.exists():
        return False
    done = _done(parts)
    return all(t.id in done for t in tasks(list(models or MODELS), grid))


def best_available(out: Path | str = DEFAULT_OUT) -> tuple[str, pd.DataFrame] | None:
    """The full atlas when it is complete, else the coarse one when complete (grid name, frame)."""
    for grid in GRIDS:
        if complete(out, grid):
            frame = load(out, grid)
            if frame is not None:
                return grid, frame
    return None


def numeric_inputs(frame: pd.DataFrame, name: str) -> list[str]:
    """The input columns of a model present in a frame."""
    return [c for c in MODELS[name].inputs if c in frame]
