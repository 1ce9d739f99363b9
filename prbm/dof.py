"""Degrees of freedom and static mode shapes of a compliant mechanism from its PRBM [bapat2015, ch. 8].

Grubler (207): F = 3(n - 1) - 2j - h, n bodies including the ground, j lower pairs, h higher pairs.
Eq (208): F_C = f_r + f_e, both by (207) on the PRBM (Prasanna et al.). F_C is Grubler's count on the
whole PRBM in which every compliant segment is replaced by the PRBM of its static mode shape. The dissertation
does not print the rule that splits it (refs [97, 98]); this module reads it off (207) itself: with
n_r rigid bodies (ground included), j_r rigid-body joints, and l_k links and p_k pivots for segment k,

    F_C = [3(n_r - 1) - 2 j_r - h] + sum_k (3 l_k - 2 p_k) = f_r + f_e,

f_r the rigid-body mechanism's count, f_e the flexible members' (3 - 2 = 1 for a fixed-pinned
segment, -2 for an SLFP, -1 / 0 / +1 for a fixed-guided segment in mode 1 / 2 / 3). With no
rigid-body joint there is no rigid-body mechanism and f_r = 0 ("for active compliance systems
f_r = 0", section 8.4), so then f_e = F_C. This split is our reading of (208), labelled as such.

  segment (mode)                       PRB links  PRB pivots   source
  fixed-pinned (1, only mode)              1          1        Figs 8.1, 8.3; eqs (41)-(50)
  SLFP (1, only mode)                      0          1        Figs 8.2, 8.4; eq (71)
  fixed-guided / fixed-fixed, mode 1       1          2        Figs 8.5, 8.7 (Howell, eq 63)
  fixed-guided / fixed-fixed, mode 2       2          3        Figs 8.6, 8.8 (one inflection, ch. 3/5)
  fixed-guided mode k (k-1 inflections)    k          k+1      section 8.2 (k >= 3 "abysmally small")

The maximum DOF (Table 9.5's "Maximum DOF by PRBM approach") is the largest F_C over the admissible
mode combinations (modes up to ``max_mode``, default 2); the expected mode shape under one load or
displacement BC is the lowest-energy one, i.e. the combination with the fewest inflection points
that gives F_C >= 1 (section 8.5, steps 1-4: F_C <= 0 is infeasible, raise a segment's mode).

Mode shapes ranked by energy (section 8.2: a segment's strain energy rises with its mode number,
mode k having k - 1 inflection points): combinations are ordered by their total number of inflection
points, then by the highest single mode (one segment in mode 3 stores more than two in mode 2), then
by the modes themselves. ``procedure`` runs the chapter-8 steps in that order: step 3 computes F_C,
step 4 rejects F_C <= 0 and raises a segment's mode, the first feasible combination is the first
static mode shape (the minimum DOF), and steps 5-7 list the higher feasible shapes, each F_C being
the number of load or displacement boundary conditions it needs; the maximum DOF is the largest.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import TypedDict

__all__ = ["grubler", "Segment", "PRBMTopology", "SEGMENT_MODES", "ModeShape"]

#: (PRB links, PRB pivots) per segment kind and mode
SEGMENT_MODES: dict[str, dict[int, tuple[int, int]]] = {
    "fixed-pinned": {1: (1, 1)},
    "fixed-free": {1: (1, 1)},
    "slfp": {1: (0, 1)},
    "fixed-guided": {1: (1, 2), 2: (2, 3), 3: (3, 4)},
    "fixed-fixed": {1: (1, 2), 2: (2, 3), 3: (3, 4)},
}


def grubler(n_bodies: int, lower_pairs: int, higher_pairs: int = 0) -> int:
    """Planar mobility F = 3(n - 1) - 2j - h, eq (207)."""
    return 3 * (n_bodies - 1) - 2 * lower_pairs - higher_pairs


class Mobility(TypedDict):
    """F_C, f_r, f_e of one mode combination (eq 208, split as in the module docstring)."""

    F_C: int
    f_r: int
    f_e: int


class ModeRow(Mobility):
    """One row of ``PRBMTopology.mode_table``: the modes, the inflection count and the counts."""

    modes: tuple[int, ...]
    inflections: int


class ProcedureStep(ModeRow):
    """One step of ``PRBMTopology.procedure``: a ``ModeRow`` with its energy rank and verdict."""

    rank: int
    verdict: str


@dataclass(frozen=True)
class Segment:
    kind: str
    name: str = ""


@dataclass(frozen=True)
class ModeShape:
    """One combination of segment modes: its DOF (eq 208 split), inflection count and energy rank."""

    modes: tuple[int, ...]
    F_C: int
    f_r: int
    f_e: int
    inflections: int
    rank: int = 0  # 1 = lowest energy

    @property
    def feasible(self) -> bool:
        """Step 4: F_C <= 0 is not a possible static mode shape."""
        return self.F_C >= 1


@dataclass
class PRBMTopology:
    """Rigid bodies (including the ground), rigid-body lower pairs, higher pairs and compliant segments."""

    rigid_bodies: int
    rigid_joints: int
    segments: list[Segment]
    higher_pairs: int = 0

    def mobility(self, modes: tuple[int, ...]) -> Mobility:
        """F_C, f_r, f_e for one mode per segment (eq 208, split as in the module docstring)."""
        links = joints = 0
        for seg, mode in zip(self.segments, modes):
            l, j = SEGMENT_MODES[seg.kind][mode]
            links += l
            joints += j
        F_C = grubler(self.rigid_bodies + links, self.rigid_joints + joints, self.higher_pairs)
        f_r = grubler(self.rigid_bodies, self.rigid_joints, self.higher_pairs) if self.rigid_joints else 0
        return {"F_C": F_C, "f_r": f_r, "f_e": F_C - f_r}

    def ranked_modes(self, max_mode: int = 2) -> list[ModeShape]:
        """Every mode combination up to ``max_mode``, lowest energy first (module docstring)."""
        choices = [[m for m in SEGMENT_MODES[s.kind] if m <= max_mode] for s in self.segments]
        shapes = []
        for modes in itertools.product(*choices):
            counts = self.mobility(modes)
            shapes.append(ModeShape(modes, counts["F_C"], counts["f_r"], counts["f_e"], sum(m - 1 for m in modes)))
        shapes.sort(key=lambda s: (s.inflections, max(s.modes, default=1), s.modes))
        return [ModeShape(s.modes, s.F_C, s.f_r, s.f_e, s.inflections, rank) for rank, s in enumerate(shapes, 1)]

    def procedure(self, max_mode: int = 2) -> list[ProcedureStep]:
        """Section 8.5 steps in energy order: each combination with F_C, f_r, f_e and the verdict."""
        steps: list[ProcedureStep] = []
        first: ModeShape | None = None
        for shape in self.ranked_modes(max_mode):
            if not shape.feasible:
                verdict = "F_C <= 0: infeasible (step 4), raise a segment's mode"
            elif first is None:
                first = shape
                verdict = f"first static mode shape: {shape.F_C} boundary condition(s) (minimum DOF)"
            else:
                verdict = f"higher static mode shape: {shape.F_C} boundary condition(s) (steps 5-7)"
            steps.append(
                {
                    "modes": shape.modes,
                    "rank": shape.rank,
                    "inflections": shape.inflections,
                    "F_C": shape.F_C,
                    "f_r": shape.f_r,
                    "f_e": shape.f_e,
                    "verdict": verdict,
                }
            )
        return steps

    def mode_table(self, max_mode: int = 2) -> list[ModeRow]:
        choices = [[m for m in SEGMENT_MODES[s.kind] if m <= max_mode] for s in self.segments]
        rows: list[ModeRow] = []
        for modes in itertools.product(*choices):
            rows.append({"modes": modes, "inflections": sum(m - 1 for m in modes), **self.mobility(modes)})
        return rows

    def max_dof(self, max_mode: int = 2) -> int:
        """Maximum possible DOF over the admissible mode combinations (Table 9.5's PRBM column)."""
        return max(r["F_C"] for r in self.mode_table(max_mode))

    def min_dof(self, max_mode: int = 2) -> int:
        """DOF of the first (lowest-energy) feasible static mode shape; 0 when none is feasible."""
        feasible = [s for s in self.ranked_modes(max_mode) if s.feasible]
        return feasible[0].F_C if feasible else 0

    def expected_mode(self, max_mode: int = 2) -> ModeRow:
        """Lowest-energy feasible mode shape: fewest inflection points with F_C >= 1 (section 8.5)."""
        feasible = [r for r in self.mode_table(max_mode) if r["F_C"] >= 1]
        if not feasible:
            raise ValueError("no mode combination up to max_mode gives F_C >= 1")
        return min(feasible, key=lambda r: (r["inflections"], r["F_C"]))
