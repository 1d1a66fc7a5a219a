"""``hapticad tolerance``: Monte Carlo of manufacturing tolerances against the design's targets.

The math is :mod:`cad.kinematics.tolerance` (pure numpy, no CAD); this module turns
command-line tolerance specs into :class:`Tolerance` objects, runs the Monte Carlo and
the first-order propagation, computes the yields against the targets and draws the chart.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from cad.dynamics.inertia import InertiaCoefficients
from cad.errors import DesignError
from cad.families.fourbar.inertia import inertia_model
from cad.io.atomic import atomic_path
from cad.io.escape import mathtext
from cad.kinematics.tolerance import (
    BAR_HOLES,
    DISTRIBUTIONS,
    LENGTHS,
    METRIC_KEYS,
    PIVOTS,
    Tolerance,
    ToleranceStudy,
    validate_tolerances,
)
from cad.report.figures import save_figure


def _value(text: str, flag: str, default_dist: str) -> tuple[float, str]:
    val, _, dist = text.partition(":")
    try:
        t = float(val)
    except ValueError:
        raise DesignError(flag, f"tolerance {val!r} is not a number (mm)") from None
    return t, (dist or default_dist)


def tolerances_from_flags(hole_mm: float | None, holes: list[str], pivot_mm: float | None,
                          pivots: list[str], length_mm: float | None, lengths: list[str],
                          distribution: str) -> tuple[Tolerance, ...]:
    """Tolerances from the CLI flags (docs/tolerances.md); specific flags override blanket ones.

    ``holes``: ``crank=T``, ``coupler.P=T[:uniform]``; ``pivots``: ``A4=T``; ``lengths``: ``l2=T``.
    """
    if distribution not in DISTRIBUTIONS:
        raise DesignError("--distribution", f"must be normal or uniform, got {distribution!r}")
    spec: dict[str, tuple[float, str]] = {}
    if hole_mm is not None:
        for b, hs in BAR_HOLES.items():
            for h in hs:
                spec[f"{b}.{h}"] = (hole_mm, distribution)
    if pivot_mm is not None:
        for p in PIVOTS:
            spec[f"base.{p}"] = (pivot_mm, distribution)
    if length_mm is not None:
        for k in LENGTHS:
            spec[f"length.{k}"] = (length_mm, distribution)
    for item in holes:
        where, sep, val = item.partition("=")
        if not sep:
            raise DesignError("--hole", f"expected BAR=T or BAR.HOLE=T (mm), got {item!r}")
        bar, _, h = where.strip().partition(".")
        if bar not in BAR_HOLES or (h and h not in BAR_HOLES[bar]):
            known = ", ".join([*BAR_HOLES, *(f"{b}.{x}" for b, xs in BAR_HOLES.items() for x in xs)])
            raise DesignError("--hole", f"unknown hole {where!r} (known: {known})")
        for x in ([h] if h else BAR_HOLES[bar]):
            spec[f"{bar}.{x}"] = _value(val, "--hole", distribution)
    for item, flag, names, prefix in [(i, "--pivot", PIVOTS, "base") for i in pivots] + \
                                     [(i, "--length", LENGTHS, "length") for i in lengths]:
        where, sep, val = item.partition("=")
        where = where.strip().removesuffix("_mm")
        if not sep or where not in names:
            raise DesignError(flag, f"expected NAME=T with NAME in {', '.join(names)}, got {item!r}")
        spec[f"{prefix}.{where}"] = _value(val, flag, distribution)
    tols = tuple(Tolerance(n, t, d) for n, (t, d) in spec.items())
    if not tols:
        raise DesignError("--hole-mm", "no tolerances given: use --hole-mm, --hole, --pivot-mm, "
                          "--pivot, --length-mm or --length")
    validate_tolerances(tols)
    return tols


#: ``inertia_source`` when H comes from the solids (the path and fidelity of ``hapticad check``).
SOLIDS_SOURCE = "solids (fidelity inertia, as hapticad check)"


def inertia_for_m11(design, inertia):
    """H for M11: the --inertia flag, else the design's ``[inertia]``, else the solids.

    The solids are the parts ``hapticad check`` builds (:func:`cad.families.fourbar.inertia.inertia_model`,
    fidelity ``inertia``, through the derived cache): a target's value is what the design
    should reach, never its inertia. Returns (InertiaCoefficients, source text). Raises
    DesignError when the parts cannot carry their joints (give ``--inertia`` instead).
    """
    if inertia is not None:
        return inertia, "--inertia"
    if design.inertia is not None:
        return design.inertia, "[inertia]"
    design.check_buildable()
    model = inertia_model(design, fidelity="inertia")
    keys = ("H11_kg_m2", "H12_kg_m2", "H22_kg_m2", "H33_kg_m2")
    H = InertiaCoefficients(*(model[k] for k in keys), math.radians(model["beta2_deg"]))
    return H, SOLIDS_SOURCE


def _quantiles(v: np.ndarray) -> dict[str, float]:
    q = np.quantile(v, [0.0, 0.01, 0.5, 0.99, 1.0]) if v.size else [math.nan] * 5
    return {"min": float(q[0]), "p01": float(q[1]), "p50": float(q[2]), "p99": float(q[3]),
            "max": float(q[4])}


def run(design, tols: tuple[Tolerance, ...], samples: int, seed: int, angles: int, H,
        targets) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """Monte Carlo + first-order propagation + yields. Returns (JSON-able result, per-sample metrics)."""
    t0 = time.perf_counter()
    st = ToleranceStudy(design.linkage, design.phi1_min_rad, design.phi1_max_rad, design.force_N,
                        tols, angles, H)
    nominal = st.nominal()
    _, m = st.monte_carlo(samples, seed)
    t_mc = time.perf_counter() - t0
    fo = st.first_order()
    valid = m["valid"]
    keys = [k for k in METRIC_KEYS if k in m]
    tg = [t for t in targets if t.key in keys]
    by_target = {}
    ok_all = valid.copy()
    for t in tg:
        ok = valid & _vector_ok(t, m[t.key])
        by_target[t.key] = {"target": t.describe(), "yield": float(ok.mean()), "nominal_ok": t.ok(nominal[t.key])}
        ok_all &= ok
    metrics = {}
    for k in keys:
        v = m[k][valid]
        metrics[k] = {"nominal": nominal[k], "mean": float(v.mean()) if v.size else math.nan,
                      "std": float(v.std(ddof=1)) if v.size > 1 else math.nan,
                      "linear_std": fo[k]["linear_std"], **_quantiles(v)}
    return {
        "name": design.name, "samples": samples, "seed": seed, "angles": angles,
        "tolerances": [t.as_dict() for t in tols],
        "metrics": metrics,
        "yield": {"overall": float(ok_all.mean()) if tg else None, "by_target": by_target},
        "failed_samples": int((~valid).sum()),
        "sensitivity": {k: fo[k]["sensitivity"] for k in keys},
        "wall_s": time.perf_counter() - t0, "monte_carlo_s": t_mc,
    }, m


def _vector_ok(t, v: np.ndarray) -> np.ndarray:
    """:meth:`cad.design.targets.Target.ok` over an array."""
    ok = np.isfinite(v)
    if t.value is not None:
        tol = t.tol_abs if t.tol_abs is not None else abs(t.value) * (t.tol_rel or 0.0)
        return ok & (np.abs(v - t.value) <= tol)
    if t.min is not None:
        ok &= v >= t.min
    if t.max is not None:
        ok &= v <= t.max
    return ok


def write_chart(res: dict[str, Any], m: dict[str, np.ndarray], targets, path) -> None:
    """Histograms of each metric (nominal and targets marked) and the sensitivity of dy_max_mm."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt


    keys = [k for k in ("dy_max_mm", "stroke_mm", "slope_max", "torque_variation", "M11_max_g")
            if k in res["metrics"]]
    fig, axes = plt.subplots(2, 3, figsize=(13, 7.5))
    flat = axes.ravel()
    for ax, k in zip(flat, keys, strict=False):
        v = m[k][m["valid"]]
        ax.hist(v, bins=60, color="#4a7ab7")
        ax.axvline(res["metrics"][k]["nominal"], color="k", lw=1.2, label="nominal")
        for t in targets:
            if t.key != k:
                continue
            for b in (t.min, t.max) if t.value is None else (t.value,):
                if b is not None:
                    ax.axvline(b, color="r", ls="--", lw=1.2, label=f"target {t.describe()}")
        y = res["yield"]["by_target"].get(k)
        ax.set_title(k + (f"  (yield {100 * y['yield']:.1f} %)" if y else ""), fontsize=10)
        ax.legend(fontsize=7)
    ax = flat[5]
    sens = res["sensitivity"]["dy_max_mm"][:8]
    ax.barh([s["tolerance"] for s in sens][::-1], [100 * s["share"] for s in sens][::-1], color="#b7684a")
    ax.set_xlabel("share of var(dy_max_mm), first order (%)")
    ax.set_title("sensitivity of dy_max_mm", fontsize=10)
    for extra in flat[len(keys):5]:
        extra.axis("off")
    tols = ", ".join(f"{t['name']} ±{t['tol_mm']:g} ({t['distribution']})" for t in res["tolerances"][:4])
    fig.suptitle(f"{mathtext(res['name'])}: {res['samples']} Monte Carlo samples; {tols}"
                 + (" ..." if len(res["tolerances"]) > 4 else ""), fontsize=10)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        save_figure(fig, tmp, "png", dpi=90)
    plt.close(fig)
