"""`FemResult`: what a solve found and how, in the style of scipy's OptimizeResult.

Per recorded load level (model nodes only, by original node index/name):
positions x = X + u, accumulated rotations theta, support reactions
R = f_int - lambda f_ext at constrained DOFs (Rx, Ry, Mz), member end forces
[N, V, M] in the element chord frame (V = -(M1 + M2)/L), the strain energy
U = sum 1/2 (k_a u_bar^2 + theta_bar^T k_b theta_bar) + sum 1/2 k dtheta^2,
and the largest bending stress |E_i (N/EA +- M c_i/EI)| when the sections
know E and c.  Consistent units throughout.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

import meshio
import numpy as np

from .corotational import strain_energy
from .section import Section
from .types import FloatArray, IntArray

if TYPE_CHECKING:
    from .assembly import System
    from .discretise import Discretisation
    from .model import Model, NodeRef
    from .newton import Path as SolverPath
    from .options import CriticalPoint

__all__ = ["FemResult", "NodalFields", "FieldSeries"]


@dataclass
class FemResult:
    converged: bool
    message: str
    control: str
    steps: int
    iterations: int
    cutbacks: int
    rejected_iterations: int  # Newton iterations spent on rejected (cut) steps
    residual_history: list[FloatArray]  # |r|/F of every iteration, per accepted step
    load_factor: FloatArray  # (n_levels,)
    positions: FloatArray  # (n_levels, n_nodes, 2)
    rotations: FloatArray  # (n_levels, n_nodes)
    critical_points: list[CriticalPoint]
    wall_time: float
    node_names: list[str]
    mesh_positions: FloatArray  # (n_levels, n_element_nodes, 2)
    mesh_rotations: FloatArray  # (n_levels, n_element_nodes)
    connectivity: IntArray  # (n_elements, 2)
    det_sign: IntArray  # (n_steps,) sign of det K at accepted steps
    refine: int = 1
    n_elements: int = 0
    extra: dict[str, Any] = field(default_factory=dict)
    # CPU seconds of the load stepping alone (Newton iterations and step control), without the model's
    # set-up (mesh, DOF numbering, sparsity) and without building this result
    analysis_time: float = 0.0
    # what the derived fields below are computed from, when first read (most runs read a few positions)
    derived: _Derived | None = field(default=None, repr=False, compare=False)

    # -- derived fields, computed when first read ---------------------------
    @property
    def _states(self) -> _Derived:
        if self.derived is None:
            raise AttributeError("this result carries no recorded states (a result of `build_result` does)")
        return self.derived

    @cached_property
    def reactions(self) -> FloatArray:
        """(n_levels, n_nodes, 3): (Rx, Ry, Mz) exerted by the supports and prescriptions."""
        return self._states.reactions()

    @cached_property
    def member_end_forces(self) -> FloatArray:
        """(n_levels, n_members, 2, 3): [N, V, M] at the start and the end of every member."""
        return self._states.member_end_forces()

    @cached_property
    def strain_energy(self) -> FloatArray:
        """(n_levels,): the elastic energy of the elements and the joint springs."""
        return self._states.strain_energy()

    @cached_property
    def max_bending_stress(self) -> FloatArray:
        """(n_levels,): the largest |E (N/EA +- M c/EI)| over the elements, NaN when the sections do
        not know E and c."""
        return self._states.max_bending_stress()

    # -- scipy-like conveniences -------------------------------------------
    @property
    def success(self) -> bool:
        return self.converged

    @property
    def status(self) -> str:
        """The result protocol shared by the libraries: 'ok' or 'not converged'."""
        return "ok" if self.converged else "not converged"

    @property
    def n_levels(self) -> int:
        return len(self.load_factor)

    def node_index(self, node: NodeRef) -> int:
        """Index of a model node given by name (or index)."""
        if isinstance(node, (int, np.integer)):
            return int(node)
        return self.node_names.index(str(node))

    def position(self, node: NodeRef, level: int = -1) -> FloatArray:
        """Current (x, y) of a model node at a recorded level."""
        xy: FloatArray = self.positions[level, self.node_index(node)].copy()
        return xy

    def displacement(self, node: NodeRef, level: int = -1) -> FloatArray:
        i = self.node_index(node)
        moved: FloatArray = self.positions[level, i] - self.mesh_positions_ref[i]
        return moved

    @property
    def mesh_positions_ref(self) -> FloatArray:
        """(n_element_nodes, 2): the element nodes' reference positions."""
        reference: FloatArray = self.extra["X"]
        return reference

    def rotation(self, node: NodeRef, level: int = -1) -> float:
        """Accumulated rotation (rad, counter-clockwise) of a model node."""
        return float(self.rotations[level, self.node_index(node)])

    def reaction(self, node: NodeRef, level: int = -1) -> FloatArray:
        """(Rx, Ry, Mz) exerted by the supports/prescriptions on the node."""
        force: FloatArray = self.reactions[level, self.node_index(node)].copy()
        return force

    def __repr__(self) -> str:
        return (
            f"FemResult(converged={self.converged}, message={self.message!r}, "
            f"levels={self.n_levels}, steps={self.steps}, iterations={self.iterations}, "
            f"wall_time={self.wall_time:.3g}s)"
        )

    def nodal_fields(self, level: int) -> NodalFields:
        """Fields at the element nodes of one recorded level (what a ParaView user colours by).

        The internal bending moment at an element end follows from the local end moments
        (a pure bend of curvature kappa gives M1 = -EI kappa, M2 = +EI kappa): -M1 at the start
        node, +M2 at the end node, so M = EI kappa with kappa = d(theta)/ds; the axial force is
        N = k_a u_bar (tension positive).  A node shared by elements takes their mean."""
        disc: Discretisation = self.extra["disc"]
        N = self.extra["element_axial_force"][level]
        M = self.extra["element_end_moments"][level]
        conn = self.connectivity
        n = len(self.mesh_positions[level])
        EI = np.array([sec.EI for sec in disc.el_section])
        count = np.bincount(conn.ravel(), minlength=n).astype(float)
        count[count == 0] = np.nan

        def at_nodes(start: FloatArray, end: FloatArray) -> FloatArray:
            summed: FloatArray = (np.bincount(conn[:, 0], start, n) + np.bincount(conn[:, 1], end, n)) / count
            return summed

        moment = at_nodes(-M[:, 0], M[:, 1])
        stress: FloatArray | None = None
        if disc.el_section and all(sec.has_stress for sec in disc.el_section):
            sigma = np.empty(len(conn))  # the larger of the two element ends
            for sec, idx in disc.section_groups:
                sigma[idx] = np.maximum(
                    sec.max_stress(N[idx], np.abs(M[idx, 0])), sec.max_stress(N[idx], np.abs(M[idx, 1]))
                )
            stress = np.full(n, 0.0)  # the largest stress of the elements meeting at a node
            np.maximum.at(stress, conn[:, 0], sigma)
            np.maximum.at(stress, conn[:, 1], sigma)
        return NodalFields(
            displacement=self.mesh_positions[level] - self.extra["X"],
            rotation=self.mesh_rotations[level].copy(),
            bending_moment=moment,
            curvature=at_nodes(-M[:, 0] / EI, M[:, 1] / EI),
            axial_force=at_nodes(N, N),
            bending_stress=stress,
        )

    def field_series(self) -> FieldSeries:
        """Every level's element-node positions and ``nodal_fields`` (all levels at once, the same
        sums in the same order as `nodal_fields`): plain data, without the solver. The point data
        are computed when first read (`FieldSeries.nodal`): most runs never draw them."""
        disc = self.extra["disc"]
        forces = _ElementForces(
            self.extra["element_axial_force"],
            self.extra["element_end_moments"],
            list(disc.el_section),
            self.mesh_positions - self.extra["X"],
            self.mesh_rotations.copy(),
        )
        return FieldSeries(
            self.extra["X"].copy(),
            self.connectivity.copy(),
            self.mesh_positions.copy(),
            np.asarray(self.load_factor, float),
            forces,
            self.rigid_links(),
        )

    def rigid_links(self) -> IntArray:
        """(k, 2) element nodes (master, slave) of every rigid link, the master the root of its chain: the
        lines a picture draws for them (a rigid body as a star from its master)."""
        disc: Discretisation = self.extra["disc"]
        return np.column_stack([disc.masters, disc.slaves]).astype(int).reshape(-1, 2)

    def to_vtu(self, prefix: str) -> list[str]:
        """Write one VTU file per level (deformed mesh, line cells, the point data of
        ``nodal_fields``), ``prefix_undeformed.vtu`` and a ParaView collection ``prefix.pvd``
        (time = level's load factor); returns the per-level VTU paths."""
        lines = np.concatenate([self.connectivity, self.rigid_links()])  # elements, then rigid links

        def write(path: str, xy: FloatArray, point_data: dict[str, FloatArray]) -> None:
            meshio.write(
                path, meshio.Mesh(np.column_stack([xy, np.zeros(len(xy))]), [("line", lines)], point_data=point_data)
            )

        write(f"{prefix}_undeformed.vtu", self.extra["X"], {})
        paths = []
        for k in range(self.n_levels):
            path = f"{prefix}_{k:04d}.vtu"
            write(path, self.mesh_positions[k], self.nodal_fields(k).point_data())
            paths.append(path)
        entries = "\n".join(
            f'    <DataSet timestep="{t:.12g}" part="0" file="{Path(p).name}"/>'
            for t, p in zip(self.load_factor, paths)
        )
        Path(f"{prefix}.pvd").write_text(
            '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
            f"  <Collection>\n{entries}\n  </Collection>\n</VTKFile>\n"
        )
        return paths


