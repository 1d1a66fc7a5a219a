"""Datasheet rows of the haptic pen: the pantograph families' rows
(:func:`cad.families.pantograph.datasheet.rows_and_limits`: workspace, force at the pen from
the motor torque and the pen Jacobian, resolution, the effective mass at home, masses) with
Table 3 of the isotropy paper beside the figures it gives, and the interference check over
the motion. No CAD import.
"""

from __future__ import annotations

from cad.datasheet import row

#: report key of our figure -> the Table 3 key beside it.
_PAPER = {"effective_mass_home.mass_x_g_apparent": "mass_x_g",
          "effective_mass_home.mass_y_g_apparent": "mass_y_g",
          "effective_mass_home.mass_z_g_apparent": "mass_z_g"}


def rows_and_limits(design, report: dict, out_dir=None, simulate_wall: bool = True):
    """(rows, limits, notes) of a haptic-pen build report (module docstring)."""
    from cad.families.pantograph.datasheet import rows_and_limits as pantograph_rows

    rows, limits, notes = pantograph_rows(design, report, out_dir, simulate_wall)
    paper = report.get("paper_table3") or {}
    out = []
    for r in rows:
        key = _PAPER.get(r.get("key", ""))
        if key and paper.get(key) is not None:
            r = {**r, "paper": paper[key]}
        out.append(r)
    itf = report.get("interference") or {}
    if itf:
        out.append(row("overlap_volume_mm3", "largest solid overlap over the motion",
                       itf.get("overlap_volume_mm3"), "mm^3",
                       f"every pair of solids at {itf.get('poses')} poses of the workspace "
                       "(home, box corners at the rotation extremes)"))
    return out, limits, notes
