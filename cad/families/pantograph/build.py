"""Build a pantograph-family device: the plain 5-bar or the twin-pantograph haptic mouse.

Contract: see :mod:`cad.pipeline` (``build(design, out_dir, formats, *, fidelity,
allow_interference, progress, phi1_deg) -> report dict``; ``phi1_deg`` must be None, the
family has no crank: refused at load time by :func:`check_options`). Isotropy paper §3
(Fig. 2, the plain 5-bar) and §4.1 (Fig. 1, Table 1, the twin pantograph).

Pipeline (``build`` is one call to :func:`cad.pipeline.run.run_family` with the family's
stages, :func:`_stages`): layout (heights, plates; numpy, :mod:`~cad.families.pantograph.layout`) ->
2-D layer clearances over the workspace (report figures,
:mod:`~cad.families.pantograph.clearances`) -> the assembly model
(:func:`~cad.families.pantograph.motion.assemble`: part kinds
:mod:`~cad.families.pantograph.kinds`, instances :mod:`~cad.families.pantograph.placement`,
the workspace motion) -> mass properties per body from the solids -> effective mass
(:mod:`~cad.families.pantograph.dynamics`) -> the one interference check over the motion
(:func:`~cad.families.pantograph.motion.interference`) -> the common outputs of
:mod:`cad.pipeline.family` (``parts/``, ``assembly.step``, ``bom.csv``, ``preview.png``,
``report.md``; rows :mod:`~cad.families.pantograph.report`).

Arrangement (our reading of Fig. 1; world frame = the kinematic base frame, z up,
z = 0 on the base plate's top face, the bench plane at ``bench_z_mm`` below it):

* the base plate stands on four leg standoffs (cap screws from above) tall enough that
  the motors under it clear the bench by :data:`cad.parts.base.LEG_GROUND_CLEARANCE_MM`;
* the lower 5-bar (the *crank* pantograph of the mouse, the only one of the plain
  5-bar) has its actuated joints at B1 = (-a/2, 0), B2 = (+a/2, 0): proximal links in
  layer L0, left distal L1, right distal L2; its motors hang under the base plate on
  motor-mount plates (cap screws into the base plate), shafts up into the hub clevises;
* plain 5-bar: the end effector E is a handle pin running in both distal clevises'
  bearings, with a knob above L2;
* twin pantograph: the crankshaft web lies above L2; the crank pin hangs down into L2
  and L1, the main journal rises through the upper group to the knob. The *knob*
  pantograph (drives the main journal) is the upper group, mirrored: right distal U2,
  left distal U1, proximal links U0 on top; its motors stand on a bridge plate above
  U0 (shafts down), the bridge carried by four posts behind the base line (cap screws
  into both ends of each post);
* every passive joint: a steel pin pressed into the proximal clevis, two ball bearings
  in the distal clevis; the journals run in the distal clevises' bearings the same way.

Body frames are planar (rotation about z, z = 0 on the base plate's top): a moving link's
origin at its first joint, x towards its second; the upper group's parts are turned over
inside their body (``tf_body_part`` carries the flip and the layer height).

The solids are checked by the one interference check of every family
(:func:`cad.assembly.interference.check_model`): every pair of bodies at every pose of
the workspace motion (home and a grid over the square; the mouse x crank angles), every
pair of parts on one body once. The 2-D gaps between parts of one layer over the finer
GII grid (capsules, ``clearances_mm``) are report figures.

Report keys: ``gii``, ``layout_mm``, ``clearances_mm``, ``bodies`` (mass properties of
each moving body from the exact B-rep, in its link frame), ``effective_mass_home``
(mouse: diag and apparent readings beside ``paper_table1``; 5-bar: the 2x2 mass matrix
at the workspace centre), ``interference`` (the check over the motion: pairs, poses,
collisions named by pair, pose and volume), ``min_clearance_mm``, ``overlap_volume_mm3``,
``bench_z_mm`` / ``lowest_z_mm``, ``bom``, ``fits`` (ISO 286 fits per part,
:mod:`cad.data.fits`), ``files``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from cad.data.families import refusal
from cad.device import encoder_bom_rows, resolve_device
from cad.errors import DesignError
from cad.export.sim import SIM_FORMATS, write_sim_files
from cad.families.pantograph.capstan import bom_lines as capstan_bom_lines
from cad.families.pantograph.capstan import layout as capstan_layout
from cad.families.pantograph.capstan import winding_steps
from cad.families.pantograph.capstan_solids import check_capstan_z

# every name of the former single-module builder stays importable from here
from cad.families.pantograph.clearances import (  # noqa: F401
    CLEARANCE_THETA_SAMPLES,
    MIN_CLEARANCE_MM,
    clearance_poses,
    clearances,
    pt_seg,
    seg_seg_distance,
)
from cad.families.pantograph.dynamics import dynamics, effective_mass, planar_props  # noqa: F401
from cad.families.pantograph.kinds import part_kinds  # noqa: F401
from cad.families.pantograph.layout import (  # noqa: F401
    KNOB_BORE_DEPTH_MM,
    MIN_ENGAGEMENT_D,
    PLAIN_KNOB_DIAMETER_MM,
    POST_DX_MM,
    POST_SCREW,
    POST_TAP_DEPTH_MM,
    SET_SCREW_SIZES,
    flip_matrix,
    home_xy_mm,
    is_twin,
    layout,
    leg_xy,
    lower_five_bar,
    rz,
    screw_plan,
    set_screw_plan,
    workspace_square,
)
from cad.families.pantograph.motion import (  # noqa: F401
    MOTION_GRID,
    MOTION_THETA_SAMPLES,
    STROKE_POSES,
    assemble,
    body_poses,
    interference,
    motion_points,
    motor_joints,
    stroke_points,
    stroke_poses,
)
from cad.families.pantograph.placement import (  # noqa: F401
    assembly,
    ground_parts,
    journal_parts,
    link_parts,
    motor_station,
    place_screw,
    place_set_screw,
)
from cad.families.pantograph.report import PAPER_TABLE1, build_report, report_md_rows  # noqa: F401
from cad.families.pantograph.sim import fivebar_sim_model, sim_model
from cad.families.pantograph.twin_placement import band_rope_offset_mm
from cad.families.pantograph.twin_placement import group_layout as twin_capstan_layout
from cad.kinematics import twin_pantograph as tw
from cad.pipeline.run import Stages, run_family
from cad.pipeline.views import write_sim_model

#: Families this module builds (others of cad.design.pantograph are refused at load).
FAMILIES = ("pantograph", "twin-pantograph")


#: Final checks of assembly.md (cad.assembly.steps).
ASSEMBLY_CHECKS = (
    "each motor shaft turned by hand moves the linkage over the whole workspace square "
    "(report.md) with no binding and no contact between links",
    "the clevis set screws are tight (no slip of a hub clevis on its shaft flat)",
)


def check_options(design, fidelity: str, phi1_deg, formats=frozenset()) -> None:
    """Refuse what this builder cannot do, before any CAD import (DesignError)."""
    if design.family not in FAMILIES:

        raise DesignError("mechanism.family", refusal("build", design.family))
    if phi1_deg is not None:
        raise DesignError(
            "--phi1-deg",
            f"a {design.family} has no crank angle, got {phi1_deg!r}; the assembly is "
            "exported at workspace.home_mm",
        )
    screw_plan(design)  # a stack no catalog screw fastens: named before any CAD
    set_screw_plan(design)  # a clevis wall no set screw fits: named before any CAD
    if design.family == "pantograph":  # capstans whose drums cannot be placed: named before any CAD
        capstan_layout(design)
    twin_capstan_layout(design)  # the twin's: a 5-bar whose drums cannot be placed named in one line






def _write_sim(design, out_dir, formats, instances, bodies, lay, home) -> list[str]:
    """``<name>.xml`` (MJCF) / ``<name>.urdf`` of the mouse when asked, from the instance list
    (:mod:`cad.families.pantograph.sim`; meshes are ``parts/<kind>.stl``)."""
    if not set(formats) & set(SIM_FORMATS):
        return []
    import dataclasses

    th = math.radians(design.workspace["home_theta_deg"])
    ik = tw.ik(design.mechanism, np.array([[home[0], home[1], th]]))
    L, U = lay["lower_layers_z_mm"], lay["upper_layers_z_mm"]
    layer_z = {
        "crank_proximal": L[0],
        "knob_proximal": U[0],
        "crank_distal_left": L[1],
        "crank_distal_right": L[2],
        "knob_distal_left": U[1],
        "knob_distal_right": U[2],
        "crankshaft": lay["web_z_mm"],
    }
    shifted = {}
    for b, mp in bodies.items():  # body frames of the sim sit at the layer height
        z = layer_z.get(b, layer_z.get(b.rsplit("_", 1)[0], 0.0))
        shifted[b] = mp.transformed(np.eye(3), np.array([0.0, 0.0, -z * 1e-3]))
    for grp in ("crank", "knob"):
        shifted[f"{grp}_distal"] = shifted[f"{grp}_distal_left"]
    model = sim_model(design, shifted, instances, lay, [*home, th], ik)
    model = dataclasses.replace(model, meshdir="parts")
    return [q.name for q in write_sim_files(model, out_dir, formats, design.name)]


def _check_shafts(design, lay: dict) -> None:
    """DesignError when a motor shaft engages less than half its hub clevis (layout only)."""
    p = design.parts
    h = p.clevis_height_mm
    for key in ("lower_shaft_engagement_mm", "upper_shaft_engagement_mm"):
        if key in lay and lay[key] < h / 2:
            raise DesignError(
                "parts.motor",
                f"{p.motor} shaft engages only {lay[key]:.1f} mm of the {h} mm hub ({key}); "
                "use thinner plates or a longer shaft",
            )


def _prepare(design) -> tuple[dict, dict]:
    """``(layout, 2-D layer clearances)`` before any solid (:func:`layout`,
    :func:`clearances`: report figures; the check is on the solids). DesignError when a
    motor shaft engages less than half its hub."""
    lay = layout(design)
    _check_shafts(design, lay)
    if "capstan" in lay:
        check_capstan_z(design, lay)
    for cap in lay.get("twin_capstan", {}).values():  # on the crank side's terms, each side's band and raise
        for band, up in zip(cap["bands"], cap["raise_mm"], strict=True):
            check_capstan_z(design, {"capstan": {"rope_z_mm": band_rope_offset_mm(design, band) - up}})
    return lay, clearances(design, lay)


def _report_of(b) -> dict:
    """The family's report dict (:func:`cad.families.pantograph.report.build_report`)."""
    lay, clr = b.pre
    return build_report(b.design, lay, clr, b.bodies, b.dyn.effective, b.dyn.bare, b.itf, b.bom,
                   b.model.extra.home_mm, b.fidelity, b.low)


