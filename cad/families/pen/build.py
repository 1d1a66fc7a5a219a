"""Build the haptic pen (isotropy paper §4.2, Fig. 4, Tables 2-3): parts, files, mass
properties, effective mass at home, the interference check over its motion, MJCF.

Contract: :mod:`cad.pipeline` (``build(design, out_dir, formats, *, fidelity,
allow_interference, progress, phi1_deg) -> report dict``; ``phi1_deg`` must be None, the pen
has no crank). ``build`` is one call to the build driver of every family
(:func:`cad.pipeline.run.run_family`) with the pen's stages (:func:`_stages`): the shared
writers of :mod:`cad.pipeline.family`
(part files, assembly STEP, BOM, report.md, assembly.md) and the one interference check of every family
(:func:`cad.assembly.interference.check_model`) over the assembly model's motion
(:func:`cad.families.pen.layout.motion_task`).

Report keys: ``layout_mm``, ``ground_mm``, ``bodies`` (mass properties of each moving body
from the exact B-rep, in its body frame), ``effective_mass_home`` (the 5 x 5 operational mass
matrix at home and its diagonal, :func:`cad.families.pen.dynamics.effective_mass`),
``interference`` (every pair of bodies at every pose of the motion, every pair of parts on
one body once), ``min_clearance_mm``, ``moving_mass_g``,
``total_mass_g``, ``bom``, ``fits``, ``files``, ``paper_table3``.
"""

from __future__ import annotations

from pathlib import Path

from cad.assembly import interference as itf
from cad.device import encoder_bom_rows, resolve_device
from cad.errors import DesignError
from cad.families.pantograph.capstan import bom_lines as capstan_bom_lines
from cad.families.pantograph.capstan import winding_steps
from cad.families.pen import assemble
from cad.families.pen import layout as L
from cad.families.pen.capstan_layout import refuse_solids as refuse_capstan_solids
from cad.families.pen.datasheet import breakdown_text
from cad.families.pen.dynamics import PenDynamics, dynamics, mass_breakdown
from cad.families.pen.layout import body_poses, stroke_task
from cad.families.pen.sim import write_mjcf
from cad.pipeline.run import Stages, run_family

#: Table 3 of the isotropy paper (the built pen at home; g, g cm^2, N, N cm).
PAPER_TABLE3 = {
    "mass_x_g": 190.0, "mass_y_g": 226.0, "mass_z_g": 156.0,
    "inertia_rx_g_cm2": 10300.0, "inertia_rz_g_cm2": 12600.0,
    "peak_force_x_N": 24.0, "peak_force_y_N": 21.0, "peak_force_z_N": 20.0,
    "continuous_force_x_N": 2.5, "continuous_force_y_N": 3.3, "continuous_force_z_N": 2.0,
}


#: Final checks of assembly.md (:mod:`cad.assembly.steps`; the steps follow the bodies in
#: the order of the assembly model, each body's parts before the fasteners that join them).
ASSEMBLY_CHECKS = (
    "each motor shaft turned by hand moves its arm over the whole workspace box (report.md) "
    "with no binding and no contact between links",
    "the pen turns freely about its own axis (the roll is passive) and in both gimbals",
    "the clevis set screws are tight (no slip of a hub on its shaft flat)",
)


def check_options(design, fidelity: str, phi1_deg, formats=frozenset()) -> None:
    """Refuse what this builder cannot do, before any CAD import (DesignError)."""
    if phi1_deg is not None:
        raise DesignError("--phi1-deg", f"a haptic pen has no crank angle, got {phi1_deg!r}; "
                          "the assembly is exported at the workspace centre")
    if "urdf" in set(formats):
        raise DesignError("--formats", "urdf is not written for the haptic pen (mjcf is)")

    refuse_capstan_solids(design)  # capstan pairs that cannot be laid out: one line with where the layout puts them
    L.layout(design)  # hardware that does not fit: named before any CAD


def interference(model, allow_interference: bool = False, same_body=None) -> dict:
    """The one interference check (:func:`cad.assembly.interference.check_model`) of the pen
    over its motion: every pair of bodies at each pose of ``model.motion`` (labelled), every
    pair of parts on one body once; touching allowed, a common volume above
    :data:`cad.assembly.interference.OVERLAP_MIN_MM3` is a clash. Returns the report's
    ``interference`` dict (``min_clearance_mm``, ``overlap_volume_mm3``, ``pairs``,
    ``collisions`` with parts, pose label and volume, ``n_poses`` ...); InterferenceError
    naming the pair, the pose and the volume of the first clash unless allow_interference. ``same_body``: the build's same-body result (:meth:`cad.pipeline.run.Build.same_body`;
    None: computed here)."""
    rep = itf.check_model(model, fail_fast=not allow_interference, same_body=same_body)
    if not allow_interference:
        itf.raise_on_collision(rep, 0.0)
    out = rep.as_dict()
    out["parts"] = len(model.instances)
    out["overlap_threshold_mm3"] = itf.OVERLAP_MIN_MM3
    return out


