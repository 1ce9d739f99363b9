"""Scale of the sweep runner, measured: speed-up on 1 and 2 local workers, and Dask's overhead.

Two sweeps over the fixed-pinned segment of ``cases/sweeps/cases/fixed_pinned_segment.toml``, FEM only
(the PRBM and elastica are too cheap to show anything):

* ``heavy``: the deflection-domain sweep (70 load directions x 20 load levels, 32 elements), one
  point per task, run on a process pool of 1 and of 2 workers (speed-up = t1 / t2) and on a Dask
  LocalCluster of 2 worker processes.
* ``light``: 1,000 points of a cheap FEM solve (4 elements, one load level), run on the process
  pool and on the LocalCluster with automatic chunking, and on the LocalCluster with one point per
  task.

Per-task overhead of an executor = (wall time x workers - sum of the tasks' own times) / tasks,
where a task's own time is measured inside the worker (``point_time``); the cluster's start-up is
timed separately and not included. Results are printed and written as JSON.

Run: ``python -m validation.bench.sweep_scale [--out reports/bench/sweep_scale.json]``.
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import platform
import tempfile
import time
from pathlib import Path

from validation.sweep.run import SWEEPS_DIR, load_results, run_sweep

CASE = SWEEPS_DIR / "cases" / "fixed_pinned_segment.toml"

HEAVY = """
[sweep]
id = "bench_heavy"
title = "bench: deflection domain, FEM"
case = "{case}"
methods = ["fem"]
chunk = 1
[sweep.options.fem]
elements = 32
[[parameters]]
path = "loads.0.direction"
mode = "angle"
linspace = {{ start = 2.5, stop = 175.0, num = 70 }}
"""

LIGHT = """
[sweep]
id = "bench_light"
title = "bench: 1,000 cheap FEM points"
case = "{case}"
methods = ["fem"]
[sweep.options.fem]
elements = 4
[[sweep.outputs]]
quantity = "y"
levels = [0]
[[parameters]]
path = "loads.0.direction"
mode = "angle"
linspace = {{ start = 10.0, stop = 170.0, num = 40 }}
[[parameters]]
path = "loads.0.ramp.count"
values = [1]
[[parameters]]
path = "loads.0.ramp"
mode = "scale"
linspace = {{ start = 0.2, stop = 1.0, num = 25 }}
"""


def _timed(spec: Path, out: Path, **kwargs) -> dict:
    started = time.perf_counter()
    status = run_sweep(spec, out, resume=False, progress=False, **kwargs)
    wall = time.perf_counter() - started
    frame = load_results(out)
    per_point = frame.drop_duplicates("point_id")
    runs = [json.loads(line) for line in (out / "runs.jsonl").read_text().splitlines()]
    workers = runs[-1]["workers"]
    chunk = runs[-1]["chunk"]
    tasks = -(-len(per_point) // chunk)
    own = float(per_point["point_time"].sum())
    return {
        "status": status,
        "points": len(per_point),
        "tasks": tasks,
        "chunk": chunk,
        "workers": workers,
        "wall_s": round(wall, 3),
        "task_time_sum_s": round(own, 3),
        "mean_point_time_ms": round(1e3 * own / max(len(per_point), 1), 3),
        "overhead_per_task_ms": round(1e3 * (wall * workers - own) / max(tasks, 1), 3),
        "ok_rows": int((frame["status"] == "ok").sum()),
        "rows": len(frame),
    }


def measure(folder: Path) -> dict:
    from distributed import Client, LocalCluster

    folder.mkdir(parents=True, exist_ok=True)
    heavy, light = folder / "heavy.toml", folder / "light.toml"
    heavy.write_text(HEAVY.format(case=CASE.as_posix()))
    light.write_text(LIGHT.format(case=CASE.as_posix()))
    result: dict = {
        "machine": {"cpus": os.cpu_count(), "python": platform.python_version(), "platform": platform.platform()}
    }
    # warm the page cache and imports once
    run_sweep(heavy, folder / "warm", executor="serial", progress=False, limit=1)
    h1 = _timed(heavy, folder / "h1", executor="process", workers=1)
    h2 = _timed(heavy, folder / "h2", executor="process", workers=2)
    result["heavy"] = {"process_1": h1, "process_2": h2, "speedup_2_over_1": round(h1["wall_s"] / h2["wall_s"], 3)}
    result["light"] = {"process_2": _timed(light, folder / "l_proc", executor="process", workers=2)}
    started = time.perf_counter()
    with (
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=logging.ERROR
        ) as cluster,
        Client(cluster) as client,
    ):
        startup = time.perf_counter() - started
        client.run(lambda: __import__("validation.methods.fem"))  # imports on the workers, untimed
        result["dask_localcluster_startup_s"] = round(startup, 3)
        result["heavy"]["dask_2"] = _timed(heavy, folder / "h_dask", executor=client)
        result["light"]["dask_2"] = _timed(light, folder / "l_dask", executor=client)
        result["light"]["dask_2_chunk_1"] = _timed(light, folder / "l_dask1", executor=client, chunk=1)
    result["light"]["process_2_chunk_1"] = _timed(light, folder / "l_proc1", executor="process", workers=2, chunk=1)
    return result


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="reports/bench/sweep_scale.json", help="JSON file (default %(default)s)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as scratch:
        result = measure(Path(scratch))
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(result, indent=2))
    print(json.dumps(result, indent=2))
    print(f"written {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
