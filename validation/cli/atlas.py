"""``prbm-validate atlas [MODEL ...]``: build (or resume) the PRBM error atlas, then its regions, the seeds'
claims checked and the maps on disk.

Lines run on local processes (``--workers``), a local Dask cluster (``--dask``) or an existing one
(``--scheduler``).  The dataset is resumable and kept per code version (``validation.atlas.dataset``):
an interrupted build keeps every finished part and the next run takes up the rest; a finished build of
the current code runs nothing.  After a build of every model the folder gets ``regions.csv`` (the
0.5/1/3/5 % regions per model), ``claims.csv`` (the seeds' claims checked) and one map per model
(``maps/MODEL.png``); ``--write-maps`` also writes the PRBM adapter's error maps from the full atlas.

Exit status: 0 built, 2 a bad model name or option, 130 interrupted (finished lines kept).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import pandas as pd
from tqdm import tqdm

from validation.atlas import dataset, regions
from validation.atlas.claims import check_claims, load_claims
from validation.atlas.map_figure import MapFigure
from validation.atlas.maps import write_maps
from validation.atlas.models import MODELS
from validation.run.exit_status import ExitStatus

CLAIMS = Path(__file__).resolve().parents[2] / "cases" / "atlas" / "claims.toml"


def _list() -> int:
    for name, m in MODELS.items():
        inputs = ", ".join(a.name for a in (*m.shape_axes, m.load))
        print(f"{name:26s} {m.points(False):6d} points ({m.points(True):4d} coarse)  inputs: {inputs}  {m.title}")
    return ExitStatus.OK


def _write_csv(frame: pd.DataFrame, path: Path) -> None:
    tmp = path.with_suffix(".tmp")
    frame.to_csv(tmp, index=False)
    tmp.replace(path)


def _summaries(frame: pd.DataFrame, folder: Path, models: list[str]) -> None:
    """Regions, claims and maps of a complete dataset (each file replaced whole)."""
    claims = load_claims(CLAIMS)
    rows = []
    maps = MapFigure()
    for name in models:
        maps.draw(frame, name, folder / "maps" / f"{name}.png", claims)
        for s in regions.summaries(frame, name):
            rows.append({**s.__dict__, "words": regions.region_words(s)})
            if s.threshold in (1.0, 5.0):
                print(f"  {name}: {regions.region_words(s)}")
    _write_csv(pd.DataFrame(rows), folder / "regions.csv")
    checked = check_claims(frame, [c for c in claims if set(c.models) <= set(models)])
    _write_csv(checked, folder / "claims.csv")
    for verdict, count in checked["verdict"].value_counts().items():
        print(f"  seeds' claims: {count} {verdict}")


def run(args) -> int:
    if args.list:
        return _list()
    unknown = [m for m in args.models if m not in MODELS]
    if unknown:
        print(f"error: unknown atlas model(s) {', '.join(unknown)}; known: {', '.join(MODELS)}", file=sys.stderr)
        return ExitStatus.BAD_INPUT
    if args.write_maps and args.coarse:
        print("error: --write-maps takes the full atlas (drop --coarse)", file=sys.stderr)
        return ExitStatus.BAD_INPUT
    models = list(args.models or MODELS)
    grid = "coarse" if args.coarse else "full"
    executor = "serial" if args.serial else ("dask" if args.dask else "process")
    points = sum(MODELS[m].points(args.coarse) for m in models)
    print(f"atlas: {len(models)} model(s), {points} points on the {grid} grid, code version {dataset.code_version()}")
    bar = tqdm(total=1, unit="line", disable=args.quiet, leave=False, file=sys.stderr)

    def progress(done: int, total: int) -> None:
        bar.total = total
        bar.n = done
        bar.refresh()

    started = time.perf_counter()
    try:
        record = dataset.build(
            grid,
            models,
            out=args.out,
            executor=executor,
            workers=args.workers,
            scheduler=args.scheduler,
            progress=progress,
        )
    except KeyboardInterrupt:
        bar.close()
        print("atlas: interrupted; the finished lines are kept, run the same command to go on", file=sys.stderr)
        return 130
    bar.close()
    print(
        f"atlas: {record.lines_run} line(s) run, {record.lines_skipped} already done, {record.points} points in "
        f"{record.seconds:.1f} s ({record.points_per_second:.0f} points/s) -> {record.folder}"
    )
    frame = dataset.load(args.out, grid)
    if frame is not None and dataset.complete(args.out, grid, models):
        _summaries(frame, Path(record.folder), models)
        if args.write_maps:
            if set(models) != set(MODELS):
                print("error: --write-maps needs every model (give no MODEL)", file=sys.stderr)
                return ExitStatus.BAD_INPUT
            print(f"maps: {write_maps(frame, record.version)}")
    print(f"atlas: done in {time.perf_counter() - started:.1f} s")
    return ExitStatus.OK