def _dynamics(b) -> PenDynamics:
    """The 5 x 5 operational mass matrix at home (:func:`cad.families.pen.dynamics.dynamics`)."""
    return dynamics(b.design, b.bodies, b.model.extra.home_task)


def _mjcf(b) -> list[str]:
    """``<name>.xml`` when ``mjcf`` is asked (:mod:`cad.families.pen.sim`)."""
    if "mjcf" not in b.formats:
        return []

    return write_mjcf(b.design, b.model, b.bodies, b.out_dir)


def _stroke(design):
    return body_poses(design, stroke_task(design))


def _assemble(design, fidelity: str):
    return assemble(design, fidelity)


def _encoder_rows(design) -> list[dict]:
    """The joint encoders the device carries (one per motor, no solid): BOM lines from the
    resolved device (:func:`cad.device.encoder_bom_rows`); the capstans' ropes with their cut
    lengths (:func:`cad.families.pantograph.capstan.bom_lines`, the shared rows)."""
    return encoder_bom_rows(resolve_device(design)) + capstan_bom_lines(design)


def _stages():
    """The pen's stages of the one build driver (:class:`cad.pipeline.run.Stages`)."""
    return Stages(
        check_options=check_options, assemble=_assemble, interference=lambda b: interference(b.model, b.allow_interference, b.same_body()),
        report=lambda b: {**_report(b.design, b.model, b.bodies, b.dyn.effective_mass_home, b.itf, b.bom, b.fidelity, b.low),
                          "effective_mass_breakdown": mass_breakdown_report(b.design, b.model, b.props)},
        md_rows=_md_rows, stroke=_stroke, motion_label="motion",
        preview_title=lambda b: f"{b.design.name}: haptic pen at the workspace centre",
        dynamics=_dynamics, bench_z_mm=lambda b: b.model.extra.ground_mm["bench_z_mm"],
        thread_notes=False,  # the pen's DXF/drawings carry no tapped-hole notes (as before)
        more_files=_mjcf, assembly=lambda design: (None, ASSEMBLY_CHECKS + winding_steps(design)),
        no_solid_rows=_encoder_rows)


def build(design, out_dir: Path, formats: set[str], *, fidelity: str = "fabrication",
          allow_interference: bool = False, progress=None, phi1_deg: float | None = None) -> dict:
    """Build the pen into ``out_dir``; return the report dict (module docstring), through the
    one build driver (:func:`cad.pipeline.run.run_family`).

    Raises InterferenceError naming both parts and the pose when two solids share volume at
    any pose of the motion (unless ``allow_interference``); GeometryError when a solid
    reaches below the bench plane.
    """
    return run_family(_stages(), design, out_dir, formats, fidelity=fidelity,
                      allow_interference=allow_interference, progress=progress,
                      phi1_deg=phi1_deg)


def _report(design, model, bodies, eff, itf, bom, fidelity, low) -> dict:
    g = design.gii()
    lay = {k: v for k, v in model.extra.layout_mm.items() if k != "bearing"}
    gl = model.extra.ground_mm
    home = model.extra.home_task
    return {
        "design": design.name,
        "gii": {"gii": g.gii, "sigma_min": g.sigma_min, "sigma_max": g.sigma_max},
        "layout_mm": lay, "ground_mm": gl,
        "home": {"x_mm": float(home[0]), "y_mm": float(home[1]), "z_mm": float(home[2]),
                 "yaw_deg": 0.0, "pitch_deg": 0.0},
        "bench_z_mm": gl["bench_z_mm"], "lowest_z_mm": low,
        "effective_mass_home": eff,
        "paper_table3": PAPER_TABLE3,
        "notes": [
            "Every pair of bodies is checked at every pose of the motion (home, the eight "
            "corners of the workspace box at two rotation extremes each, the four rotation "
            "corners at the centre; cad.assembly.interference.check_model), every pair of parts "
            f"on one body once: common volume > {itf['overlap_threshold_mm3']:g} mm^3 is a "
            "collision.",
            "The pen's roll is passive; the poses keep the pen hub's b axis horizontal.",
            "Effective mass: 5 x 5 operational mass matrix at home, task velocity (x, y, z m/s, "
            "w_yaw, w_pitch rad/s), from the solids' body mass properties and the rotors' "
            "inertia through the pen Jacobian. Table 3 (paper) is measured on the built device.",
            "Every screw is sized from its stack by the twin pantograph's screw plan (fasteners, "
            "tapped_holes). Not modelled yet: the hub set screws, the bracket-to-hub screws, "
            "the counterbalances behind the shoulder motors.",
        ],
    }


