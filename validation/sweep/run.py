"""``prbm-validate sweep SPEC``: a parameter sweep over one or more cases, at scale.

A sweep spec (TOML, under ``cases/sweeps/``) names a base case, the methods to run, the outputs wanted,
and the parameters to vary, each addressed by a dotted path into the case data. Grid parameters
(``values`` or ``linspace``) form a Cartesian product; random parameters (``distribution``:
uniform, normal, truncated normal) are drawn ``samples`` times from a seeded generator and the same
draws are used at every grid point (common random numbers). Every point is one task: the base case
with the point's values written in, validated by the case schema again, run by each method
(``validation.sweep.task``). A point the schema rejects or a method that fails is a row with its
status and message, never a crash and never dropped.

Points run on local processes (``ProcessPoolExecutor``, the default), on a local Dask cluster
(``--dask``) or on an existing one (``--scheduler tcp://HOST:PORT``); dask.distributed does the
distribution. Finished points are written as Parquet part files under ``OUT/parts/`` every few
seconds, so an interrupted sweep is resumed by running the same command again: a point whose id
(a hash of the prepared case, the methods with their options and code, the outputs and the
parameter values) is already in the dataset is not run again. A point whose task failed around it
(status ``task_failed``: a worker lost, a broken pool) has no outcome of its own: the next run runs it
again, and its summary says how many were retried and how many failed again.

Spec format (every field; a bad one is a one-line error naming the file and the field)::

    [sweep]
    id = "cantilever_domain"                 # names the output folder
    title = "Deflection domain of the tip-loaded cantilever"
    case = "cases/fixed_pinned.toml"         # a case id under cases/, or a file relative to this
                                             # spec; a list of them sweeps each case
    methods = ["fem", "prbm"]                # run these (the case's options are kept)
    outputs = "case"                         # the case's own outputs, or [[sweep.outputs]] tables
    samples = 200                            # draws of the random parameters (needs a distribution)
    seed = 1                                 # of the random draws
    chunk = 0                                # points per task (0 = automatic)

    [sweep.options.fem]                      # method options merged over the case's
    elements = 16

    [[sweep.outputs]]                        # like a case's [[outputs]]
    quantity = "y"
    levels = [4, 9]

    [[parameters]]
    path = "loads.0.direction"               # dotted path into the case data (list items by index)
    mode = "angle"                           # set | scale | offset | angle (degrees -> [cos, sin])
    linspace = { start = 0, stop = 180, num = 19 }   # or values = [...] or distribution = {...}
    name = "load_angle"                      # result column (default: the path)

    [[parameters]]
    path = "segment.E"
    mode = "scale"
    distribution = { kind = "truncnormal", mean = 1.0, std = 0.025, low = 0.95, high = 1.05 }

    [plot]                                   # what plot_sweep draws
    kind = "domain"                          # domain | scatter | convergence | none
    x = "x"                                  # quantities on the axes (domain, scatter)
    y = "y"
    point = "tip"
    by = "methods.fem.elements"              # convergence: the parameter on the horizontal axis

Output folder: ``parts/*.parquet`` (one row per point x method x output x level: the parameter
columns, value, unit, error estimate, converged, status, message, times), ``sweep.json`` (the spec,
the cases, the ids of the current points), ``runs.jsonl`` (one line per run: points run, skipped,
failed, wall time, executor) and the plots.

Exit status: 0 finished, 1 finished with failed points (recorded), 2 bad spec, 130 interrupted.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import logging
import math
import os
import sys
import time
import tomllib
import uuid
import zlib
from collections import Counter
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterator, Literal

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
from pydantic import Field, ValidationError, model_validator
from scipy.special import ndtr, ndtri
from tqdm import tqdm

from validation.case.capabilities import method_quantities
from validation.case.loader import CASES_DIR, CaseError, SpecError, find_case_files, load_case, read_toml_model
from validation.case.overrides import PathError, apply, check_path, parent_of
from validation.case.schema import Case, Finite, OutputSpec, Positive, Strict
from validation.run.cache import code_hash, package_version
from validation.run.exit_status import ExitStatus, print_error
from validation.sweep.task import ROW_COLUMNS, _row, prepare, run_chunk

SWEEPS_DIR = CASES_DIR / "sweeps"
EXIT_OK, EXIT_FAILED_POINTS, EXIT_BAD_INPUT, EXIT_INTERRUPTED = (
    ExitStatus.OK,
    ExitStatus.FAILED,
    ExitStatus.BAD_INPUT,
    ExitStatus.INTERRUPTED,
)  # the rule, in sweep words
FAILED = ("error", "invalid", "not_converged", "not_applicable", "task_failed")  # exit status 1 (exit_status.py)
SHOWN_FAILURES = 3  # failed points named on screen; the rest are in FAILED_CSV
MESSAGE_CHARS = 160
FAILED_CSV = "failed.csv"
TASK_FAILED = "task_failed"  # no outcome of the point itself (a worker lost, a broken pool): run again


class Linspace(Strict):
    start: Finite
    stop: Finite
    num: int = Field(ge=1, le=1_000_000)


class Distribution(Strict):
    """uniform(low, high); normal(mean, std); truncnormal(mean, std) cut to [low, high]."""

    kind: Literal["uniform", "normal", "truncnormal"]
    mean: Finite | None = None
    std: Positive | None = None
    low: Finite | None = None
    high: Finite | None = None

    @model_validator(mode="after")
    def _complete(self) -> "Distribution":
        need = {"uniform": ("low", "high"), "normal": ("mean", "std"), "truncnormal": ("mean", "std", "low", "high")}[
            self.kind
        ]
        for name in need:
            if getattr(self, name) is None:
                raise ValueError(f"distribution '{self.kind}' needs '{name}'")
        if self.low is not None and self.high is not None and not self.low < self.high:
            raise ValueError("'low' must be below 'high'")
        return self

    def _needed(self, value: float | None, name: str) -> float:
        """A parameter the distribution's kind needs (``_complete`` has checked it is given)."""
        if value is None:
            raise ValueError(f"distribution '{self.kind}' needs '{name}'")
        return value

    def draw(self, n: int, seed: int, stream: str) -> list[float]:
        """n draws by inverse CDF of seeded uniforms: the first k draws do not depend on n."""

        rng = np.random.default_rng([seed, zlib.crc32(stream.encode())])
        u = np.clip(rng.random(n), 1e-15, 1 - 1e-15)
        if self.kind == "uniform":
            low, high = self._needed(self.low, "low"), self._needed(self.high, "high")
            x = low + (high - low) * u
        elif self.kind == "normal":
            x = self._needed(self.mean, "mean") + self._needed(self.std, "std") * ndtri(u)
        else:
            mean, std = self._needed(self.mean, "mean"), self._needed(self.std, "std")
            low, high = self._needed(self.low, "low"), self._needed(self.high, "high")
            lo, hi = ndtr((low - mean) / std), ndtr((high - mean) / std)
            x = np.clip(mean + std * ndtri(lo + u * (hi - lo)), low, high)
        return [float(v) for v in x]


