"""Shared fixtures: a private cache folder per test, so no test reads another's cached runs.

BLAS runs single-threaded in the tests: the FEM's systems are small, and on a shared 2-core machine
a threaded BLAS busy-waits for cores it does not get (a case that takes 3 s of CPU then takes 30 s).

``--dist loadgroup`` (pyproject addopts) sends the tests marked ``xdist_group(name)`` to one worker,
so a result shared by several tests (a module- or session-scoped fixture, an ``lru_cache``) is
computed once.  pytest-xdist marks a grouped test by appending ``@name`` to its node id on the
workers (``item._nodeid``); pytest 9 keeps the node id in ``item._id`` instead, so that assignment is
lost and every group is silently spread over both workers.  ``pytest_collection_modifyitems`` below
appends the suffix where pytest 9 reads it (and does nothing where xdist's own suffix took).
"""
import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")

import pytest  # noqa: E402

pytest_plugins = ["pytester"]  # test_library_use runs the case-file plugin on a user's folder in process

try:  # pytest >= 9: the structured node id
    from _pytest.nodeid import NodeId
except ImportError:  # older pytest: xdist's own suffix works
    NodeId = None


def group_suffix(item) -> str:
    """'@name' for a test marked xdist_group(name) (names joined as xdist joins them), else ''."""
    names = {str(m.args[0] if m.args else m.kwargs.get("name", "default")) for m in item.iter_markers("xdist_group")}
    return "@" + "_".join(sorted(names)) if names else ""


def pytest_collection_modifyitems(config, items):
    if NodeId is None or not getattr(config.option, "loadgroup", False):
        return
    for item in items:
        suffix = group_suffix(item)
        if suffix and not item.nodeid.endswith(suffix):
            item._id = NodeId.parse(item.nodeid + suffix)


@pytest.fixture(autouse=True)
def _private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("PRBM_VALIDATE_CACHE", str(tmp_path / "cache"))
