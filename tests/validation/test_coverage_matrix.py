"""The coverage matrix (``validation/run/coverage.py``): generated from the adapters, it is the README's
table "What each method can do" (so the table cannot drift from the code), and a few of its cells are
known from the methods' own documentation."""
from pathlib import Path

import pytest

from validation.run import coverage
from validation.case.schema import Case
from validation.cli.main import main
from validation.run.runner import run_method

ROOT = Path(__file__).resolve().parents[2]
SECTION = "## What each method can do"


@pytest.fixture(scope="module")
def cells() -> list[coverage.Cell]:
    return coverage.matrix()


def cell(cells, load: str, boundary: str, method: str) -> coverage.Cell:
    return next(c for c in cells if (c.load, c.boundary, c.method) == (load, boundary, method))


def readme_table() -> str:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    section = text[text.index(SECTION):]
    section = section[:section.find("\n## ", 1)] if "\n## " in section[1:] else section
    return "\n".join(line for line in section.splitlines() if line.startswith("|"))


def test_the_readme_table_is_the_generated_matrix(cells):
    assert readme_table() == coverage.markdown(cells), (
        "README.md's table 'What each method can do' differs from the generated matrix: paste the output of "
        "'prbm-validate list --methods --markdown' into it")


def test_every_load_kind_on_every_boundary_for_every_method(cells):
    assert len(cells) == len(coverage.LOAD_KINDS) * len(coverage.BOUNDARIES) * len(coverage.METHODS)
    assert {c.status for c in cells} <= {"answers", "refuses", "fails", "invalid case"}
    assert all(c.reason for c in cells if c.status != "answers")


def test_known_cells(cells):
    assert cell(cells, "force", "fixed-free", "fem").status == "answers"
    # the exact elastica solves mechanisms too (validation/methods/elastica_network.py)
    assert cell(cells, "force", "parallel-guided mechanism", "elastica").status == "answers"
    assert cell(cells, "prescribed displacement", "fixed-guided", "prbm").status == "answers"
    assert cell(cells, "distributed load", "fixed-free", "prbm").status == "answers"
    assert cell(cells, "follower force", "fixed-free", "bcm").label() == "refuses: BCM has no follower force"


def test_the_prbm_answers_a_distributed_load_by_the_chain_algorithm():
    case = Case.model_validate(coverage.minimal_case("distributed load", "fixed-free", "prbm"))
    run = run_method(case, "prbm")
    assert run.ok and run.extras["model"].startswith("Chain Algorithm")


def test_a_rejected_combination_is_a_gap_of_the_case_format(monkeypatch):
    """A load the schema refuses is 'invalid case', with the schema's reason, not a method's refusal."""
    monkeypatch.setattr(coverage, "_load", lambda kind, boundary: dict(kind="moment", point="tip", values=[1.0], follower=True))
    found = coverage.cell("moment", "fixed-free", "fem")
    assert found.status == "invalid case" and "follower" in found.reason


def test_shorten_keeps_the_reason():
    assert coverage.shorten("not applicable: loads.0: the BCM takes no force toward a fixed point") == \
        "the BCM takes no force toward a fixed point"
    assert coverage.shorten("error: FreeMotion: the model can move (at free_motion.py:334)") == "the model can move"
    long = coverage.shorten("not applicable: " + "word " * 40)
    assert len(long) <= 72 and long.endswith("...")


def test_list_methods_prints_the_matrix(capsys, cells):
    assert main(["list", "--methods", "--markdown"]) == 0
    assert capsys.readouterr().out.strip() == coverage.markdown(cells)
    assert main(["list", "--methods", "cantilever_tip_load"]) == 2
    assert main(["list", "--markdown"]) == 2


def test_the_elastica_refuses_a_load_along_a_mechanisms_beams():
    """A self-weight or distributed load on a mechanism was read as a prescribed displacement of the
    loaded point (y = 0, status ok, against the FEM's 0.99995): the elastica mechanism model has no load
    along its beams, so it refuses, naming the load."""
    for load in ("self-weight", "distributed load"):
        cell = coverage.cell(load, "parallel-guided mechanism", "elastica")
        assert cell.status == "refuses" and "along the beams of a mechanism" in cell.reason, cell


def test_the_fem_refuses_two_held_points_of_one_rigid_body():
    """A prescribed displacement of the crank's end with the crank's pivot pinned: master-slave elimination
    cannot state it (it raised 'prescribed DOF on a rigid-link slave node', a crash); now a refusal that
    names the link and both points."""
    cell = coverage.cell("prescribed displacement", "circular-guided mechanism", "fem")
    assert cell.status == "refuses" and "rigid link 'crank'" in cell.reason, cell
