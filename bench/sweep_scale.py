"""Sweep scale: 1 vs 2 local workers, Dask LocalCluster, per-task overhead (see validation/sweep_bench.py)."""
from validation.sweep_bench import main

if __name__ == "__main__":
    raise SystemExit(main())
