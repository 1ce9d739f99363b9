"""Inputs the schema allows but an adapter had not taken: an input force per level (``ma.F_i``, a
``PositivePerLevel``), a force toward a fixed point (no ``direction``) in the FEM-elastica check, and the
SLFP sizes of a PRB four-bar (one to four in the options, four springs in the model)."""

from __future__ import annotations

import tomllib

import pytest

from validation.case.loader import CASES_DIR, load_case
from validation.case.schema import Case
from validation.methods.base import RunStatus
from validation.run.compare import axial_strain_bound
from validation.run.runner import run_method

SLIDER_CRANK = CASES_DIR / "chapter7" / "example1.toml"  # prbm_fourbar.run_slider, ma = {F_i, d_i}
FOUR_BAR_MA = CASES_DIR / "chapter7" / "example6.toml"  # prbm_fourbar.run_fourbar, ma = {F_i, d_i, d_o}
SLIDER_MA = CASES_DIR / "chapter7" / "example4a.toml"  # prbm_ma, model = 'compliance', slider Type 1
ROPE = CASES_DIR / "chapter9" / "test1c_rope.toml"  # a segment pulled toward a pulley
SLFP_FOUR_BAR = CASES_DIR / "chapter6" / "example1.toml"  # [methods.prbm] slfp = {t, l} of four pivots


def _mechanical_advantage(data: dict, F_i) -> dict[int, float]:
    data["methods"]["prbm"]["ma"]["F_i"] = F_i
    run = run_method(Case.model_validate(data), "prbm")
    assert run.status is RunStatus.OK, run.message
    values = {r.level: v for r, v in run.values.items() if r.quantity == "mechanical_advantage"}
    assert values
    return values


@pytest.mark.parametrize("path", [SLIDER_CRANK, FOUR_BAR_MA, SLIDER_MA], ids=lambda p: p.stem)
def test_an_input_force_per_level_is_taken_level_by_level(path):
    data = tomllib.loads(path.read_text())
    n = Case.model_validate(data).n_levels()
    F = data["methods"]["prbm"]["ma"]["F_i"]
    forces = [F * (1.0 + 0.5 * (level % 2)) for level in range(n)]  # two forces, alternating
    per_level = _mechanical_advantage(data, forces)
    for force in set(forces):
        alone = _mechanical_advantage(data, force)
        assert all(per_level[level] == alone[level] for level in alone if forces[level] == force)


def test_a_force_toward_a_fixed_point_bounds_the_axial_strain_by_its_magnitude():
    case = load_case(ROPE).case
    rope = case.loads[0]
    assert rope.toward is not None and rope.direction is None
    EA = case.require_segment().axial_stiffness()
    assert [axial_strain_bound(case, level) for level in range(case.n_levels())] == pytest.approx(
        [abs(v) / EA for v in rope.levels()]
    )


def test_a_four_bar_with_fewer_than_four_slfp_sizes_is_misconfigured():
    data = tomllib.loads(SLFP_FOUR_BAR.read_text())
    prbm_options = data["methods"]["prbm"]
    prbm_options.pop("springs", None)
    slfp = prbm_options["slfp"]
    slfp["t"], slfp["l"] = slfp["t"][:2], slfp["l"][:2]
    run = run_method(Case.model_validate(data), "prbm")
    assert run.status is RunStatus.MISCONFIGURED and "slfp" in run.message, run.message
