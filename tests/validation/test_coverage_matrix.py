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
# one worker for the module: the matrix (``cells``, module scope; every cell a run of its minimal case) is
# worked out once, not once per worker
pytestmark = pytest.mark.xdist_group("coverage_matrix")


@pytest.fixture(scope="module")
def cells() -> list[coverage.Cell]:
    return coverage.matrix()


def cell(cells, load: str, boundary: str, method: str) -> coverage.Cell:
    return next(c for c in cells if (c.load, c.boundary, c.method) == (load, boundary, method))


def readme_table() -> str:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    section = text[text.index(SECTION) :]
    section = section[: section.find("\n## ", 1)] if "\n## " in section[1:] else section
    return "\n".join(line for line in section.splitlines() if line.startswith("|"))


def test_the_readme_table_is_the_generated_matrix(cells):
    assert readme_table() == coverage.markdown(cells), (
        "README.md's table 'What each method can do' differs from the generated matrix: paste the output of "
        "'prbm-validate list --methods --markdown' into it"
    )


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
    monkeypatch.setattr(
        coverage, "_load", lambda kind, boundary: dict(kind="moment", point="tip", values=[1.0], follower=True)
    )
    found = coverage.cell("moment", "fixed-free", "fem")
    assert found.status == "invalid case" and "follower" in found.reason


def test_shorten_keeps_the_reason():
    assert (
        coverage.shorten("not applicable: loads.0: the BCM takes no force toward a fixed point")
        == "the BCM takes no force toward a fixed point"
    )
    assert coverage.shorten("error: FreeMotion: the model can move (at free_motion.py:334)") == "the model can move"
    long = coverage.shorten("not applicable: " + "word " * 40)
    assert len(long) <= 72 and long.endswith("...")


def test_list_methods_prints_the_matrix(capsys, cells, monkeypatch):
    """``list --methods --markdown`` prints the matrix; ``coverage.matrix()`` of every method is the module's
    ``cells`` (the same function, worked out once), any other selection is worked out again."""
    whole = coverage.matrix
    monkeypatch.setattr(
        coverage, "matrix", lambda methods=coverage.METHODS: cells if methods == coverage.METHODS else whole(methods)
    )
    assert main(["list", "--methods", "--markdown"]) == 0
    assert capsys.readouterr().out.strip() == coverage.markdown(cells)
    assert main(["list", "--methods", "cantilever_tip_load"]) == 2
    assert main(["list", "--markdown"]) == 2


@pytest.mark.parametrize("load", ["distributed load", "self-weight"])
@pytest.mark.parametrize(
    "boundary", ["fixed-fixed", "pinned-pinned", "parallel-guided mechanism", "circular-guided mechanism"]
)
def test_the_elastica_carries_a_load_along_the_beams_as_the_fem_does(load, boundary):
    """A distributed or self-weight load on the segments solved as a mechanism and on the mechanisms: the
    exact elastica (a uniform load along each beam, elastica.mechanism) against the FEM, whose own estimate
    bounds its discretisation error (a load left out, or read as a prescribed displacement of the loaded
    point, would miss by the whole deflection)."""
    _agree_with_the_fem(load, boundary)


def _agree_with_the_fem(load: str, boundary: str) -> None:
    """The cell's minimal case asking for what the load moves (a segment's root reactions, a mechanism's
    loaded point) and the strain energy, each clear of zero, elastica and FEM within 3 FEM estimates."""
    data = coverage.minimal_case(load, boundary, "elastica")
    data["methods"] = {"elastica": {}, "fem": {"elements": 16, "error_estimate": True}}
    point = data["loads"][0]["point"]
    if load != "force toward a point":
        data["loads"][0]["values"] = [20.0]  # a large deflection (the matrix's unit load bends little)
    if load == "self-weight" and boundary not in coverage.SEGMENTS:  # gravity across the beams (as the
        data["loads"][0]["direction"] = list(coverage.MECHANISMS[boundary].direction)  # row's force): along
        # them, 20 times the weight would buckle the parallel guide's beams
    data["outputs"] = (
        [{"quantity": q, "point": "root"} for q in ("reaction_x", "reaction_y", "reaction_moment")]
        if boundary in coverage.SEGMENTS
        else [{"quantity": q, "point": point} for q in ("dx", "dy")]
    )
    data["outputs"].append({"quantity": "strain_energy", "point": point})
    case = Case.model_validate(data)
    exact, fem = run_method(case, "elastica"), run_method(case, "fem")
    assert exact.ok and fem.ok, (exact.message, fem.message)
    moved = [req for req, value in exact.values.items() if abs(value) > 1e-3]
    assert any(req.quantity == "strain_energy" for req in moved) and len(moved) >= 2, exact.values
    for req, value in exact.values.items():
        bound = 3.0 * fem.error_estimate[req] + 1e-7
        assert abs(value - fem.values[req]) <= bound, (req, value, fem.values[req], bound)


def test_the_fem_holds_and_drives_two_points_of_one_rigid_link():
    """A prescribed displacement of the crank's end with the crank's pivot pinned: master-slave elimination
    cannot prescribe a slave node's motion, so the crank is a stiff bar, and the force the motion needs
    agrees with the exact elastica within the FEM's estimate (a bar 1e6 times stiffer than the beam adds
    ~1e-6 of the beam's strain)."""
    data = coverage.minimal_case("prescribed displacement", "circular-guided mechanism", "fem")
    data["methods"] = {"fem": {"elements": 16, "error_estimate": True}, "elastica": {}}
    case = Case.model_validate(data)
    fem, exact = run_method(case, "fem"), run_method(case, "elastica")
    assert fem.ok and exact.ok, (fem.message, exact.message)
    for req, value in exact.values.items():
        assert abs(value) > 1e-3
        assert abs(fem.values[req] - value) <= 3.0 * fem.error_estimate[req] + 1e-6 * abs(value), (req, value)


@pytest.mark.parametrize("boundary", ["fixed-fixed", "parallel-guided mechanism", "circular-guided mechanism"])
def test_the_elastica_pulls_toward_a_fixed_point_as_the_fem_does(boundary):
    """A force toward a fixed point (a rope) on a held segment and on the mechanisms: the exact elastica
    (the mechanism solver, the pull's direction at the solved position) against the FEM, whose own
    estimate bounds its discretisation error. A pull fixed along the unloaded line would miss by far more."""
    _agree_with_the_fem("force toward a point", boundary)
