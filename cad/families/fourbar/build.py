"""Build a four-bar haptic display: parts, masses, H11..H33, interference, exports, report.

Pipeline (``hapticad build designs/hoeken.toml``):

1. the assembly (:func:`cad.families.fourbar.assemble`): kinematics, z-layers and joint
   stacks, every part placed on its body, the bodies at the exported crank angle and over
   the sweep;
2. mass properties per part kind and per body in the link frame, by the pipeline's one
   body-mass-property function (:func:`cad.pipeline.family.kind_props`,
   :func:`cad.pipeline.family.body_props`); H11..H33 and the apparent mass M(phi1)
   (:mod:`cad.dynamics.inertia`, Hoeken paper eqs 14-22) with the motor's rotor inertia Jm;
3. interference sweep (:mod:`cad.assembly.interference`): an
   :class:`cad.errors.InterferenceError` unless ``allow_interference``;
4. files into ``out_dir`` through the shared writers: ``parts/<part>.step|.stl|.dxf`` and
   ``assembly.step`` (:func:`cad.pipeline.family.write_outputs`), ``assembly.glb``,
   ``parts.3mf``, ``animation.gif`` + ``render.png``
   (:func:`cad.pipeline.views.write_viewer_outputs`), MJCF/URDF
   (:func:`cad.pipeline.views.write_sim_model`), ``bom.csv``, ``assembly.md``,
   ``preview.png`` and ``report.md`` (:mod:`cad.pipeline.family`; the dispatcher adds
   ``report.json``, ``report.html`` and ``manifest.json``).

``build`` is one call to the build driver of every family
(:func:`cad.pipeline.run.run_family`) with the four-bar's stages (:func:`_stages`). Once the
parts exist, the part files + assembly STEP, the viewer files (glb, 3mf, GIF, still) and the
same-body check run in forked children beside the mass properties (as for every family);
once H is known, the paper's plots run in a further child beside the sweep
(:mod:`cad.pipeline.forked`; serial where forking is off, same bytes either way). The report carries the stages' wall times (``_timings_s``).

Fidelity (issue 7): ``fabrication`` -- every feature, bd_warehouse bearings with balls,
exact interference confirmation; ``inertia`` -- cosmetic features dropped (knob round,
bearing balls: the bearing mass is the catalog mass at every fidelity), exact
interference; ``preview`` -- as ``inertia`` with STL at 0.1 mm, at most
:data:`cad.families.fourbar.layout.PREVIEW_POSES` poses and a mesh-only interference
sweep. The report states what the dropped features cost on this design
(``fidelity_costs``).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any

import numpy as np

from cad.analysis import METRIC_KEYS, apparent_mass_curves
from cad.assembly import interference as itf
from cad.device import encoder_bom_rows, resolve_device
from cad.dynamics.inertia import PlanarLinkInertia, apparent_mass_summary, h_from_links
from cad.export.nesting import plan_sheets, sheets_report
from cad.families.fourbar import capstan
from cad.families.fourbar.layout import (
    LINKS,
    PREVIEW_POSES,
    assemble,
    check_layout,
    exported_phi1_rad,
    sweep_angles,
)
from cad.families.fourbar.pose import body_transforms
from cad.families.fourbar.sheet_tolerance import handle_floor_mm, tolerance_report
from cad.families.fourbar.sim import sim_model
from cad.kinematics.fourbar import solve
from cad.kinematics.metrics import compute_metrics
from cad.parts import PartKind
from cad.parts.handle import knob_shape
from cad.pipeline import family
from cad.pipeline.run import Stages, run_family
from cad.pipeline.views import STROKE_POSES, write_sim_model
from cad.report.fourbar import plot_apparent_mass, plot_kinematics
from cad.structure.device import structure_of_build
from cad.tolerances import PREVIEW_STL_TOL_MM

__all__ = ["LINKS", "PREVIEW_POSES", "PREVIEW_STL_TOL_MM", "build", "check_layout", "sweep_angles"]

#: Final checks of assembly.md (cad.assembly.steps).
ASSEMBLY_CHECKS = (
    "the crank turns by hand over its whole range (report.md: crank range) with no binding "
    "and no contact between the bars",
    "the motor turns the crank with the hub's set screw tight (no slip on the shaft flat)",
)


def encoder_bom_row(design) -> dict:
    """The crank encoder as a bought BOM line (no solid: it sits on the motor's rear shaft):
    the resolved device's encoder (:func:`cad.device.encoder_bom_rows`)."""
    return encoder_bom_rows(resolve_device(design))[0]


def inertia_from_links(design, link_props: dict, Jm_kg_m2: float):
    """H11..H33 (Hoeken paper eqs 16-19, COM angle generalization) from the link mass props
    (``{link: MassProps}`` SI, link frame); returns ``(H, {link: PlanarLinkInertia})``."""
    pl = {
        k: PlanarLinkInertia.from_com(
            link_props[k].mass_kg, link_props[k].com_m, float(link_props[k].inertia_com_kg_m2[2, 2])
        )
        for k in LINKS
    }
    return h_from_links(design.linkage, pl["crank"], pl["coupler"], pl["rocker"], Jm_kg_m2), pl


def apparent_mass(design, H) -> dict:
    """M11/M12/M22 over the stroke (Hoeken paper eq 22), summarised (g)."""
    return apparent_mass_summary(apparent_mass_curves(design, H)["M_kg"])


def joint_axes(J) -> dict:
    return {
        ("crank", "ground"): [(J["crank"]["A1"], J["ground"]["A1"])],
        ("coupler", "crank"): [(J["coupler"]["A2"], J["crank"]["A2"])],
        ("coupler", "rocker"): [(J["coupler"]["A3"], J["rocker"]["A3"])],
        ("ground", "rocker"): [(J["ground"]["A4"], J["rocker"]["A4"])],
    }


def _preview_title(b) -> str:
    phi_deg = math.degrees(b.model.extra.pose_phi1_rad)
    return f"{b.design.name}: {b.design.family}, phi1 = {phi_deg:.1f} deg"


def _marks(b) -> list:
    """The coupler point's path on preview.png's top view."""
    return [("P path", solve(b.design.linkage, sweep_angles(b.design, 200)).P_mm)]


def _figures(b) -> list[str]:
    """The paper's plots from the solids (coupler curve, y deviation and torque; M11 / M12 /
    M22 over x, Fig. 6, which needs H)."""
    plot_kinematics(b.design, b.out_dir / "kinematics.png")
    plot_apparent_mass(b.design, b.dyn.H, b.out_dir / "apparent_mass.png")
    return ["kinematics.png", "apparent_mass.png"]


@dataclasses.dataclass(frozen=True)
class FourBarDynamics:
    """The four-bar's dynamics from the solids (``Build.dyn``): mass properties per kind
    (``props``) and per link in the link frame (``links``, SI), each link's parts
    (``shares``), the motor (catalog spec with ``[motor]`` applied) and its rotor inertia
    ``Jm_kg_m2``, H11..H33 (``H``, Hoeken paper eqs 13-21) and the planar link terms,
    the apparent mass over the stroke (eq 22), the fidelity costs and the structure model."""

    props: dict
    links: dict
    shares: dict
    motor: Any
    Jm_kg_m2: float
    H: Any
    planar: dict
    apparent_mass: dict
    fidelity_costs: dict
    structure: Any


def _dynamics(b) -> FourBarDynamics:
    """From the driver's mass properties (``b.props`` per kind, ``b.bodies`` per body in the
    link frame, SI): Jm, H and the apparent mass, the fidelity costs and the structure."""
    design, model = b.design, b.model
    dev = resolve_device(design)
    dm = dev.motor  # [motor] and parts.motor_rotor_inertia_g_cm2 applied
    Jm = dev.joint_rotor_inertia_kg_m2("crank")  # n^2 J_m through a capstan
    H, planar = inertia_from_links(design, b.bodies, Jm)
    am = apparent_mass(design, H)
    return FourBarDynamics(
        props=b.props, links=b.bodies, shares=family.body_shares(model.instances, b.props),
        motor=dm.spec, Jm_kg_m2=Jm, H=H, planar=planar, apparent_mass=am,
        fidelity_costs=_fidelity_costs(design, model, b.props, H, am, Jm, b.fidelity),
        structure=structure_of_build(design, model, b.props, am["M11_max_g"]))


def _fidelity_costs(design, model, props: dict, H, am: dict, Jm: float, fidelity: str) -> dict:
    """What dropping the cosmetic features costs on this design (measured, not assumed)."""
    out = {"bearing_balls": "none: the bearing mass is the catalog mass at every fidelity"}
    if model.extra.handle_script is not None or design.parts.handle_fillet_mm <= 0:
        out["handle_round"] = "not applicable"
        return out
    floor = handle_floor_mm(model.extra.plan, design.parts)
    other = knob_shape(design.parts, floor, cosmetic=fidelity != "fabrication")
    kind = model.kinds()["handle"]
    alt = family.kind_mass_props(PartKind(name="handle", shape=other, material=kind.material,
                                          made=True))
    H2, _ = inertia_from_links(design, family.body_props(model.instances, {**props, "handle": alt}),
                               Jm)
    am2 = apparent_mass(design, H2)
    sign = 1.0 if fidelity == "fabrication" else -1.0  # report inertia - fabrication
    out["handle_round"] = {
        "delta_mass_g": sign * (alt.mass_kg - props["handle"].mass_kg) * 1e3,
        "delta_H22_rel": sign * (H2.H22_kg_m2 - H.H22_kg_m2) / H.H22_kg_m2,
        "delta_M11_max_g": sign * (am2["M11_max_g"] - am["M11_max_g"]),
        "meaning": "inertia-fidelity value minus fabrication value",
    }
    return out


def interference(design, model, fidelity: str, allow_interference: bool, same_body=None):
    """The one interference check of every family (:func:`cad.assembly.interference.check_model`)
    on the four-bar: every body pair over ``model.motion`` by crank angle (the closest pose
    refined between samples), exact (``preview``: mesh-only), contact or a distance under
    ``parts.clearance_min_mm`` a clash; merged with the same-body check ``same_body``.
    InterferenceError unless ``allow_interference``. Returns the
    :class:`cad.assembly.interference.InterferenceReport`."""
    parts, fb = design.parts, design.linkage

    def tf_at(p):
        return {b: v[0] for b, v in body_transforms(fb, [p]).items()}

    rep = itf.check_model(
        model, parts.clearance_min_mm,
        mesh_tol_mm=itf.SWEEP_MESH_TOL_MM if fidelity != "preview" else PREVIEW_STL_TOL_MM,
        exact=fidelity != "preview", contact_ok=False, joints=joint_axes(model.extra.joints_mm),
        phi1_rad=model.extra.phi1_rad, tf_at=tf_at, same_body=same_body)
    if not allow_interference:
        itf.raise_on_collision(rep, parts.clearance_min_mm)
    return rep


def _sim_files(b) -> list[str]:
    """``<name>.xml`` (MJCF) / ``<name>.urdf`` when asked (:mod:`cad.families.fourbar.sim`)."""
    design, model, mp = b.design, b.model, b.dyn
    return write_sim_model(
        lambda: sim_model(design, model, mp.links, mp.Jm_kg_m2, mp.motor,
                          model.extra.pose_phi1_rad),
        b.out_dir, b.formats, design.name)


def check_options(design, fidelity: str, phi1_deg, formats=frozenset()) -> None:
    """A bad ``--phi1-deg`` (outside the crank range) before any CAD (DesignError)."""

    exported_phi1_rad(design, phi1_deg)


def _stages(phi1_deg: float | None, allow_interference: bool):
    """The four-bar's stages of the one build driver (:class:`cad.pipeline.run.Stages`): its
    layout, the coupler path on the preview, the paper's plots (which need H), its dynamics
    (H, M, structure), the encoder and capstan rows, its report."""
    return Stages(
        check_options=check_options,
        assemble=lambda design, fidelity: assemble(design, fidelity, phi1_deg=phi1_deg,
                                                   strict=not allow_interference),
        interference=lambda b: interference(b.design, b.model, b.fidelity, b.allow_interference,
                                            b.same_body()).as_dict(),
        report=_report, md_rows=_md_rows, preview_title=_preview_title,
        stroke=lambda d: body_transforms(d.linkage, sweep_angles(d, STROKE_POSES)),
        motion_label="crank range", moving_bodies=lambda model: list(model.bodies),
        dynamics=_dynamics, more_files=_sim_files,
        assembly=lambda design: (None, ASSEMBLY_CHECKS + capstan.assembly_checks(design)),
        marks=_marks, preview_hide_ground_below_mm=-1.0, figures=_figures,
        no_solid_rows=lambda design: [encoder_bom_row(design), *capstan.bom_lines(design)],
        md_images=(("coupler curve, deviation and torque", "kinematics.png"),
                   ("apparent mass over the stroke (eq 22, H from the solids)",
                    "apparent_mass.png")))


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
    """Build ``design`` into ``out_dir`` (a fresh temporary directory); return the report dict
    (module docstring), through the one build driver (:func:`cad.pipeline.run.run_family`).
    Raises DesignError (``--phi1-deg`` outside the crank range, no layer order, ...),
    InterferenceError (a clash, unless ``allow_interference``), MeshError."""
    return run_family(_stages(phi1_deg, allow_interference), design, out_dir, formats,
                      fidelity=fidelity, allow_interference=allow_interference,
                      progress=progress, phi1_deg=phi1_deg)


def _links_report(mp: FourBarDynamics) -> dict:
    """report.json ``links``: per moving link its mass properties (link frame), lG, beta,
    Jzz about the COM and each part's share."""
    out = {}
    for k in LINKS:
        lp, pl = mp.links[k], mp.planar[k]
        out[k] = {
            **lp.to_dict(),
            "mass_g": lp.mass_kg * 1e3,
            "com_link_mm": (np.asarray(lp.com_m) * 1e3).tolist(),
            "lG_mm": pl.lG_m * 1e3,
            "beta_deg": math.degrees(pl.beta_rad),
            "Jzz_com_kg_m2": pl.Jzz_com_kg_m2,
            "parts": mp.shares.get(k, []),
        }
    return out


def _layers_report(plan, parts) -> dict:
    """report.json ``layers``: the layer order, heights, gaps and joint stacks."""
    return {
        "order": list(plan.order),
        "z_mm": plan.z_mm,
        "gaps_mm": list(plan.gaps_mm),
        "top_mm": plan.top_mm,
        "candidates": list(plan.candidates),
        "joints": {
            j: {
                "upper": s.upper,
                "lower": s.lower,
                "spacer_mm": s.spacer_mm,
                "head_spacer_mm": s.shim_mm,
                "pin": f"{parts.pin} x {s.pin_length_mm:g}",
            }
            for j, s in plan.joints.items()
        },
    }


def _report(b) -> dict:
    """report.json's content from the build's results (the driver adds ``files``, the
    dispatcher the rest); the driver's common keys (``b.common``) placed among the
    four-bar's; ``sheets`` (the nested stock sheets) when ``parts.process = "laser"``."""
    design, model, mp, bom, c = b.design, b.model, b.dyn, b.bom, b.common
    fb, parts, H, motor = design.linkage, design.parts, mp.H, mp.motor
    m = compute_metrics(fb, design.phi1_min_rad, design.phi1_max_rad, force_N=design.force_N,
                        samples=design.samples).as_dict()
    script = model.extra.handle_script
    report = {
        **design.resolved_linkage(),
        "force_N": design.force_N,
        **{k: m[k] for k in METRIC_KEYS if k in m},
        "H11_kg_m2": H.H11_kg_m2,
        "H12_kg_m2": H.H12_kg_m2,
        "H22_kg_m2": H.H22_kg_m2,
        "H33_kg_m2": H.H33_kg_m2,
        "beta2_deg": math.degrees(H.beta2_rad),
        "Jm_kg_m2": mp.Jm_kg_m2,
        "apparent_mass": mp.apparent_mass,
        "structure": mp.structure,
        "links": _links_report(mp),
        "part_masses_g": {r["part"]: r["mass_g"] for r in bom},
        # material of every solid of assembly.step, by its name there (hapticad massprops)
        "part_materials": c["part_materials"],
        "ground_mass_g": mp.links["ground"].mass_kg * 1e3,
        **{k: c[k] for k in ("fasteners", "tapped_holes")},
        "fits": c["fits"],
        "placement": c["placement"],
        "layers": _layers_report(model.extra.plan, parts),
        "base_plate_mm": list(model.extra.base_rect_mm),
        "motor": {
            "key": motor.key,
            **({"name": motor.winding} if dict(b.design.motor).get("name") else {}),
            "mass_kg": motor.mass_kg,
            # the rotor's own (Jm_kg_m2 is n^2 (J_m + J_capstan) at the crank)
            "rotor_inertia_g_cm2": resolve_device(b.design).motor.rotor_inertia_kg_m2 * 1e7,
            "source": (motor.source if not b.design.motor else
                       f"the design's [motor] table over the mount of {motor.key} ({motor.source})"),
        },
        "fidelity_costs": mp.fidelity_costs,
        "handle": "user script " + script.name if script is not None else "built-in knob",
        "parts_spec": parts.as_dict(report=True),
        "preview": "preview.png",
    }
    _sheets(b, report)
    return report


def _sheets(b, report: dict) -> None:
    """``report["sheets"]`` when ``parts.process = "laser"``: the nested stock sheets and
    every fastener touching a sheet over the sheets' thickness bands (issue 25)."""
    model = b.model
    if not family.laser_kinds(model.instances):
        return

    report["sheets"] = sheets_report(plan_sheets(model.instances), "dxf" in b.formats)
    report["sheets"]["thickness_tolerance"] = tolerance_report(
        model.instances, model.holes, model.extra.plan, b.design.parts)


def _md_rows(r: dict) -> list[tuple[str, str]]:
    """report.md's table: the linkage, H, M11, clearance and layers (the driver adds the
    paper's plots, :attr:`cad.pipeline.run.Stages.md_images`, and the BOM)."""
    am = r["apparent_mass"]
    return [
        ("l1..l5, le (mm)", f"{r['l1_mm']:.3f}, {r['l2_mm']:.3f}, {r['l3_mm']:.3f}, "
                            f"{r['l4_mm']:.3f}, {r['l5_mm']:.3f}, {r['le_mm']:.3f}"),
        ("phi_e, crank range (deg)",
         f"{r['phi_e_deg']:.2f}, {r['phi1_min_deg']:.1f}..{r['phi1_max_deg']:.1f}"),
        ("H11, H12, H22, H33 (kg m^2)", f"{r['H11_kg_m2']:.4g}, {r['H12_kg_m2']:.4g}, "
                                        f"{r['H22_kg_m2']:.4g}, {r['H33_kg_m2']:.4g}"),
        ("M11 over the stroke (g)", f"{am['M11_min_g']:.2f} .. {am['M11_max_g']:.2f}"),
        ("min clearance (mm)",
         f"{r['min_clearance_mm']:.3f} ({r['interference']['method']})"),
        ("overlap volume (mm^3)", f"{r['overlap_volume_mm3']:.4g}"),
        ("layers (bottom to top)", ", ".join(r["layers"]["order"])),
    ]