#: Table 3's effective mass along x (g), the figure the breakdown is set against.
PAPER_MASS_X_G = PAPER_TABLE3["mass_x_g"]
#: Groups of the breakdown: (label, test on (body, kind name)), first match wins; rotors apart.
BREAKDOWN_GROUPS = (
    ("shoulder motors (on the waist brackets)", lambda b, k: b.endswith("_waist") and k.startswith("motor")),
    ("waist brackets (bracket, hub, screws)", lambda b, k: b.endswith("_waist")),
    ("links (tubes, clevises, pins, bearings)", lambda b, k: "proximal" in b or "distal" in b),
    ("gimbals (yokes, rings, their pins and bearings)", lambda b, k: b.endswith(("_yoke", "_ring"))),
    ("pen (rod, hubs, bearings)", lambda b, k: b == "pen"),
)


def mass_breakdown_report(design, model, props: dict) -> dict:
    """report.json ``effective_mass_breakdown``: the effective mass at home along x (diagonal,
    others held) split over every part and the rotors
    (:func:`cad.families.pen.dynamics.mass_breakdown`), grouped by :data:`BREAKDOWN_GROUPS`, with
    Table 3's 190 g beside it and the figure with the shoulder motors taken off the waists
    (``without_shoulder_motors_g``: what grounding them would leave; not the paper's layout,
    whose shoulder motors turn with the waists, §4.2). Grams."""
    parts: dict[str, list] = {}
    for i in model.instances:
        mp = props.get(i.kind.name)
        if mp is not None:
            T = i.tf_body_part
            parts.setdefault(i.body, []).append((i.kind.name, mp.transformed(T[:3, :3], T[:3, 3] * 1e-3)))
    home = model.extra.home_task
    r = mass_breakdown(design, parts, home, "x")
    groups = {label: 0.0 for label, _ in BREAKDOWN_GROUPS}
    by_kind: dict[str, float] = {}
    for body, kind, v in r["parts"]:
        label = next(lab for lab, test in (*BREAKDOWN_GROUPS, ("other", lambda b, k: True)) if test(body, kind))
        groups[label] = groups.get(label, 0.0) + v * 1e3
        by_kind[kind] = by_kind.get(kind, 0.0) + v * 1e3
    groups["motor rotors (reflected)"] = sum(v for _, v in r["rotors"]) * 1e3
    motors = groups[BREAKDOWN_GROUPS[0][0]]
    return {"axis": "x", "at_task": [float(v) for v in home], "total_g": r["total"] * 1e3,
            "groups_g": groups, "by_kind_g": dict(sorted(by_kind.items(), key=lambda kv: -kv[1])),
            "rotors_g": {j: v * 1e3 for j, v in r["rotors"]},
            "without_shoulder_motors_g": r["total"] * 1e3 - motors, "paper_g": PAPER_MASS_X_G}


def _md_rows(r: dict) -> list[tuple[str, str]]:
    em = r["effective_mass_home"]
    rows = [("GII (workspace)", f"{r['gii']['gii']:.4f}"),
            ("moving mass (g)", f"{r['moving_mass_g']:.1f}"),
            ("total mass (g)", f"{r['total_mass_g']:.1f}"),
            ("poses checked / smallest clearance over them (mm)",
             f"{r['interference']['n_poses']} / {r['min_clearance_mm']:.3g}"),
            ("largest overlap (mm^3)", f"{r['overlap_volume_mm3']:.4g}"),
            ("bench plane / lowest solid z (mm)", f"{r['bench_z_mm']:.1f} / {r['lowest_z_mm']:.1f}")]
    for k, v in em.items():
        if isinstance(v, float):
            rows.append((f"effective mass at home: {k}", f"{v:.4g}"))
    bd = r.get("effective_mass_breakdown")
    if bd:

        rows.append(("effective mass along x: where it comes from", breakdown_text(bd)))
    return rows
