"""Everything numba compiles (``cache=True``) for the FEM Newton corrector, in one module: the
corotational element loop, the scatter of element entries into solver storage, and the
load-control Newton corrector compiled whole.

One module on purpose: numba's cache is keyed on the source file of each compiled function only,
so a cached function calling a compiled function of another file keeps running the old machine
code after that file is edited (numba's "Notes on caching"). `tests/project/test_compiled_cache.py`
checks that no cached function calls into another module.

The mathematics is that of `corotational` (Crisfield 1991 ch. 7; Battini 2002 ch. 2), written
element by element so that one call does what took some thirty NumPy calls:

    chord       d = X2 + u_2 - X1 - u_1,  L = |d|,  c = d_x/L,  s = d_y/L
    chord angle beta = beta_prev + wrap(atan2(d_y, d_x) - beta_prev)
    local       u_bar = (L^2 - L0^2)/(L + L0),  theta_i = wrap(theta_i + beta0 - beta)
    forces      N = k_a u_bar,  [M1, M2] = k_b [theta_1, theta_2],  V = (M1 + M2)/L
                f = [-(cN + sV), -(sN - cV), M1, cN + sV, sN - cV, M2]
    tangent     K = E^T C E,  E = [r; z; e3; e6],  r = [-c, -s, 0, c, s, 0],  z = [s, -c, 0, -s, c, 0]
                C = [[k_a, V/L, 0, 0], [V/L, (k11+k12+k21+k22)/L^2 + N/L, -(k11+k21)/L, -(k12+k22)/L],
                     [0, -(k11+k12)/L, k11, k12], [0, -(k21+k22)/L, k21, k22]]

The numbers are those of the NumPy expressions to rounding; the first call compiles (a few
seconds) and writes the machine code to numba's cache beside this module, so later processes load it.

The load-control Newton corrector of `newton` compiled whole (`newton_load`), for the
common system: dead loads only (no followers, no forces toward points, no distributed loads), a
dense or banded tangent; with or without rigid links (their slaves placed by the master's rotation,
the constraint coefficients turned with it and the slaves' geometric tangent term, as
`assembly.System` has them).

One call runs every iteration of

    r(q) = J^T (f_int(q) - lambda f_ext),   K(q) dq = -r,   q <- q + dq

with the same steps, in the same order, as the NumPy corrector: the element loop above,
the scatter of the element forces and tangents into the full vector and into the solver's
storage (here column-major, as LAPACK reads it), the factorisation and back-substitution (a dense
tangent: LAPACK ``dgetrf``/``dgetrs``, scipy's own, called through ``scipy.linalg.cython_lapack``; a
banded one: `band_lu`/`band_solve`, LAPACK's ``dgbtf2``/``dgbtrs`` compiled here, the same operations
in the same order: bit for bit scipy's factors and solutions at the narrow bands RCM gives most
models (half-bandwidth 4 and 6 checked); at wider ones (8 and up) scipy's BLAS (OpenBLAS) updates
the columns with vector kernels and the two differ in the last bits), the rotation-limited correction, and the convergence tests
(residual, energy, negligible correction) and rotation-increment cut of `newton`. Norms and dot
products are BLAS ``ddot`` as in NumPy, so the numbers are those of the NumPy corrector (to rounding
where the band is wider).

It returns an `Outcome` (a status code and what goes with it); `newton` turns it into the same
`NewtonOutcome` or `StepFailed`.

At the converged state it also does what the Python side did after it: the det-K sign confirmed on
the converged tangent when the iterate's factors said it is not positive, and the inertia test of the
stability check (a Cholesky of the shifted, Jacobi-scaled tangent in band storage), so that neither
leaves compiled code nor turns the tangent row-major.

What the first run compiles is kept small (``validation.bench.compile_cost`` measures it), and the
code is written for it:

- the functions only compiled code calls (``_assemble``, ``_band_lu``, ``_band_solve``,
  ``_cholesky_fails``, ``_tangent``) have no Python-callable wrapper (``no_cpython_wrapper``): the
  wrapper of a function taking the groups is about as large as its body. The tests call thin
  functions around them (`_evaluate`, `band_lu`, `band_solve`, `_shifted_cholesky_fails`), compiled
  only when a test calls them. No function has a C-callable one (``no_cfunc_wrapper``), and none goes
  through numba's rewrite passes (``no_rewrites``: whole-array expressions and raises with constant
  arguments, which the loops here do not use; a constant index compiles to the same machine code);
- the functions that allocate nothing are compiled without reference counting (``_nrt=False``): for
  a function of the groups, the increments and decrements numba writes for every array in a group at
  every use of it are most of its code. `newton_load` allocates the arrays the others work in, and
  leaves its loop in one place and returns in one: numba releases every array it holds at each;
- no function is inlined by numba (``inline="always"`` copies the callee into its caller and compiles
  it again there); `_tangent` is left to LLVM's inliner (``forceinline``);
- every NumPy function (and ``min``, ``max``) a compiled function calls is compiled anew for each
  set of argument types and of the caller's options: the allocating functions share their options
  and call ``np.empty`` only, with a few argument types (zeroed by loops, ``min``/``max`` written
  out); LAPACK's arguments by reference are addresses of array entries (`_address`), not slices.

The compiled functions take their arrays in a few named groups (named tuples, each field read by its
name): `Beams` (the elements' geometry and section), `DofMap` (the constraint map and element DOFs),
`Couplings` (rigid links and springs), `Storage` (where the tangent's entries go, with the `Band`
shape of the storage), `Load`, `Start` (the state a step starts from), `Controls` (tolerances and
limits), `Work` and `ElementState` (the arrays written). `assembly.System` builds the groups of a
system, `newton` those of a solve, each by keyword.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Callable, NamedTuple, Protocol, cast

import llvmlite.binding as llvm
import numpy as np
from numpy.typing import NDArray
from numba import njit, types
from numba.core import cgutils
from numba.extending import get_cython_function_address, intrinsic

from .types import BoolArray, FloatArray, Int32Array, IntArray

if TYPE_CHECKING:
    from .linear_solver import MatrixLayout

__all__ = [
    "element_kernel",
    "scatter",
    "scatter_add",
    "CompiledLayout",
    "newton_load",
    "Beams",
    "DofMap",
    "Couplings",
    "Band",
    "Storage",
    "Load",
    "Start",
    "Controls",
    "Work",
    "ElementState",
    "Outcome",
    "element_outputs",
    "work_arrays",
    "CONVERGED",
    "NOT_FINITE",
    "NO_CONVERGENCE",
    "SINGULAR",
    "NON_FINITE_TANGENT",
    "ROTATION_TOO_LARGE",
    "CONVERGED_JUMPED",
]


# -- the argument groups ---------------------------------------------------------------------------------
# Named tuples of arrays and scalars (numba types each field apart and reads it by name). They live in
# this module because numba's cache is keyed on this file: a group's fields are part of the compiled code.


class Beams(NamedTuple):
    """The elements' reference geometry and section stiffness, one row per element (n_el of them).

    X1, X2 : (n_el, 2) reference positions of the start and end nodes (length)
    L0     : (n_el,) reference length |X2 - X1| (length)
    beta0  : (n_el,) reference chord angle, the direction of X2 - X1 (rad)
    ka     : (n_el,) axial stiffness k_a, N = k_a u_bar (force / length)
    kb     : (n_el, 2, 2) bending stiffness k_b, [M1, M2] = k_b [theta_1, theta_2] (force length / rad)
    """

    X1: FloatArray
    X2: FloatArray
    L0: FloatArray
    beta0: FloatArray
    ka: FloatArray
    kb: FloatArray


class DofMap(NamedTuple):
    """The full DOFs u (nf = n_full + 1 entries, the last the always-zero ground entry) from the reduced
    unknowns q (n of them): `discretise`'s constraint map, at most two columns,
    u_i = C0_i q_{I0_i} + C1_i q_{I1_i}, an index n standing for no unknown (a zero term).

    I0, C0     : (nf,) first column: unknown index (int), coefficient
    I1, C1     : (nf,) second column, rigid links only ((0,) without them); C1 the reference
                 coefficients (a slave's rows turn with its master's rotation: `Work.C1w`)
    edofs      : (n_el, 6) each element's full DOFs [ux1, uy1, rz1, ux2, uy2, rz2] (int)
    prescribed : (n_p,) full DOFs with prescribed values (int; the values: `Load.presc`)
    ground     : the ground entry's index (= n_full)
    rotation   : (n,) bool, q_k is a rotation (rad), else a displacement (length)
    """

    I0: IntArray
    C0: FloatArray
    I1: IntArray
    C1: FloatArray
    edofs: IntArray
    prescribed: IntArray
    ground: int
    rotation: BoolArray


class Couplings(NamedTuple):
    """Rigid links (n_s) and torsional springs (n_sp) between full DOFs; no rows: none.

    links    : (n_s, 4) per link: slave node, (root) master node, their rotation DOFs (int)
    links_X  : (n_s, 4) reference positions of slave and master, (x_s, y_s, x_m, y_m) (length)
    springs  : (n_sp, 2) full DOFs (theta_a, theta_b) of each spring, theta_b possibly the ground (int)
    spring_k : (n_sp,) stiffness k, moment M = k (theta_a - theta_b) (force length / rad)
    """

    links: IntArray
    links_X: FloatArray
    springs: IntArray
    spring_k: FloatArray


class Band(NamedTuple):
    """The shape of the reduced tangent's column-major storage (n unknowns): LAPACK's general band,
    A[i, j] at j ld + kl + ku + i - j (``banded``), or a dense matrix, A[i, j] at j ld + i.

    banded : the band storage (else dense)
    kl, ku : sub- and superdiagonals of the band (0 when dense)
    ld     : leading dimension, 2 kl + ku + 1 (band) or n (dense)
    """

    banded: bool
    kl: int
    ku: int
    ld: int


class Storage(NamedTuple):
    """Where the full tangent's entries go in the reduced tangent's storage (m reduced entries fed by
    full entries: the element tangents, 36 each, row-major, then 4 per spring, then one per rigid link,
    the slave's geometric term on its master's rotation).

    band               : `Band`, the storage's shape
    flat               : (m,) position of each reduced entry in the storage (int)
    source             : (m,) the full entry feeding it (int)
    coef               : (m,) its constant factor C_a C_b (without rigid links)
    pair               : (m,) with rigid links, the constraint columns w1, w2 of its row and column as
                         2 w1 + w2 ((0,) without them; int)
    rows_full, cols_full : (number of full entries,) full row and column of each full entry (int)
    """

    band: Band
    flat: IntArray
    source: IntArray
    coef: FloatArray
    pair: IntArray
    rows_full: IntArray
    cols_full: IntArray


class Load(NamedTuple):
    """The load of one Newton solve: lambda f_ref with dead loads only.

    lam     : load factor lambda
    F_fixed : (nf,) dead forces and moments, full vector (force, force length)
    presc   : (n_p,) values of the prescribed DOFs `DofMap.prescribed` (length or rad)
    """

    lam: float
    F_fixed: FloatArray
    presc: FloatArray


class Start(NamedTuple):
    """The converged state a step starts from.

    q    : (n,) its reduced unknowns (the step's rotation increment is measured from them)
    beta : (n_el,) its chord angles (rad): each element's new chord angle continues from it
    """

    q: FloatArray
    beta: FloatArray


class Controls(NamedTuple):
    """The corrector's tolerances and limits (`options.SolveOptions`, `assembly.System`).

    rtol, atol   : converged when |r| <= rtol F_scale + floor + atol (atol, floor: force)
    floor        : the residual's rounding floor, ~ eps EA (force)
    L_ref        : reference length of the energy criterion and of a negligible correction (length)
    maxiter      : iterations before NO_CONVERGENCE
    damp         : largest rotation of one correction (rad; 0: no limit)
    max_rot_inc  : largest rotation increment of a step (rad)
    confirm_sign : confirm a det K sign that is not positive on the converged tangent
    inertia_tol  : threshold of the inertia test at a converged state (NaN: no test)
    """

    rtol: float
    atol: float
    floor: float
    L_ref: float
    maxiter: int
    damp: float
    max_rot_inc: float
    confirm_sign: bool
    inertia_tol: float


class ElementState(NamedTuple):
    """Every element's forces, tangent and local state (n_el rows), written by `element_kernel`.

    f         : (n_el, 6) internal forces in the element DOFs (force, force length)
    K         : (n_el, 6, 6) tangent ((0, 6, 6) when not asked for)
    N         : (n_el,) axial force (force)
    M         : (n_el, 2) end moments M1, M2 (force length)
    L         : (n_el,) deformed chord length (length)
    beta      : (n_el,) chord angle (rad)
    theta_bar : (n_el, 2) end rotations relative to the chord (rad)
    u_bar     : (n_el,) elongation L - L0 (length)
    jumped    : (n_el,) bool, an end rotation is about 2 pi off the chord
    """

    f: FloatArray
    K: FloatArray
    N: FloatArray
    M: FloatArray
    L: FloatArray
    beta: FloatArray
    theta_bar: FloatArray
    u_bar: FloatArray
    jumped: BoolArray


class Work(NamedTuple):
    """The corrector's arrays at the current iterate (written in place; the last evaluation's on return).

    K       : (size,) the reduced tangent in the column-major storage of `Storage.band`
    u       : (nf,) full displacements (length, rad)
    f_int   : (nf,) internal forces
    f_ref   : (nf,) reference load, zero at the ground entry
    R       : (nf,) full residual f_int - lambda f_ref
    r       : (n,) reduced residual J^T R
    fr      : (n,) reduced reference load J^T f_ref
    C1w     : (nf,) current second constraint coefficients, turned with the masters ((0,) without links)
    spring  : (nf,) the springs' moments (scratch)
    hist    : (maxiter + 1,) |r| / F_scale of each iteration
    """

    K: FloatArray
    u: FloatArray
    f_int: FloatArray
    f_ref: FloatArray
    R: FloatArray
    r: FloatArray
    fr: FloatArray
    C1w: FloatArray
    spring: FloatArray
    hist: FloatArray


class Outcome(NamedTuple):
    """What `newton_load` returns.

    status     : CONVERGED, CONVERGED_JUMPED or the failure's code
    iterations : iterations made
    sign       : sign of det K of the last factorisation (2: none made)
    scale      : F_scale of the last evaluation (force)
    rotation   : the largest rotation increment from `Start.q` (rad): of the converged state, or of a
                 ROTATION_TOO_LARGE cut; 0 otherwise
    final      : the sign is of the converged state's own factorisation
    below      : the inertia test: 1 an eigenvalue below -inertia_tol, 0 none, -1 not made
    """

    status: int
    iterations: int
    sign: int
    scale: float
    rotation: float
    final: bool
    below: int


def element_outputs(n_el: int, tangent: bool = True) -> ElementState:
    """Empty `ElementState` arrays of ``n_el`` elements (the tangent zeroed; (0, 6, 6) without it)."""
    return ElementState(
        f=np.empty((n_el, 6)),
        K=np.zeros((n_el, 6, 6) if tangent else (0, 6, 6)),
        N=np.empty(n_el),
        M=np.empty((n_el, 2)),
        L=np.empty(n_el),
        beta=np.empty(n_el),
        theta_bar=np.empty((n_el, 2)),
        u_bar=np.empty(n_el),
        jumped=np.empty(n_el, dtype=bool),
    )


def work_arrays(n: int, nf: int, size: int, maxiter: int, links: bool) -> Work:
    """Empty `Work` arrays: n unknowns, nf full DOFs, a storage of ``size`` entries, maxiter + 1
    iterations, the turned constraint column with rigid ``links``."""
    return Work(
        K=np.empty(size),
        u=np.empty(nf),
        f_int=np.empty(nf),
        f_ref=np.empty(nf),
        R=np.empty(nf),
        r=np.empty(n),
        fr=np.empty(n),
        C1w=np.empty(nf if links else 0),
        spring=np.empty(nf),
        hist=np.empty(maxiter + 1),
    )


class _Chord(NamedTuple):
    """One element's deformed chord: direction cosines c, s and length L."""

    c: float
    s: float
    L: float


