"""A model that can move without deforming is refused before any Newton iteration, by a named error
(`fem.FreeMotion`) that says which node and DOF nothing holds (issue 22, item 2: the zero pivot of the
unloaded stiffness as the last line of defence)."""
import numpy as np
import pytest

import fem


def _beam(support: str | None, joint_at_tip: bool = False) -> fem.Model:
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("mid", 0.5, 0.0)
    m.add_node("tip", 1.0, 0.0)
    sec = fem.Section.from_EI(EA=1e4, EI=1.0)
    m.add_member("root", "mid", sec, n_elements=4)
    m.add_member("mid", "tip", sec, n_elements=4)
    if support:
        m.add_support("root", support)
    m.add_force("tip", 0.0, 0.1)
    return m


def test_held_cantilever_solves():
    """The same beam clamped at the root is held: it solves (the check does not refuse it)."""
    assert fem.solve(_beam("fixed")).converged


@pytest.mark.parametrize("control", ["load", "arclength"])
def test_unsupported_beam_is_refused_naming_a_dof(control):
    """No support at all: three rigid-body motions; the error names a node and a DOF."""
    with pytest.raises(fem.FreeMotion, match=r"(root|mid|tip|interior node).*(ux|uy|rz)"):
        fem.solve(_beam(None), control=control, lambda_max=1.0)


def test_pinned_root_turns_freely():
    """A single pin leaves the rigid rotation about it: refused."""
    with pytest.raises(fem.FreeMotion, match="can move without deforming"):
        fem.solve(_beam("pinned"))


def test_free_hinge_in_the_span():
    """Clamped root, but a revolute joint without a spring at 'mid': the outer half swings freely.
    The error names the joint node."""
    m = _beam("fixed")
    m.add_joint("mid", k=0.0)
    with pytest.raises(fem.FreeMotion, match="mid|tip|interior node of member 'm1'"):
        fem.solve(m)
    m2 = _beam("fixed")
    m2.add_joint("mid", k=5.0)          # the same hinge with a spring: held
    r = fem.solve(m2)
    assert r.converged and np.isfinite(r.position("tip")).all()