@dataclass
class NodalFields:
    """Point data at the element nodes of one level, in the model's consistent units
    (rotation in radians, counter-clockwise; tension positive; bending stress None when the
    sections do not know E and the extreme-fibre distance)."""

    displacement: FloatArray  # (n, 2)
    rotation: FloatArray  # (n,)
    curvature: FloatArray  # (n,)
    bending_moment: FloatArray  # (n,)
    axial_force: FloatArray  # (n,)
    bending_stress: FloatArray | None  # (n,) largest |sigma| on the sections meeting at the node

    def point_data(self) -> dict[str, FloatArray]:
        """VTK point arrays (3-component displacement, as ParaView's Warp By Vector expects)."""
        data = {
            "displacement": np.column_stack([self.displacement, np.zeros(len(self.displacement))]),
            "rotation": self.rotation,
            "curvature": self.curvature,
            "bending_moment": self.bending_moment,
            "axial_force": self.axial_force,
        }
        if self.bending_stress is not None:
            data["bending_stress"] = self.bending_stress
        return data


@dataclass
class _ElementForces:
    """What `FieldSeries.nodal` is computed from: per level the element axial forces N (levels,
    elements) and end moments M (levels, elements, 2), every element's section, the element-node
    displacements and rotations (levels, n, 2) and (levels, n)."""

    N: FloatArray
    M: FloatArray
    sections: list[Section]
    displacement: FloatArray
    rotation: FloatArray

    def section_groups(self) -> list[tuple[Section, IntArray]]:
        """(section, element indices) of the elements that share a section (as
        `Discretisation.section_groups`)."""
        by_id: dict[int, tuple[Section, list[int]]] = {}
        for e, sec in enumerate(self.sections):
            by_id.setdefault(id(sec), (sec, []))[1].append(e)
        return [(sec, np.array(idx)) for sec, idx in by_id.values()]