class _Forces(NamedTuple):
    """One element's axial force N and shear V = (M1 + M2)/L."""

    N: float
    V: float


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]  # an option numba's annotations omit
def element_kernel(beams: Beams, p: FloatArray, beta_prev: FloatArray, need_tangent: bool, out: ElementState) -> None:
    """Into ``out``: internal forces f (n,6), tangent K (n,6,6) (untouched when not needed), and the
    local state N (n,), M (n,2), L, beta, theta_bar (n,2), u_bar, jumped (n,) of all elements at the
    element displacements ``p`` (n,6), each chord angle continued from ``beta_prev`` (n,). (Outputs
    are passed in, not returned: returning arrays from numba costs more than the loop for small
    meshes.)"""
    X1, X2, L0, beta0, ka, kb = beams.X1, beams.X2, beams.L0, beams.beta0, beams.ka, beams.kb
    f, K, N, M, L, beta = out.f, out.K, out.N, out.M, out.L, out.beta
    theta_bar, u_bar, jumped = out.theta_bar, out.u_bar, out.jumped
    n = L0.shape[0]
    for e in range(n):
        dx = X2[e, 0] - X1[e, 0] + p[e, 3] - p[e, 0]
        dy = X2[e, 1] - X1[e, 1] + p[e, 4] - p[e, 1]
        Le = math.hypot(dx, dy)
        c, s = dx / Le, dy / Le
        turn = math.atan2(dy, dx) - beta_prev[e]
        b = beta_prev[e] + math.atan2(math.sin(turn), math.cos(turn))  # angles wrapped into (-pi, pi]
        ub = (Le * Le - L0[e] * L0[e]) / (Le + L0[e])
        t1_raw = p[e, 2] + (beta0[e] - b)
        t2_raw = p[e, 5] + (beta0[e] - b)
        t1 = math.atan2(math.sin(t1_raw), math.cos(t1_raw))
        t2 = math.atan2(math.sin(t2_raw), math.cos(t2_raw))
        j1, j2 = abs(t1_raw - t1), abs(t2_raw - t2)
        jumped[e] = (j2 if j2 > j1 else j1) > 1.0
        k11, k12, k21, k22 = kb[e, 0, 0], kb[e, 0, 1], kb[e, 1, 0], kb[e, 1, 1]
        Ne = ka[e] * ub
        M1 = k11 * t1 + k12 * t2
        M2 = k21 * t1 + k22 * t2
        V = (M1 + M2) / Le
        a = c * Ne + s * V
        bb = s * Ne - c * V
        f[e, 0], f[e, 1], f[e, 2], f[e, 3], f[e, 4], f[e, 5] = -a, -bb, M1, a, bb, M2
        N[e], M[e, 0], M[e, 1], L[e], beta[e] = Ne, M1, M2, Le, b
        theta_bar[e, 0], theta_bar[e, 1], u_bar[e] = t1, t2, ub
        if need_tangent:
            _tangent(K[e], _Chord(c=c, s=s, L=Le), _Forces(N=Ne, V=V), ka[e], kb[e])


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True, no_cpython_wrapper=True, _nrt=False, forceinline=True)  # type: ignore[call-overload]  # an option numba's annotations omit
def _tangent(Ke: FloatArray, chord: _Chord, forces: _Forces, ka: float, kb: FloatArray) -> None:
    """Ke = E^T C E (one element's 6 x 6 tangent) with E = [r; z; e3; e6], ``kb`` its (2, 2) bending
    stiffness: the products of the dense loops with the zero entries of E and C left out (adding an
    exact zero changes no bit, so the sums are those of the dense loops, term for term and in the same
    order), column by column: column j of C E, then column j of Ke."""
    c, s, L = chord.c, chord.s, chord.L
    N, V = forces.N, forces.V
    k11, k12, k21, k22 = kb[0, 0], kb[0, 1], kb[1, 0], kb[1, 1]
    r = (-c, -s, 0.0, c, s, 0.0)
    z = (s, -c, 0.0, -s, c, 0.0)
    c01 = V / L
    c11 = (k11 + k12 + k21 + k22) / (L * L) + N / L
    c12, c13 = -(k11 + k21) / L, -(k12 + k22) / L
    c21, c31 = -(k11 + k12) / L, -(k21 + k22) / L
    # column j of C E (C[0] = [ka, c01, 0, 0], C[1] = [c01, c11, c12, c13],
    # C[2] = [0, c21, k11, k12], C[3] = [0, c31, k21, k22])
    for j in range(6):
        e3 = 1.0 if j == 2 else 0.0
        e6 = 1.0 if j == 5 else 0.0
        ce0 = 0.0 + ka * r[j] + c01 * z[j] + 0.0 * e3 + 0.0 * e6
        ce1 = 0.0 + c01 * r[j] + c11 * z[j] + c12 * e3 + c13 * e6
        ce2 = 0.0 + 0.0 * r[j] + c21 * z[j] + k11 * e3 + k12 * e6
        ce3 = 0.0 + 0.0 * r[j] + c31 * z[j] + k21 * e3 + k22 * e6
        for i in range(6):
            if i == 2:
                Ke[i, j] = 0.0 + ce2
            elif i == 5:
                Ke[i, j] = 0.0 + ce3
            else:
                Ke[i, j] = 0.0 + r[i] * ce0 + z[i] * ce1


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]  # an option numba's annotations omit
def scatter_add(target: IntArray, source: IntArray, factor: FloatArray, values: FloatArray, out: FloatArray) -> None:
    """out[target[j]] += values[source[j]] * factor[j], in the order of j (the assembly of element
    entries into solver storage through precomputed index maps)."""
    for j in range(target.shape[0]):
        out[target[j]] += values[source[j]] * factor[j]


