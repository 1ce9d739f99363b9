"""Degrees of freedom and static mode shapes of a compliant mechanism from its PRBM (seed 000 ch. 8).

Grubler (207): F = 3(n - 1) - 2j - h, n bodies including the ground, j lower pairs, h higher pairs.
Eq (208): F_C = f_r + f_e, both by (207) on the PRBM (Prasanna et al.); the seed does not print the
rules that split F_C into f_r and f_e, so only F_C is computed: Grubler's count on the whole PRBM in
which every compliant segment is replaced by the PRBM of its static mode shape:

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
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass

__all__ = ["grubler", "Segment", "PRBMTopology", "SEGMENT_MODES"]

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


@dataclass(frozen=True)
class Segment:
    kind: str
    name: str = ""


@dataclass
class PRBMTopology:
    """Rigid bodies (including the ground), rigid-body lower pairs, higher pairs and compliant segments."""

    rigid_bodies: int
    rigid_joints: int
    segments: list[Segment]
    higher_pairs: int = 0

    def mobility(self, modes: tuple[int, ...]) -> dict[str, int]:
        """F_C, f_r, f_e for one mode per segment."""
        links = joints = 0
        for seg, mode in zip(self.segments, modes):
            l, j = SEGMENT_MODES[seg.kind][mode]
            links += l
            joints += j
        F_C = grubler(self.rigid_bodies + links, self.rigid_joints + joints, self.higher_pairs)
        return {"F_C": F_C}

    def mode_table(self, max_mode: int = 2) -> list[dict]:
        choices = [[m for m in SEGMENT_MODES[s.kind] if m <= max_mode] for s in self.segments]
        rows = []
        for modes in itertools.product(*choices):
            row = {"modes": modes, "inflections": sum(m - 1 for m in modes)}
            row.update(self.mobility(modes))
            rows.append(row)
        return rows

    def max_dof(self, max_mode: int = 2) -> int:
        """Maximum possible DOF over the admissible mode combinations (Table 9.5's PRBM column)."""
        return max(r["F_C"] for r in self.mode_table(max_mode))

    def min_dof(self, max_mode: int = 2) -> int:
        feasible = [r["F_C"] for r in self.mode_table(max_mode) if r["F_C"] >= 1]
        return min(feasible) if feasible else 0

    def expected_mode(self, max_mode: int = 2) -> dict:
        """Lowest-energy feasible mode shape: fewest inflection points with F_C >= 1 (section 8.5)."""
        feasible = [r for r in self.mode_table(max_mode) if r["F_C"] >= 1]
        if not feasible:
            raise ValueError("no mode combination up to max_mode gives F_C >= 1")
        return min(feasible, key=lambda r: (r["inflections"], r["F_C"]))
