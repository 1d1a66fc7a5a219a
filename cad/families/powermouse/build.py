"""Build a PowerMouse design: actuator optimum -> solids -> mass properties -> clearances -> exports.

Contract: see :mod:`cad.pipeline` (``build(design, out_dir, formats, *, fidelity,
allow_interference, progress, phi1_deg) -> report dict``). ``out_dir`` is the
dispatcher's temporary directory. Isotropy paper sections 5-6.

Pipeline (``build`` is one call to :func:`cad.pipeline.run.run_family` with the
PowerMouse's stages, :func:`_stages`): actuator optimum (eqs 8-9) -> geometry -> one list of part instances
(:func:`assembly`: bodies ``flotor`` and ``ground``) -> mass properties from the solids
-> wrench map and isotropy -> the one interference check of every family over the
flotor's motion (:func:`cad.families.powermouse.motion.interference`: the flotor against
the stator at the centre and every excursion, every pair of parts on one body once) -> the
common outputs of :mod:`cad.pipeline.family`. Modules: :mod:`~.actuator` (eq 8 optimum,
Fig. 8), :mod:`~.placement` (part kinds and instances), :mod:`~.motion` (excursions, the
assembly model, the check), :mod:`~.report` (report rows).

Files written (the layout of every family): ``parts/<part>.step|.stl`` (``pm_flotor_body``
and ``pm_flotor_lid``, ``pm_coil`` x6, ``pm_handle``, ``pm_core``, ``pm_post``,
``pm_magnet`` x24, ``pm_iron_plate`` x6, ``pm_housing_body`` and ``pm_housing_lid``),
``assembly.step``, ``bom.csv``, ``preview.png``, ``report.md`` (+ ``report.json``,
``manifest.json`` by the dispatcher), and ``actuator_fig8.png/.svg`` (force vs gap and
field along the centre line, the paper's Fig. 8).

``rig/``: the single-actuator test rig of Fig. 7 (one flat coil between two magnet
pairs on iron plates, on a base plate) -- a separate bench fixture to measure one
actuator's force against eq (8), *not* part of the PowerMouse: ``rig/parts/``,
``rig/assembly.step``, ``rig/bom.csv``.

Report keys (units in names): ``actuator`` (the optimum: optimal_gap_mm,
coil_width_mm, Bg_T, force_N, eta_geom, model, and the same for the other
field models), ``wrench_map`` (6x6, N/A and N m/A),
``wrench_map_singular_values`` (descending), ``isotropy`` (force/torque
groups and spreads), ``flotor`` (mass_kg, com_mm, inertia_com_kg_m2 from the
solids, per part masses), ``peak_force_N``, ``continuous_force_N``,
``peak_acceleration_m_s2`` / ``_G``, ``clearances_mm``, ``paper_table4``, ``fits`` (ISO 286
fits per part: the post bore / post and handle socket / stem, H7/g6).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import numpy as np

from cad.actuators import powermouse as pm
from cad.errors import DesignError
from cad.families.powermouse import parts as pp

# every name of the former single-module builder stays importable from here
from cad.families.powermouse.actuator import actuator_gap_mm, actuator_optimum, fig8_chart  # noqa: F401
from cad.families.powermouse.motion import (  # noqa: F401
    assemble,
    interference,
    motion_poses,
    pose_clearances,
    pose_group,
    stroke_poses,
)
from cad.families.powermouse.placement import (  # noqa: F401
    PARTS,
    assembly,
    leg_parts,
    lid_holes,
    lid_plans,
    lid_screws,
    materials,
    part_fits,
    part_kind,
    part_labels,
    post_set_screw_parts,
    rig_parts,
    screw_uses,
    tf,
    turned_tips,
)
from cad.families.powermouse.report import PAPER_TABLE4, build_report, report_md_rows  # noqa: F401
from cad.families.powermouse.sim import sim_model
from cad.parts import voicecoil as pv
from cad.pipeline import family
from cad.pipeline.run import Stages, run_family
from cad.pipeline.views import write_sim_model


def check_options(design, fidelity: str, phi1_deg, formats=frozenset()) -> None:
    """Refuse what this builder cannot do, before any CAD import (DesignError)."""
    if phi1_deg is not None:
        raise DesignError("--phi1-deg", f"the PowerMouse has no crank angle, got {phi1_deg!r}")
    if "urdf" in set(formats):
        raise DesignError("--formats", "urdf is not written for the PowerMouse: URDF has no force "
                          "actuator at a point (its six coils) and no free body; mjcf is")

    pp.lid_screw_plan(design.stator.housing_wall_mm)  # walls too thin for the lid screws
    g = pp.geometry(design, actuator_gap_mm(design))  # the post's and the handle's shoulders
    pp.flotor_lid_screw_plan(g, design.flotor.material)
    pp.post_plan(g)  # a collar too thin for a set screw
    pp.leg_plan(design.stator.housing_wall_mm)  # no catalog leg screw for the wall


@dataclasses.dataclass(frozen=True)
class PowerMouseDynamics:
    """The PowerMouse's dynamics from the solids (``Build.dyn``): the flotor's mass
    properties (flotor frame, SI), its parts' and the stator's masses (kg), the coil gain
    (N per ampere-turn), the wrench maps about the cube centre (``W``, 6 x 6) and about the
    flotor's COM (``W_com``), its isotropy (``iso``) and the test rig's BOM rows."""

    flotor_mp: Any
    parts_mass: dict
    stator_mass_kg: float
    gain_per_At: float
    W: Any
    iso: Any
    W_com: Any
    rig_bom: list


def _dynamics(b) -> PowerMouseDynamics:
    """The flotor's mass properties, masses, the wrench map (:func:`_wrench`) and the rig's
    BOM rows (:class:`PowerMouseDynamics`)."""
    inst, props, act = b.instances, b.props, b.model.extra.actuator
    flotor_mp = b.bodies["flotor"]
    gain_per_At, W, iso, W_com = _wrench(b.design, act, b.model.extra.geometry, flotor_mp)
    return PowerMouseDynamics(
        flotor_mp=flotor_mp,
        parts_mass={i.name: props[i.kind.name].mass_kg for i in inst if i.body == "flotor"},
        stator_mass_kg=sum(props[i.kind.name].mass_kg for i in inst if i.body == "ground"),
        gain_per_At=gain_per_At, W=W, iso=iso, W_com=W_com,
        rig_bom=list(b.model.extra.rig_bom))  # report.json: the rows rig/bom.csv holds


def rig_bom(rig) -> list[dict]:
    """The BOM rows of the single-actuator test rig's instances (its own kinds' masses)."""
    return family.bom_rows(rig, family.kind_props(rig))


def assemble_built(design, fidelity: str):
    """:func:`assemble` with the rig's BOM rows in its layout record (``extra.rig_bom``),
    computed once in the build's process before the export child forks: ``rig/bom.csv``
    and report.json's ``rig_bom`` are the same rows."""
    model = assemble(design, fidelity)
    extra = dataclasses.replace(model.extra, rig_bom=tuple(rig_bom(model.extra.rig)))
    return dataclasses.replace(model, extra=extra)


