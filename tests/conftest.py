"""Shared fixtures: a private cache folder per test, so no test reads another's cached runs."""
import pytest


@pytest.fixture(autouse=True)
def _private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("PRBM_VALIDATE_CACHE", str(tmp_path / "cache"))
