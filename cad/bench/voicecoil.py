"""Benchmark: voice-coil gap field, closed form eq (9) vs image series vs magpylib, error against time.

Geometry: the paper's Fig. 8 actuator (l_m = 20, w_m = 8, t_m = 4 mm, B_r = 1.2 T)
at gaps d = 6, 11 and 30 mm. Quantity: B_z at the gap centre of ONE magnet
pair between two ideal (mu -> infinity, infinite) iron plates.

Reference: the converged two-plate image series, 4096 slabs per side plus its
asymptotic tail (:func:`cad.actuators.voicecoil.bg_image_converged_T`; it
agrees with 2^20 plain terms to ~1e-13). ``error`` = max over the three gaps
of |B - B_ref| / B_ref. ``time_s`` = median wall time of one evaluation (all
three gaps, divided by 3) over repeats.

Methods (points):
* ``closed-form eq 9`` -- one image per plate (knob: none);
* ``image series`` -- K slabs per side (knob K), plain partial sums: error ~ 1/K^2;
* ``image series + tail`` -- K slabs plus the asymptotic tail: error ~ 1/K^4;
* ``magpylib core`` -- magpylib's vectorised cuboid kernel on the same image
  stack (knob K); ``magpylib object`` -- ``magnet.Cuboid`` + ``getB``, K = 1;
* ``coil quadrature`` -- the coil-volume mean of B_z (whole actuator, 32 slabs)
  against Gauss-Legendre order (knob n per axis; reference: order 16x12x12).

Models (how the optimal gap moves, isotropy paper Fig. 8 gives ~11 mm):
eq (9); the converged image series; magpylib whole actuator (opposite
neighbour pair) at the gap centre; the same averaged over the coil volume;
and (full run, when magpylib-material-response is installed) finite
plates of susceptibility 1000 at the gap centre. Also the force along the
stroke with the coil's real cross-section against eq (8)'s uniform field.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from cad.actuators import field_magpylib as fm
from cad.actuators import voicecoil as vc
from cad.bench.common import median_time as _median_time
from cad.io.atomic import atomic_path
from cad.report.figures import save_figure

GEOM = {
    "magnet_length_mm": 20.0,
    "magnet_width_mm": 8.0,
    "magnet_thickness_mm": 4.0,
    "rattle_mm": 6.0,
}
BR_T = 1.2
GAPS_MM = (6.0, 11.0, 30.0)
REFERENCE = (
    "converged two-plate ideal-iron image series (4096 slabs/side + asymptotic tail), one magnet pair, "
    "gap centre; B_r = 1.2 T, l,w,t = 20,8,4 mm; max relative error over d = 6, 11, 30 mm"
)


def _field_points(repeats: int, quick: bool) -> tuple[list[dict], dict]:
    lm, w, t = GEOM["magnet_length_mm"], GEOM["magnet_width_mm"], GEOM["magnet_thickness_mm"]
    ref = {d: vc.bg_image_converged_T(d, lm, w, t, BR_T) for d in GAPS_MM}
    check = {d: vc.bg_image_series_T(d, lm, w, t, BR_T, 2**20) for d in GAPS_MM}
    pts: list[dict] = []

    def add(method, knob, fn):
        tm, vals = _median_time(lambda: [fn(d) for d in GAPS_MM], repeats)
        err = max(abs(v - ref[d]) / ref[d] for v, d in zip(vals, GAPS_MM, strict=True))
        pts.append(
            {"method": method, "knob": knob, "time_s": tm / len(GAPS_MM), "error": float(err)}
        )

    add("closed-form eq 9", None, lambda d: float(vc.bg_eq9_T(d, lm, w, t, BR_T)))
    ks = (1, 2, 4, 8, 16, 32, 64, 128, 256, 1024, 4096) if not quick else (1, 4, 16, 64, 256, 1024)
    for k in ks:
        add("image series", k, lambda d, k=k: vc.bg_image_series_T(d, lm, w, t, BR_T, k))
    for k in (1, 2, 4, 8, 16, 32, 64) if not quick else (1, 4, 16, 64):
        add("image series + tail", k, lambda d, k=k: vc.bg_image_converged_T(d, lm, w, t, BR_T, k))
    for k in (1, 4, 16, 64, 256) if not quick else (1, 16, 64):
        add("magpylib core", k, lambda d, k=k: fm.bg_center_T(d, lm, w, t, BR_T, n_slabs=k))
    add("magpylib object", 1, lambda d: fm.bg_center_T(d, lm, w, t, BR_T, n_slabs=1, api="object"))
    meta = {
        "reference_T": {str(d): ref[d] for d in GAPS_MM},
        "reference_vs_2^20_plain_terms": max(abs(ref[d] - check[d]) / ref[d] for d in GAPS_MM),
        "eq9_vs_magpylib_one_image": max(
            abs(
                float(vc.bg_eq9_T(d, lm, w, t, BR_T))
                - fm.bg_center_T(d, lm, w, t, BR_T, api="object")
            )
            / float(vc.bg_eq9_T(d, lm, w, t, BR_T))
            for d in GAPS_MM
        ),
        "image_series_over_eq9": {
            str(d): ref[d] / float(vc.bg_eq9_T(d, lm, w, t, BR_T)) - 1.0 for d in GAPS_MM
        },
    }
    return pts, meta


def _quadrature_points(repeats: int, quick: bool) -> list[dict]:
    p = vc.VoiceCoilParams(**GEOM, br_T=BR_T)
    d = 11.0
    ref = fm.coil_mean_bz_T(d, p, n_quad=(16, 12, 12))
    pts = []
    for n in (1, 2, 3, 4, 6, 8) if not quick else (1, 2, 4, 6):
        nq = (n, n, n)
        tm, v = _median_time(lambda nq=nq: fm.coil_mean_bz_T(d, p, n_quad=nq), repeats)
        pts.append(
            {"method": "coil quadrature", "knob": n, "time_s": tm, "error": abs(v - ref) / abs(ref)}
        )
    return pts


def _models(quick: bool) -> dict:
    p = vc.VoiceCoilParams(**GEOM, br_T=BR_T)
    out = {}

    def opt(label, model, **kw):
        t0 = time.perf_counter()
        o = vc.optimal_gap(p, model, xatol_mm=1e-4, **kw)
        out[label] = {
            "optimal_gap_mm": o.optimal_gap_mm,
            "Bg_T": o.Bg_T,
            "force_N": o.force_N,
            "time_s": time.perf_counter() - t0,
        }

    opt("eq9 closed form (one image per plate, centre)", "closed-form")
    opt("image series converged (one pair, centre)", "images")
    opt("magpylib whole actuator, 32 slabs, centre", "magpylib", average="centre")
    opt("magpylib whole actuator, 32 slabs, coil-volume mean", "magpylib")
    if not quick and fm.material_response_available():
        import scipy.optimize as so

        t0 = time.perf_counter()

        def neg(d):
            bg = fm.bg_finite_iron_T(d, p, plate_thickness_mm=4.0, cells=(6, 8, 2))
            return -float(vc.force_eq8_N(bg, d, p))

        r = so.minimize_scalar(neg, bounds=(8.0, 14.0), method="bounded", options={"xatol": 1e-2})
        out["finite iron plates chi=1000 (magpylib-material-response), centre"] = {
            "optimal_gap_mm": float(r.x),
            "force_N": -float(r.fun),
            "time_s": time.perf_counter() - t0,
        }
    elif not fm.material_response_available():
        out["finite iron plates"] = "magpylib-material-response not installed (optional)"
    return out


def _finite_iron(quick: bool) -> dict:
    """Finite-permeability, finite-size plates (optional package): B at the gap centre vs mesh."""
    if not fm.material_response_available():
        return {"available": False}
    p = vc.VoiceCoilParams(**GEOM, br_T=BR_T)
    ideal = fm.bg_center_T(11.0, 20.0, 8.0, 4.0, BR_T, n_slabs=64, neighbour=True)
    rows = []
    meshes = ((4, 5, 1), (8, 10, 2)) if quick else ((4, 5, 1), (8, 10, 2), (12, 15, 3))
    for cells in meshes:
        t0 = time.perf_counter()
        b = fm.bg_finite_iron_T(11.0, p, plate_thickness_mm=4.0, cells=cells)
        rows.append(
            {
                "cells": list(cells),
                "Bg_T": b,
                "time_s": time.perf_counter() - t0,
                "vs_ideal_infinite_plates": b / ideal - 1.0,
            }
        )
    return {
        "available": True,
        "gap_mm": 11.0,
        "susceptibility": 1000.0,
        "ideal_infinite_plates_T": ideal,
        "meshes": rows,
    }


def _stroke() -> dict:
    p = vc.VoiceCoilParams(**GEOM, br_T=BR_T)
    d = vc.optimal_gap(p).optimal_gap_mm
    x = np.linspace(-p.rattle_mm / 2, p.rattle_mm / 2, 13)
    s = vc.stroke_force(d, p, x)
    return {
        "gap_mm": d,
        "x_mm": x.tolist(),
        "force_N": s.force_N.tolist(),
        "force_eq8_N": s.force_eq8_N,
        "ratio_at_centre": float(s.force_N[len(x) // 2] / s.force_eq8_N),
        "ratio_at_ends": float(s.force_N[0] / s.force_eq8_N),
    }


def _chart(points: list[dict], out_dir: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt


    fig, ax = plt.subplots(figsize=(7, 5))
    floor = 1e-17
    for method in dict.fromkeys(p["method"] for p in points):
        ps = [p for p in points if p["method"] == method]
        label = method + (" (ref: order 16x12x12)" if method == "coil quadrature" else "")
        ax.loglog(
            [p["time_s"] for p in ps], [max(p["error"], floor) for p in ps], "o-", label=label
        )
        for p in ps:
            if p["knob"] is not None:
                ax.annotate(
                    str(p["knob"]),
                    (p["time_s"], max(p["error"], floor)),
                    fontsize=7,
                    xytext=(3, 3),
                    textcoords="offset points",
                )
    ax.set_xlabel("time per evaluation (s), median")
    ax.set_ylabel("relative error")
    ax.set_title(
        "Voice-coil gap field vs converged image series (knob: slabs K / quadrature order)",
        fontsize=9,
    )
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    out_dir = Path(out_dir)
    names = []
    for ext in ("png", "svg"):
        target = out_dir / f"bench_voicecoil.{ext}"
        with atomic_path(target) as tmp:
            save_figure(fig, tmp, ext, dpi=110)
        names.append(target.name)
    plt.close(fig)
    return names


def run(quick: bool, out_dir: Path) -> dict:
    """Run the benchmark, write ``bench_voicecoil.png/.svg`` into ``out_dir``, return JSON-able results.

    quick: 3 repeats per point and fewer knobs, no finite-iron optimum (full: 9 repeats).
    """
    repeats = 3 if quick else 9
    pts, meta = _field_points(repeats, quick)
    qpts = _quadrature_points(repeats, quick)
    charts = _chart(pts + qpts, Path(out_dir))
    return {
        "topic": "voicecoil",
        "reference": REFERENCE,
        "reference_coil_quadrature": "coil-volume mean of B_z, Gauss-Legendre 16x12x12, d = 11 mm",
        "repeats": repeats,
        "points": pts + qpts,
        "meta": meta,
        "optimal_gap_by_model": _models(quick),
        "finite_iron": _finite_iron(quick),
        "stroke_force": _stroke(),
        "charts": charts,
    }


if __name__ == "__main__":  # pragma: no cover - manual run
    import json
    import sys

    res = run(quick="--full" not in sys.argv, out_dir=Path("bench_out"))
    print(json.dumps(res, indent=1))
