"""Benchmark: mass-property error against time, exact B-rep vs adaptive vs meshes.

Two parts with closed-form mass properties:

* ``bar``: a link-like stadium plate (centre distance ``L``, end radius ``R``,
  thickness ``T``) with a through-hole of radius ``r`` at each end centre -- the shape of
  a four-bar link;
* ``tube``: a hollow cylinder (outer radius ``Ro``, inner ``Ri``, length ``h``).

Methods (each timed end to end, median of repeats):

* ``occt-exact`` -- ``BRepGProp.VolumeProperties_s`` default mode (the library's method);
* ``occt-eps`` -- OCCT's adaptive mode at several ``eps``;
* ``occt-triangulation`` -- BRepMesh at an absolute tolerance on a fresh copy + OCCT
  integration over the triangulation (meshing included in the time);
* ``trimesh`` -- the same mesh pulled into trimesh (meshing + pull + integration);
* ``manifold3d`` -- the same mesh, volume only (its error is the mass error).

Error = relative error against the closed form, on the mass and on Izz (about the
COM, z = plate normal / tube axis); ``error`` is the larger of the two.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from cad.bench.common import median_time as _median_time
from cad.io.atomic import atomic_path
from cad.massprops import mesh, occt
from cad.parts.reference_solids import stadium_bar, tube
from cad.report.figures import save_figure
from cad.tolerances import BENCH_MASSPROPS_MESH_TOLERANCES_MM as MESH_TOLERANCES_MM
from cad.tolerances import BENCH_OCCT_EPS as OCCT_EPS

#: Density of every benchmark part (aluminium 6061), kg/m^3.
BENCH_DENSITY_KG_M3 = 2700.0
#: Angular deflection used for every mesh (the library default), rad. It caps the chord
#: angle, so on these radii (3-10 mm) tolerances >= 0.3 mm give the same mesh.
MESH_ANGULAR_RAD = 0.5
#: Errors below this are drawn at this value on the log axis (exact results give 0).
ERROR_FLOOR = 1e-17

BAR = {"L_mm": 80.0, "R_mm": 8.0, "r_mm": 3.0, "T_mm": 6.0}
TUBE = {"Ro_mm": 10.0, "Ri_mm": 6.0, "h_mm": 40.0}

REFERENCE = (
    "closed form: bar = rectangle + 2 half-discs - 2 holes (extruded), "
    "tube = pi (Ro^2 - Ri^2) h, Izz = m (Ro^2 + Ri^2) / 2"
)


# ------------------------------------------------------------------ closed forms
def stadium_bar_closed_form(
    L_mm: float, R_mm: float, r_mm: float, T_mm: float, density_kg_m3: float
) -> tuple[float, np.ndarray]:
    """Mass (kg) and principal inertia diag (Ixx, Iyy, Izz) about the COM (kg m^2) of a holed stadium plate.

    Parameters
    ----------
    L_mm : distance between the two end-circle centres (x axis), mm.
    R_mm : end radius (half the width, y), mm.
    r_mm : radius of the through-hole at each end centre, mm (< R).
    T_mm : thickness (z), mm.
    density_kg_m3 : density, kg/m^3.

    Section second moments about the centroid (origin):
    rectangle ``S_xx = W L^3/12, S_yy = L W^3/12`` (W = 2R); each half-disc at
    ``x = +-L/2`` adds ``(L/2)^2 pi R^2/2 + L (2R^3/3) + pi R^4/8`` to ``S_xx``
    (``integral u dA = 2R^3/3`` over a half-disc) and together ``pi R^4/4`` to
    ``S_yy``; each hole removes ``pi r^4/4 + pi r^2 (L/2)^2`` / ``pi r^4/4``.
    For a prism of thickness T: ``Ixx = rho T S_yy + m T^2/12``,
    ``Iyy = rho T S_xx + m T^2/12``, ``Izz = rho T (S_xx + S_yy)``.
    """
    L, R, r, T = (x * 1e-3 for x in (L_mm, R_mm, r_mm, T_mm))
    W = 2 * R
    area = L * W + math.pi * R**2 - 2 * math.pi * r**2
    sxx = (
        W * L**3 / 12
        + 2 * ((L / 2) ** 2 * math.pi * R**2 / 2 + L * (2 * R**3 / 3) + math.pi * R**4 / 8)
        - 2 * (math.pi * r**4 / 4 + math.pi * r**2 * (L / 2) ** 2)
    )
    syy = L * W**3 / 12 + math.pi * R**4 / 4 - 2 * math.pi * r**4 / 4
    m = density_kg_m3 * area * T
    return m, np.array(
        [
            density_kg_m3 * T * syy + m * T**2 / 12,
            density_kg_m3 * T * sxx + m * T**2 / 12,
            density_kg_m3 * T * (sxx + syy),
        ]
    )


def tube_closed_form(
    Ro_mm: float, Ri_mm: float, h_mm: float, density_kg_m3: float
) -> tuple[float, np.ndarray]:
    """Mass (kg) and inertia diag (Ixx, Iyy, Izz) about the COM (kg m^2) of a tube along z.

    ``m = rho pi (Ro^2 - Ri^2) h``; ``Izz = m (Ro^2 + Ri^2)/2``;
    ``Ixx = Iyy = m (3 (Ro^2 + Ri^2) + h^2) / 12``.
    """
    Ro, Ri, h = (x * 1e-3 for x in (Ro_mm, Ri_mm, h_mm))
    m = density_kg_m3 * math.pi * (Ro**2 - Ri**2) * h
    ixx = m * (3 * (Ro**2 + Ri**2) + h**2) / 12
    return m, np.array([ixx, ixx, m * (Ro**2 + Ri**2) / 2])


# ------------------------------------------------------------------ solids
# stadium_bar and tube: cad.parts.reference_solids (part scripts)


# ------------------------------------------------------------------ timing


def _rel(a: float, b: float) -> float:
    return abs(a - b) / abs(b)


def _bench_part(part: str, shape, m_ref: float, izz_ref: float, repeats: int) -> list[dict]:
    rho = BENCH_DENSITY_KG_M3
    pts: list[dict] = []

    def add(method, knob, t, props=None, volume_mm3=None, n_tri=None):
        if props is not None:
            em = _rel(props.mass_kg, m_ref)
            ei = _rel(float(props.inertia_com_kg_m2[2, 2]), izz_ref)
            err = max(em, ei)
        else:
            em = _rel(rho * volume_mm3 * 1e-9, m_ref)
            ei = None
            err = em
        pts.append(
            {
                "part": part,
                "method": method,
                "knob": knob,
                "time_s": t,
                "error": err,
                "error_mass": em,
                "error_Izz": ei,
                "n_triangles": n_tri,
            }
        )

    t, p = _median_time(lambda: occt.solid_mass_props(shape, rho, check=False), repeats)
    add("occt-exact", "default", t, p)
    for eps in OCCT_EPS:
        t, p = _median_time(
            lambda eps=eps: occt.solid_mass_props(shape, rho, eps=eps, check=False), repeats
        )
        add("occt-eps", f"eps={eps:g}", t, p)
    for tol in MESH_TOLERANCES_MM:
        t, r = _median_time(
            lambda tol=tol: mesh.occt_triangulation_mass_props(shape, rho, tol, MESH_ANGULAR_RAD),
            repeats,
        )
        add("occt-triangulation", f"tol={tol:g}mm", t, r.props, n_tri=r.n_triangles)
        t, r = _median_time(
            lambda tol=tol: mesh.trimesh_mass_props(shape, rho, tol, MESH_ANGULAR_RAD), repeats
        )
        add("trimesh", f"tol={tol:g}mm", t, r.props, n_tri=r.n_triangles)
        t, r = _median_time(
            lambda tol=tol: mesh.manifold_shape_volume_mm3(shape, tol, MESH_ANGULAR_RAD), repeats
        )
        add("manifold3d", f"tol={tol:g}mm", t, volume_mm3=r.volume_mm3, n_tri=r.n_triangles)
    return pts


def _chart(points: list[dict], out_dir: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt


    parts = sorted({p["part"] for p in points})
    methods = ["occt-exact", "occt-eps", "occt-triangulation", "trimesh", "manifold3d"]
    markers = dict(zip(methods, ["*", "D", "o", "s", "^"], strict=True))
    fig, axes = plt.subplots(1, len(parts), figsize=(6 * len(parts), 4.8), squeeze=False)
    for ax, part in zip(axes[0], parts, strict=True):
        for meth in methods:
            sel = [p for p in points if p["part"] == part and p["method"] == meth]
            if not sel:
                continue
            xs = [p["time_s"] for p in sel]
            ys = [max(p["error"], ERROR_FLOOR) for p in sel]
            label = meth + (" (mass only)" if meth == "manifold3d" else "")
            ax.loglog(
                xs, ys, marker=markers[meth], linestyle="-" if len(sel) > 1 else "", label=label
            )
            if meth in ("occt-triangulation",):
                for p, x, y in zip(sel, xs, ys, strict=True):
                    ax.annotate(
                        p["knob"].replace("tol=", ""),
                        (x, y),
                        fontsize=7,
                        textcoords="offset points",
                        xytext=(4, 3),
                    )
        ax.set_title(f"{part}: relative error max(mass, Izz) vs time")
        ax.set_xlabel("time per evaluation [s] (median)")
        ax.set_ylabel(f"relative error (floored at {ERROR_FLOOR:g})")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("reference: " + REFERENCE, fontsize=8)
    fig.tight_layout(rect=(0, 0, 1, 0.94))
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    for ext in ("png", "svg"):
        target = out_dir / f"massprops_error_vs_time.{ext}"
        with atomic_path(target) as tmp:
            save_figure(fig, tmp, ext, dpi=120)
        paths.append(str(target))
    plt.close(fig)
    return paths


def run(quick: bool, out_dir: Path) -> dict:
    """Run the benchmark, write the chart (PNG + SVG) into ``out_dir``, return the points.

    ``quick``: 3 repeats per point instead of 9 (same methods and tolerances).
    """
    repeats = 3 if quick else 9
    rho = BENCH_DENSITY_KG_M3
    points: list[dict] = []
    m_bar, i_bar = stadium_bar_closed_form(**BAR, density_kg_m3=rho)
    points += _bench_part("bar", stadium_bar(**BAR), m_bar, float(i_bar[2]), repeats)
    m_tube, i_tube = tube_closed_form(**TUBE, density_kg_m3=rho)
    points += _bench_part("tube", tube(**TUBE), m_tube, float(i_tube[2]), repeats)
    charts = _chart(points, Path(out_dir))
    return {
        "topic": "massprops",
        "reference": REFERENCE,
        "density_kg_m3": rho,
        "parts": {"bar": BAR, "tube": TUBE},
        "mesh_angular_rad": MESH_ANGULAR_RAD,
        "repeats": repeats,
        "points": points,
        "charts": charts,
    }


if __name__ == "__main__":  # pragma: no cover - manual run
    import json
    import sys

    res = run(quick="--full" not in sys.argv, out_dir=Path("bench_out"))
    print(json.dumps(res, indent=1))
