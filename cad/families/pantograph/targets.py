"""Values of a design of the pantograph families (pantograph, twin pantograph, haptic pen:
the families whose commands are ``check``/``fit`` without the four-bar's inertia model) for
``hapticad check`` and ``hapticad fit`` targets: the GII, the effective and moving masses of
a build, and every datasheet figure (:mod:`cad.families.pantograph.datasheet`: forces from
the motors, resolution, first modes, compliances, stress, clearance, total mass) when a
target needs it. (Was in cad/pipeline/inertia.py; the four-bar's part is
:mod:`cad.families.fourbar.inertia`.)"""

from __future__ import annotations

from cad.design.targets import PANTOGRAPH_DATASHEET_KEYS
from cad.families import family_package
from cad.families.pantograph.mode_ceiling import mode_ceiling
from cad.pipeline import build_design
from cad.structure.pantograph import WEB_WIDTH_MIN_MM

#: Datasheet figures that need no build (the Jacobian, the motors, the encoder).
NO_BUILD_KEYS = frozenset({"continuous_force_N", "peak_force_N", "force_any_dir_N", "force_best_dir_N",
                           "resolution_um"})


def pantograph_target_values(design, fidelity: str, wanted: set[str]) -> tuple[dict, dict]:
    """(flat values for targets, build report) of a pantograph-family design: the GII always;
    effective mass, moving mass and the datasheet figures of the build when a target needs
    them (the figures of :data:`NO_BUILD_KEYS` without a build)."""
    import tempfile
    from pathlib import Path

    values = {"gii": float(design.gii().gii)}
    rest = wanted - {"gii"}
    if not rest:
        return values, {}
    rep: dict = {}
    if rest - NO_BUILD_KEYS:

        with tempfile.TemporaryDirectory() as tmp:
            rep = build_design(design, Path(tmp) / "b", set(), fidelity=fidelity, use_cache=False,
                               simulate_wall=False)
    for k, v in (rep.get("effective_mass_home") or {}).items():
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            values[k] = float(v)
    if isinstance(rep.get("moving_mass_g"), (int, float)):
        values["moving_mass_g"] = float(rep["moving_mass_g"])
    if rest & set(PANTOGRAPH_DATASHEET_KEYS):
        values.update(datasheet_values(design, rep))
    return values, rep


def datasheet_values(design, report: dict) -> dict[str, float]:
    """{row key: value} of the design's datasheet rows (its family's ``rows_and_limits`` on
    the build ``report``; ``{}`` for the rows that need no build), None values left out."""
    rows, _, _ = family_package(design.family).datasheet_rows(design, report, None,
                                                             simulate_wall=False)
    return {r["key"]: float(r["value"]) for r in rows if r["value"] is not None}


def mode_blocker_lines(design, report: dict, rows) -> list[str]:
    """For a missed first-mode target (``first_mode_Hz``, rows of :func:`cad.checks.evaluate`
    with a ``min``) of a planar family's build ``report``: the line of
    :func:`cad.families.pantograph.mode_ceiling.mode_ceiling` saying what limits the mode and
    the best figure the tubes reach in this layout; none otherwise."""
    missed = [r for r in rows if r.key == "first_mode_Hz" and not r.ok and (r.target_data or {}).get("min") is not None]
    if not missed or not report.get("bodies"):
        return []
    web = (report.get("layout_mm") or {}).get("web_width_mm", WEB_WIDTH_MIN_MM)
    return [mode_ceiling(design, report["bodies"], web, float(missed[0].target_data["min"]))["text"]]
