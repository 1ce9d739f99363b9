"""Stress suite (bounded for CI): invariances, hard paths and bad input, each a real assertion."""

import pytest

from validation.stress.checks import (
    bad_input_checks,
    bistable_check,
    column_check,
    hard_path_checks,
    invariance_checks,
    prbm_edge_checks,
)


@pytest.mark.parametrize(
    "block",
    [invariance_checks, hard_path_checks, column_check, bistable_check, prbm_edge_checks, bad_input_checks],
    ids=["invariance", "hard paths", "buckled column", "bistable four-bar", "prbm edges", "bad input"],
)
def test_stress_block(block):
    checks = block()
    assert checks, "a block must try something"
    failed = [f"{c.name}: {c.detail}" for c in checks if not c.passed]
    assert not failed, "\n".join(failed)
