"""Report rows of a pantograph-family build: ``report.json`` keys and the ``report.md`` table."""

from __future__ import annotations

import numpy as np

from cad.device import resolve_device
from cad.families.pantograph.layout import is_twin

#: Paper Table 1 (haptic mouse at its home position).
PAPER_TABLE1 = {
    "mass_x_g": 395.0,
    "mass_y_g": 370.0,
    "inertia_theta_g_cm2": 4781.0,
    "peak_force_x_N": 23.0,
    "peak_force_y_N": 22.0,
    "continuous_force_x_N": 2.4,
}


def capstan_json(cap: dict) -> dict:
    """The layout's ``capstan`` entry (:func:`cad.families.pantograph.capstan.layout`) as plain
    JSON: each motor's direction, centre distance, position, joint range and drum arc (mm, deg)."""
    sides = [{"joint": sd.joint, "alpha_deg": sd.alpha_deg, "centre_distance_mm": sd.centre_distance_mm,
              "motor_xy_mm": [float(v) for v in sd.motor_xy_mm], "joint_range_deg": list(sd.q_range_deg),
              "drum_arc_link_deg": [sd.arc_start_deg, sd.arc_span_deg],
              "tangents_mm": np.asarray(sd.tangents_mm).tolist()} for sd in cap["sides"]]
    return {"sides": sides, "rope_z_mm": cap["rope_z_mm"], "drum_z_mm": list(cap["drum_z_mm"]),
            "lift_mm": cap["lift_mm"]}


def build_report(design, lay, clr, bodies, eff, eff_bare, itf, bom, home, fidelity, low) -> dict:
    g = design.gii()
    dev_motor = resolve_device(design).motor  # the motor the BOM orders
    mot = dev_motor.spec
    report = {
        "design": design.name,
        "gii": {
            "gii": g.gii,
            "sigma_min": g.sigma_min,
            "sigma_max": g.sigma_max,
            "sigma_min_at": g.sigma_min_at.tolist(),
            "sigma_max_at": g.sigma_max_at.tolist(),
        },
        "layout_mm": {k: (capstan_json(v) if k == "capstan" else v) for k, v in lay.items()},
        "clearances_mm": clr,
        "bench_z_mm": lay["bench_z_mm"],
        "lowest_z_mm": low,
        "motor": {
            "key": mot.key,
            **({"name": dev_motor.name} if dev_motor.from_motor_table else {}),
            "rotor_inertia_g_cm2": mot.rotor_inertia_g_cm2,
            # as the four-bar's report: a [motor] table is named, never the catalog's source alone
            "source": (mot.source if not dev_motor.from_motor_table else
                       f"the design's [motor] table over the mount of {mot.key} ({mot.source})"),
        },
        "home": {"x_mm": float(home[0]), "y_mm": float(home[1])},
        "effective_mass_home": eff,
        "notes": [
            "The base plate stands on four leg standoffs: no solid lies below the bench plane "
            f"z = {lay['bench_z_mm']:.1f} mm (lowest solid at {low:.1f} mm).",
            f"Every pair of bodies is checked on the solids at {itf['n_poses']} poses of the "
            "workspace (home, a grid over the square" + (", x crank angles over the full turn"
            if is_twin(design) else "") + "), every pair of parts on one body once (common "
            f"volume > {itf['overlap_threshold_mm3']:g} mm^3 is a collision; touching is "
            "allowed); clearances_mm gives the 2-D gaps between parts of one layer over the "
            "finer GII grid.",
            "Every screw is sized from its stack (fasteners, tapped_holes): catalog ISO 4762 "
            "length, engagement between 1.5 d (aluminium; the maker's minimum in the motor "
            "face) and the tapped hole's depth, one screw per hole. Each hub clevis is locked on "
            f"its {'link axle' if 'capstan' in lay else 'motor shaft'} by an ISO 4026 {lay['set_screw']['size']} x "
            f"{lay['set_screw']['length_mm']:g} set screw tapped radially through its wall "
            "(the longest catalog length not proud of the round end, >= 1.5 d).",
        ],
    }
    if is_twin(design):
        report["crank_mm"] = design.mechanism.crank_mm
        report["home"]["theta_deg"] = float(design.workspace["home_theta_deg"])
        report["effective_mass_home_without_rotors"] = eff_bare
        report["paper_table1"] = PAPER_TABLE1
        report["effective_mass_note"] = (
            "diag = mass felt moving one task axis with the others held; apparent = 1/(M^-1)_ii, "
            "the others free. Ours differs from Table 1 because the paper's values are measured on "
            "the built device (closed-loop identification, includes the real motors, encoders, "
            "cabling, fasteners and friction) and its link lengths, tube sizes and motors are not "
            "published; here the moving parts are the solids above with catalogue bearing and rotor data."
        )
    return report


def report_md_rows(r: dict) -> list[tuple[str, str]]:
    rows = [
        ("GII (workspace)", f"{r['gii']['gii']:.4f}"),
        ("moving mass (g)", f"{r['moving_mass_g']:.1f}"),
        ("total mass (g)", f"{r['total_mass_g']:.1f}"),
        (
            "min layer clearance over the workspace (mm)",
            f"{r['clearances_mm']['min_gap_mm']:.2f} ({r['clearances_mm']['worst']})",
        ),
        (
            "solids / poses of the workspace checked",
            f"{r['interference']['parts']} / {r['interference']['n_poses']}",
        ),
        ("min clearance between bodies over the workspace (mm)", f"{r['min_clearance_mm']:.2f}"),
        ("overlap volume over the workspace (mm^3)", f"{r['overlap_volume_mm3']:.4g}"),
        ("bench plane / lowest solid z (mm)", f"{r['bench_z_mm']:.1f} / {r['lowest_z_mm']:.1f}"),
    ]
    for k, v in r["effective_mass_home"].items():
        if isinstance(v, float):
            rows.append((f"effective mass at home: {k}", f"{v:.4g}"))
    return rows
