"""Build a PowerMouse design: actuator optimum -> solids -> mass properties -> clearances -> exports.

Contract: see :mod:`cad.build` (``build(design, out_dir, formats, *, fidelity,
allow_interference, progress, phi1_deg) -> report dict``). ``out_dir`` is the
dispatcher's temporary directory. Isotropy paper sections 5-6.

Files written: one STEP/STL per distinct part (``pm_flotor_shell``,
``pm_coil`` x6, ``pm_handle``, ``pm_core_post``, ``pm_magnet`` x24,
``pm_iron_plate`` x6, ``pm_housing``), the single actuator of Fig. 7
(``act_*``; its plates also as DXF), ``powermouse_assembly.step`` (every
placed solid, named and coloured), ``actuator_assembly.step``, ``bom.csv``
and ``actuator_fig8.png/.svg`` (force vs gap and field along the centre line,
the paper's Fig. 8).

Report keys (units in names): ``actuator`` (the optimum: optimal_gap_mm,
coil_width_mm, Bg_T, force_N, eta_geom, model, and the same for the other
field models), ``wrench_map`` (6x6, N/A and N m/A),
``wrench_map_singular_values`` (descending), ``isotropy`` (force/torque
groups and spreads), ``flotor`` (mass_kg, com_mm, inertia_com_kg_m2 from the
solids, per part masses), ``peak_force_N``, ``continuous_force_N``,
``peak_acceleration_m_s2`` / ``_G``, ``clearances_mm``, ``paper_table4``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cad.errors import InterferenceError

#: Paper Table 4 (PowerMouse performance), for side-by-side reporting.
PAPER_TABLE4 = {
    "workspace": "+-3 mm, +-5 deg",
    "continuous_force_N": 16.0,
    "peak_force_N": 34.0,
    "effective_mass_g": 260.0,
    "peak_acceleration_G": ">10",
}


def _step(progress, text: str, done: int, total: int) -> None:
    if progress is not None:
        progress(text, done, total)


def actuator_optimum(design) -> dict:
    """The gap used by the design and the eq (8) optimum under every field model (dict of dicts)."""
    from cad.actuators import voicecoil as vc

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


def _fig8_chart(design, gap_mm: float, out_dir: Path) -> list[str]:
    """Paper Fig. 8: eq (8) force vs gap (three models) and B_z along the centre line at the gap used."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from cad.actuators import voicecoil as vc

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
    from cad.io.atomic import atomic_path

    names = []
    for ext in ("png", "svg"):
        target = Path(out_dir) / f"actuator_fig8.{ext}"
        with atomic_path(target) as tmp:
            fig.savefig(tmp, format=ext, dpi=110)
        names.append(target.name)
    plt.close(fig)
    return names


