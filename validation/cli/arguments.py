"""The command line of ``prbm-validate``: every verb and its arguments, with no solver imported
(``--help`` and a bad command line answer at once; ``validation.cli.main`` loads the verb's module).
"""

from __future__ import annotations

import argparse

from validation.run.exit_status import RULE

DESCRIPTION = "prbm-validate: list, run, solve, report, bench, stress, audit, sweep, synthesize and atlas."


def _add_atlas(atlas: argparse.ArgumentParser) -> None:
    atlas.add_argument(
        "models",
        nargs="*",
        metavar="MODEL",
        help="atlas models to build (default: all; 'prbm-validate atlas --list' names them)",
    )
    atlas.add_argument("--list", action="store_true", help="name the models, their inputs and points, and stop")
    atlas.add_argument("--coarse", action="store_true", help="the coarse grid (a few hundred points a model)")
    atlas.add_argument("--out", default="reports/atlas", help="folder of the datasets (default %(default)s)")
    atlas.add_argument("--workers", type=int, help="local worker processes (default: every core)")
    where = atlas.add_mutually_exclusive_group()
    where.add_argument("--serial", action="store_true", help="run in this process")
    where.add_argument("--dask", action="store_true", help="run on a local Dask cluster")
    where.add_argument("--scheduler", help="run on the Dask cluster at this address (tcp://HOST:PORT)")
    atlas.add_argument(
        "--write-maps",
        action="store_true",
        help="write the PRBM adapter's error maps (validation/atlas/error_maps.json) from the full atlas",
    )
    atlas.add_argument("--quiet", action="store_true", help="no progress bar")


def _add_sweep(sweep: argparse.ArgumentParser) -> None:
    sweep.add_argument("spec", help="sweep spec file, or its name under cases/sweeps/")
    sweep.add_argument("--out", help="output folder (default reports/sweeps/<sweep id>)")
    sweep.add_argument("--workers", type=int, help="local worker processes (default: every core)")
    where = sweep.add_mutually_exclusive_group()
    where.add_argument("--dask", action="store_true", help="run on a local Dask cluster of --workers processes")
    where.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="run on this existing Dask cluster")
    where.add_argument("--serial", action="store_true", help="run in this process (debugging)")
    sweep.add_argument("--restart", action="store_true", help="discard earlier results instead of resuming")
    sweep.add_argument("--limit", type=int, help="run at most this many pending points now")
    sweep.add_argument("--chunk", type=int, help="points per task (default: automatic)")
    sweep.add_argument("--no-plot", action="store_true", help="do not draw the study's plots")
    sweep.add_argument("--quiet", action="store_true", help="no progress bar")


def _add_synthesize(synthesize: argparse.ArgumentParser) -> None:
    synthesize.add_argument("spec", help="design specification (TOML), e.g. cases/specs/bapat2015_ch6_ex3.toml")
    synthesize.add_argument("--out", default="reports/synthesis", help="output folder (default %(default)s)")
    synthesize.add_argument("--no-fem", action="store_true", help="skip the FEM check")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="prbm-validate", description=DESCRIPTION, epilog=RULE)
    sub = parser.add_subparsers(dest="command", required=True)

    def add(name: str, help: str) -> argparse.ArgumentParser:
        return sub.add_parser(name, help=help, description=help, epilog=RULE)

    listing = add("list", "every case (or the given ids, files, folders), one line each; checks every file")
    listing.add_argument("cases", nargs="*", help="case ids, files, folders or globs (default: all)")
    listing.add_argument(
        "--methods",
        action="store_true",
        help="instead of the cases, what each method can do: every load kind on every boundary, "
        "each method run on a minimal case (validation/run/coverage.py)",
    )
    listing.add_argument("--markdown", action="store_true", help="with --methods: as a Markdown table")

    run = add("run", "run cases and compare with the published numbers")
    run.add_argument("cases", nargs="*", help="case ids, files, folders or globs (default: all)")
    run.add_argument("--method", action="append", help="only this method (repeatable)")
    run.add_argument("--out", default="reports/latest", help="folder for the result tables (default %(default)s)")
    run.add_argument("--jobs", type=int, default=1, help="parallel processes (default %(default)s)")
    run.add_argument("--no-cache", action="store_true", help="recompute even unchanged cases")
    run.add_argument("--quiet", action="store_true", help="no progress bar")

    solve = add("solve", "one case, every requested output at every level with its loads, as JSON")
    solve.add_argument("case", help="a case id, or a case file anywhere")
    solve.add_argument("--method", action="append", help="this method (repeatable; default: every method of the case)")
    solve.add_argument("--json", action="store_true", help="JSON (the only format)")
    solve.add_argument("--out", help="write the JSON to this file instead of stdout")
    solve.add_argument("--compact", action="store_true", help="the JSON on one line (default: indented)")

    report = add("report", "run (or reuse) every case and write the report")
    report.add_argument(
        "cases",
        nargs="*",
        help="case ids, files, folders or globs (default: all, with the domain study and the atlas page)",
    )
    report.add_argument("--out", default="reports", help="folder of the report (default %(default)s)")
    report.add_argument("--jobs", type=int, default=2, help="parallel processes (default %(default)s)")
    report.add_argument("--no-cache", action="store_true", help="recompute even unchanged cases")

    bench = add("bench", "run time against error for every method")
    bench.add_argument(
        "--out", default="reports/bench", help="folder of the benchmark's tables and plots (default %(default)s)"
    )
    bench.add_argument("--quick", action="store_true", help="fewer meshes and repeats")
    stress = add("stress", "numerical stability, invariances and bad input")
    stress.add_argument("--out", default="reports/stress", help="folder of the stress results (default %(default)s)")
    stress.add_argument("--long", action="store_true", help="many more random cases")
    stress.add_argument("--seed", type=int, default=20261122, help="seed of the random cases (default %(default)s)")
    stress.add_argument(
        "--configurations",
        type=int,
        default=10_000,
        help="generated configurations of the quantity contract with --long (default %(default)s)",
    )
    stress.add_argument(
        "--mutants",
        type=int,
        default=None,
        help="mutated case files fuzzed through solve/run (default 300, 10000 with --long)",
    )
    stress.add_argument(
        "--mutant-timeout",
        type=float,
        default=20.0,
        help="seconds each mutated case file may take (default %(default)s)",
    )
    stress.add_argument("--workers", type=int, default=None, help="worker processes (default 2)")
    stress.add_argument("--dask", action="store_true", help="run --long on a local Dask cluster")
    stress.add_argument("--scheduler", default=None, help="run --long on the Dask cluster at this address")

    audit = add("audit", "plant errors in each method and count the cases that catch them")
    audit.add_argument("cases", nargs="*", help="case ids, files or globs (default: all)")
    audit.add_argument(
        "--plant",
        action="append",
        help="only this planted error (repeatable; default: all; names in validation/stress/plants.py)",
    )
    audit.add_argument("--jobs", type=int, default=2, help="worker processes")
    audit.add_argument("--out", default="reports/audit", help="folder for audit.csv (default %(default)s)")
    _add_sweep(add("sweep", "a parameter sweep over a case (grids, Monte Carlo), resumable"))
    _add_synthesize(add("synthesize", "design a compliant mechanism from a specification and check it with the FEM"))
    _add_atlas(add("atlas", "the PRBM error atlas: every PRBM segment model against the exact elastica, resumable"))
    return parser