def scatter(target: IntArray, source: IntArray, factor: FloatArray, values: FloatArray, size: int) -> FloatArray:
    """A new vector of length ``size``: zeros, then `scatter_add`."""
    out = np.zeros(size)
    scatter_add(target, source, factor, values, out)
    return out


CONVERGED, NOT_FINITE, NO_CONVERGENCE, SINGULAR, NON_FINITE_TANGENT, ROTATION_TOO_LARGE = range(6)
CONVERGED_JUMPED = 6  # converged, and some element's end rotations are 2 pi off its chord (`newton.accept_check`)


def _lapack(name: str, n_args: int) -> Any:
    """scipy's LAPACK routine ``name`` as a function compiled code calls by symbol (so that numba
    can cache the machine code: the symbol is bound to the address again in every process)."""
    symbol = f"fem_lapack_{name}"
    llvm.add_symbol(symbol, get_cython_function_address("scipy.linalg.cython_lapack", name))
    return types.ExternalFunction(symbol, types.void(*[types.voidptr] * n_args))


_dgetrf = _lapack("dgetrf", 6)
_dgetrs = _lapack("dgetrs", 9)
_dpotrf = _lapack("dpotrf", 5)
_dpbtrf = _lapack("dpbtrf", 6)


class _Loaded(Protocol):
    """What `CompiledLayout.applies` reads of a system (`assembly.System`): its tangent's storage, its
    number of unknowns and its configuration-dependent loads."""

    layout: MatrixLayout
    n: int
    fol_nodes: IntArray
    pt_nodes: IntArray
    dist_follower: BoolArray