def build(
    design,
    out_dir: Path,
    formats: set[str],
    *,
    fidelity: str = "fabrication",
    allow_interference: bool = False,
    progress=None,
    phi1_deg: float | None = None,
) -> dict:
    """Build the PowerMouse and its actuator into ``out_dir``; return the report dict (see module docstring).

    fidelity: "fabrication" checks all 52 extreme poses of the motion range
    and exports everything; "inertia"/"preview" check only the 12 on-axis
    poses. phi1_deg is ignored (no crank). Raises InterferenceError when the
    flotor overlaps the stator at the centre or anywhere in the range,
    unless allow_interference.
    """
    from cad.actuators import powermouse as pm
    from cad.export import export_assembly_step, export_part, write_bom
    from cad.massprops.occt import solid_mass_props
    from cad.massprops.props import combine
    from cad.materials import get_material
    from cad.parts import powermouse as pp
    from cad.parts import voicecoil as pv

    out_dir = Path(out_dir)
    total = 7
    _step(progress, "actuator optimum (eqs 8-9)", 0, total)
    act = actuator_optimum(design)
    gap = act["gap_mm"]
    g = pp.geometry(design, gap)

    _step(progress, "solids", 1, total)
    fl = pp.flotor_solids(g)
    st = pp.stator_solids(g)
    ag = pv.ActuatorGeometry(
        design.actuator.magnet_length_mm,
        design.actuator.magnet_width_mm,
        design.actuator.magnet_thickness_mm,
        gap,
        design.actuator.rattle_mm,
        design.actuator.plate_thickness_mm,
    )
    acts = pv.actuator_solids(ag)

    eta = design.actuator.eta_pack
    role_material = {
        "shell": design.flotor.material,
        "coil": design.flotor.coil_material,
        "handle": design.handle.material,
        "core": design.stator.iron_material,
        "iron": design.stator.iron_material,
        "magnet": design.stator.magnet_material,
        "housing": design.stator.housing_material,
        "spacer": "aluminium-6061",
        "carrier": design.flotor.material,
        "base": "aluminium-6061",
    }

    def density(role: str) -> float:
        rho = get_material(role_material[role]).density_kg_m3
        return (
            eta * rho if role == "coil" else rho
        )  # wound coil: conductor fraction eta_pack (insulation neglected)

    _step(progress, "mass properties from the solids", 2, total)
    parts_mp = {name: solid_mass_props(shape, density(role)) for name, (shape, role) in fl.items()}
    flotor_mp = combine(list(parts_mp.values()))
    stator_mass_kg = sum(solid_mass_props(s, density(r)).mass_kg for s, r in st.values())

    _step(progress, "wrench map and isotropy", 3, total)
    coils = g.coils()
    gain_per_At = act["Bg_T"] * 2.0 * design.actuator.magnet_length_mm * 1e-3  # N per ampere-turn
    W = pm.wrench_map(coils, gain_per_At)
    iso = pm.isotropy(W)
    com_mm = flotor_mp.com_m * 1e3
    W_com = pm.wrench_map(coils, gain_per_At, about_mm=com_mm)
    peak_F = pm.peak_force_N(act["peak_force_N"])
    cont_F = pm.peak_force_N(act["force_N"])
    acc = pm.peak_acceleration_m_s2(act["peak_force_N"], flotor_mp.mass_kg)

    _step(progress, "motion-range clearances", 4, total)
    poses = None
    if fidelity != "fabrication":
        poses = [
            p
            for p in pm.workspace_poses(design.motion.range_mm, design.motion.range_deg)
            if p[0].startswith("t")
            and sorted(map(abs, p[2])) == [0.0, 0.0, design.motion.range_mm]
            or p[0].startswith("r(")
            and p[0][1:10] in ("(1, 0, 0)", "(0, 1, 0)", "(0, 0, 1)")
        ]
    cl = pp.motion_clearances(g, design.motion.range_mm, design.motion.range_deg, fl, st, poses)
    worst = min(cl.nominal_mm, cl.translation_mm, cl.rotation_mm)
    if worst < 0 and not allow_interference:
        bad = [k for k, v in cl.poses.items() if v[0] < 0]
        raise InterferenceError(
            f"flotor overlaps the stator at {len(bad)} pose(s) of the +-{design.motion.range_mm:g} mm / "
            f"+-{design.motion.range_deg:g} deg range (e.g. {bad[0] if bad else 'centre'}); "
            "enlarge actuator.rattle_mm or flotor.corner_hole_mm, or pass --allow-interference"
        )
    rattle_single = pv.rattle_clearances_mm(ag, acts)

    _step(progress, "exports", 5, total)
    files: list[str] = []
    colors = {role: get_material(m).color_rgb for role, m in role_material.items()}
    unique = [
        ("pm_flotor_shell", fl["flotor_shell"][0], "shell", 1, "made", "CNC / 3D print"),
        ("pm_coil", fl["coil_+x"][0], "coil", 6, "made", "wound, potted"),
        ("pm_handle", fl["handle"][0], "handle", 1, "made", "turned"),
        ("pm_core_post", st["core_post"][0], "core", 1, "made", "machined"),
        ("pm_magnet", st["magnet_+x_inner-A"][0], "magnet", 24, "bought", "NdFeB block"),
        ("pm_iron_plate", st["iron_+x"][0], "iron", 6, "made", "machined"),
        ("pm_housing", st["housing"][0], "housing", 1, "made", "machined"),
    ]
    for key in ("iron_top", "spacer_+y", "coil", "coil_carrier", "base", "magnet_top_A"):
        shape, role = acts[key]
        qty = {"iron_top": 2, "spacer_+y": 2, "magnet_top_A": 4}.get(key, 1)
        kind = "bought" if role == "magnet" else "made"
        unique.append(
            (
                f"act_{key.replace('_top_A', '').replace('_top', '_plate').replace('_+y', '')}",
                shape,
                role,
                qty,
                kind,
                "",
            )
        )
    bom = []
    for name, shape, role, qty, kind, proc in unique:
        plate = name in ("act_iron_plate", "act_base", "pm_iron_plate")
        if formats:
            for p in export_part(
                shape, name, out_dir, formats, plate=plate, color=colors[role], stl=(kind == "made")
            ):
                files.append(p.name)
        mass_g = solid_mass_props(shape, density(role)).mass_kg * 1e3
        bom.append(
            {
                "part": name,
                "material": role_material[role],
                "quantity": qty,
                "made_or_bought": kind,
                "process": proc,
                "mass_g": mass_g,
            }
        )
    if "step" in formats:
        items = [(n, s, colors[r]) for n, (s, r) in {**fl, **st}.items()]
        files.append(export_assembly_step(items, out_dir / "powermouse_assembly.step").name)
        items = [(n, s, colors[r]) for n, (s, r) in acts.items()]
        files.append(export_assembly_step(items, out_dir / "actuator_assembly.step").name)
    files.append(write_bom(bom, out_dir).name)

    _step(progress, "Fig. 8 chart", 6, total)
    files += _fig8_chart(design, gap, out_dir)
    _step(progress, "done", total, total)

    return {
        "name": design.name,
        "family": design.family,
        "source": design.source,
        "actuator": act,
        "actuator_geometry_mm": {
            "gap_mm": gap,
            "coil_width_mm": ag.coil_width_mm,
            "plate_thickness_mm": ag.plate_thickness_mm,
            "height_mm": ag.height_mm,
            "rattle_clearances_mm": rattle_single,
        },
        "geometry_mm": {
            "flotor_edge_mm": g.flotor_edge_mm,
            "coil_plane_half_mm": g.coil_plane_half_mm,
            "core_half_mm": g.core_half_mm,
            "housing_inner_half_mm": g.housing_inner_half_mm,
        },
        "wrench_map": W.tolist(),
        "wrench_map_units": "columns per ampere-turn of each coil; rows F (N), tau about the cube centre (N m)",
        "wrench_map_singular_values": iso.singular_values.tolist(),
        "isotropy": {
            "force_singular_values": iso.force_sv.tolist(),
            "torque_singular_values": iso.torque_sv.tolist(),
            "force_spread": iso.force_spread,
            "torque_spread": iso.torque_spread,
            "force_torque_coupling": iso.coupling,
            "coupling_about_flotor_com": pm.isotropy(W_com).coupling,
        },
        "flotor": {
            **flotor_mp.to_dict(),
            "parts_mass_kg": {k: v.mass_kg for k, v in parts_mp.items()},
            "coil_density_kg_m3": density("coil"),
        },
        "stator_mass_kg": stator_mass_kg,
        "continuous_force_N": cont_F,
        "peak_force_N": peak_F,
        "peak_acceleration_m_s2": acc,
        "peak_acceleration_G": acc / pm.G0_M_S2,
        "clearances_mm": {
            "nominal_mm": cl.nominal_mm,
            "translation_mm": cl.translation_mm,
            "rotation_mm": cl.rotation_mm,
            "worst_translation": cl.worst_translation,
            "worst_rotation": cl.worst_rotation,
            "poses_checked": len(cl.poses),
            "range_mm": design.motion.range_mm,
            "range_deg": design.motion.range_deg,
            "poses": {k: {"clearance_mm": v[0], "closest": v[1]} for k, v in cl.poses.items()},
        },
        "paper_table4": PAPER_TABLE4,
        "files": sorted(files),
        "notes": [
            "Fig. 6 is lost: the cyclic coil layout, the inner core and the diagonal post/handle are our reconstruction.",
            "Forces use eq (8) with B_g of the chosen field model; peak force = 2 x actuator force at peak_power_W "
            "(the guaranteed zero-torque force in any direction).",
            f"touching (clearance 0) at the +-{design.motion.range_mm:g} mm limit is by design: rattle_mm/2 = "
            f"{design.actuator.rattle_mm / 2:g} mm.",
        ],
        "gain_N_per_ampere_turn": gain_per_At,
    }
