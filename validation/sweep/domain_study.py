"""Chapter 4 of [bapat2015]: characteristic deflection domains from the exact elliptic solutions beside
the PRBM, their pseudo-rigid-body bounds fitted and held against the printed ones, and the
PRBM-vs-exact error of the end position over each domain.

For each segment type (fixed-pinned, section 4.4; initially curved fixed-pinned, 4.5; fixed-guided
with one inflection point, 4.6) on the grids of ``cases/sweeps/studies/chapter4_domains.toml`` (the printed ones, or
coarser where stated):

1. the exact cloud (``elastica.domains``): eqs (6)-(11) with Su's theta0max (112), the Kimball-Tsai
   form for the inflection case;
2. its boundaries by one stated rule (``prbm.domain.boundary_curves``: per bin of b/l, the least and
   the largest a/l), each fitted with a PRB arc about (1 - gamma, 0) (``prbm.domain.fit_radius``; the
   lower bound of the inflection domain about the clamp, eq 117), and the extreme-n trajectories
   fitted the same way (the reading of notes seed-ch2-4 section 6.2); eq (116) and the gamma-bar_l
   circle are compared with the exact lower boundary over the printed range 0.4 <= b/l <= 0.85;
3. the PRBM at the same loads, point by point on a sample of the exact cloud: the Pauly-Midha
   fixed-pinned PRBM (eqs 41-49), the curved PRBM (53-61) with kappa0 = alpha sqrt(2 kappa), and the
   chapter-3 inflection PRBM (``prbm.solve_loads``) with M = alpha sqrt(2 kappa): the distance
   between the PRBM and exact end points over l (max, mean).  Under load BCs the inflection beam has
   several equilibria (at n >~ 2 buckled ones); the PRBM root nearest the exact point is compared
   (the question is whether the PRBM reaches that end point under those loads), and a load with no
   converged PRBM root counts as ``failed``.

``run_study(out)`` writes ``summary.json`` (every number), ``domains.png`` (clouds, boundaries and
the printed arcs overlaid) and returns the ``DomainStudy``.  ``python -m validation.sweep.domain_study
--out DIR``; by default it writes under reports/sweeps/chapter4_domains, where the report
page shows the figure with the sweep studies.
"""

from __future__ import annotations

import argparse
import json
import math
import tomllib
from dataclasses import asdict, dataclass, field
from pathlib import Path

import matplotlib
import numpy as np

import prbm
from elastica.domains import (
    DomainCloud,
    curved_fixed_pinned_cloud,
    fixed_guided_inflection_cloud,
    fixed_pinned_cloud,
    kappa_range,
)
from prbm.domain import boundary_curves, fit_radius
from prbm.domain_bounds import clamp_arc, inflection_lower_bound, prbm_arc

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

DATA = Path(__file__).resolve().parents[2] / "cases" / "sweeps" / "studies" / "chapter4_domains.toml"
DEFAULT_OUT = Path("reports/sweeps/chapter4_domains")
DEG = math.pi / 180.0
DPI = 110  # of the figure and of its PNG


@dataclass
class BoundFit:
    """One printed bound beside the value fitted to the exact cloud by a named rule."""

    name: str
    printed: float
    computed: float
    rule: str

    @property
    def relative(self) -> float:
        return (self.computed - self.printed) / self.printed


@dataclass
class TipError:
    """PRBM-vs-exact end-position error over l on a sample of a domain."""

    model: str
    samples: int
    failed: int
    max: float
    mean: float
    p90: float


@dataclass
class BoundCheck:
    """A printed bound curve against the exact boundary it claims to follow: its largest and mean relative
    deviation (%) over the printed range, and the printed claim (%)."""

    name: str
    claim_percent: float
    max_percent: float
    mean_percent: float
    over: str


@dataclass
class DomainResult:
    segment: str
    points: int
    excluded: dict[str, int]
    bounds: list[BoundFit] = field(default_factory=list)
    prbm_error: TipError | None = None
    notes: list[str] = field(default_factory=list)
    checks: list[BoundCheck] = field(default_factory=list)


@dataclass
class DomainStudy:
    results: list[DomainResult]


def _grid(spec: dict, scale: float = 1.0) -> np.ndarray:
    count = int(round((spec["stop"] - spec["start"]) / spec["step"])) + 1
    return np.linspace(spec["start"], spec["stop"], count) * scale