class CompiledLayout:
    """Column-major storage indices of the reduced tangent for LAPACK (dense: A[i, j] at j n + i;
    banded: the LAPACK band, ab[kl + ku + i - j, j] at j (2 kl + ku + 1) + kl + ku + i - j), and
    how to turn it back into the row-major storage of `linear_solver.MatrixLayout`.
    ``applies(system)``: the system is one the compiled corrector handles.

    ``band``: the storage's `Band`; ``flat``: the position of each reduced entry (``rows``, ``cols``);
    ``size``, ``n``: the storage's length and the number of unknowns."""

    @staticmethod
    def applies(system: _Loaded) -> bool:
        return (
            system.layout.kind in ("dense", "banded")
            and system.n > 0
            and len(system.fol_nodes) == 0
            and len(system.pt_nodes) == 0
            and len(system.dist_follower) == 0
        )

    def __init__(self, layout: MatrixLayout, rows: IntArray, cols: IntArray):
        n = layout.n
        if layout.kind == "banded":
            self.band = Band(banded=True, kl=int(layout.kl), ku=int(layout.ku), ld=int(layout.nrow))
            self.flat: IntArray = cols * layout.nrow + (layout.kl + layout.ku + rows - cols)
        else:
            self.band = Band(banded=False, kl=0, ku=0, ld=int(n))
            self.flat = cols * n + rows
        self.size, self.n = int(layout.size), int(n)

    def row_major(self, data: FloatArray) -> FloatArray:
        """The storage of `MatrixLayout` (row-major) from the column-major one."""
        return np.ascontiguousarray(data.reshape(self.n, self.band.ld).T).ravel()


