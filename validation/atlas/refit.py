"""Beyond the seeds, measured: the (gamma, K_Theta) that minimise the worst tip error over a region of
the atlas, against the published n-fits on points not used to fit.

The model, for a unit segment (L = 1, EI = 1) under a force F L^2/EI at the angle phi from the
undeformed axis, with two free parameters: the characteristic radius gamma and the stiffness
coefficient K_Theta.  The initially curved fixed-pinned PRBM [bapat2015, eqs 53-61] with the initial
curvature kappa0 = L/R_i:

    a_i = sin(kappa0)/kappa0,  b_i = (1 - cos kappa0)/kappa0                     (55)-(56)
    rho = |(a_i - (1 - gamma), b_i)|,  Theta_i = atan2(b_i, a_i - (1 - gamma))   (54), (57)
    F rho sin(phi - Theta) = rho K_Theta (Theta - Theta_i)                         (58), spring (*)
    a = 1 - gamma + rho cos Theta,  b = rho sin Theta                              (59)-(60)

(phi taken on its branch within pi of Theta_i, as ``prbm.segments._curved_level`` does).  At kappa0 = 0
it is the straight fixed-pinned PRBM [bapat2015, eqs 44-49]: rho = gamma, Theta_i = 0,
F sin(phi - Theta) = K_Theta Theta, a = 1 - gamma (1 - cos Theta), b = gamma sin Theta.  The tip
angle c_theta (Theta - Theta_i) (+ kappa0) does not enter the tip position (a, b), so c_theta is not
fitted (the objective is the tip position; c_theta only moves the tip-angle error).  ``prbm_tip``
evaluates it on arrays of points (the spring equation by ``prbm.spring_angle``), each point with its
own parameters if given arrays: the published ones are the Pauly-Midha n-fits (41), (43) at
n = -cot phi (extrapolated outside -4 < n <= 10, as the atlas does; the curved model uses the same
straight-beam fits).

Procedure, for each region (a load-angle band, and for the curved model a kappa0 band, limited to the
levels whose exact tip rotation |theta - theta_unloaded| is at most a stated value, optionally also
a load cap; bands closed, so a line on a band's edge belongs to both neighbours):

1. the solved atlas points ("ok" rows) are split in two halves, no point in both (``holdout``): by
   default a checkerboard over the grid, (line index + load-level index) even: fit, odd: held out,
   so every held-out point has its neighbours along the line and across lines in the fit half;
   ``split="lines"`` holds out every other line whole (stricter: a held-out line is seen only
   through its neighbours);
2. on the fit half, minimise the worst tip error max_i |r_PRBM(F_i; gamma, K_Theta) - r_exact,i|
   (% of L, at equal load) by Nelder-Mead on the maximum itself, started from the published values
   averaged over the fit points and restarted from its own answer until it stops improving (a
   simplex can collapse on the kinks of a maximum; a restart rebuilds it);
3. on the held-out half, the worst tip error of the published n-fits and of the refit pair; the gain
   is their ratio (> 1: the refit is better).

The refit is one constant pair per region, the published fits vary with n across the region's lines.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.optimize import minimize

from prbm.fits import PAULY_MIDHA
from prbm.segments import spring_angle

FIXED_PINNED = "fixed-pinned"
CURVED = "curved fixed-pinned"
ATLAS_MODELS = {"fixed_pinned_pauly_midha": FIXED_PINNED, "curved_fixed_pinned": CURVED}  # atlas name -> kind
LOAD_ANGLE_BANDS = ((5.0, 45.0), (45.0, 90.0), (90.0, 135.0), (135.0, 175.0))
KAPPA0_BANDS = ((0.0, 1.0), (1.0, 2.0), (2.0, 3.0))
ROTATION_LIMITS = (60.0, 90.0)


@dataclass(frozen=True)
class Region:
    """A part of a model's input space: closed load-angle and kappa0 bands, levels whose exact tip
    rotation is at most ``max_rotation_deg`` (kappa0 None: a straight segment's atlas)."""

    load_angle_deg: tuple[float, float]
    max_rotation_deg: float
    kappa0: tuple[float, float] | None = None
    max_load: float = math.inf  # F L^2/EI (the rotation limit does not bound the load on a line whose
    # tip turns toward the force by less than the limit)

    @property
    def name(self) -> str:
        lo, hi = self.load_angle_deg
        text = f"phi {lo:g}-{hi:g} deg"
        if self.kappa0 is not None:
            text = f"kappa0 {self.kappa0[0]:g}-{self.kappa0[1]:g}, " + text
        text += f", rotation <= {self.max_rotation_deg:g} deg"
        return text if math.isinf(self.max_load) else text + f", F L^2/EI <= {self.max_load:g}"

    def mask(self, df: pd.DataFrame) -> np.ndarray:
        phi = df["load_angle_deg"].to_numpy()
        inside = (phi >= self.load_angle_deg[0]) & (phi <= self.load_angle_deg[1])
        inside &= np.abs(df["exact_rotation_deg"].to_numpy()) <= self.max_rotation_deg
        inside &= df["load"].to_numpy() <= self.max_load
        if self.kappa0 is not None:
            k0 = df["kappa0"].to_numpy()
            inside &= (k0 >= self.kappa0[0]) & (k0 <= self.kappa0[1])
        return inside


@dataclass(frozen=True)
class Params:
    """The two free parameters of a refit: the characteristic radius factor and the stiffness coefficient."""

    gamma: float
    K_theta: float


@dataclass(frozen=True)
class RefitResult:
    """One region's refit; errors are worst tip errors in % of L (held out: on points not used to fit)."""

    model: str
    region: Region
    split: str  # checkerboard | lines (``holdout``)
    fitted: Params
    start: Params  # the published values averaged over the fit points
    fit_worst: float  # the refit on its own fit points
    published_worst: float  # held out, the published n-fits
    refit_worst: float  # held out, the refit pair
    fit_points: int
    test_points: int

    @property
    def gain(self) -> float:
        return self.published_worst / self.refit_worst if self.refit_worst > 0 else math.inf


def prbm_tip(load, phi, gamma, K_theta, kappa0=0.0, c_theta=1.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The PRBM tip (x, y, theta) of a unit segment (module docstring), broadcast over the arguments:
    load F L^2/EI, phi the force angle (rad), gamma, K_theta, kappa0 = L/R_i, c_theta."""
    load, phi, gamma, K_theta, kappa0 = np.broadcast_arrays(
        *(np.asarray(v, float) for v in (load, phi, gamma, K_theta, kappa0))
    )
    bent = np.abs(kappa0) > 1e-12
    k0 = np.where(bent, kappa0, 1.0)
    a_i = np.where(bent, np.sin(k0) / k0, 1.0)
    b_i = np.where(bent, (1.0 - np.cos(k0)) / k0, 0.0)
    rho = np.hypot(a_i - (1.0 - gamma), b_i)
    Theta_i = np.arctan2(b_i, a_i - (1.0 - gamma))
    d = phi - Theta_i
    Theta, _, _ = spring_angle(load * rho, Theta_i + np.arctan2(np.sin(d), np.cos(d)), rho * K_theta, Theta_i)
    return 1.0 - gamma + rho * np.cos(Theta), rho * np.sin(Theta), kappa0 + c_theta * (Theta - Theta_i)


def published(load_angle_deg) -> Params:
    """The Pauly-Midha gamma(n), K_Theta(n) at n = -cot phi (arrays), extrapolated as the atlas does."""
    phi = np.radians(np.asarray(load_angle_deg, float))
    gamma, _, K = PAULY_MIDHA.parameters(-np.cos(phi) / np.sin(phi), "allow")
    return Params(gamma, K)


def holdout(df: pd.DataFrame, split: str = "checkerboard") -> np.ndarray:
    """True for the held-out half of the atlas's grid: (line index + load-level index) odd
    (``checkerboard``), or the line index odd (``lines``).  The line is the shape inputs (the columns
    before ``load``), the level the load's rank in the common load grid."""
    shape_columns = [
        c for c in df.columns[: df.columns.get_loc("load")] if c not in ("model", "line_id") and df[c].notna().all()
    ]
    line = df.groupby(shape_columns, sort=True).ngroup().to_numpy() if shape_columns else np.zeros(len(df), int)
    if split == "lines":
        return line % 2 == 1
    if split != "checkerboard":
        raise ValueError(f"split must be 'checkerboard' or 'lines', not {split!r}")
    level = np.unique(df["load"].to_numpy(), return_inverse=True)[1]
    return (line + level) % 2 == 1


def _points(df: pd.DataFrame) -> dict[str, np.ndarray]:
    return {
        "load": df["load"].to_numpy(float),
        "phi": np.radians(df["load_angle_deg"].to_numpy(float)),
        "kappa0": df["kappa0"].to_numpy(float) if "kappa0" in df else np.zeros(len(df)),
        "x": df["exact_x"].to_numpy(float),
        "y": df["exact_y"].to_numpy(float),
        "load_angle_deg": df["load_angle_deg"].to_numpy(float),
    }


def worst_error(p: dict[str, np.ndarray], gamma, K_theta) -> float:
    """The worst tip error (% of L) of the PRBM with (gamma, K_theta) over the points ``p``."""
    if p["load"].size == 0:
        return math.nan
    x, y, _ = prbm_tip(p["load"], p["phi"], gamma, K_theta, p["kappa0"])
    return 100.0 * float(np.max(np.hypot(x - p["x"], y - p["y"])))


def minimax(p: dict[str, np.ndarray], start: Params, restarts: int = 4) -> tuple[Params, float]:
    """(gamma, K_theta) minimising ``worst_error`` on the points (module docstring, step 2)."""

    def objective(v: np.ndarray) -> float:
        return worst_error(p, v[0], v[1]) if v[0] > 0.0 and v[1] > 0.0 else math.inf

    best, value = np.array([start.gamma, start.K_theta]), objective(np.array([start.gamma, start.K_theta]))
    for _ in range(restarts):
        res = minimize(objective, best, method="Nelder-Mead", options={"xatol": 1e-8, "fatol": 1e-10, "maxiter": 4000})
        improved = res.fun < value - 1e-9
        if res.fun < value:
            best, value = res.x, float(res.fun)
        if not improved:
            break
    return Params(float(best[0]), float(best[1])), value


def refit_region(df: pd.DataFrame, region: Region, model: str, split: str = "checkerboard") -> RefitResult | None:
    """Steps 1-3 of the module docstring on one region of an atlas (None where it has no point)."""
    held = holdout(df, split)
    ok = (df["status"] == "ok").to_numpy() & region.mask(df)
    fit, test = _points(df[ok & ~held]), _points(df[ok & held])
    if fit["load"].size < 2 or test["load"].size == 0:
        return None
    pub_fit = published(fit["load_angle_deg"])
    start = Params(float(np.mean(pub_fit.gamma)), float(np.mean(pub_fit.K_theta)))
    fitted, fit_worst = minimax(fit, start)
    pub_test = published(test["load_angle_deg"])
    return RefitResult(
        model,
        region,
        split,
        fitted,
        start,
        fit_worst,
        worst_error(test, pub_test.gamma, pub_test.K_theta),
        worst_error(test, fitted.gamma, fitted.K_theta),
        fit["load"].size,
        test["load"].size,
    )


def default_regions(model: str) -> list[Region]:
    """Load-angle bands x rotation limits; for the curved model kappa0 bands x rotation limits (all load
    angles, so one pair per band of curvature)."""
    if model == CURVED:
        return [Region((5.0, 175.0), r, k) for k in KAPPA0_BANDS for r in ROTATION_LIMITS]
    return [Region(b, r) for b in LOAD_ANGLE_BANDS for r in ROTATION_LIMITS]


def refit_results(
    atlas, model: str | None = None, regions: list[Region] | None = None, split: str = "checkerboard"
) -> list[RefitResult]:
    """Every region's refit of an atlas (a DataFrame or its rows; the model from its columns: kappa0
    present, the curved one)."""
    df = atlas if isinstance(atlas, pd.DataFrame) else pd.DataFrame(list(atlas))
    if model in ATLAS_MODELS or (model is None and "model" in df and df["model"].nunique() == 1):
        name = model or str(df["model"].iloc[0])
        df = (df[df["model"] == name] if "model" in df else df).dropna(axis=1, how="all")
        model = ATLAS_MODELS.get(name, model)
    if "model" in df and df["model"].nunique() > 1:
        raise ValueError("refit one atlas model at a time: name it (e.g. 'fixed_pinned_pauly_midha')")
    model = model or (CURVED if "kappa0" in df and df["kappa0"].notna().any() else FIXED_PINNED)
    results = (refit_region(df, r, model, split) for r in (regions or default_regions(model)))
    return [r for r in results if r is not None]


def refit_table(
    atlas, model: str | None = None, regions: list[Region] | None = None, split: str = "checkerboard"
) -> pd.DataFrame:
    """``refit_results`` as a table, one row a region."""
    return pd.DataFrame(
        [
            {
                "model": r.model,
                "region": r.region.name,
                "split": r.split,
                "gamma": r.fitted.gamma,
                "K_theta": r.fitted.K_theta,
                "gamma_published": r.start.gamma,
                "K_theta_published": r.start.K_theta,
                "fit_worst": r.fit_worst,
                "published_worst": r.published_worst,
                "refit_worst": r.refit_worst,
                "gain": r.gain,
                "fit_points": r.fit_points,
                "test_points": r.test_points,
            }
            for r in refit_results(atlas, model, regions, split)
        ]
    )


def finding_text(table: pd.DataFrame) -> str:
    """A short paragraph with the numbers of a ``refit_table``."""
    if table.empty:
        return "No region of the atlas had points to refit."
    parts = [
        f"in {row.region} from {row.published_worst:.2f} % to {row.refit_worst:.2f} % of L "
        f"(gamma = {row.gamma:.3f}, K_Theta = {row.K_theta:.3f})"
        for row in table.itertuples()
    ]
    better = table["gain"] > 1.0
    text = (
        f"{table['model'].iloc[0].capitalize()}: on held-out points (the {table['split'].iloc[0]} half of "
        f"each region not used to fit) the refit pair takes the worst tip error (at equal load) of the published "
        f"n-fits " + "; ".join(parts) + f": lower in {int(better.sum())} of {len(table)} regions "
        f"(gain {table['gain'].min():.2f}x to {table['gain'].max():.2f}x)."
    )
    if not better.all():
        text += " Not lower in " + ", ".join(table.loc[~better, "region"]) + "."
    return text
