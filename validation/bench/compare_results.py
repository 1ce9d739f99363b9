"""Compare two ``results.csv`` files (``prbm-validate run --no-cache --out A`` before a change, ``--out B``
after it): every row's value and error estimate must agree to rounding, and the same rows must converge.

A value agrees when |a - b| <= rtol |a| + atol scale (scale: the row's characteristic scale, or 1);
an error estimate (a difference of two solutions, |u_2n - u_n|/3) to the same bound on the value,
since rounding of the values, not of the estimate, is what moves it.
Prints every row that differs and exits 1 if any does.

Run:  python validation/bench/compare_results.py BEFORE/results.csv AFTER/results.csv [--rtol 1e-8] [--atol 1e-10]
"""

from __future__ import annotations

import argparse
import sys

import numpy as np
import pandas as pd

KEY = ["case", "method", "quantity", "point", "level", "reference_label", "reference_value"]


def differences(before: pd.DataFrame, after: pd.DataFrame, rtol: float, atol: float) -> pd.DataFrame:
    """The rows whose value, error estimate or convergence changed, and rows found in only one file."""
    both = before.merge(after, on=KEY, how="outer", suffixes=("_before", "_after"), indicator=True)
    scale = both["scale_before"].abs().fillna(1.0).replace(0.0, 1.0)
    bad = both["_merge"] != "both"
    bound = rtol * both["value_before"].astype(float).abs().fillna(0.0) + atol * scale
    for column in ("value", "error_estimate"):
        a, b = both[f"{column}_before"].astype(float), both[f"{column}_after"].astype(float)
        same_nan = a.isna() & b.isna()
        bad |= ~(same_nan | (np.abs(a - b) <= bound))
    bad |= both["converged_before"].astype(str) != both["converged_after"].astype(str)
    return both[bad]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--rtol", type=float, default=1e-8)
    parser.add_argument("--atol", type=float, default=1e-10)
    args = parser.parse_args()
    before, after = (pd.read_csv(p, keep_default_na=True) for p in (args.before, args.after))
    for frame in (before, after):
        frame["point"] = frame["point"].fillna("")
        frame["reference_label"] = frame["reference_label"].fillna("")
    diff = differences(before, after, args.rtol, args.atol)
    print(
        f"{len(before)} rows before, {len(after)} after; {len(diff)} differ "
        f"(rtol {args.rtol:g}, atol {args.atol:g} x scale)"
    )
    if len(diff):
        cols = KEY[:5] + ["value_before", "value_after", "error_estimate_before", "error_estimate_after", "_merge"]
        with pd.option_context("display.width", 250, "display.max_rows", 200, "display.max_columns", 20):
            print(diff[cols].to_string(index=False))
    return 1 if len(diff) else 0


if __name__ == "__main__":
    sys.exit(main())
