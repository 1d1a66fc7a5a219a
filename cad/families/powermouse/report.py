"""Report rows of a PowerMouse build: ``report.json`` keys and the ``report.md`` table; Table 4
of the paper beside ours."""

from __future__ import annotations

from cad.actuators import powermouse as pm
from cad.data.materials import get_material
from cad.families.powermouse.motion import pose_clearances

#: Paper Table 4 (PowerMouse performance), for side-by-side reporting.
PAPER_TABLE4 = {
    "workspace": "+-3 mm, +-5 deg",
    "continuous_force_N": 16.0,
    "peak_force_N": 34.0,
    "effective_mass_g": 260.0,
    "peak_acceleration_G": ">10",
}


def _notes(design) -> list[str]:
    """The notes of ``report.md`` / ``report.json``."""
    return [
        "Fig. 6 is lost: the cyclic coil layout, the inner core and the diagonal post/handle are our reconstruction.",
        "Forces use eq (8) with B_g of the chosen field model; peak force = 2 x actuator force at peak_power_W "
        "(the guaranteed zero-torque force in any direction).",
        f"touching (clearance 0) at the +-{design.motion.range_mm:g} mm limit is by design: rattle_mm/2 = "
        f"{design.actuator.rattle_mm / 2:g} mm.",
        "Assembly: the steps are in assembly.md (generated from the part instances and the "
        "fastener records, cad.assembly.steps, in the order of ASSEMBLY_PLAN).",
        "Finding the core's tapped hole: hold the housing with its (-,-,-) corner down (the diagonal "
        "vertical). The flotor then rests on the three lower outer magnet groups and the core on the "
        "flotor's three lower walls, each moved d_r/2 on every axis, i.e. along the diagonal: the "
        "post's tip meets the core's hole on its axis. Screw it in until its shoulder seats, draw the "
        "post out until its end is flush with the collar's end (the core is then centred), tighten "
        "the set screw. Magnets and iron plates are bonded (structural epoxy).",
        "rig/ holds the single-actuator test rig of Fig. 7 (one coil between two magnet pairs): a bench "
        "fixture to measure one actuator's force against eq (8), not part of the PowerMouse.",
        "Interference over the motion range (cad.assembly.interference.check_model, the check "
        "of every family): the flotor against the stator at the centre and every excursion "
        "(fcl mesh distances, exact OCCT where within 0.15 mm of contact and at the closest "
        "pose of each group), every pair of parts on one body once; touching is allowed, a "
        "common volume is a clash.",
    ]


def build_report(
    design,
    act,
    ag,
    g,
    W,
    iso,
    W_com,
    flotor_mp,
    parts_mass,
    stator_mass_kg,
    itf,
    cl,
    bom,
    rig_bom,
    rattle_single,
    gain_per_At,
) -> dict:
    peak_F = pm.peak_force_N(act["peak_force_N"])
    acc = pm.peak_acceleration_m_s2(act["peak_force_N"], flotor_mp.mass_kg)
    return {
        "actuator": act,
        "actuator_geometry_mm": {
            "gap_mm": ag.gap_mm,
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
            "parts_mass_kg": parts_mass,
            "coil_density_kg_m3": design.actuator.eta_pack
            * get_material(design.flotor.coil_material).density_kg_m3,
        },
        "flotor_mass_g": flotor_mp.mass_kg * 1e3,
        "stator_mass_kg": stator_mass_kg,
        "continuous_force_N": pm.peak_force_N(act["force_N"]),
        "peak_force_N": peak_F,
        "peak_acceleration_m_s2": acc,
        "peak_acceleration_G": acc / pm.G0_M_S2,
        "clearances_mm": pose_clearances(design, cl),
        "paper_table4": PAPER_TABLE4,
        "rig_bom": rig_bom,
        "notes": _notes(design),
        "gain_N_per_ampere_turn": gain_per_At,
    }


def report_md_rows(r: dict) -> list[tuple[str, str]]:
    c = r["clearances_mm"]
    return [
        ("actuator gap d (mm)", f"{r['actuator']['gap_mm']:.3f} ({r['actuator']['gap_source']})"),
        ("flotor mass (g)", f"{r['flotor_mass_g']:.1f}"),
        ("peak force (N), paper", f"{r['peak_force_N']:.1f}, {PAPER_TABLE4['peak_force_N']:g}"),
        ("peak acceleration (G)", f"{r['peak_acceleration_G']:.2f}"),
        (
            "clearance centre / translations / rotations / combined (mm)",
            f"{c['nominal_mm']:.3f} / {c['translation_mm']:.3f} / {c['rotation_mm']:.3f} / "
            + ("–" if c["combined_mm"] is None else f"{c['combined_mm']:.3f}"),
        ),
        (
            "solids / poses of the motion checked",
            f"{r['interference']['parts']} / {r['interference']['n_poses']}",
        ),
        ("overlap volume over the motion (mm^3)", f"{r['overlap_volume_mm3']:.4g}"),
    ]
