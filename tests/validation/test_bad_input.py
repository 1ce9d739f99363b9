"""Bad input found before any solve, all of it at once: a free-floating mechanism, a file with
three errors, an unknown case and an unknown point."""

from __future__ import annotations

import copy

import tomli_w

import pytest

from validation.cli.main import main
from validation.case.loader import CaseError, case_by_id, find_case_files, load_case
from validation.case.mobility import rigid_body_modes
from validation.case.schema import Case

from tests.validation.test_exit_status import GOOD, write

TEST2 = case_by_id("bapat2015_test2").case.model_dump(mode="json", exclude_none=True)


def with_supports(*supports, spring: float = 0.0) -> Case:
    data = copy.deepcopy(TEST2)
    data["mechanism"]["supports"] = list(supports)
    data["mechanism"]["joints"][0]["spring"] = spring
    return Case.model_validate(data)


def test_held_mechanisms_have_no_rigid_body_mode():
    for path in find_case_files(None):
        case = load_case(path).case
        if case.mechanism is not None:
            assert rigid_body_modes(case) == [], path


def test_pinned_four_bar_without_spring_rotates_about_its_pin():
    # the four-bar clamp C replaced by a pin: a one-degree-of-freedom linkage, nothing resists it
    case = with_supports({"node": "C", "kind": "pinned"}, {"node": "O4", "kind": "pinned"})
    modes = rigid_body_modes(case)
    assert len(modes) == 1 and "rotates about node" in modes[0].motion
    # a torsional spring at the joint A holds it (its energy is not zero in that motion)
    assert (
        rigid_body_modes(with_supports({"node": "C", "kind": "pinned"}, {"node": "O4", "kind": "pinned"}, spring=5.0))
        == []
    )


def test_free_floating_mechanism_is_one_line_naming_case_body_and_constraint(tmp_path):
    # only the rocker's pivot is held: the compliant segment, the coupler and the rocker swing freely
    data = copy.deepcopy(TEST2)
    data["mechanism"]["supports"] = [{"node": "O4", "kind": "pinned"}]
    path = tmp_path / "free.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    with pytest.raises(CaseError) as info:
        load_case(path)
    message = str(info.value)
    assert "\n" not in message and message.startswith(str(path))
    assert "case 'bapat2015_test2'" in message and "body '" in message and "missing constraint" in message
    # held only against rotation and y at C: the whole model slides along x
    sliding = copy.deepcopy(TEST2)
    sliding["mechanism"]["supports"] = [
        {"node": "C", "kind": "guided", "direction": [1.0, 0.0]},
        {"node": "O4", "kind": "slider", "direction": [1.0, 0.0]},
    ]
    sliding["mechanism"]["joints"] = []  # weld the joints: one rigid assembly
    modes = rigid_body_modes(Case.model_validate(sliding))
    assert len(modes) == 1 and modes[0].motion in ("translates along (1, 0)", "translates along (-1, 0)")


def test_three_errors_all_listed_first_first(tmp_path):
    text = (
        GOOD.replace("thickness = 0.0625", "thickness = -0.0625")  # 1: negative thickness
        .replace("E = 30e6", "E = 30e6\nlenght = 3.0")  # 2: misspelled field
        .replace('quantity = "y"\n\n[methods', 'quantity = "yy"\n\n[methods')
    )  # 3: unknown quantity
    path = write(tmp_path, "three.toml", text)
    with pytest.raises(CaseError) as info:
        load_case(path)
    lines = str(info.value).splitlines()
    assert len(lines) == 3 and all(line.startswith(f"{path}: ") for line in lines)
    joined = "\n".join(lines)
    assert "segment.section.thickness: Input should be greater than 0" in joined
    assert "segment.lenght: unknown field; did you mean 'length'?" in joined
    assert (
        "outputs.0.quantity: Value error, unknown quantity 'yy'; nearest: y" in joined
        or "outputs.0.quantity: unknown quantity 'yy'; nearest: y" in joined
    )
    assert "(and" not in joined


