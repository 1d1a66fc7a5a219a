"""Datasheet rows of the PowerMouse (maglev, 6 Lorentz actuators; isotropy paper §5).

From the build report: the workspace (``[motion]`` range), the wrench map ``W`` (6 x 6,
columns per ampere-turn of each coil, rows force N and torque N m about the cube centre):
the force and the torque available in every direction per ampere-turn of coil current are
the smallest singular values of its force rows and its torque rows (the other part of the
wrench left free); the continuous and peak force at the coil powers ``power_W`` /
``peak_power_W`` (eq 8-9 actuator force, two actuators per axis with zero torque:
:func:`cad.actuators.powermouse.peak_force_N`), the flotor's mass (the moving mass), its
peak acceleration and the clearances over the motion; Table 4 of the paper beside them.
No CAD import.
"""

from __future__ import annotations

import numpy as np

from cad.datasheet import row
from cad.datasheet.limits import Limit


def rows_and_limits(design, report: dict, out_dir=None, simulate_wall: bool = True):
    """(rows, limits, notes) of a PowerMouse build report (module docstring)."""
    paper = report.get("paper_table4") or {}
    mo = design.motion
    rows = [row("workspace", f"workspace +-{mo.range_mm:g} mm, +-{mo.range_deg:g} deg", mo.range_mm, "mm",
                "[motion] range: every pose of translation and rotation checked for clearance",
                paper=paper.get("workspace"))]
    W = np.asarray(report.get("wrench_map") or np.zeros((6, 6)), float)
    fsv = np.linalg.svd(W[:3], compute_uv=False)
    tsv = np.linalg.svd(W[3:], compute_uv=False)
    rows.append(row("force_per_At_N", "force per ampere-turn, every direction", fsv[-1], "N/At",
                    "sigma_min of the wrench map's force rows (torque left free)", lo=fsv[-1], hi=fsv[0]))
    rows.append(row("torque_per_At_mNm", "torque per ampere-turn, every direction", tsv[-1] * 1e3, "mN m/At",
                    "sigma_min of the wrench map's torque rows about the cube centre", lo=tsv[-1] * 1e3, hi=tsv[0] * 1e3))
    act = design.actuator
    rows.append(row("continuous_force_N", "continuous force, every direction", report.get("continuous_force_N"), "N",
                    f"2 x the eq (8-9) actuator force at power_W = {act.power_W:g} W per coil (zero torque)",
                    paper=paper.get("continuous_force_N")))
    rows.append(row("peak_force_N", "peak force, every direction", report.get("peak_force_N"), "N",
                    f"2 x the actuator force at peak_power_W = {act.peak_power_W:g} W per coil (zero torque)",
                    paper=paper.get("peak_force_N")))
    rows.append(row("flotor_mass_g", "moving mass (flotor with coils and handle)", report.get("flotor_mass_g"), "g",
                    "from the solids", boundary="levitated: no joint, the whole flotor moves",
                    paper=paper.get("effective_mass_g")))
    rows.append(row("peak_acceleration_G", "peak acceleration", report.get("peak_acceleration_G"), "G",
                    "peak force / flotor mass", paper=paper.get("peak_acceleration_G")))
    rows.append(row("min_clearance_mm", "smallest clearance over the motion", report.get("min_clearance_mm"), "mm",
                    "coils, post and handle against the stator at every pose of [motion]"))
    if isinstance(report.get("stator_mass_kg"), (int, float)):
        rows.append(row("total_mass_g", "total mass (stator + flotor)",
                        report["stator_mass_kg"] * 1e3 + (report.get("flotor_mass_g") or 0.0), "g", "from the solids"))
    rows.append(row("resolution_um", "position resolution", None, "um",
                    "not modelled: the PowerMouse's position sensors are not part of the design"))
    rows.append(row("friction_N", "Coulomb friction at the handle", 0.0, "N",
                    "none by construction: the flotor levitates (no contact, no bearing)"))
    limits = {"min_clearance_mm": Limit(">=", 0.0, "no overlap anywhere in [motion]; touching at the +-range "
                                        "stop (rattle_mm / 2) is by design",
                                        "motion.range_mm / range_deg, actuator.rattle_mm, flotor.corner_hole_mm")}
    return rows, limits, []
