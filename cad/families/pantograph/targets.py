"""Values of a design of the pantograph families (pantograph, twin pantograph, haptic pen:
the families whose commands are ``check``/``fit`` without the four-bar's inertia model) for
``hapticad check`` and ``hapticad fit`` targets: the GII, and the effective and moving
masses of a build when a target needs them. (Was in cad/pipeline/inertia.py; the four-bar's
part is :mod:`cad.families.fourbar.inertia`.)"""

from __future__ import annotations


def pantograph_target_values(design, fidelity: str, wanted: set[str]) -> tuple[dict, dict]:
    """(flat values for targets, build report) of a pantograph-family design: the GII always; effective mass and moving mass from a build when a target needs them."""
    import tempfile
    from pathlib import Path

    values = {"gii": float(design.gii().gii)}
    if not wanted - {"gii"}:
        return values, {}
    from cad.pipeline import build_design

    with tempfile.TemporaryDirectory() as tmp:
        rep = build_design(design, Path(tmp) / "b", set(), fidelity=fidelity, use_cache=False,
                           simulate_wall=False)
    for k, v in (rep.get("effective_mass_home") or {}).items():
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            values[k] = float(v)
    if isinstance(rep.get("moving_mass_g"), (int, float)):
        values["moving_mass_g"] = float(rep["moving_mass_g"])
    return values, rep
