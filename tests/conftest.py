"""Shared fixtures: a private cache folder per test, so no test reads another's cached runs.

BLAS runs single-threaded in the tests: the FEM's systems are small, and on a shared 2-core machine
a threaded BLAS busy-waits for cores it does not get (a case that takes 3 s of CPU then takes 30 s).
"""
import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")

import pytest  # noqa: E402


@pytest.fixture(autouse=True)
def _private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("PRBM_VALIDATE_CACHE", str(tmp_path / "cache"))