@dataclass
class FieldSeries:
    """The deformed mesh and its point data at every recorded level (what a ParaView series needs)."""

    reference: FloatArray  # (n, 2) undeformed element nodes
    connectivity: IntArray  # (m, 2)
    positions: FloatArray  # (levels, n, 2)
    load_factor: FloatArray  # (levels,) the load factor (or level) of each
    forces: _ElementForces
    # (k, 2) the rigid links' (master, slave) element nodes: drawn as lines (a rigid body as a star from
    # its master node), no element of their own, so no forces (their nodes' point data come from the
    # elements meeting there, NaN at a node no element reaches)
    links: IntArray = field(default_factory=lambda: np.zeros((0, 2), int))

    @cached_property
    def nodal(self) -> list[NodalFields]:
        """`NodalFields` per level: an element node takes the mean of the element ends meeting there
        (-M1 at a start, +M2 at an end; kappa = M/EI; N), the stress the largest of theirs."""
        f, conn = self.forces, self.connectivity
        levels, n = self.positions.shape[0], self.positions.shape[1]
        count = np.bincount(conn.ravel(), minlength=n).astype(float)
        count[count == 0] = np.nan
        # node k of level l is bin l n + k: one bincount sums every level, element by element in order
        # (the order, and so the sums, of np.add.at level by level)
        offset = (np.arange(levels) * n)[:, None]
        starts, ends = (offset + conn[:, 0]).ravel(), (offset + conn[:, 1]).ravel()

        def at_nodes(start: FloatArray, end: FloatArray) -> FloatArray:
            first = np.bincount(starts, weights=np.ravel(start), minlength=levels * n).reshape(levels, n)
            second = np.bincount(ends, weights=np.ravel(end), minlength=levels * n).reshape(levels, n)
            summed: FloatArray = (first + second) / count
            return summed

        N, M = f.N, f.M
        EI = np.array([sec.EI for sec in f.sections])
        moment = at_nodes(-M[:, :, 0], M[:, :, 1])
        curvature = at_nodes(-M[:, :, 0] / EI, M[:, :, 1] / EI)
        axial = at_nodes(N, N)
        stress: list[FloatArray | None] = [None] * levels
        if f.sections and all(sec.has_stress for sec in f.sections):
            sigma = np.empty((levels, len(conn)))
            for sec, idx in f.section_groups():
                sigma[:, idx] = np.maximum(
                    sec.max_stress(N[:, idx], np.abs(M[:, idx, 0])), sec.max_stress(N[:, idx], np.abs(M[:, idx, 1]))
                )
            top = np.zeros((levels, n))
            # (numpy's annotations of ufunc.at leave out an index tuple with a slice, which it takes)
            np.maximum.at(top, (slice(None), conn[:, 0]), sigma)  # type: ignore[arg-type]
            np.maximum.at(top, (slice(None), conn[:, 1]), sigma)  # type: ignore[arg-type]
            stress = list(top)
        return [
            NodalFields(
                displacement=f.displacement[k],
                rotation=f.rotation[k].copy(),
                bending_moment=moment[k],
                curvature=curvature[k],
                axial_force=axial[k],
                bending_stress=stress[k],
            )
            for k in range(levels)
        ]


