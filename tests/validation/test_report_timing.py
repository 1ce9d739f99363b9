"""The report's time breakdown (validation/run/timeline.py) and the shapes figure's PRB outlines.

The breakdown must add up what was timed (no timing is asserted: speed is measured by the report
run itself), and a PRB body's outline must not cross itself (a Z across the slant parallelogram's
coupler was drawn when its pins and points were joined in the order they were listed)."""

import math
import time

import numpy as np
import pandas as pd

from validation.methods.prbm_network import _outline
from validation.report import build
from validation.run import timeline
from validation.run.timeline import Timed, breakdown, command_age, csv_text, timed


def _through_the_body(polyline: np.ndarray) -> int:
    """How many segments of the polyline cut through the body: other points lie on both sides of them
    (an outline of points in convex position has none)."""
    count = 0
    for p, q in zip(polyline[:-1], polyline[1:]):
        sides = [(q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]) for r in polyline]
        count += max(sides) > 1e-9 and min(sides) < -1e-9
    return count


def test_a_body_outline_does_not_cross_itself():
    listed = np.array(
        [[-2.277, -23.013], [17.723, -23.013], [-2.464, -24.878], [17.536, -24.878], [7.536, -24.878]]
    )  # pins first, then points: a Z through the coupler as listed
    assert _through_the_body(listed) == 1
    outline = _outline(listed)
    assert _through_the_body(outline) == 0
    assert len(outline) == len(listed) + 1 and (outline[0] == outline[-1]).all()  # closed
    assert {tuple(p) for p in outline} == {tuple(p) for p in listed}  # every point kept
    line = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 0.0]])  # collinear: along the line
    assert _outline(line)[:, 0].tolist() == [0.0, 1.0, 2.0]


def test_the_breakdown_adds_up_what_was_timed():
    records = [
        Timed("compile", "fem", 10.0, 9.5, 0.0, 1),
        Timed("compile", "elastica", 30.0, 29.0, 0.0, 2),
        Timed("case", "a", 2.0, 1.9, 10.0, 1),
        Timed("method", "a:fem", 1.5, start=10.0, pid=1),
        Timed("method", "a:prbm", 0.25, start=10.0, pid=1),
        Timed("page", "a", 1.0, 0.9, 12.0, 1),
        Timed("case", "b", 4.0, 3.0, 30.0, 2),
        Timed("method", "b:prbm", 3.5, start=30.0, pid=2),
        Timed("extra", "chapter-4 domain study", 6.0, 5.0, 0.0, 3),
    ]
    text = breakdown(records, jobs=2)
    assert "numba compile (primer) elastica" in text and "numba compile (primer) fem" in text
    assert "cases (run, incl. findings' re-runs) (2)" in text and "6.0 s wall" in text  # 2 + 4 s
    prbm = next(line for line in text.splitlines() if "method prbm" in line)
    assert "3.8 s wall" in prbm  # 0.25 + 3.5
    assert "chapter-4 domain study" in text and "slowest cases: b 4.0, a 2.0" in text
    busy = 10 + 30 + 2 + 1 + 4 + 6  # pooled work only
    assert f"workers busy {busy:.1f} s of 2 x 34.0 s" in text  # 0 .. 34 s
    # the last to finish is process 2 (case b ends at 34 s): its compile 30 s + case 4 s, idle 0 s
    assert "critical path: the last worker to finish 34.0 s (compile 30.0 s + case 4.0 s, idle 0.0 s)" in text
    rows = csv_text(records).splitlines()
    # derived: the longest record first, its wall (the input 30.0 s above) written with four decimals
    assert rows[0] == "kind,name,wall,cpu,start,pid" and rows[1].startswith("compile,elastica,30.0000")


def test_timing_csv_reads_back_with_a_comma_in_a_name(tmp_path):
    """The main process's step 'tables (results.csv, summary.csv)' has a comma: the CSV quotes it, so the
    next report reads its cases' costs back (an unquoted one made every later read fail)."""
    records = [
        Timed("main", "tables (results.csv, summary.csv)", 4.0, 3.0, 0.0, 1),
        Timed("case", "a", 2.0, 1.9, 10.0, 1),
        Timed("page", "a", 0.5, 0.4, 12.0, 1),
    ]
    (tmp_path / "timing.csv").write_text(csv_text(records))
    back = pd.read_csv(tmp_path / "timing.csv")
    assert back["name"].tolist()[0] == "tables (results.csv, summary.csv)"
    assert build._last_costs(tmp_path) == {"a": 2.5}  # the case's run and its page


def test_timed_records_wall_and_cpu_of_its_block():
    into = []
    with timed("main", "work", into) as watch:
        sum(i * i for i in range(200000))
    assert into == [watch.record] and watch.record.kind == "main"
    assert watch.record.wall > 0 and watch.record.cpu > 0 and watch.record.end >= watch.record.start


def test_command_age_counts_from_the_commands_first_line(monkeypatch, capsys):
    """The report states the whole command's time, its imports included (what the person who typed it
    waited): ``prbm-validate`` marks its clock at its first line, before its imports."""
    from validation.cli import main as cli

    monkeypatch.setattr(timeline, "_command_start", math.nan)
    assert math.isnan(command_age())  # the library called from Python: no command to count
    began = time.perf_counter()
    timeline.mark_command_start(began - 2.0)  # a command that began 2 s ago
    assert 2.0 <= command_age() <= 2.0 + (time.perf_counter() - began)
    monkeypatch.setattr(timeline, "_command_start", math.nan)
    cli.main(["--help"])
    assert timeline._command_start == cli.STARTED  # the process's first command: the module's first line
    again = time.perf_counter()
    cli.main(["--help"])  # main() called again from Python: its own start
    capsys.readouterr()
    assert timeline._command_start >= again


def test_without_a_command_the_command_time_is_left_out(tmp_path):
    records = [Timed("main", "index page", 0.5, 0.5, 0.0, 1)]
    started = time.perf_counter()
    assert "the command" not in build._write_timing(records, tmp_path, 2, started, 0.0, math.nan)
    text = build._write_timing(records, tmp_path, 2, started, 1.5, 2.0)
    assert "the command" in text and "2.0 s of start-up and imports before the report began" in text