def _wrench(design, act: dict, g, flotor_mp) -> tuple:
    """``(N per ampere-turn, wrench map about the cube centre (6, 6), its isotropy, wrench map
    about the flotor's COM)`` (:mod:`cad.actuators.powermouse`)."""
    coils = g.coils()
    gain_per_At = act["Bg_T"] * 2.0 * design.actuator.magnet_length_mm * 1e-3  # N per ampere-turn
    W = pm.wrench_map(coils, gain_per_At)
    iso = pm.isotropy(W)
    W_com = pm.wrench_map(coils, gain_per_At, about_mm=flotor_mp.com_m * 1e3)
    return gain_per_At, W, iso, W_com


def _report_of(b) -> dict:
    """The family's report dict (:func:`cad.families.powermouse.report.build_report`)."""
    x, dy = b.model.extra, b.dyn
    itf, cl = b.itf, b.itf["poses"]
    return build_report(b.design, x.actuator, x.actuator_geometry, x.geometry, dy.W,
                   dy.iso, dy.W_com, dy.flotor_mp, dy.parts_mass,
                   dy.stator_mass_kg, itf, cl, b.bom, dy.rig_bom,
                   pv.rattle_clearances_mm(x.actuator_geometry, x.actuator_solids),
                   dy.gain_per_At)


def _assembly(design) -> tuple:
    """``(plan, checks)`` of ``assembly.md``."""
    return ASSEMBLY_PLAN, [
        f"the flotor moves freely by +-{design.motion.range_mm:g} mm and "
        f"+-{design.motion.range_deg:g} deg about the centre, touching only "
        "at the limits (clearances in report.md)"]