def test_unknown_case_lists_nearest_ids(tmp_path, capsys):
    assert main(["run", "cantilever_tip_lod", "--quiet", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "no case file matches" in err and "nearest: cantilever_tip_load" in err
    out = capsys.readouterr().out
    assert "-1" not in out
    with pytest.raises(CaseError, match="nearest: cantilever_tip_load"):
        case_by_id("cantilever_tip_lod")


def test_unknown_point_lists_nearest_points(tmp_path):
    data = copy.deepcopy(TEST2)
    data["outputs"][0]["point"] = "PP"
    data["loads"][0]["point"] = "a"
    with pytest.raises(Exception) as info:
        Case.model_validate(data)
    message = str(info.value)
    assert "unknown point 'PP'; nearest: P" in message
    assert "unknown point 'a'; valid: A, B, C, O4, P, input" in message


PARALLEL_GUIDED = """
[case]
id = "parallel_guided"
title = "two clamped parallel beams carrying a rigid stage"
group = "tests"
units = "SI"

[mechanism]
E = 2.0e11
nodes = [{ name = "G1", x = 0.0, y = 0.0 }, { name = "G2", x = 0.0, y = 0.02 },
         { name = "T1", x = 0.1, y = 0.0 }, { name = "T2", x = 0.1, y = 0.02 }]
beams = [
  { name = "lower", start = "G1", end = "T1", section = { kind = "rectangle", width = 0.01, thickness = 0.001 } },
  { name = "upper", start = "G2", end = "T2", section = { kind = "rectangle", width = 0.01, thickness = 0.001 } },
]
links = [{ name = "stage", nodes = ["T1", "T2"] }]
supports = [{ node = "G1", kind = "fixed" }, { node = "G2", kind = "fixed" }]

[[loads]]
kind = "force"
point = "T1"
direction = [0.0, 1.0]
values = [0.0, 10.0, 1000.0]

[[outputs]]
quantity = "dy"
point = "T1"

[methods.bcm]
"""


def test_bcm_beyond_its_equations_is_a_run_that_did_not_converge_not_a_crash(tmp_path):
    from validation.methods.base import Request, RunStatus
    from validation.run.runner import run_method

    case = load_case(write(tmp_path, "pg.toml", PARALLEL_GUIDED)).case
    run = run_method(case, "bcm")
    assert run.status is RunStatus.NOT_CONVERGED and "no BCM equilibrium from level 2" in run.message
    # the levels before still stand: two guided beams, P L^3 / (24 EI) at small load
    EI = 2.0e11 * 0.01 * 0.001**3 / 12
    assert run.values[Request("dy", "T1", 1)] == pytest.approx(10.0 * 0.1**3 / (24 * EI), rel=0.01)
    assert run.level_converged == {0: True, 1: True, 2: False}


def beams_case(nodes, beams, supports, joints=(), links=()) -> Case:
    """A small SI mechanism of steel strips (no case file has these)."""
    section = {"kind": "rectangle", "width": 0.01, "thickness": 0.001}
    return Case.model_validate(
        {
            "case": {"id": "frame", "title": "t", "group": "tests", "units": "SI"},
            "mechanism": {
                "E": 2e11,
                "nodes": [{"name": n, "x": x, "y": y} for n, (x, y) in nodes.items()],
                "beams": [{"name": b, "start": s, "end": e, "section": section} for b, (s, e) in beams.items()],
                "links": [{"name": k, "nodes": list(v)} for k, v in dict(links).items()],
                "joints": [{"node": n, "members": list(m)} for n, m in joints],
                "supports": list(supports),
            },
            "outputs": [{"quantity": "dy", "point": list(nodes)[-1]}],
            "methods": {"fem": {}},
        }
    )


LINE = {"A": (0.0, 0.0), "B": (0.1, 0.0), "C": (0.2, 0.0)}


@pytest.mark.parametrize(
    "name, case, expected",
    [
        ("cantilever", beams_case(LINE, {"ab": ("A", "B"), "bc": ("B", "C")}, [{"node": "A", "kind": "fixed"}]), None),
        (
            "simply supported",
            beams_case(
                LINE,
                {"ab": ("A", "B"), "bc": ("B", "C")},
                [{"node": "A", "kind": "pinned"}, {"node": "C", "kind": "slider"}],
            ),
            None,
        ),
        (
            "one pin",
            beams_case(LINE, {"ab": ("A", "B"), "bc": ("B", "C")}, [{"node": "A", "kind": "pinned"}]),
            "rotates about node 'A'",
        ),
        (
            "hinge at B",
            beams_case(
                LINE,
                {"ab": ("A", "B"), "bc": ("B", "C")},
                [{"node": "A", "kind": "fixed"}],
                joints=[("B", ("ab", "bc"))],
            ),
            "body 'bc' rotates about node 'B'",
        ),
        (
            "roller only",
            beams_case(
                LINE, {"ab": ("A", "B"), "bc": ("B", "C")}, [{"node": "A", "kind": "guided", "direction": [1.0, 0.0]}]
            ),
            "translates along (1, 0)",
        ),
        (
            "three-hinge arch",
            beams_case(
                {"A": (0.0, 0.0), "B": (0.1, 0.05), "C": (0.2, 0.0)},
                {"ab": ("A", "B"), "bc": ("B", "C")},
                [{"node": "A", "kind": "pinned"}, {"node": "C", "kind": "pinned"}],
                joints=[("B", ("ab", "bc"))],
            ),
            None,
        ),
        (
            "flat three-hinge",
            beams_case(
                LINE,
                {"ab": ("A", "B"), "bc": ("B", "C")},
                [{"node": "A", "kind": "pinned"}, {"node": "C", "kind": "pinned"}],
                joints=[("B", ("ab", "bc"))],
            ),
            "rotates about",
        ),
    ],
)
def test_rigid_body_check_on_frames_no_case_file_has(name, case, expected):
    from validation.case.mobility import check

    problems = check(case)
    if expected is None:
        assert problems == [], name
    else:
        assert len(problems) == 1 and expected in problems[0][1], (name, problems)


def test_cli_prints_every_problem_as_its_own_error_line(tmp_path, capsys):
    text = GOOD.replace("thickness = 0.0625", "thickness = -0.0625").replace("E = 30e6", "E = 30e6\nlenght = 3.0")
    path = write(tmp_path, "two.toml", text)
    assert main(["list", str(path)]) == 2
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 2 and all(line.startswith(f"error: {path}: segment.") for line in lines)