def _sample(cloud: DomainCloud, count: int) -> np.ndarray:
    """Indices of an even sample of the cloud (every k-th point), n strictly inside the fits' range."""
    inside = np.nonzero(cloud.n > -4.0 + 1e-9)[0]
    return inside[:: max(1, inside.size // count)]


def _point_errors(cloud: DomainCloud, idx, prbm_tip) -> np.ndarray:
    """Distance over l between the PRBM and the exact end point at each sampled index (NaN: no PRBM root)."""
    errors = np.full(len(idx), np.nan)
    for j, i in enumerate(idx):
        try:
            a, b = prbm_tip(i)
        except (ValueError, ArithmeticError):
            continue
        errors[j] = math.hypot(a - cloud.a[i], b - cloud.b[i])
    return errors


def _summary(model: str, errors: np.ndarray) -> TipError:
    e = errors[np.isfinite(errors)]
    failed = int(errors.size - e.size)
    if not e.size:
        return TipError(model, int(errors.size), failed, math.nan, math.nan, math.nan)
    return TipError(model, int(errors.size), failed, float(e.max()), float(e.mean()), float(np.percentile(e, 90)))


def _tip_error(model: str, cloud: DomainCloud, idx, prbm_tip) -> TipError:
    return _summary(model, _point_errors(cloud, idx, prbm_tip))


def _arc_fits(cloud: DomainCloud, printed: dict, bins: int) -> list[BoundFit]:
    bc = boundary_curves(cloud.a, cloud.b, bins=bins)
    return [
        BoundFit(
            "gamma_l",
            printed["gamma_l"],
            fit_radius(bc["lower"], bc["b"]),
            "PRB arc fitted to the least a/l per bin of b/l",
        ),
        BoundFit(
            "gamma_u",
            printed["gamma_u"],
            fit_radius(bc["upper"], bc["b"]),
            "PRB arc fitted to the largest a/l per bin of b/l",
        ),
    ]


def fixed_pinned(data: dict, sample: int = 200, bins: int = 60) -> tuple[DomainResult, DomainCloud]:
    spec = data["fixed_pinned"]
    cloud = fixed_pinned_cloud(_grid(spec["n"]), _grid(spec["theta0_deg"], DEG))
    res = DomainResult("fixed-pinned (4.4)", cloud.size, cloud.excluded, _arc_fits(cloud, spec, bins))
    for n, name in ((spec["n"]["stop"], "gamma_l"), (spec["n"]["start"], "gamma_u")):
        on = cloud.n == n
        res.bounds.append(
            BoundFit(
                name, spec[name], fit_radius(cloud.a[on], cloud.b[on]), f"PRB arc fitted to the n = {n:g} trajectory"
            )
        )

    def tip(i):
        out = prbm.fixed_pinned_tip(float(cloud.alpha[i] ** 2), float(cloud.n[i]), length=1.0, EI=1.0).outputs
        return float(out["a"]), float(out["b"])

    res.prbm_error = _tip_error("Pauly-Midha fixed-pinned PRBM (eqs 41-49)", cloud, _sample(cloud, sample), tip)
    return res, cloud


def curved_fixed_pinned(data: dict, sample: int = 200, bins: int = 60) -> tuple[DomainResult, DomainCloud]:
    spec = data["curved_fixed_pinned"]
    cloud = curved_fixed_pinned_cloud(_grid(spec["n"]), _grid(spec["theta0_deg"], DEG), _grid(spec["kappa"]))
    res = DomainResult("initially curved fixed-pinned (4.5)", cloud.size, cloud.excluded, _arc_fits(cloud, spec, bins))
    res.notes.append(
        "Su's bound (112) applied with kappa_F = kappa/eta (elastica.domains); the cloud mixes "
        "initial curvatures kappa0 = alpha sqrt(2 kappa), as the printed (n, theta0, kappa) grid does"
    )

    def tip(i):
        alpha, k0 = float(cloud.alpha[i]), float(cloud.alpha[i] * math.sqrt(2.0 * cloud.kappa[i]))
        out = prbm.curved_fixed_pinned_tip(alpha**2, float(cloud.n[i]), length=1.0, EI=1.0, curvature=k0).outputs
        return float(out["a"]), float(out["b"])

    res.prbm_error = _tip_error("curved fixed-pinned PRBM (eqs 53-61)", cloud, _sample(cloud, sample), tip)
    return res, cloud


def _beam_EI(data: dict) -> tuple[float, float]:
    beam = data["beam"]
    return beam["length"], beam["E"] * beam["width"] * beam["thickness"] ** 3 / 12.0


def _kappa_note(spec: dict) -> str:
    """The routine of section 4.6.1 (eqs 123, 124; Figs 4.16-4.22 missing) over its grid, -4 <= n <= 10 and
    -60 <= theta0 <= 60 deg, beside the adopted range of eq (126)."""
    pairs = [kappa_range(t * DEG, n) for n in _grid(spec["n"]) for t in np.arange(-60.0, 61.0, 5.0)]
    lo, hi = np.array(pairs).T
    k126 = spec["kappa"]
    return (
        f"kappa bounds by eqs (123)-(124) and the routine of 4.6.1 over -4 <= n <= 10, -60 <= theta0 <= 60 deg "
        f"(kappa = M^2/(2 F EI)): kappa_min from {lo.min():.3f} to {lo.max():.3f}, kappa_max from {hi.min():.3f} "
        f"to {hi.max():.3f} (a negative value: (120) holds at that theta_i for every kappa >= 0); eq (126) adopts "
        f"{k126['start']} <= kappa <= {k126['stop']}"
    )


def inflection_domain(data: dict, sample: int = 40, bins: int = 40) -> tuple[DomainResult, DomainCloud]:
    spec = data["fixed_guided_inflection"]
    length, EI = _beam_EI(data)
    load_range = tuple(p * length**2 / EI for p in spec["P"])  # alpha^2 = P l^2/EI
    cloud = fixed_guided_inflection_cloud(
        _grid(spec["n"]), _grid(spec["theta0_deg"], DEG), _grid(spec["kappa"]), load_range=load_range
    )
    bc = boundary_curves(cloud.a, cloud.b, bins=bins)
    res = DomainResult(
        "fixed-guided, one inflection point (4.6)",
        cloud.size,
        cloud.excluded,
        [
            BoundFit(
                "gamma_bar_l",
                spec["gamma_bar_l"],
                fit_radius(bc["lower"], bc["b"], centre="clamp"),
                "circle about the clamp fitted to the least a/l per bin of b/l",
            ),
            BoundFit(
                "gamma_u",
                spec["gamma_u"],
                fit_radius(bc["upper"], bc["b"]),
                "PRB arc fitted to the largest a/l per bin of b/l",
            ),
        ],
    )
    lo, hi = spec["lower_fit_range"]
    window = (bc["b"] >= lo) & (bc["b"] <= hi)
    for label, curve in (
        ("eq (116)", inflection_lower_bound(bc["b"][window])),
        ("gamma-bar_l circle (117)", clamp_arc(spec["gamma_bar_l"], bc["b"][window])),
    ):
        dev = np.abs(curve - bc["lower"][window]) / bc["lower"][window]
        res.checks.append(
            BoundCheck(
                label,
                100.0 * spec["lower_fit_claim"],
                100.0 * float(dev.max()),
                100.0 * float(dev.mean()),
                f"{lo} <= b/l <= {hi}",
            )
        )
        res.notes.append(
            f"{label} against the exact lower boundary for {lo} <= b/l <= {hi}: max |error| "
            f"{dev.max():.2%}, mean {dev.mean():.2%} (printed claim for (117): within "
            f"{spec['lower_fit_claim']:.0%})"
        )
    res.notes.append(_kappa_note(spec))
    beam = prbm.InflectionBeam(1.0, 1.0)

    def tip(i):
        P = float(cloud.alpha[i] ** 2)
        out = prbm.solve_loads(beam, P, float(cloud.n[i]) * P, float(cloud.alpha[i] * math.sqrt(2 * cloud.kappa[i])))
        if not out.converged:
            raise ValueError(out.message)
        a, b = np.ravel(out.outputs["a"]), np.ravel(out.outputs["b"])
        j = int(np.nanargmin(np.hypot(a - cloud.a[i], b - cloud.b[i])))  # the root on the exact branch
        return float(a[j]), float(b[j])

    idx = _sample(cloud, sample)
    errors = _point_errors(cloud, idx, tip)
    model = "chapter-3 inflection PRBM (eqs 83-104, load BCs)"
    res.prbm_error = _summary(model, errors)
    for label, part in (("n < 1", cloud.n[idx] < 1.0), ("n >= 1", cloud.n[idx] >= 1.0)):
        e = _summary(model, errors[part])
        res.notes.append(
            f"PRBM vs exact for {label}: max {e.max:.4f} l, 90th percentile {e.p90:.4f} l, mean "
            f"{e.mean:.4f} l over {e.samples} points ({e.failed} without a PRBM root)"
        )
    return res, cloud


def _cells(x: np.ndarray, y: np.ndarray, step: float = 1e-3) -> tuple[np.ndarray, np.ndarray]:
    """One point per occupied ``step`` x ``step`` cell (about half a pixel of the figure): the same
    picture of a cloud from far fewer markers."""
    ix, iy = np.round(np.asarray(x) / step).astype(np.int64), np.round(np.asarray(y) / step).astype(np.int64)
    key = np.unique((ix << 32) + (iy - iy.min()))
    return (key >> 32) * step, ((key & 0xFFFFFFFF) + iy.min()) * step


def _plot(clouds: list[tuple[DomainResult, DomainCloud]], data: dict, out: Path) -> Path:
    keys = ["fixed_pinned", "curved_fixed_pinned", "fixed_guided_inflection"]
    fig, axes = plt.subplots(1, 3, figsize=(16, 5.2), dpi=DPI)  # laid out and saved by one renderer
    b = np.linspace(0.0, 1.0, 400)
    for ax, (res, cloud), key in zip(axes, clouds, keys):
        spec = data[key]
        ax.scatter(*_cells(cloud.b, cloud.a), s=0.3, c="0.75", label=f"exact (elliptic), {cloud.size} points")
        bc = boundary_curves(cloud.a, cloud.b, bins=60)
        ax.plot(bc["b"], bc["lower"], "b-", lw=1, label="exact boundaries (rule of the study)")
        ax.plot(bc["b"], bc["upper"], "b-", lw=1)
        if "gamma_l" in spec:
            ax.plot(b, prbm_arc(spec["gamma_l"], b), "r--", label=f"printed gamma_l = {spec['gamma_l']}")
        if "gamma_bar_l" in spec:
            ax.plot(b, clamp_arc(spec["gamma_bar_l"], b), "r--", label=f"printed gamma-bar_l = {spec['gamma_bar_l']}")
            ax.plot(b, inflection_lower_bound(b), "m:", label="printed fit, eq (116)")
        ax.plot(b, prbm_arc(spec["gamma_u"], b), "r-.", label=f"printed gamma_u = {spec['gamma_u']}")
        ax.set(title=res.segment, xlabel="b / l", ylabel="a / l", xlim=(0, 1.02), ylim=(0, 1.02))
        ax.set_aspect("equal")
        ax.legend(fontsize=7, loc="lower left")
    if clouds and clouds[0][0].segment.startswith("fixed-pinned"):
        pr = prbm.fixed_pinned_domain(theta0_max_deg=90.0)
        axes[0].scatter(*_cells(pr["b"], pr["a"]), s=0.2, c="g", alpha=0.3, label="PRBM (prbm.domain)")
        axes[0].legend(fontsize=7, loc="lower left")
    out.mkdir(parents=True, exist_ok=True)
    path = out / "domains.png"
    fig.tight_layout()
    fig.set_layout_engine(None)  # laid out: savefig then draws it once, not once more for a layout engine
    fig.savefig(path, dpi=DPI, pil_kwargs={"compress_level": 1})
    plt.close(fig)
    return path


def run_study(out: Path | str = DEFAULT_OUT, data_file: Path = DATA, *, plot: bool = True) -> DomainStudy:
    data = tomllib.loads(Path(data_file).read_text())
    pairs = [fixed_pinned(data), curved_fixed_pinned(data), inflection_domain(data)]
    study = DomainStudy([res for res, _ in pairs])
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    summary = [
        asdict(r) | {"bounds": [asdict(bf) | {"relative": bf.relative} for bf in r.bounds]} for r in study.results
    ]
    (out / "summary.json").write_text(json.dumps(summary, indent=1))
    if plot:
        _plot(pairs, data, out)
    return study


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m validation.sweep.domain_study", description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=str(DEFAULT_OUT))
    args = parser.parse_args(argv)
    study = run_study(args.out)
    for r in study.results:
        print(f"{r.segment}: {r.points} exact points, excluded {r.excluded}")
        for bf in r.bounds:
            print(f"  {bf.name}: printed {bf.printed:.4f}, computed {bf.computed:.4f} ({bf.relative:+.2%}) [{bf.rule}]")
        if r.prbm_error:
            e = r.prbm_error
            print(
                f"  PRBM vs exact ({e.model}): max {e.max:.4f} l, 90th percentile {e.p90:.4f} l, mean {e.mean:.4f} l "
                f"over {e.samples} points "
                f"({e.failed} without a PRBM solution)"
            )
        for note in r.notes:
            print(f"  {note}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
