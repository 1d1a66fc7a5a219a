"""The PowerMouse's actuator: the eq (8) gap optimum under every field model and the paper's
Fig. 8 chart (isotropy paper section 6)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cad.actuators import voicecoil as vc
from cad.io.atomic import atomic_path
from cad.report.figures import save_figure


def actuator_optimum(design) -> dict:
    """The gap used by the design and the eq (8) optimum under every field model (dict of dicts)."""
    params = design.actuator.params()
    models = {}
    for m in vc.MODELS:
        models[m] = vc.optimal_gap(params, m).as_dict()
    chosen = models[design.actuator.field_model]
    gap = design.actuator.gap_mm if design.actuator.gap_mm is not None else chosen["optimal_gap_mm"]
    bg = vc.gap_field_T(gap, params, design.actuator.field_model)
    return {
        "gap_mm": gap,
        "gap_source": "design"
        if design.actuator.gap_mm is not None
        else f"optimum ({design.actuator.field_model})",
        "coil_width_mm": gap - design.actuator.rattle_mm,
        "Bg_T": bg,
        "force_N": float(vc.force_eq8_N(bg, gap, params)),
        "peak_force_N": float(
            vc.force_eq8_N(bg, gap, design.actuator.params(design.actuator.peak_power_W))
        ),
        "eta_geom": params.eta_geom,
        "ampere_turns_at_power": vc.ampere_turns(gap, params),
        "field_model": design.actuator.field_model,
        "models": models,
    }


def fig8_chart(design, gap_mm: float, out_dir: Path) -> list[str]:
    """Paper Fig. 8: eq (8) force vs gap (three models) and B_z along the centre line at the gap used."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt


    p = design.actuator.params()
    d = np.linspace(p.rattle_mm + 0.05, p.rattle_mm + 30.0, 200)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    ax1.plot(d, vc.force_vs_gap_N(d, p, "closed-form"), label="eq (9) closed form")
    ax1.plot(
        d,
        [
            float(
                vc.force_eq8_N(
                    vc.bg_image_converged_T(
                        x,
                        p.magnet_length_mm,
                        p.magnet_width_mm,
                        p.magnet_thickness_mm,
                        p.br_T,
                        1024,
                    ),
                    x,
                    p,
                )
            )
            for x in d
        ],
        label="two-plate image series",
    )
    ax1.axvline(gap_mm, color="k", lw=0.8, ls="--")
    ax1.set_xlabel("gap d (mm)")
    ax1.set_ylabel(f"force (N) at {p.power_W:g} W")
    ax1.set_title(
        f"d_r = {p.rattle_mm:g} mm, l,w,t = {p.magnet_length_mm:g},{p.magnet_width_mm:g},{p.magnet_thickness_mm:g} mm"
    )
    ax1.legend()
    z = np.linspace(-0.49 * gap_mm, 0.49 * gap_mm, 101)
    ax2.plot(
        z,
        vc.bz_centerline_eq9_T(
            z, gap_mm, p.magnet_length_mm, p.magnet_width_mm, p.magnet_thickness_mm, p.br_T
        ),
    )
    ax2.set_xlabel("z across the gap (mm)")
    ax2.set_ylabel("B_z on the magnet centre line (T)")
    ax2.set_title(f"gap {gap_mm:.2f} mm (eq 9 extended)")
    fig.tight_layout()

    names = []

    for ext in ("png", "svg"):  # same bytes every build (save_figure)
        target = Path(out_dir) / f"actuator_fig8.{ext}"
        with atomic_path(target) as tmp:
            save_figure(fig, tmp, ext, dpi=110)
        names.append(target.name)
    plt.close(fig)
    return names


def actuator_gap_mm(design) -> float:
    """The magnet gap d (mm): the design's, else the eq (8) optimum of its field model."""
    a = design.actuator
    if a.gap_mm is not None:
        return a.gap_mm
    return vc.optimal_gap(a.params(), a.field_model).as_dict()["optimal_gap_mm"]