class Parameter(Strict):
    path: str = Field(pattern=r"^[A-Za-z0-9_-]+(\.[A-Za-z0-9_-]+)*$")
    mode: Literal["set", "scale", "offset", "angle"] = "set"
    values: list[Any] | None = Field(default=None, min_length=1)
    linspace: Linspace | None = None
    distribution: Distribution | None = None
    name: str | None = Field(default=None, pattern=r"^[A-Za-z0-9_.:-]+$")

    @model_validator(mode="after")
    def _one_source(self) -> "Parameter":
        given = [k for k in ("values", "linspace", "distribution") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError("give exactly one of 'values', 'linspace' or 'distribution'")
        if self.mode != "set" and self.values is not None and not all(_is_number(v) for v in self.values):
            raise ValueError(f"mode '{self.mode}' needs numbers in 'values'")
        return self

    @property
    def column(self) -> str:
        return self.name or self.path

    @property
    def random(self) -> bool:
        return self.distribution is not None

    def grid(self) -> list[Any]:
        if self.values is not None:
            return list(self.values)
        s = self.linspace
        if s is None:
            raise ValueError("give exactly one of 'values', 'linspace' or 'distribution'")
        if s.num == 1:
            return [float(s.start)]
        return [s.start + (s.stop - s.start) * i / (s.num - 1) for i in range(s.num)]

    def arrow_type(self) -> str:
        if self.values is not None and all(isinstance(v, int) and not isinstance(v, bool) for v in self.values):
            return "int64"
        if self.values is not None and not all(_is_number(v) for v in self.values):
            return "string"  # lists, strings, true/false: stored as JSON text
        return "float64"


class PlotSpec(Strict):
    kind: Literal["domain", "scatter", "convergence", "difference", "none"] = "none"
    x: str | None = Field(default=None, description="default: x, else dx")
    y: str | None = Field(default=None, description="default: y, else dy")
    point: str | None = Field(default=None, description="default: the first point with both quantities")
    by: str | None = None
    levels: list[int] | None = None


class SweepInfo(Strict):
    id: str = Field(pattern=r"^[A-Za-z0-9_.-]+$")
    title: str
    description: str = ""
    case: str | list[str] = Field(description="case id under cases/, or file relative to the spec")
    methods: list[str] = Field(min_length=1)
    options: dict[str, dict[str, Any]] = Field(default_factory=dict)
    outputs: Literal["case"] | list[OutputSpec] = "case"
    samples: int | None = Field(default=None, ge=1, le=10_000_000)
    seed: int = 0
    chunk: int = Field(default=0, ge=0)

    @model_validator(mode="after")
    def _coherent(self) -> "SweepInfo":

        for method in self.methods:
            method_quantities(method)  # ValueError naming an unknown method
        for name in self.options:
            if name not in self.methods:
                raise ValueError(f"options.{name}: method '{name}' is not in 'methods'")
        if isinstance(self.case, list) and not self.case:
            raise ValueError("'case' names no case")
        return self

    @property
    def cases(self) -> list[str]:
        return [self.case] if isinstance(self.case, str) else list(self.case)


class SweepSpec(Strict):
    sweep: SweepInfo
    parameters: list[Parameter] = Field(min_length=1)
    plot: PlotSpec = PlotSpec()

    @model_validator(mode="after")
    def _columns(self) -> "SweepSpec":
        names = [p.column for p in self.parameters]
        for name in names:
            if name in ROW_COLUMNS:
                raise ValueError(f"parameter name '{name}' is a result column; give it another 'name'")
        if len(set(names)) != len(names):
            raise ValueError("parameter names must be unique (give 'name' to two uses of one path)")
        if any(p.random for p in self.parameters) and self.sweep.samples is None:
            raise ValueError("random parameters need 'sweep.samples'")
        if self.sweep.samples is not None and not any(p.random for p in self.parameters):
            raise ValueError("'sweep.samples' is given but no parameter has a 'distribution'")
        return self


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


# ---------------------------------------------------------------- loading


@dataclass(frozen=True)
class LoadedSweep:
    path: Path
    text: str
    spec: SweepSpec
    cases: dict[str, dict]  # case id -> prepared case data (methods, outputs; references dropped)
    case_files: dict[str, str]  # case id -> file


def find_spec(name: str | Path) -> Path:
    """A spec file given as a path, or as a name under ``cases/sweeps/`` (with or without ``.toml``)."""
    path = Path(name)
    if path.is_file():
        return path
    for candidate in (SWEEPS_DIR / path, SWEEPS_DIR / f"{name}.toml"):
        if candidate.is_file():
            return Path(os.path.relpath(candidate))
    return path  # load_spec reports that it cannot be read


def _find_case(ref: str, spec_path: Path, field: str) -> Path:
    """A case file: a path (relative to the spec, then to cwd) or an id under ``cases/``."""
    if ref.endswith(".toml"):
        for candidate in (spec_path.parent / ref, Path(ref)):
            if candidate.is_file():
                return candidate
        raise SpecError(spec_path, field, f"case file '{ref}' not found (relative to the spec or cwd)")
    unreadable = 0
    for path in find_case_files(None):
        if f'"{ref}"' not in path.read_text(encoding="utf-8", errors="replace"):
            continue
        try:
            if load_case(path).id == ref:
                return path
        except CaseError:
            unreadable += 1
    note = f" ({unreadable} possible file(s) could not be read)" if unreadable else ""
    raise SpecError(spec_path, field, f"no case file under cases/ has id '{ref}'{note}")


def _check_field(data: dict, param: Parameter) -> None:
    """A path to a field the case does not set must still name a field of the schema."""

    node, key = parent_of(data, param.path)
    if not isinstance(node, dict) or key in node:
        return
    d = param.distribution
    trial = param.grid()[0] if d is None else (d.mean if d.mean is not None else d.low)
    probe = json.loads(json.dumps(data))
    apply(probe, param.path, param.mode, trial)
    try:
        Case.model_validate(probe)
    except ValidationError as exc:
        for err in exc.errors():
            if err["type"] == "extra_forbidden" and ".".join(map(str, err["loc"])) == param.path:
                raise PathError(f"'{param.path}': no such field in the case schema") from None


def load_spec(path: Path | str) -> LoadedSweep:
    """Read and validate a spec and its base cases; raise ``SpecError`` with a one-line message."""
    path = Path(path)
    text, spec = read_toml_model(path, SweepSpec, SpecError)
    info = spec.sweep
    outputs = None if info.outputs == "case" else [o.model_dump(exclude_none=True) for o in info.outputs]
    cases, files = {}, {}
    for i, ref in enumerate(info.cases):
        field = "sweep.case" if isinstance(info.case, str) else f"sweep.case.{i}"
        case_path = _find_case(ref, path, field)
        try:
            loaded = load_case(case_path)
        except CaseError as exc:
            raise SpecError(path, field, str(exc)) from None
        data = prepare(tomllib.loads(loaded.text), info.methods, info.options, outputs)
        try:
            Case.model_validate(data)
        except ValidationError as exc:
            err = exc.errors()[0]
            where = ".".join(str(p) for p in err["loc"])
            raise SpecError(
                path,
                field,
                f"case '{loaded.id}' with methods {info.methods}: "
                f"{where + ': ' if where else ''}"
                f"{err['msg'].removeprefix('Value error, ')}",
            ) from None
        if not data["outputs"]:
            raise SpecError(
                path, "sweep.outputs", f"no output of case '{loaded.id}' can be given by {', '.join(info.methods)}"
            )
        for j, param in enumerate(spec.parameters):
            try:
                check_path(data, param.path, param.mode)
                _check_field(data, param)
            except PathError as exc:
                raise SpecError(path, f"parameters.{j}.path", f"case '{loaded.id}': {exc}") from None
        if loaded.id in cases:
            raise SpecError(path, field, f"case '{loaded.id}' is named twice")
        cases[loaded.id], files[loaded.id] = data, str(case_path)
    return LoadedSweep(path=path, text=text, spec=spec, cases=cases, case_files=files)


# ---------------------------------------------------------------- points


def _jsonable(value: Any) -> Any:
    return value if _is_number(value) or isinstance(value, str) else json.dumps(value, sort_keys=True)


def _code_hashes(methods: list[str]) -> dict[str, str]:

    return {m: code_hash(m) for m in methods} | {"version": package_version()}


def make_points(loaded: LoadedSweep) -> list[dict]:
    """Every point of the sweep, in order (case, grid product, sample), without repeats."""
    spec = loaded.spec
    grid = [p for p in spec.parameters if not p.random]
    random = [p for p in spec.parameters if p.random]
    n = spec.sweep.samples or 1
    draws = {
        p.column: p.distribution.draw(n, spec.sweep.seed, p.column)
        for p in spec.parameters
        if p.distribution is not None
    }
    code = _code_hashes(spec.sweep.methods)
    points: dict[str, dict] = {}
    for case_id, data in loaded.cases.items():
        case_hash = hashlib.sha256(json.dumps([data, code], sort_keys=True, default=str).encode()).hexdigest()
        for combo in itertools.product(*(p.grid() for p in grid)):
            for sample in range(n):
                values = {p.column: v for p, v in zip(grid, combo)}
                values |= {p.column: draws[p.column][sample] for p in random}
                key = [case_hash] + [[p.path, p.mode, values[p.column]] for p in spec.parameters]
                point_id = hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()[:20]
                columns = {
                    p.column: (values[p.column] if p.arrow_type() != "string" else json.dumps(values[p.column]))
                    for p in spec.parameters
                }
                points.setdefault(
                    point_id,
                    dict(id=point_id, case=case_id, sample=sample if random else 0, values=values, columns=columns),
                )
    return list(points.values())


def arrow_schema(spec: SweepSpec):

    types = {"string": pa.string(), "int64": pa.int64(), "float64": pa.float64(), "bool": pa.bool_()}
    fields = [pa.field(name, types[kind]) for name, kind in ROW_COLUMNS.items()]
    fields += [pa.field(p.column, types[p.arrow_type()]) for p in spec.parameters]
    return pa.schema(fields)


# ---------------------------------------------------------------- dataset


class PartWriter:
    """Buffers finished rows; writes a Parquet part file every ``every`` points or ``seconds``."""

    def __init__(self, folder: Path, schema, run_id: str, every: int = 500, seconds: float = 5.0):
        self.folder, self.schema, self.run_id = folder, schema, run_id
        self.every, self.seconds = every, seconds
        self.rows: list[dict] = []
        self.points = 0
        self.parts = 0
        self.last = time.monotonic()
        folder.mkdir(parents=True, exist_ok=True)

    def add(self, rows: list[dict], points: int) -> None:
        self.rows.extend(rows)
        self.points += points
        if self.points >= self.every or time.monotonic() - self.last >= self.seconds:
            self.flush()

    def flush(self) -> None:

        self.last = time.monotonic()
        if not self.rows:
            return
        table = pa.Table.from_pylist(self.rows, schema=self.schema)
        name = f"part-{self.run_id}-{self.parts:05d}.parquet"
        temporary = self.folder / f".{name}.tmp"  # hidden: a reader never sees a half-written part
        pq.write_table(table, temporary)
        os.replace(temporary, self.folder / name)
        self.parts += 1
        self.rows, self.points = [], 0


def _parts(out: Path) -> list[Path]:
    return sorted((out / "parts").glob("part-*.parquet"))


def _done_ids(out: Path) -> tuple[set[str], set[str]]:
    """(ids of the points that have their own outcome, ids of those whose every row is a failed task):
    a point's outcome, ok or not, is final; a task that failed around it is not, and is run again."""
    done: set[str] = set()
    task_failed: set[str] = set()
    for part in _parts(out):
        table = pq.read_table(part, columns=["point_id", "status"]).to_pydict()
        for point, status in zip(table["point_id"], table["status"]):
            (task_failed if status == TASK_FAILED else done).add(point)
    return done, task_failed - done


def load_results(out: Path | str):
    """The sweep's rows as a pandas DataFrame: current points only, latest row per output."""

    out = Path(out)
    parts = _parts(out)
    if not parts:
        return pd.DataFrame()
    frame = pd.concat([pq.read_table(p).to_pandas() for p in parts], ignore_index=True)
    manifest = out / "sweep.json"
    if manifest.is_file():
        current = set(json.loads(manifest.read_text())["point_ids"])
        frame = frame[frame["point_id"].isin(current)]
    answered = set(frame.loc[frame["status"] != TASK_FAILED, "point_id"])
    frame = frame[(frame["status"] != TASK_FAILED) | ~frame["point_id"].isin(answered)]  # retried since
    frame = frame.drop_duplicates(["point_id", "method", "quantity", "point", "level"], keep="last")
    frame["level"] = frame["level"].astype("Int64")
    return frame.reset_index(drop=True)


# ---------------------------------------------------------------- executors


def _failed_chunk(chunk: list[dict], run_id: str, exc: BaseException) -> list[dict]:
    """Rows of a chunk whose task failed (a worker lost, a broken pool): status TASK_FAILED, so that the
    next run of the sweep runs these points again."""
    message = f"task failed: {type(exc).__name__}: {exc}".replace("\n", " ")
    return [_row(p, run_id, status=TASK_FAILED, message=message) for p in chunk]


def _is_dask_client(obj: Any) -> bool:
    return type(obj).__name__ == "Client" and type(obj).__module__.startswith("distributed")


def _dask_completed(client, context, chunks, task=run_chunk) -> Iterator[tuple[list[dict], list[dict] | BaseException]]:
    from distributed import as_completed

    shared = client.scatter(context, broadcast=True)
    futures = {client.submit(task, shared, chunk, pure=False): i for i, chunk in enumerate(chunks)}
    try:
        for future in as_completed(futures):
            chunk = chunks[futures[future]]
            try:
                yield chunk, future.result()
            except Exception as exc:  # a worker lost, a pickling error: recorded, not fatal
                yield chunk, exc
    finally:
        client.cancel(list(futures))


def _pool_completed(pool, context, chunks, task=run_chunk) -> Iterator[tuple[list[dict], list[dict] | BaseException]]:

    futures = {pool.submit(task, context, chunk): i for i, chunk in enumerate(chunks)}
    try:
        for future in as_completed(futures):
            chunk = chunks[futures[future]]
            try:
                yield chunk, future.result()
            except Exception as exc:  # e.g. BrokenProcessPool: the chunk is recorded as failed
                yield chunk, exc
    finally:
        for future in futures:
            future.cancel()


def completed(
    executor: Any,
    context: dict,
    chunks: list[list[Any]],
    workers: int | None = None,
    scheduler: str | None = None,
    task=run_chunk,
) -> Iterator[tuple[list[Any], list[dict] | BaseException]]:
    """(chunk, rows or exception) for every chunk, in the order they finish.

    ``executor``: 'serial' (this process), 'process' (a ProcessPoolExecutor of ``workers``),
    'dask' (a new ``distributed.LocalCluster`` of ``workers`` processes, or the cluster at
    ``scheduler``), or an object you own: a ``concurrent.futures.Executor`` or a
    ``distributed.Client``. ``task(context, chunk) -> rows`` is what a worker runs (default: sweep
    points; ``prbm-validate stress --long`` passes its own).
    """
    if scheduler is not None or executor == "dask":
        from distributed import Client, LocalCluster

        cluster = None
        if scheduler is not None:
            client = Client(scheduler)
        else:
            cluster = LocalCluster(
                n_workers=workers or os.cpu_count(),
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
                silence_logs=logging.ERROR,
            )
            client = Client(cluster)
        try:
            yield from _dask_completed(client, context, chunks, task)
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    elif executor == "serial":
        for chunk in chunks:
            yield chunk, task(context, chunk)
    elif executor == "process":
        pool = ProcessPoolExecutor(max_workers=workers or os.cpu_count())
        try:
            yield from _pool_completed(pool, context, chunks, task)
        finally:
            pool.shutdown(wait=True, cancel_futures=True)
    elif _is_dask_client(executor):
        yield from _dask_completed(executor, context, chunks, task)
    elif hasattr(executor, "submit"):
        yield from _pool_completed(executor, context, chunks, task)
    else:
        raise ValueError(f"unknown executor {executor!r}: use 'serial', 'process', 'dask' or an executor")


def _chunk_size(n: int, workers: int, asked: int) -> int:
    """Points per task: about 16 tasks per worker, at most 64 points each."""
    if asked:
        return asked
    return max(1, min(64, math.ceil(n / (16 * max(workers, 1)))))


# ---------------------------------------------------------------- the sweep


def _prepare_folder(out: Path, schema, resume: bool) -> bool:
    """Delete earlier parts (no resume), or refuse a folder holding another sweep's results."""
    manifest_path = out / "sweep.json"
    if not resume:
        for part in _parts(out):
            part.unlink()
    elif manifest_path.is_file():
        earlier = json.loads(manifest_path.read_text())
        if earlier.get("schema") != schema.to_string() and _parts(out):
            print(
                f"error: {out}: holds results of a sweep with other parameters; use another --out or --restart",
                file=sys.stderr,
            )
            return False
    return True


def _write_manifest(out: Path, loaded: "LoadedSweep", schema, points: list[dict]) -> None:
    spec = loaded.spec
    out.mkdir(parents=True, exist_ok=True)
    manifest = {
        "spec_file": str(loaded.path),
        "spec": loaded.text,
        "sweep": spec.sweep.id,
        "cases": loaded.case_files,
        "plot": spec.plot.model_dump(),
        "parameters": [p.model_dump(exclude_none=True) for p in spec.parameters],
        "methods": spec.sweep.methods,
        "schema": schema.to_string(),
        "point_ids": [p["id"] for p in points],
    }
    (out / "sweep.json").write_text(json.dumps(manifest, indent=1, default=str))


def _worker_count(executor: Any, workers: int | None) -> int:
    if executor == "serial":
        return 1
    if _is_dask_client(executor):
        return len(executor.scheduler_info()["workers"]) or 1
    return workers or getattr(executor, "_max_workers", None) or os.cpu_count() or 1


def _append_record(out: Path, record: dict) -> None:
    with (out / "runs.jsonl").open("a") as handle:
        handle.write(json.dumps(record) + "\n")


def run_sweep(
    spec_path: Path | str,
    out: Path | str | None = None,
    executor: Any = "process",
    scheduler: str | None = None,
    workers: int | None = None,
    resume: bool = True,
    progress: bool = True,
    *,
    chunk: int | None = None,
    limit: int | None = None,
    flush_every: int = 500,
    flush_seconds: float = 5.0,
) -> int:
    """Run every point of the spec not yet in ``out`` and write it there; the exit status.

    ``resume=False`` deletes the part files first. ``limit`` runs at most that many pending
    points (the rest on the next run). Bad specs print one line to stderr and return 2.
    """

    started = time.perf_counter()
    try:
        loaded = load_spec(find_spec(spec_path))
    except (CaseError, ValueError) as exc:
        print_error(exc)
        return EXIT_BAD_INPUT
    spec = loaded.spec
    out = Path(out) if out is not None else Path("reports") / "sweeps" / spec.sweep.id
    points = make_points(loaded)
    schema = arrow_schema(spec)
    if not _prepare_folder(out, schema, resume):
        return EXIT_BAD_INPUT
    done, earlier_failed = _done_ids(out) if resume else (set(), set())
    pending = [p for p in points if p["id"] not in done]
    skipped = len(points) - len(pending)
    if limit is not None:
        pending = pending[:limit]
    _write_manifest(out, loaded, schema, points)
    run_id = time.strftime("%Y%m%dT%H%M%S") + f"-{uuid.uuid4().hex[:8]}"  # unique: part names never clash
    n_workers = _worker_count(executor, workers)
    size = _chunk_size(len(pending), n_workers, chunk if chunk is not None else spec.sweep.chunk)
    chunks = [pending[i : i + size] for i in range(0, len(pending), size)]
    context = {
        "run": run_id,
        "cases": loaded.cases,
        "methods": spec.sweep.methods,
        "pin_blas": executor != "serial",
        "parameters": [{"path": p.path, "mode": p.mode, "name": p.column} for p in spec.parameters],
    }
    writer = PartWriter(out / "parts", schema, run_id, every=flush_every, seconds=flush_seconds)
    bar = tqdm(total=len(points), initial=skipped, unit="pt", disable=not progress, leave=False, desc=spec.sweep.id)
    failed = ran = 0
    retried = {p["id"] for p in pending} & earlier_failed
    task_failures: Counter = Counter()  # message -> points, of this run's failed tasks
    failed_tasks: set[str] = set()  # the points of this run's failed tasks
    status = EXIT_OK
    try:
        for chunk_points, rows in completed(executor, context, chunks, workers, scheduler):
            if isinstance(rows, BaseException):
                rows = _failed_chunk(chunk_points, run_id, rows)
            bad = {r["point_id"] for r in rows if r["status"] in FAILED}
            failed += len(bad)
            for r in rows:
                if r["status"] == TASK_FAILED:
                    task_failures[r["message"]] += 1
                    failed_tasks.add(r["point_id"])
            ran += len(chunk_points)
            writer.add(rows, len(chunk_points))
            bar.update(len(chunk_points))
    except KeyboardInterrupt:
        status = EXIT_INTERRUPTED
    finally:
        writer.flush()
        bar.close()
    wall = time.perf_counter() - started
    record = {
        "run": run_id,
        "executor": executor if isinstance(executor, str) else type(executor).__name__,
        "scheduler": scheduler,
        "workers": n_workers,
        "chunk": size,
        "points": len(points),
        "skipped": skipped,
        "ran": ran,
        "failed": failed,
        "left": len(points) - skipped - ran,
        "retried": len(retried),
        "task_failed": sum(task_failures.values()),
        "wall_time_s": round(wall, 3),
        "interrupted": status == EXIT_INTERRUPTED,
    }
    _append_record(out, record)
    if status == EXIT_INTERRUPTED:
        print(
            f"interrupted: {skipped + ran} of {len(points)} points are in {out}; run the same command again to resume",
            file=sys.stderr,
        )
        return status
    again = (
        (f" ({len(retried)} retried after a failed task, {len(retried & failed_tasks)} of them failed again)")
        if retried
        else ""
    )
    _print_summary(loaded, out, record, again, task_failures)
    return EXIT_FAILED_POINTS if failed else EXIT_OK


def _print_summary(loaded: LoadedSweep, out: Path, record: dict, again: str, task_failures: Counter) -> None:
    """The run's line (points run, already done, failed, left; wall time; where the results are), then
    the first ``SHOWN_FAILURES`` failed points of the sweep, each with its parameters and message (and
    the case's own word when it records that failure as expected), and where every one is
    (``failed.csv``, ``failed_points``); a failed task's message on stderr."""
    spec, columns = loaded.spec, [p.column for p in loaded.spec.parameters]
    left = f", {record['left']} left (run again to continue)" if record["left"] else ""
    failures = failed_points(out, columns)
    in_all = failures["point_id"].nunique()
    earlier = f" ({in_all} in the whole sweep)" if in_all != record["failed"] else ""
    print(
        f"{spec.sweep.id}: {record['ran']} point(s) run{again}, {record['skipped']} already done, "
        f"{record['failed']} failed{earlier}{left}; {record['wall_time_s']:.1f} s; results in {out}"
    )
    for _, row in failures.head(SHOWN_FAILURES).iterrows():
        values = ", ".join(f"{c} = {row[c]:g}" if isinstance(row[c], float) else f"{c} = {row[c]}" for c in columns)
        message = " ".join(str(row["message"]).split())
        expected = (loaded.cases.get(row["case"], {}).get("case") or {}).get("expected_failure", {})
        print(
            f"  failed: point {row['point_id']} ({values}): {row['case']} {row['method']} "
            f"{row['status']}: {message[:MESSAGE_CHARS]}{'...' if len(message) > MESSAGE_CHARS else ''}"
            + (" (the case records this as an expected failure)" if row["method"] in expected else "")
        )
    if len(failures):
        more = f"{len(failures) - SHOWN_FAILURES} more; " if len(failures) > SHOWN_FAILURES else ""
        print(
            f"  {more}every failed point with its parameters and message: {out / FAILED_CSV} "
            f"(all rows: {out / 'parts'})"
        )
    for message, count in task_failures.most_common():
        print(f"  {count} point(s): {message}; run the same command again to retry them", file=sys.stderr)


def failed_points(out: Path, columns: list[str]) -> pd.DataFrame:
    """Every failed point of the sweep in ``out`` (this run's and the earlier runs'), one row per point
    and method that failed there: its id, parameters, case, method, status and message, written to
    ``failed.csv`` (removed when none failed)."""
    frame = load_results(out)
    keep = ["point_id", *columns, "case", "method", "status", "message"]
    if not len(frame):
        failures = pd.DataFrame(columns=keep)
    else:
        failures = frame[frame["status"].isin(FAILED)].drop_duplicates(["point_id", "case", "method"])[keep]
    target = out / FAILED_CSV
    if len(failures):
        failures.to_csv(target, index=False)
    elif target.exists():
        target.unlink()
    return failures.reset_index(drop=True)


# ---------------------------------------------------------------- command line