def _stages():
    """The PowerMouse's stages of the one build driver (:class:`cad.pipeline.run.Stages`)."""
    return Stages(
        check_options=check_options, assemble=assemble_built, interference=lambda b: interference(b.model, b.allow_interference, b.same_body()),
        report=_report_of, md_rows=report_md_rows, stroke=stroke_poses,
        preview_title=lambda b: f"{b.design.name}: PowerMouse at the centre pose",
        motion_label="motion range", mass_label="mass properties and wrench map",
        prepare_label="actuator optimum (eqs 8-9)", dynamics=_dynamics,
        thread_notes=False,  # no tapped-hole notes in the DXF/drawings (as before)
        more_exports=_write_rig, cutaway=PICTURE_CUTAWAY, more_files=_sim_files,
        figures=lambda b: fig8_chart(b.design, b.model.extra.actuator["gap_mm"], b.out_dir),
        assembly=_assembly)


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
    """Build the PowerMouse and its test rig into ``out_dir``; return the report dict (module
    docstring), through the one build driver (:func:`cad.pipeline.run.run_family`).

    fidelity: "fabrication" checks the centre and every extreme and combined pose of the
    motion range (:func:`motion_poses`); "inertia" / "preview" the centre and the 12 on-axis
    poses. Raises InterferenceError when two solids share a volume at any of them
    (:func:`interference`), unless allow_interference.
    """
    return run_family(_stages(), design, out_dir, formats, fidelity=fidelity,
                      allow_interference=allow_interference, progress=progress,
                      phi1_deg=phi1_deg)


#: The PowerMouse's assembly order (cad.assembly.steps): (title, instance name patterns,
#: checks); the screws follow each stage once their parts are in place.
ASSEMBLY_PLAN = (
    ("coils wound and potted into the pockets of the open flotor box", ["flotor_body", "coil_[+-][xy]",
                                                                        "coil_+z"]),
    ("inner magnets bonded onto the core (structural epoxy)", ["core", "magnet_*_inner-*"]),
    ("core into the open flotor box (upside down); flotor lid (-z wall, its coil potted) on",
     ["flotor_lid", "coil_-z"]),
    ("outer magnets bonded onto their iron plates; five plates bonded into the open housing box",
     ["housing_body", "iron_[+-][xy]", "iron_-z", "magnet_[+-][xy]_outer-*", "magnet_-z_outer-*"]),
    ("flotor (with the core) lowered into the housing box: its side faces slide past the side "
     "magnets at the rattle gap", []),
    ("post through the housing's corner collar and the flotor's corner hole, its M4 tip screwed "
     "into the core until its shoulder seats on the core's flat", ["post"],
     ["finding the core's tapped hole: hold the housing with its (-,-,-) corner down (the "
      "diagonal vertical); the flotor rests on the three lower outer magnet groups and the core "
      "on the flotor's three lower walls, each moved d_r/2 along the diagonal, so the post's tip "
      "meets the core's hole on its axis; screw it in until its shoulder seats, draw the post out "
      "until its end is flush with the collar's end (the core is then centred), then tighten the "
      "set screw"]),
    ("housing lid (+z wall) with its iron plate and outer magnets bonded on, put on",
     ["housing_lid", "iron_+z", "magnet_+z_outer-*"]),
    ("handle stem through the lid's corner hole into the flotor's corner socket, its M4 tip "
     "screwed into the corner boss", ["handle"]),
    ("legs under the housing", ["leg_[0-9]"]),
)


#: Instances drawn cut away (the quarter facing the viewer removed) in render.png and
#: animation.gif: the housing, its plates and magnets, the flotor box and their lid screws,
#: so that the flotor, its coils and the core show (issue 24 §3); the glb keeps them whole.
PICTURE_CUTAWAY = ("housing_*", "iron_*", "magnet_*_outer-*", "flotor_body", "flotor_lid",
                   "*lid_screw_*")



def _sim_files(b) -> list[str]:
    """``<name>.xml`` (MJCF) when asked: the free flotor and its coil actuators
    (:func:`cad.families.powermouse.sim.sim_model`)."""
    return write_sim_model(lambda: sim_model(b.design, b.model, b.dyn.flotor_mp, b.model.extra.actuator),
                           b.out_dir, b.formats, b.design.name)


def _write_rig(b) -> list[str]:
    """The single-actuator test rig (Fig. 7) in ``rig/``: part files, assembly STEP, BOM."""
    return [
        "rig/" + f
        for f in family.write_outputs(
            b.model.extra.rig,
            {"rig": np.eye(4)},
            b.out_dir / "rig",
            b.formats,
            name=f"{b.design.name}_rig",
            title="single-actuator test rig (Fig. 7), not part of the device",
            bom=list(b.model.extra.rig_bom),
            preview=False,
        )
    ]