def _transfer_slave_forces(d: Discretisation, R: FloatArray, u: FloatArray) -> FloatArray:
    """Move the unbalanced forces of rigid-link slaves to their masters (statics)."""
    if not len(d.slaves):
        return R
    R = R.copy()
    for s, m in zip(d.slaves, d.masters):
        dx = d.X[s, 0] + u[2 * s] - d.X[m, 0] - u[2 * m]
        dy = d.X[s, 1] + u[2 * s + 1] - d.X[m, 1] - u[2 * m + 1]
        R[2 * m] += R[2 * s]
        R[2 * m + 1] += R[2 * s + 1]
        R[d.rot_dof[m]] += R[d.rot_dof[s]] + dx * R[2 * s + 1] - dy * R[2 * s]
        R[[2 * s, 2 * s + 1, d.rot_dof[s]]] = 0.0
    return R


@dataclass
class _Derived:
    """The recorded states a result's derived fields (reactions, member end forces, energy, stress)
    are computed from, when first read."""

    disc: Discretisation
    snapshots: list[dict[str, Any]]  # `newton.snapshot` of every recorded level
    N: FloatArray  # (levels, elements) axial forces
    M: FloatArray  # (levels, elements, 2) end moments

    def reactions(self) -> FloatArray:
        d, snaps = self.disc, self.snapshots
        nm, nl = d.n_model_nodes, len(snaps)
        mask = np.zeros(d.n_full + 1)
        mask[: d.n_full] = d.constrained
        R = np.array([_transfer_slave_forces(d, s["R_full"], s["u"]) for s in snaps]).reshape(nl, d.n_full + 1)
        R *= mask
        reac = np.empty((nl, nm, 3))
        reac[:, :, :2] = R[:, : 2 * nm].reshape(nl, nm, 2)
        reac[:, :, 2] = R[:, d.rot_dof[:nm]]
        return reac

    def member_end_forces(self) -> FloatArray:
        d, snaps = self.disc, self.snapshots
        L = np.array([s["L"] for s in snaps]).reshape(len(snaps), len(d.conn))
        return _member_end_forces(d, self.N, self.M, L)

    def strain_energy(self) -> FloatArray:
        d, snaps = self.disc, self.snapshots
        energy = np.zeros(len(snaps))
        for k, s in enumerate(snaps):
            energy[k] = strain_energy(d.ka, d.kb, s["u_bar"], s["theta_bar"]).sum()
            if len(d.springs):
                dth = s["u"][d.springs[:, 0]] - s["u"][d.springs[:, 1]]
                energy[k] += 0.5 * np.sum(d.spring_k * dth**2)
        return energy

    def max_bending_stress(self) -> FloatArray:
        d, nl = self.disc, len(self.snapshots)
        stress = np.full(nl, np.nan)
        if nl and d.el_section and all(sec.has_stress for sec in d.el_section):
            Mabs = np.abs(self.M).max(axis=2)
            stress = np.max(
                [np.max(sec.max_stress(self.N[:, idx], Mabs[:, idx]), axis=1) for sec, idx in d.section_groups], axis=0
            )
        return stress


