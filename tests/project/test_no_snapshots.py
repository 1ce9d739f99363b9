"""No test asserts the project's own earlier output.

Every number with four or more significant decimals in an assertion must name its source or
derivation on its line or above it in the same test (its docstring or a comment: a seed table or equation,
the notes, an exact or closed-form solution, a derivation). This test lists every assertion that
does not, and the tests known to have been snapshots, which must stay gone.
"""

from __future__ import annotations

import re
from pathlib import Path

TESTS = Path(__file__).resolve().parents[1]  # tests/, every folder under it
SOURCE = re.compile(
    r"(?i)seed|table|\beqs?\b|eq\.|notes|anchors|derived|derivation|exact|closed.form|printed|"
    r"source|bisshopp|mattiasson|howell|dadeppo|analytic|input, not output"
)
LONG_NUMBER = re.compile(r"(?<![\w.])-?\d+\.\d{4,}(?:e-?\d+)?")
# tests that asserted this project's own output and were replaced by sourced checks (issue 25)
REMOVED_SNAPSHOTS = {
    "prbm/test_prbm_tables.py": [
        "test_test2_pose_under_design_torques_is_the_documented_finding",
        "test_test1_plain_prbm_with_sum_ei_is_the_documented_forward",
    ]
}


def unsourced_assertions() -> list[str]:
    found = []
    for path in sorted(TESTS.rglob("test_*.py")):
        if path.resolve() == Path(__file__).resolve():
            continue
        lines = path.read_text().split("\n")
        for i, line in enumerate(lines):
            if ("assert" not in line and "approx" not in line) or not LONG_NUMBER.search(line):
                continue
            start = i
            while start > 0 and not lines[start].startswith("def "):
                start -= 1
            context = "\n".join(lines[start : i + 1])
            if not SOURCE.search(context):
                found.append(f"{path.relative_to(TESTS).as_posix()}:{i + 1}: {line.strip()}")
    return found


def test_every_long_number_in_an_assertion_names_its_source():
    found = unsourced_assertions()
    assert not found, "assertions with unsourced numbers (snapshots?):\n" + "\n".join(found)


def test_the_scan_finds_an_unsourced_number(tmp_path, monkeypatch):
    (tmp_path / "test_planted.py").write_text("def test_x():\n    assert f() == 1.23456\n")
    monkeypatch.setattr(f"{__name__}.TESTS", tmp_path)
    assert unsourced_assertions() == ["test_planted.py:2: assert f() == 1.23456"]


def test_removed_snapshot_tests_stay_removed():
    back = [
        f"{name}::{test}"
        for name, tests in REMOVED_SNAPSHOTS.items()
        for test in tests
        if f"def {test}(" in (TESTS / name).read_text()
    ]
    assert not back, back
