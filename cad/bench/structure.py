"""Benchmark: link stiffness, beam closed form vs finite elements, error against time.

Bar: the bundled Hoeken's coupler segment A2-A3 (62.5 mm, 20 x 6 mm aluminium 6061,
14 mm pocket slot starting 11 mm from each joint) and, as a bar with a closed form,
the same bar without the slot. Quantity: cantilever tip compliance in plane (y) and out
of plane (z). Reference: the finest plane-stress FE mesh (128 x 16 quadratic
quadrilaterals); for the solid bar also the Timoshenko closed form.

Methods (points): ``beam`` -- Euler-Bernoulli with the pocket section over the whole
length (what ``method = "beam"`` uses); ``fem`` -- scikit-fem plane stress, knob: the
mesh (elements along x, across). ``error`` = max over y and z of |c - c_ref| / c_ref.
Device level: ``hapticad build``'s ``structure`` with both methods on the Hoeken design.
"""

from __future__ import annotations

import time
from pathlib import Path

from cad.bench.common import median_time, save_chart
from cad.design import load_design
from cad.structure import device, fem
from cad.structure.fem import euler_bernoulli_tip_m_per_N

E, NU = 68.9e9, 0.33
BARS = {
    "solid 62.5x20x6": (62.5, 20.0, 6.0, 0.0, 0.0),
    "pocketed 62.5x20x6, slot 14": (62.5, 20.0, 6.0, 14.0, 11.0),
}
MESHES = ((4, 1), (8, 1), (16, 2), (32, 4), (64, 8))
REF_MESH = (128, 16)


def _beam(L, w, t, wp):
    Iz = t * (w**3 - wp**3) / 12 * 1e-12
    Iy = (w - wp) * t**3 / 12 * 1e-12
    return euler_bernoulli_tip_m_per_N(L * 1e-3, E, Iz), euler_bernoulli_tip_m_per_N(L * 1e-3, E, Iy)


def _fem(g, n):
    return fem.cantilever(g, E, NU, "y", n), fem.cantilever(g, E, NU, "z", n)


def bar_points(quick: bool) -> list[dict]:
    pts = []
    for label, dims in BARS.items():
        g = fem.BarGeometry(*dims)
        ref = _fem(g, REF_MESH if not quick else MESHES[-1])
        def err(c, ref=ref):
            return max(abs(a - b) / b for a, b in zip(c, ref, strict=True))

        t, c = median_time(lambda dims=dims: _beam(*dims[:3], dims[3]), 20)
        pts.append({"bar": label, "method": "beam", "knob": None, "time_s": t, "error": err(c),
                    "compliance_um_per_N": [x * 1e6 for x in c]})
        for n in MESHES[: -1 if quick else None]:
            t, c = median_time(lambda n=n, g=g: _fem(g, n), 1 if quick else 3)
            pts.append({"bar": label, "method": "fem", "knob": list(n), "time_s": t, "error": err(c),
                        "compliance_um_per_N": [x * 1e6 for x in c]})
        if dims[3] == 0:
            inertias = (dims[2] * dims[1] ** 3 / 12 * 1e-12, dims[1] * dims[2] ** 3 / 12 * 1e-12)
            A = dims[1] * dims[2] * 1e-6
            timo = [fem.timoshenko_tip_m_per_N(dims[0] * 1e-3, E, i, E / 2 / (1 + NU), A) for i in inertias]
            pts.append({"bar": label, "method": "timoshenko closed form", "knob": None, "time_s": None,
                        "error": err(timo), "compliance_um_per_N": [x * 1e6 for x in timo]})
    return pts


def device_points() -> dict:
    d = load_design(Path(__file__).resolve().parents[2] / "designs" / "hoeken.toml")
    out = {}
    for m in device.METHODS:
        device._fem_compliances.cache_clear()
        t0 = time.perf_counter()
        r = device.analyse(d, [], {}, m)
        out[m] = {"time_s": time.perf_counter() - t0, "compliance_um_per_N": r["compliance_um_per_N"],
                  "max_stress_MPa": r["max_stress_MPa"]}
    return out


def run(quick: bool, out_dir: Path) -> dict:
    pts = bar_points(quick)
    result = {"topic": "structure: beam vs finite elements", "reference": f"FE mesh {REF_MESH}",
              "points": pts, "device_hoeken_bars_only": device_points(), "quick": quick}
    result["charts"] = _plot(pts, Path(out_dir))
    return result


def _plot(pts, out_dir: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 4.5))
    ax = fig.subplots()
    for bar, mk in zip(BARS, ("o", "s"), strict=True):
        for meth, col in (("beam", "C3"), ("fem", "C0")):
            p = [q for q in pts if q["bar"] == bar and q["method"] == meth]
            ax.loglog([q["time_s"] for q in p], [max(q["error"], 1e-6) for q in p], mk + "-", color=col,
                      label=f"{meth}, {bar}")
    ax.set_xlabel("time per evaluation (s)")
    ax.set_ylabel("max relative error of tip compliance (y, z)")
    ax.set_title("link stiffness: Euler-Bernoulli beam vs scikit-fem (ref: finest mesh)")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=7)
    return save_chart(fig, out_dir, "structure_error_vs_time")