def build_result(
    model: Model,
    sys: System,
    path: SolverPath,
    *,
    converged: bool,
    message: str,
    critical_points: list[CriticalPoint],
    wall_time: float,
    control: str,
    refine: int,
    analysis_time: float = 0.0,
) -> FemResult:
    """The result of a path: positions and rotations now, the derived fields (`_Derived`) when read."""
    d = sys.disc
    nm = d.n_model_nodes
    snaps = path.snapshots
    nl = len(snaps)
    n_x = len(d.X)
    U = np.array([s["u"] for s in snaps]).reshape(nl, d.n_full + 1)
    N_all = np.array([s["N"] for s in snaps]).reshape(nl, len(d.conn))
    M_all = np.array([s["M"] for s in snaps]).reshape(nl, len(d.conn), 2)
    pos = d.X + U[:, : 2 * n_x].reshape(nl, n_x, 2)
    node_rot_dof = np.where(d.node_rotation_used, d.rot_dof[:nm], d.node_first_end_rot)
    rot_dofs_all = d.rot_dof.copy()
    rot_dofs_all[:nm] = node_rot_dof
    rot = U[:, rot_dofs_all]
    lam = np.array([s["lam"] if control != "load" else s["level"] for s in snaps], dtype=float)
    return FemResult(
        converged=converged,
        message=message,
        control=control,
        steps=len(path.iterations),
        iterations=int(sum(path.iterations)),
        cutbacks=path.cutbacks,
        rejected_iterations=path.rejected_iterations,
        residual_history=path.residuals,
        load_factor=lam,
        positions=pos[:, :nm],
        rotations=rot[:, :nm],
        critical_points=critical_points,
        wall_time=wall_time,
        node_names=list(model.node_names),
        mesh_positions=pos,
        mesh_rotations=rot,
        connectivity=d.conn.copy(),
        det_sign=np.array(path.det_signs),
        refine=refine,
        n_elements=len(d.conn),
        extra=dict(
            X=d.X.copy(),
            disc=d,
            u_full=U,
            element_axial_force=N_all,
            element_end_moments=M_all,
            step_load_factor=np.array(path.step_lams),
            step_path_parameter=np.array(path.step_s),
            step_control=np.array(path.step_ctrl),
            element_moments=M_all.copy(),
        ),
        analysis_time=analysis_time,
        derived=_Derived(d, list(snaps), N_all, M_all),
    )


def _member_end_forces(d: Discretisation, N: FloatArray, M: FloatArray, L: FloatArray) -> FloatArray:
    """[N, V, M] at the start and the end of every member, V = -(M1 + M2)/L (levels, members, 2, 3)."""
    first = np.array([els[0] for els in d.member_elements], dtype=int)
    last = np.array([els[-1] for els in d.member_elements], dtype=int)
    V = -(M[:, :, 0] + M[:, :, 1]) / L
    mef = np.empty((len(N), len(first), 2, 3))
    for side, els in enumerate((first, last)):
        mef[:, :, side, 0] = N[:, els]
        mef[:, :, side, 1] = V[:, els]
        mef[:, :, side, 2] = M[:, els, side]
    return mef