def _sim_files(b) -> list[str]:
    """MJCF / URDF when asked: the twin pantograph (:func:`_write_sim`), the plain 5-bar
    (:func:`cad.families.pantograph.sim.fivebar_sim_model`, from the assembly model)."""
    if not is_twin(b.design):

        return write_sim_model(lambda: fivebar_sim_model(b.design, b.model, b.bodies), b.out_dir,
                               b.formats, b.design.name)
    return _write_sim(b.design, b.out_dir, b.formats, b.instances, b.bodies, b.pre[0],
                      b.model.extra.home_mm)


def _title(b) -> str:
    home = b.model.extra.home_mm
    return f"{b.design.name}: {b.design.family} at home {home.round(2).tolist()} mm"


def _encoder_rows(design) -> list[dict]:
    """The joint encoders the device carries (one per motor, no solid): BOM lines from the
    resolved device (:func:`cad.device.encoder_bom_rows`)."""
    return encoder_bom_rows(resolve_device(design))


def _no_solid_rows(design) -> list[dict]:
    """BOM lines with no solid: the joint encoders and, through capstans, each motor's rope
    with its cut length (:func:`cad.families.pantograph.capstan.bom_lines`)."""
    return _encoder_rows(design) + capstan_bom_lines(design)


def _stages():
    """The family's stages of the one build driver (:class:`cad.pipeline.run.Stages`)."""
    return Stages(
        check_options=check_options, assemble=assemble, interference=lambda b: interference(b.model, b.allow_interference, b.same_body()),
        report=_report_of, md_rows=report_md_rows, stroke=stroke_poses, preview_title=_title,
        motion_label="workspace", prepare=_prepare, prepare_label="layout and clearances",
        dynamics=lambda b: dynamics(b.design, b.bodies, b.model.extra.home_mm),
        bench_z_mm=lambda b: b.pre[0]["bench_z_mm"],
        marks=lambda b: [("workspace", workspace_square(b.design.workspace))],
        more_files=_sim_files, assembly=lambda design: (None, ASSEMBLY_CHECKS + winding_steps(design)),
        no_solid_rows=_no_solid_rows)


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
    """Build a plain 5-bar or a twin-pantograph mouse into ``out_dir``; return the report dict,
    through the one build driver (:func:`cad.pipeline.run.run_family`).

    fidelity: "fabrication" uses bd_warehouse ball bearings (races and balls); "inertia"
    and "preview" a plain ring (same catalogue mass: the mass properties do not change).
    Raises InterferenceError when two solids share a volume at any pose of the workspace
    motion (:func:`~cad.families.pantograph.motion.interference`: pair, pose and volume
    named), unless allow_interference; GeometryError if a solid reaches below the bench.
    """
    return run_family(_stages(), design, out_dir, formats, fidelity=fidelity,
                      allow_interference=allow_interference, progress=progress,
                      phi1_deg=phi1_deg)
