"""Datasheet rows of the haptic pen: the pantograph families' rows
(:func:`cad.families.pantograph.datasheet.rows_and_limits`: workspace, force at the pen from
``[actuators] torque_max_Nm`` and the pen Jacobian, resolution, the effective mass at home,
masses), the continuous and peak force from the catalog motors' data-sheet torques (waist
motors on q1, q4, shoulder motors on the others; same ellipsoid model: the smallest singular
value of the translational rows of ``J^T S_J`` over the workspace samples, the moments left
free), with Table 3 of the isotropy paper beside the figures it gives, and the interference
check over the motion. No CAD import.
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
    out += motor_force_rows(design, paper)
    itf = report.get("interference") or {}
    if itf:
        out.append(row("overlap_volume_mm3", "largest solid overlap over the motion",
                       itf.get("overlap_volume_mm3"), "mm^3",
                       f"every pair of solids at {itf.get('n_poses')} poses of the workspace "
                       "(home, box corners at the rotation extremes)"))
    return out, limits, notes


def motor_force_rows(design, paper: dict) -> list[dict]:
    """Continuous and peak force in every direction at the pen over the workspace, from the
    catalog torques of the waist and shoulder motors (module docstring); Table 3's smallest
    axis value beside each (its x, y, z figures are per axis)."""
    import numpy as np

    from cad.data.catalog import get_motor
    from cad.families.pantograph.datasheet import FORCE_COLS, jacobian_and_limits

    J, _, ok = jacobian_and_limits(design)
    w, s = get_motor(design.parts.waist_motor), get_motor(design.parts.motor)
    rows = []
    for key, field, label in (("continuous_force_N", "torque_continuous_mNm", "continuous"),
                              ("peak_force_N", "torque_peak_mNm", "peak")):
        tw, ts = getattr(w, field), getattr(s, field)
        if tw is None or ts is None or not ok.any():
            rows.append(row(key, f"{label} force in every direction", None, "N",
                            "no data-sheet torque for a motor"))
            continue
        tau = np.array([tw, ts, ts, tw, ts, ts]) * 1e-3
        A = np.swapaxes(J, -1, -2)[:, FORCE_COLS["haptic-pen"], :] * tau[None, None, :]
        sig = np.linalg.svd(A[ok], compute_uv=False)[:, -1]
        ref = [paper.get(f"{label}_force_{a}_N") for a in "xyz"]
        unverified = w.is_unverified(field) or s.is_unverified(field)
        rows.append(row(key, f"{label} force in every direction", sig.min(), "N",
                        f"min over the workspace of sigma_min(J^T S_J), S_J = the {label} torques "
                        f"of {w.key} (waist, {tw:g} mN m) and {s.key} (shoulders, {ts:g} mN m)",
                        lo=sig.min(), hi=sig.max(), unverified=unverified,
                        paper=min(v for v in ref if v is not None) if any(ref) else None))
    return rows