def _address_of(typingctx: Any, array: Any, index: Any) -> Any:
    """The address of ``array[index]`` (a C-contiguous 1-D array) as a ``void *``: LAPACK's arguments
    by reference (what ``array[index:].ctypes`` passes, without building the slice)."""
    if not (isinstance(array, types.Array) and array.ndim == 1 and array.layout == "C"):
        return None

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        data = context.make_array(signature.args[0])(context, builder, args[0]).data
        return builder.bitcast(builder.gep(data, [args[1]]), cgutils.voidptr_t)

    return types.voidptr(array, index), codegen


# called as _address(array, index) in compiled code (numba's annotations type it by its typing function)
_address = cast("Callable[[Any, int], Any]", intrinsic(_address_of))


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True, error_model="numpy", _nrt=False)  # type: ignore[call-overload]  # an option numba's annotations omit
def band_lu(ab: FloatArray, n: int, kl: int, ku: int, ld: int, ipiv: Int32Array) -> int:
    """`_band_lu` from Python (the tests): the LU of the band ``ab`` in place, LAPACK's info returned."""
    info: int = _band_lu(ab, n, kl, ku, ld, ipiv)
    return info


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True, no_cpython_wrapper=True, error_model="numpy", _nrt=False)  # type: ignore[call-overload]  # an option numba's annotations omit
def _band_lu(ab: FloatArray, n: int, kl: int, ku: int, ld: int, ipiv: Int32Array) -> int:
    """LU with partial pivoting of the column-major LAPACK band ``ab`` in place (A[i, j] at
    j ld + kl + ku + i - j, ld >= 2 kl + ku + 1): LAPACK's ``dgbtf2`` step for step (what ``dgbtrf``
    runs when the lower bandwidth is below its block size, always so for a beam mesh), compiled here
    because scipy's ``dgbtrf`` spends most of a small band's time in its BLAS calls (``idamax``,
    ``dswap``, ``dscal``, ``dger`` per column). ``ipiv`` 1-based as LAPACK's. Returns LAPACK's info:
    0, or the 1-based column of the first exactly zero pivot."""
    kv = ku + kl
    info = 0
    for j in range(ku + 1, n if n < kv else kv):  # zero the fill-in of the first columns
        for i in range(kv - j, kl):
            ab[j * ld + i] = 0.0
    ju = 0  # last column touched by the row swaps (0-based)
    for j in range(n):
        if j + kv < n:  # fill-in of column j + kv
            for i in range(kl):
                ab[(j + kv) * ld + i] = 0.0
        km = kl if kl <= n - 1 - j else n - 1 - j  # subdiagonal entries of column j
        d = j * ld + kv  # the diagonal entry
        jp, big = 0, abs(ab[d])
        for t in range(1, km + 1):  # idamax: the first largest magnitude
            v = abs(ab[d + t])
            if v > big:
                jp, big = t, v
        ipiv[j] = jp + j + 1
        if ab[d + jp] != 0.0:
            last = j + ku + jp if j + ku + jp < n - 1 else n - 1  # last column the swap reaches
            if last > ju:
                ju = last
            if jp != 0:  # swap rows j and j + jp over columns j..ju
                for c in range(ju - j + 1):
                    a, b = d + jp + c * (ld - 1), d + c * (ld - 1)
                    ab[a], ab[b] = ab[b], ab[a]
            if km > 0:
                r = 1.0 / ab[d]
                for t in range(1, km + 1):
                    ab[d + t] *= r
                for c in range(1, ju - j + 1):  # rank-1 update of the band right of column j
                    y = ab[d + c * (ld - 1)]
                    if y != 0.0:
                        temp = -y
                        base = d + c * (ld - 1)
                        for t in range(1, km + 1):
                            ab[base + t] += ab[d + t] * temp
        elif info == 0:
            info = j + 1
    return info


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True, error_model="numpy", _nrt=False)  # type: ignore[call-overload]  # an option numba's annotations omit
def band_solve(ab: FloatArray, n: int, kl: int, ku: int, ld: int, ipiv: Int32Array, x: FloatArray) -> None:
    """`_band_solve` from Python (the tests): x <- A^-1 x with the factors of `band_lu`."""
    _band_solve(ab, n, kl, ku, ld, ipiv, x)


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True, no_cpython_wrapper=True, error_model="numpy", _nrt=False)  # type: ignore[call-overload]  # an option numba's annotations omit
def _band_solve(ab: FloatArray, n: int, kl: int, ku: int, ld: int, ipiv: Int32Array, x: FloatArray) -> None:
    """x <- A^-1 x with the factors of `band_lu`: LAPACK's ``dgbtrs`` (no transpose, one right-hand
    side) step for step: the row swaps and L by columns, then U by ``dtbsv`` (upper, by columns). A zero
    pivot divides as LAPACK does (IEEE: inf or NaN, no exception); the corrector never solves with one."""
    kv = ku + kl
    if kl > 0:
        for j in range(n - 1):
            lm = kl if kl <= n - 1 - j else n - 1 - j
            p = ipiv[j] - 1
            if p != j:
                x[p], x[j] = x[j], x[p]
            if x[j] != 0.0:
                temp = -x[j]
                d = j * ld + kv
                for t in range(1, lm + 1):
                    x[j + t] += ab[d + t] * temp
    for j in range(n - 1, -1, -1):
        if x[j] != 0.0:
            d = j * ld + kv
            x[j] = x[j] / ab[d]
            temp = x[j]
            for i in range(j - 1, (j - kv if j > kv else 0) - 1, -1):
                x[i] -= temp * ab[d - (j - i)]


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # an option numba's annotations omit
def _shifted_cholesky_fails(K: FloatArray, band: Band, n: int, held: int, tol: float) -> bool:
    """True when the Cholesky factorisation of  S A S + tol I  breaks down (a pivot not positive), A the
    symmetric n x n tangent in the corrector's column-major storage ``K`` of shape ``band``: entry
    (i, j) at j ld + r, r = kl + ku + i - j in LAPACK's general band storage (``banded``, its upper
    triangle read) or r = i (dense, read as (A + A^T)/2). S = diag(1/sqrt|A_ii|) (1 where A_ii = 0),
    the row and column of DOF ``held`` (>= 0) replaced by a unit diagonal. By Sylvester's law of inertia: some
    eigenvalue of S A S is below -tol. The shifted matrix is written in LAPACK's symmetric upper
    storage, a band of half-bandwidth ku (dpbtrf) or the full matrix (dpotrf), and factorised by
    scipy's LAPACK, as `stability.eigenvalue_below` does (no factorisation loop of its own for numba to
    compile).

    In arrays of its own: the tests compile its ``py_func``; `newton_load` runs `_cholesky_fails` in
    its own arrays."""
    size = (band.ku + 1) * n if band.banded else n * n
    fails: bool = _cholesky_fails(
        K, band, n, held, tol, np.empty(size), np.empty(n), np.empty(1, np.uint8), np.empty(4, np.int32)
    )
    return fails


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True, no_cpython_wrapper=True, _nrt=False)  # type: ignore[call-overload]  # an option numba's annotations omit
def _cholesky_fails(
    K: FloatArray,
    band: Band,
    n: int,
    held: int,
    tol: float,
    up: FloatArray,
    d: FloatArray,
    chars: NDArray[np.uint8],
    ints: Int32Array,
) -> bool:
    """`_shifted_cholesky_fails` in the arrays given: ``up`` (at least (ku + 1) n entries, banded, or
    n n, dense) for the shifted matrix, ``d`` (n) for the scaling, ``chars`` (1) and ``ints`` (4) for
    LAPACK's arguments."""
    banded, kl, ku, ldk = band.banded, band.kl, band.ku, band.ld
    w = ku if banded else n - 1
    base = kl + ku if banded else 0
    ld = w + 1 if banded else n  # entry (i, j), i <= j, at j ld + (w + i - j) (band) or j ld + i
    for k in range(ld * n):
        up[k] = 0.0
    for j in range(n):
        a = abs(K[j * ldk + (base if banded else j)])
        d[j] = math.sqrt(a) if a != 0.0 else 1.0
    for j in range(n):
        for i in range(j - w if j > w else 0, j + 1):
            if banded:
                a = K[j * ldk + base + i - j]
            else:
                a = 0.5 * (K[j * ldk + i] + K[i * ldk + j])
            a = a / (d[i] * d[j])
            if i == held or j == held:
                a = 1.0 if i == j else 0.0
            if i == j:
                a += tol
            up[j * ld + (w + i - j if banded else i)] = a
    chars[0] = 85  # 'U'
    ints[0], ints[1], ints[2], ints[3] = n, w, ld, 0
    if banded:
        _dpbtrf(
            _address(chars, 0),
            _address(ints, 0),
            _address(ints, 1),
            _address(up, 0),
            _address(ints, 2),
            _address(ints, 3),
        )
    else:
        _dpotrf(_address(chars, 0), _address(ints, 0), _address(up, 0), _address(ints, 2), _address(ints, 3))
    return bool(ints[3] > 0)


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True, no_cpython_wrapper=True, _nrt=False)  # type: ignore[call-overload]  # an option numba's annotations omit
def _dot(a: FloatArray, b: FloatArray) -> float:
    """The dot product a . b summed in index order: the same rounding on every CPU (NumPy's ``np.dot``
    is BLAS ``ddot``, whose kernel, and with it the order of the partial sums, depends on the CPU), so
    the convergence tests that read it decide alike everywhere."""
    total = 0.0
    for i in range(a.shape[0]):
        total += a[i] * b[i]
    return total


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # an option numba's annotations omit
def _evaluate(
    q: FloatArray,
    beta_prev: FloatArray,
    load: Load,
    beams: Beams,
    dofs: DofMap,
    couplings: Couplings,
    storage: Storage,
    work: Work,
    el: ElementState,
) -> float:
    """`_assemble` at q, from Python (the tests): the residual, reference load and tangent into
    ``work`` and ``el``; returns F_scale = max(|lambda f_ref|, |f_int|) as `newton_load` computes it.
    `newton_load` calls `_assemble` itself, which has no Python wrapper: the wrapper of a function
    taking these groups is about as large as its body, and only this function, compiled when a test
    first calls it, has one."""
    _assemble(q, beta_prev, load, beams, dofs, couplings, storage, work, el, np.empty((dofs.edofs.shape[0], 6)))
    f_ext = load.lam * work.f_ref
    scale_ext, scale_int = math.sqrt(_dot(f_ext, f_ext)), math.sqrt(_dot(work.f_int, work.f_int))
    return scale_int if scale_int > scale_ext else scale_ext


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True, no_cpython_wrapper=True, _nrt=False)  # type: ignore[call-overload]  # an option numba's annotations omit
def _assemble(
    q: FloatArray,
    beta_prev: FloatArray,
    load: Load,
    beams: Beams,
    dofs: DofMap,
    couplings: Couplings,
    storage: Storage,
    work: Work,
    el: ElementState,
    p: FloatArray,
) -> None:
    """Residual r, reduced reference load fr and tangent K (column-major storage) at q, each element's
    chord angle continued from ``beta_prev``, into ``work`` and ``el``; ``p`` (n_el, 6): scratch for the
    element displacements. It allocates nothing and calls no NumPy function.

    Rigid links (none: ``couplings.links`` has no rows), as `assembly.System.full_displacements` and
    ``evaluate`` treat them: the slaves placed by their master's rotation, the constraint map's second
    column (I1, C1) turned with it into ``work.C1w``; the tangent's entries weighted by the current
    coefficients of the two columns ``storage.pair`` of each reduced entry, the slaves' geometric term
    -(R_s . (x_s - x_m)) among the full entries after the springs'."""
    lam, F_fixed, presc = load.lam, load.F_fixed, load.presc
    I0, C0, I1, C1, edofs = dofs.I0, dofs.C0, dofs.I1, dofs.C1, dofs.edofs
    links, links_X, springs, spring_k = couplings.links, couplings.links_X, couplings.springs, couplings.spring_k
    flat, valid_src, coef, pair = storage.flat, storage.source, storage.coef, storage.pair
    rows_full, cols_full = storage.rows_full, storage.cols_full
    K, u, f_int, f_ref, R = work.K, work.u, work.f_int, work.f_ref, work.R
    r, fr, C1w, sp = work.r, work.fr, work.C1w, work.spring
    n, nf = q.shape[0], u.shape[0]
    wide = links.shape[0] > 0
    for i in range(nf):
        k = I0[i]
        t0 = C0[i] * q[k] if k < n else C0[i] * 0.0
        if wide:
            k1 = I1[i]
            u[i] = t0 + (C1[i] * q[k1] if k1 < n else C1[i] * 0.0)
            C1w[i] = C1[i]
        else:
            u[i] = t0
    for j in range(dofs.prescribed.shape[0]):
        u[dofs.prescribed[j]] = presc[j]
    for t in range(links.shape[0]):  # slaves: x_s = x_m + R(theta_m) (X_s - X_m), theta_s = theta_m
        s, m, rs, rm = links[t, 0], links[t, 1], links[t, 2], links[t, 3]
        th = u[rm]
        d0x, d0y = links_X[t, 0] - links_X[t, 2], links_X[t, 1] - links_X[t, 3]
        cs, sn = math.cos(th), math.sin(th)
        rd0, rd1 = cs * d0x - sn * d0y, sn * d0x + cs * d0y
        u[2 * s] = u[2 * m] + rd0 - d0x
        u[2 * s + 1] = u[2 * m + 1] + rd1 - d0y
        u[rs] = th
        C1w[2 * s] = -rd1
        C1w[2 * s + 1] = rd0
    n_el = edofs.shape[0]
    for e in range(n_el):
        for j in range(6):
            p[e, j] = u[edofs[e, j]]
    tangent = n_el >= 0  # True, typed as a run-time bool like the Python callers' (one compiled variant)
    element_kernel(beams, p, beta_prev, tangent, el)
    fe, Ke = el.f, el.K
    for i in range(nf):
        f_int[i] = 0.0
    for e in range(n_el):
        for j in range(6):
            f_int[edofs[e, j]] += fe[e, j]
    if springs.shape[0]:
        for i in range(nf):
            sp[i] = 0.0
        for s in range(springs.shape[0]):
            m = spring_k[s] * (u[springs[s, 0]] - u[springs[s, 1]])
            sp[springs[s, 0]] += m
            sp[springs[s, 1]] += -m
        for i in range(nf):
            f_int[i] += sp[i]
    for i in range(nf):
        f_ref[i] = F_fixed[i]
    f_ref[dofs.ground] = 0.0
    f_int[dofs.ground] = 0.0
    for i in range(nf):
        R[i] = f_int[i] - lam * f_ref[i]
    for k in range(n):
        r[k] = 0.0
        fr[k] = 0.0
    for i in range(nf):
        k = I0[i]
        if k < n:
            r[k] += C0[i] * R[i]
            fr[k] += C0[i] * f_ref[i]
        if wide:
            k1 = I1[i]
            if k1 < n:
                r[k1] += C1w[i] * R[i]
                fr[k1] += C1w[i] * f_ref[i]
    for j in range(K.shape[0]):
        K[j] = 0.0
    n_ke = n_el * 36
    ke = Ke.flat  # the element tangents as one flat, row-major vector
    n_sp4 = n_ke + 4 * springs.shape[0]
    for j in range(flat.shape[0]):
        src = valid_src[j]
        if src < n_ke:
            v = ke[src]
        elif src < n_sp4:
            s = (src - n_ke) // 4
            corner = (src - n_ke) % 4  # 0 and 3: the diagonal entries
            v = spring_k[s] * (1.0 if corner == 0 or corner == 3 else -1.0)
        else:  # a slave's geometric term on its master's rotation
            t = src - n_sp4
            s, m = links[t, 0], links[t, 1]
            xs = links_X[t, 0] + u[2 * s] - links_X[t, 2] - u[2 * m]
            ys = links_X[t, 1] + u[2 * s + 1] - links_X[t, 3] - u[2 * m + 1]
            v = -(R[2 * s] * xs + R[2 * s + 1] * ys)
        if wide:
            a, b = rows_full[src], cols_full[src]
            K[flat[j]] += v * (C0[a] if pair[j] < 2 else C1w[a]) * (C0[b] if pair[j] % 2 == 0 else C1w[b])
        else:
            K[flat[j]] += v * coef[j]


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # an option numba's annotations omit
def newton_load(
    q: FloatArray,
    start: Start,
    load: Load,
    beams: Beams,
    dofs: DofMap,
    couplings: Couplings,
    storage: Storage,
    controls: Controls,
    work: Work,
    el: ElementState,
) -> Outcome:
    """Every iteration of the load-control corrector from q (updated in place), the step starting at
    ``start``. Returns the `Outcome`; the evaluation at the final q is left in ``work`` and ``el``. The
    sign: 2 when nothing was factorised (a failed first iteration); a run that converges before any
    correction factorises the tangent at its state for it (0: singular or not finite there). The
    rotation increment: of a ROTATION_TOO_LARGE cut, or of the converged state from ``start.q``
    (CONVERGED, or CONVERGED_JUMPED when an element's end rotations jumped by about 2 pi).

    At a converged state (what `newton.det_sign` and `solver._even_crossing` would otherwise compute
    afterwards, here without leaving compiled code or turning the tangent row-major):
    ``controls.confirm_sign``: a sign not positive from the factors of the iterate before convergence is
    confirmed by the same factorisation of the converged tangent a run that converges before any
    correction makes; ``final`` says the sign is of the converged state itself (that factorisation).
    ``controls.inertia_tol`` (NaN: not asked): when the sign is not negative and some element is in
    compression, ``below`` is 1 when the Jacobi-scaled tangent has an eigenvalue below -inertia_tol
    (`_shifted_cholesky_fails`), else 0; -1 when not computed."""
    rtol, atol, floor, L_ref = controls.rtol, controls.atol, controls.floor, controls.L_ref
    damp, q_start, rot, band = controls.damp, start.q, dofs.rotation, storage.band
    K, r, hist = work.K, work.r, work.hist
    n = q.shape[0]
    buffer = np.empty(K.shape[0])  # the factors
    ipiv = np.empty(n if n > 1 else 1, np.int32)
    ints = np.empty(6, np.int32)  # LAPACK's integer arguments: n at 0, ld at 3, nrhs at 4, info at 5
    for k in range(6):
        ints[k] = 0
    chars = np.empty(1, np.uint8)  # LAPACK's character argument
    dq = np.empty(n)
    p = np.empty((dofs.edofs.shape[0], 6))  # the element displacements (`_assemble`'s scratch)
    f_ext = np.empty(work.f_ref.shape[0])  # lambda f_ref
    has_rot = False
    for k in range(n):
        if rot[k]:
            has_rot = True
    dq_small = False
    sign = 2
    final = False  # the sign is of the converged state's own factors
    # one return, after the loop, and three places that leave the loop: at each, numba releases every
    # array the function holds, those of the groups one by one
    failed = -1  # the failure's status code; -1: none, converged
    iterations, rotation, scale = 0, 0.0, 0.0
    for it in range(controls.maxiter + 1):
        iterations = it
        _assemble(q, start.beta, load, beams, dofs, couplings, storage, work, el, p)
        for i in range(f_ext.shape[0]):  # F_scale = max(|lambda f_ref|, |f_int|), as `_evaluate`
            f_ext[i] = load.lam * work.f_ref[i]
        scale_ext, scale_int = math.sqrt(_dot(f_ext, f_ext)), math.sqrt(_dot(work.f_int, work.f_int))
        scale = scale_int if scale_int > scale_ext else scale_ext
        rn = math.sqrt(_dot(r, r))
        tol = rtol * scale + floor + atol
        hist[it] = rn / (1e-300 if 1e-300 > scale else scale)
        converged = (rn <= tol or dq_small) and (it > 0 or rn <= rtol * scale + atol)
        if not math.isfinite(rn):
            failed = NOT_FINITE
        elif not converged and it == controls.maxiter:
            failed = NO_CONVERGENCE
        # done: failed, or converged with the last factors' sign standing (positive, or not asked to be
        # confirmed)
        if failed >= 0 or (converged and (n == 0 or sign == 1 or (sign != 2 and not controls.confirm_sign))):
            break
        # the factorisation: of the correction, or (converged) for the sign at this state itself: before
        # any correction, or to confirm a sign not positive from the iterate before
        finite = True
        for j in range(K.shape[0]):
            if not math.isfinite(K[j]):
                finite = False
                break
            buffer[j] = K[j]
        if finite:  # LU: a band by `band_lu`, a dense matrix by LAPACK dgetrf
            if band.banded:
                ints[5] = _band_lu(buffer, n, band.kl, band.ku, band.ld, ipiv)
            else:
                ints[0], ints[3] = n, band.ld
                _dgetrf(
                    _address(ints, 0),
                    _address(ints, 0),
                    _address(buffer, 0),
                    _address(ints, 3),
                    _address(ipiv, 0),
                    _address(ints, 5),
                )
        if finite and ints[5] == 0:
            sign = 1  # of det K: the signs of U's diagonal times the pivot parity; 0: a pivot zero or not finite
            for j in range(n):
                d = buffer[j * band.ld + (band.kl + band.ku if band.banded else j)]
                if d == 0.0 or not math.isfinite(d):
                    sign = 0
                    break
                if d < 0.0:
                    sign = -sign
                if ipiv[j] - 1 != j:
                    sign = -sign
            if sign == 0 and not converged:
                failed, sign = SINGULAR, 2
        elif converged:  # not finite, or an exactly zero pivot, at the converged state
            sign = 0
        else:
            failed = SINGULAR if finite else NON_FINITE_TANGENT
        if converged or failed >= 0:
            final = converged  # the sign is of the converged state itself
            break
        for k in range(n):
            dq[k] = -r[k]
        if band.banded:
            _band_solve(buffer, n, band.kl, band.ku, band.ld, ipiv, dq)
        else:
            chars[0] = 78  # 'N'
            ints[4] = 1
            _dgetrs(
                _address(chars, 0),
                _address(ints, 0),
                _address(ints, 4),
                _address(buffer, 0),
                _address(ints, 3),
                _address(ipiv, 0),
                _address(dq, 0),
                _address(ints, 0),
                _address(ints, 5),
            )
        if damp > 0.0 and has_rot:
            big = 0.0
            for k in range(n):
                if rot[k]:
                    a = abs(dq[k])
                    if a > big:
                        big = a
            if big > damp:
                for k in range(n):
                    dq[k] = dq[k] * (damp / big)
        # converged by the energy criterion, or the correction taken
        energy_small = it > 0 and abs(_dot(dq, r)) <= rtol * rtol * scale * L_ref
        if not energy_small:
            dq_small = True
            for k in range(n):
                q[k] = q[k] + dq[k]
                if abs(dq[k]) > 1e-13 * (1.0 if rot[k] else L_ref):
                    dq_small = False
            if has_rot:
                dth = 0.0
                for k in range(n):
                    if rot[k]:
                        a = abs(q[k] - q_start[k])
                        if a > dth:
                            dth = a
                limit = (2.0 if it == 0 else 4.0) * controls.max_rot_inc
                if dth > limit:
                    failed, iterations, rotation = ROTATION_TOO_LARGE, it + 1, dth
        if energy_small or failed >= 0:
            break
    below = -1
    if failed >= 0:
        status = failed
    else:  # converged: what `newton.accept_check` reads of the state
        status = CONVERGED
        for e in range(el.jumped.shape[0]):
            if el.jumped[e]:
                status = CONVERGED_JUMPED
        for k in range(n):
            if rot[k]:
                a = abs(q[k] - q_start[k])
                if a > rotation:
                    rotation = a
        inertia_tol = controls.inertia_tol
        if inertia_tol == inertia_tol and 0 <= sign <= 1 and n > 0:
            compressed = False
            for e in range(el.N.shape[0]):
                if el.N[e] < 0.0:
                    compressed = True
            if compressed:
                # in the arrays of the factors and the correction (neither is needed any more)
                below = 1 if _cholesky_fails(K, band, n, -1, inertia_tol, buffer, dq, chars, ints) else 0
    return Outcome(
        status=status, iterations=iterations, sign=sign, scale=scale, rotation=rotation, final=final, below=below
    )
