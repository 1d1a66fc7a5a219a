"""Build a PowerMouse design: actuator optimum -> solids -> mass properties -> clearances -> exports.

Contract: see :mod:`cad.pipeline` (``build(design, out_dir, formats, *, fidelity,
allow_interference, progress, phi1_deg) -> report dict``). ``out_dir`` is the
dispatcher's temporary directory. Isotropy paper sections 5-6.

Pipeline: actuator optimum (eqs 8-9) -> geometry -> one list of part instances
(:func:`assembly`: bodies ``flotor`` and ``ground``) -> mass properties from the solids
-> wrench map and isotropy -> every pair of solids at the centre pose and the flotor
against the stator over the motion range (fast mesh pass, exact OCCT near contact:
:mod:`cad.assembly.static`) -> the common outputs of :mod:`cad.pipeline.family`.

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

from pathlib import Path

import numpy as np

from cad.errors import DesignError, InterferenceError

#: Source the output depends on (build cache key).
CODE_DEPS = (
    "pipeline",
    "families",
    "datasheet",
    "firmware",  # --formats firmware (cad/firmware/powermouse.py)
    "report",  # report.html, the stroke GIF and render (cad/report)
    "parts",
    "assembly",
    "export",
    "massprops",
    "actuators",
    "design",
    "io",
    "data",
    "errors.py",
)

#: Paper Table 4 (PowerMouse performance), for side-by-side reporting.
PAPER_TABLE4 = {
    "workspace": "+-3 mm, +-5 deg",
    "continuous_force_N": 16.0,
    "peak_force_N": 34.0,
    "effective_mass_g": 260.0,
    "peak_acceleration_G": ">10",
}


def _step(progress, text: str, done: int, total: int) -> None:
    if progress is not None:
        progress(text, done, total)


def actuator_optimum(design) -> dict:
    """The gap used by the design and the eq (8) optimum under every field model (dict of dicts)."""
    from cad.actuators import voicecoil as vc

    params = design.actuator.params()
    models = {}
    for m in vc.MODELS:
        models[m] = vc.optimal_gap(params, m).as_dict()
    chosen = models[design.actuator.field_model]
    gap = design.actuator.gap_mm if design.actuator.gap_mm is not None else chosen["optimal_gap_mm"]
    bg = vc.gap_field_T(gap, params, design.actuator.field_model)
    return {
        "gap_mm": gap,
        "gap_source": "design"
        if design.actuator.gap_mm is not None
        else f"optimum ({design.actuator.field_model})",
        "coil_width_mm": gap - design.actuator.rattle_mm,
        "Bg_T": bg,
        "force_N": float(vc.force_eq8_N(bg, gap, params)),
        "peak_force_N": float(
            vc.force_eq8_N(bg, gap, design.actuator.params(design.actuator.peak_power_W))
        ),
        "eta_geom": params.eta_geom,
        "ampere_turns_at_power": vc.ampere_turns(gap, params),
        "field_model": design.actuator.field_model,
        "models": models,
    }


def _fig8_chart(design, gap_mm: float, out_dir: Path) -> list[str]:
    """Paper Fig. 8: eq (8) force vs gap (three models) and B_z along the centre line at the gap used."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from cad.actuators import voicecoil as vc

    p = design.actuator.params()
    d = np.linspace(p.rattle_mm + 0.05, p.rattle_mm + 30.0, 200)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    ax1.plot(d, vc.force_vs_gap_N(d, p, "closed-form"), label="eq (9) closed form")
    ax1.plot(
        d,
        [
            float(
                vc.force_eq8_N(
                    vc.bg_image_converged_T(
                        x,
                        p.magnet_length_mm,
                        p.magnet_width_mm,
                        p.magnet_thickness_mm,
                        p.br_T,
                        1024,
                    ),
                    x,
                    p,
                )
            )
            for x in d
        ],
        label="two-plate image series",
    )
    ax1.axvline(gap_mm, color="k", lw=0.8, ls="--")
    ax1.set_xlabel("gap d (mm)")
    ax1.set_ylabel(f"force (N) at {p.power_W:g} W")
    ax1.set_title(
        f"d_r = {p.rattle_mm:g} mm, l,w,t = {p.magnet_length_mm:g},{p.magnet_width_mm:g},{p.magnet_thickness_mm:g} mm"
    )
    ax1.legend()
    z = np.linspace(-0.49 * gap_mm, 0.49 * gap_mm, 101)
    ax2.plot(
        z,
        vc.bz_centerline_eq9_T(
            z, gap_mm, p.magnet_length_mm, p.magnet_width_mm, p.magnet_thickness_mm, p.br_T
        ),
    )
    ax2.set_xlabel("z across the gap (mm)")
    ax2.set_ylabel("B_z on the magnet centre line (T)")
    ax2.set_title(f"gap {gap_mm:.2f} mm (eq 9 extended)")
    fig.tight_layout()
    from cad.io.atomic import atomic_path

    names = []
    from cad.report.figures import save_figure

    for ext in ("png", "svg"):  # same bytes every build (save_figure)
        target = Path(out_dir) / f"actuator_fig8.{ext}"
        with atomic_path(target) as tmp:
            save_figure(fig, tmp, ext, dpi=110)
        names.append(target.name)
    plt.close(fig)
    return names


def check_options(design, fidelity: str, phi1_deg, formats=frozenset()) -> None:
    """Refuse what this builder cannot do, before any CAD import (DesignError)."""
    if phi1_deg is not None:
        raise DesignError("--phi1-deg", f"the PowerMouse has no crank angle, got {phi1_deg!r}")
    from cad.parts import powermouse as pp

    pp.lid_screw_plan(design.stator.housing_wall_mm)  # walls too thin for the lid screws
    g = pp.geometry(design, _gap_mm(design))  # the post's and the handle's shoulders
    pp.flotor_lid_screw_plan(g, design.flotor.material)
    pp.post_plan(g)  # a collar too thin for a set screw
    pp.leg_plan(design.stator.housing_wall_mm)  # no catalog leg screw for the wall


def _gap_mm(design) -> float:
    """The magnet gap d (mm): the design's, else the eq (8) optimum of its field model."""
    from cad.actuators import voicecoil as vc

    a = design.actuator
    if a.gap_mm is not None:
        return a.gap_mm
    return vc.optimal_gap(a.params(), a.field_model).as_dict()["optimal_gap_mm"]


def _materials(design) -> dict[str, str]:
    return {
        "shell": design.flotor.material,
        "coil": design.flotor.coil_material,
        "handle": design.handle.material,
        "core": design.stator.iron_material,
        "post": "steel-1018",
        "iron": design.stator.iron_material,
        "magnet": design.stator.magnet_material,
        "housing": design.stator.housing_material,
        "spacer": "aluminium-6061",
        "carrier": design.flotor.material,
        "base": "aluminium-6061",
    }


#: BOM text per part: (description, process, made).
_PARTS = {
    "pm_flotor_body": (
        "flotor: open cube shell (open at -z) with 5 coil pockets, post hole at (-,-,-), "
        "handle socket and boss inside the (+,+,+) corner",
        "CNC milled; ream handle socket; tap M2.5 x4 (lid screws, bottom of the side walls); "
        "tap {ht} x1 through the corner boss (handle)",
        True,
    ),
    "pm_flotor_lid": (
        "flotor lid (-z wall) with 1 coil pocket, 4 lid screw clearance holes",
        "CNC milled",
        True,
    ),
    "pm_coil": ("flat racetrack coil, wound and potted into its pocket (mass: the conductor, "
                "eta_pack x copper; the potting is not weighed)", "wound, potted", True),
    "pm_handle": (
        "handle: stem in the flotor's (+,+,+) corner socket, shoulder on the corner boss, "
        "{ht} tip screwed into it; spherical knob",
        "turned; thread {ht} x {hl:g} (tip)",
        True,
    ),
    "pm_core": (
        "inner iron core (back iron of the 12 inner magnets), both diagonal corners faced",
        "machined; tap {pt} x1 (post, (-,-,-) corner flat)",
        True,
    ),
    "pm_post": (
        "stator post: {pt} tip screwed into the core, shoulder on its flat; locked in the "
        "housing collar by a set screw",
        "turned; thread {pt} x {pl:g} (tip)",
        True,
    ),
    "pm_magnet": ("NdFeB block magnet, bonded (structural epoxy) to its iron plate or the core",
                  "bought", False),
    "pm_iron_plate": (
        "outer back-iron plate (2 magnets each), bonded (structural epoxy) to the housing wall",
        "machined",
        True,
    ),
    "pm_housing_body": (
        "housing: open cube shell, post bore through a collar at (-,-,-)",
        "machined; ream post bore; tap M3 x4 (lid screws, top of the side walls); tap {st} x1 (radial, "
        "collar: post set screw); 4 x M3 clearance holes in the bottom wall (legs)",
        True,
    ),
    "pm_housing_lid": (
        "housing lid (+z wall) with the handle hole, 4 lid screw clearance holes",
        "machined",
        True,
    ),
    "pm_leg": ("leg under the housing (the post's collar stands below its bottom face)",
               "turned; tap M3 x1 (top)", True),
    "rig_magnet": ("NdFeB block magnet", "bought", False),
    "rig_iron_plate": ("back-iron plate", "machined", True),
    "rig_spacer": ("non-magnetic spacer holding the plates apart", "machined", True),
    "rig_coil": ("flat racetrack coil", "wound, potted", True),
    "rig_coil_carrier": ("coil carrier, attaches to the force sensor", "CNC milled", True),
    "rig_base": ("base plate, 4 x M3 clearance holes", "waterjet/laser plate", True),
}


def _tf(R, t) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = np.asarray(R, float), np.asarray(t, float)
    return T


def _labels(g) -> dict:
    """Thread sizes and lengths named in the BOM texts of :data:`_PARTS`."""
    from cad.parts import powermouse as pp

    ss = pp.post_plan(g)["set_screw"]["size"]
    return {"ht": pp.HANDLE_THREAD.split("-")[0], "hl": g.handle_thread_mm,
            "pt": pp.POST_THREAD.split("-")[0], "pl": g.post_thread_mm, "st": ss.split("-")[0]}


def _kind(name, shape, role, design, labels=None, **kw):
    from cad.parts import PartKind

    desc, proc, made = _PARTS[name]
    if labels:
        desc, proc = desc.format(**labels), proc.format(**labels)
    topo = getattr(shape, "wrapped", shape)
    mat = _materials(design)[role]
    if role == "coil":  # wound coil: conductor fraction eta_pack (insulation neglected)
        from cad.data.materials import get_material
        from cad.massprops.occt import solid_mass_props

        rho = get_material(mat).density_kg_m3
        kw["mass_kg"] = design.actuator.eta_pack * solid_mass_props(topo, rho).mass_kg
    return PartKind(
        name=name, shape=topo, material=mat, made=made, description=desc, process=proc, **kw
    )


def assembly(design, g, acts) -> tuple[list, list]:
    """``(device instances, rig instances)``: :class:`cad.parts.PartInstance` lists.

    Device bodies: ``flotor`` (frame = the flotor frame of :mod:`cad.parts.powermouse`)
    and ``ground`` (the stator), both at the identity at the centre pose. Repeated parts
    (coils, magnets, iron plates) are one kind placed several times.
    """
    from cad.actuators import powermouse as pm
    from cad.export.shapes import placed
    from cad.parts import PartInstance
    from cad.parts import powermouse as pp

    fl, st = pp.flotor_solids(g), pp.stator_solids(g)
    coils = g.coils()
    inst: list = []
    labels, tips, fits = _labels(g), _turned_tips(design, g), _fits(g)

    def local(shape, T):
        return placed(getattr(shape, "wrapped", shape), np.linalg.inv(T))

    for key, kname, body in (
        ("flotor_body", "pm_flotor_body", "flotor"),
        ("flotor_lid", "pm_flotor_lid", "flotor"),
        ("handle", "pm_handle", "flotor"),
        ("core", "pm_core", "ground"),
        ("post", "pm_post", "ground"),
        ("housing_body", "pm_housing_body", "ground"),
        ("housing_lid", "pm_housing_lid", "ground"),
    ):
        shape, role = (fl | st)[key]
        kind = _kind(kname, shape, role, design, labels, fits=fits.get(key, ()))
        inst.append(PartInstance(key, kind, body, np.eye(4), fastener=tips.get(key)))
    Tc = {c.face: _tf(c.R_flotor_act, c.centre_mm) for c in coils}
    ck = _kind("pm_coil", local(fl[f"coil_{coils[0].face}"][0], Tc[coils[0].face]), "coil", design)
    inst += [PartInstance(f"coil_{f}", ck, "flotor", T) for f, T in Tc.items()]
    a, d, t = g.coil_plane_half_mm, g.gap_mm, g.magnet_thickness_mm
    zc = a + d / 2 + t + g.plate_thickness_mm / 2
    Ti = {c.face: _tf(c.R_flotor_act, c.normal * zc) for c in coils}
    ik = _kind(
        "pm_iron_plate", local(st[f"iron_{coils[0].face}"][0], Ti[coils[0].face]), "iron", design
    )
    inst += [PartInstance(f"iron_{f}", ik, "ground", T) for f, T in Ti.items()]
    mags = pm.stator_magnets(coils, d, g.magnet_length_mm, g.magnet_width_mm, t, 1.0)
    Tm = {f"magnet_{coils[m.actuator].face}_{m.role}": _tf(m.R, m.centre_mm) for m in mags}
    k0 = next(iter(Tm))
    mk = _kind("pm_magnet", local(st[k0][0], Tm[k0]), "magnet", design)
    inst += [PartInstance(k, mk, "ground", T) for k, T in Tm.items()]
    return inst + _lid_screws(design, g) + [_post_set_screw(g)] + _legs(design, g), _rig(design, acts)


def _screw_uses(design, g) -> dict:
    """``{(size, length): "housing lid, legs"}``: what each ISO 4762 screw kind holds (one
    BOM row per kind, so screws of one size and length share its text)."""
    from cad.parts import powermouse as pp

    uses: dict = {}
    for sp, _, _, _, lid, _ in _lid_plans(design, g).values():
        uses.setdefault((sp["size"], sp["length_mm"]), []).append(lid.replace("_", " "))
    lp = pp.leg_plan(design.stator.housing_wall_mm)
    uses.setdefault((lp["size"], lp["length_mm"]), []).append("legs")
    return {k: ", ".join(v) for k, v in uses.items()}


def _legs(design, g) -> list:
    """The four legs under the housing and their ISO 4762 screws (from inside the housing,
    head on the bottom wall's inner face), each screw with its fastener record."""
    from cad.assembly.fasteners import Fastener
    from cad.parts import PartInstance, joints, translation
    from cad.parts import powermouse as pp

    sp = pp.leg_plan(design.stator.housing_wall_mm)
    Ho = g.housing_inner_half_mm + g.housing_wall_mm
    leg = _kind("pm_leg", pp.leg_shape(g), "base", design)
    screw = joints.cap_screw_kind(sp["size"], sp["length_mm"], "stator.housing_wall_mm",
                                  _screw_uses(design, g)[sp["size"], sp["length_mm"]])
    out = []
    for k, (x, y) in enumerate(pp.leg_xy_mm(g), start=1):
        out.append(PartInstance(f"leg_{k}", leg, "ground", translation(x, y, -Ho)))
        f = Fastener("ISO 4762", sp["size"], sp["length_mm"], ("housing_body",), f"leg_{k}:top",
                     sp["engagement_mm"])
        out.append(PartInstance(f"leg_screw_{k}", screw, "ground",
                                translation(x, y, -g.housing_inner_half_mm), fastener=f))
    return out


def _fits(g) -> dict[str, tuple[str, ...]]:
    """ISO 286 fits of the two diagonal sliding fits (:data:`cad.data.fits.FITS`):
    the housing collar's post bore on the stator post and the flotor's handle socket on the
    handle stem, both H7/g6 (diameters: ``stator.post_diameter_mm``,
    ``handle.diameter_mm``). No bearings in the PowerMouse."""
    from cad.data.fits import fit

    return {
        "housing_body": (fit("post bore", g.post_diameter_mm),),
        "post": (fit("post", g.post_diameter_mm),),
        "flotor_body": (fit("handle socket", g.handle_diameter_mm),),
        "handle": (fit("handle stem", g.handle_diameter_mm),),
    }


def _turned_tips(design, g) -> dict:
    """Fastener records of the two turned parts screwed in along the diagonal: ``handle``
    (its tip in the flotor's corner boss) and ``post`` (its tip in the core)."""
    from cad.assembly.fasteners import Fastener
    from cad.parts import powermouse as pp

    h, t = pp.handle_plan(g, design.flotor.material), pp.post_plan(g)["tip"]
    return {
        "handle": Fastener("turned tip", h["size"], h["engagement_mm"], (),
                           "flotor_body:handle", h["engagement_mm"]),
        "post": Fastener("turned tip", t["size"], t["engagement_mm"], (), "core:post",
                         t["engagement_mm"]),
    }


def _post_set_screw(g):
    """The ISO 4026 set screw locking the post in the housing's collar, with its record."""
    from cad.assembly.fasteners import Fastener
    from cad.data.catalog import FASTENER_MATERIAL
    from cad.parts import PartInstance, PartKind
    from cad.parts import powermouse as pp
    from cad.parts.motor import set_screw_shape

    ss = pp.post_plan(g)["set_screw"]
    size, L = ss["size"], ss["length_mm"]
    kind = PartKind(
        name=f"set_screw_{size}x{L:g}", shape=set_screw_shape(L, size),
        material=FASTENER_MATERIAL, made=False, process="bought",
        description=f"set screw ISO 4026 {size} x {L:g} (locks the stator post in the "
        "housing collar)",
    )
    f = Fastener("ISO 4026", size, L, ("post",), "housing_body:post_set_screw", L)
    return PartInstance("post_set_screw", kind, "ground", pp.post_set_screw_tf(g, size),
                        fastener=f)


def _lid_plans(design, g) -> dict:
    """``{prefix: (plan, screw (x, y) list, z of the lid's outer face, body, lid, tapped
    part)}`` for the housing lid (+z wall, screws from above) and the flotor lid (-z wall,
    screws from below) (:mod:`cad.parts.powermouse`)."""
    from cad.parts import powermouse as pp

    return {
        "lid_screw": (pp.lid_screw_plan(design.stator.housing_wall_mm), pp.lid_screw_xy_mm(g),
                      g.housing_inner_half_mm + g.housing_wall_mm, "ground", "housing_lid",
                      "housing_body"),
        "flotor_lid_screw": (pp.flotor_lid_screw_plan(g, design.flotor.material),
                             pp.flotor_lid_screw_xy_mm(g), -g.flotor_edge_mm / 2, "flotor",
                             "flotor_lid", "flotor_body"),
    }


def lid_holes(design, g) -> dict:
    """Every tapped hole of the device -> :class:`cad.assembly.fasteners.TappedHole`: the lid
    screws' ``housing_body:lid_<k>`` and ``flotor_body:lid_<k>`` (depth and minimum
    engagement from :func:`cad.parts.powermouse.lid_screw_plan`), ``flotor_body:handle``,
    ``core:post`` and ``housing_body:post_set_screw``
    (:func:`cad.parts.powermouse.handle_plan`, :func:`cad.parts.powermouse.post_plan`)."""
    from cad.assembly.fasteners import TappedHole
    from cad.parts import powermouse as pp

    out = {}
    for sp, xy, _, _, _, part in _lid_plans(design, g).values():
        for k in range(len(xy)):
            n = f"{part}:lid_{k + 1}"
            out[n] = TappedHole(n, part, sp["size"], sp["depth_mm"], sp["min_engagement_mm"])
    lp = pp.leg_plan(design.stator.housing_wall_mm)
    for k in range(1, 5):
        n = f"leg_{k}:top"
        out[n] = TappedHole(n, f"leg_{k}", lp["size"], lp["depth_mm"], lp["min_engagement_mm"])
    pl = pp.post_plan(g)
    for n, x in (("flotor_body:handle", pp.handle_plan(g, design.flotor.material)),
                 ("core:post", pl["tip"]), ("housing_body:post_set_screw", pl["set_screw"])):
        out[n] = TappedHole(n, n.split(":")[0], x["size"], x["depth_mm"], x["min_engagement_mm"])
    return out


def _lid_screws(design, g) -> list:
    """The ISO 4762 screws holding the housing lid and the flotor lid (heads on the lid,
    shanks through its clearance holes into the side walls), each with its fastener record."""
    from cad.assembly.fasteners import Fastener
    from cad.parts import PartInstance, flip_x, joints, translation

    out, uses = [], _screw_uses(design, g)
    for prefix, (sp, xy, z, body, lid, part) in _lid_plans(design, g).items():
        size, L = sp["size"], sp["length_mm"]
        kind = joints.cap_screw_kind(size, L, "stator.housing_wall_mm", uses[size, L])
        up = np.eye(4) if z > 0 else flip_x()  # head on the lid's outer face
        out += [
            PartInstance(
                f"{prefix}_{k + 1}", kind, body, translation(x, y, z) @ up,
                fastener=Fastener("ISO 4762", size, L, (lid,), f"{part}:lid_{k + 1}",
                                  sp["engagement_mm"]),
            )
            for k, (x, y) in enumerate(xy)
        ]
    return out


def _rig(design, acts) -> list:
    """The Fig. 7 test rig: instances of translated copies share one kind."""
    from cad.assembly.static import exact_box
    from cad.parts import PartInstance, translation

    groups = {
        "magnet": "rig_magnet",
        "iron": "rig_iron_plate",
        "spacer": "rig_spacer",
        "coil": "rig_coil",
        "carrier": "rig_coil_carrier",
        "base": "rig_base",
    }
    first: dict[str, tuple] = {}
    inst = []
    for key, (shape, role) in acts.items():
        c = exact_box(getattr(shape, "wrapped", shape)).mean(axis=0)
        if role not in first:
            kw = {"plate": role in ("iron", "base")}
            first[role] = (_kind(groups[role], shape, role, design, **kw), c)
        kind, c0 = first[role]
        inst.append(PartInstance(key, kind, "rig", translation(*(c - c0))))
    return inst


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
    """Build the PowerMouse and its test rig into ``out_dir``; return the report dict (module docstring).

    fidelity: "fabrication" checks all 52 extreme poses of the motion range; "inertia" /
    "preview" only the 12 on-axis poses. Raises InterferenceError when two solids overlap
    at the centre pose or the flotor overlaps the stator anywhere in the range, unless
    allow_interference.
    """
    from cad.actuators import powermouse as pm
    from cad.parts import powermouse as pp
    from cad.parts import voicecoil as pv
    from cad.pipeline import family, forked

    check_options(design, fidelity, phi1_deg)
    out_dir = Path(out_dir)
    total = 6
    _step(progress, "actuator optimum (eqs 8-9)", 0, total)
    act = actuator_optimum(design)
    gap = act["gap_mm"]
    g = pp.geometry(design, gap)
    a = design.actuator
    ag = pv.ActuatorGeometry(
        a.magnet_length_mm,
        a.magnet_width_mm,
        a.magnet_thickness_mm,
        gap,
        a.rattle_mm,
        a.plate_thickness_mm,
    )

    _step(progress, "solids", 1, total)
    acts = pv.actuator_solids(ag)
    inst, rig = assembly(design, g, acts)
    fasteners = family.fastener_report(inst, lid_holes(design, g))
    tfs = {"flotor": np.eye(4), "ground": np.eye(4)}

    _step(progress, "mass properties and wrench map", 2, total)
    props = family.kind_props(inst)
    flotor_mp = family.body_props(inst, props, ["flotor"])["flotor"]
    parts_mass = {i.name: props[i.kind.name].mass_kg for i in inst if i.body == "flotor"}
    stator_mass_kg = sum(props[i.kind.name].mass_kg for i in inst if i.body == "ground")
    coils = g.coils()
    gain_per_At = act["Bg_T"] * 2.0 * a.magnet_length_mm * 1e-3  # N per ampere-turn
    W = pm.wrench_map(coils, gain_per_At)
    iso = pm.isotropy(W)
    W_com = pm.wrench_map(coils, gain_per_At, about_mm=flotor_mp.com_m * 1e3)

    # the files (parts, assembly STEP, BOM, preview, rig) and the viewer files + Fig. 8 are
    # written by two forked children while this process checks the solids (cad.pipeline.forked;
    # serial where forking is off)
    bom = family.bom_rows(inst, props)
    rig_bom = family.bom_rows(rig, family.kind_props(rig))

    def exports() -> list[str]:
        return _write_files(design, inst, tfs, rig, bom, rig_bom, out_dir, formats)

    def views() -> tuple[list[str], bytes]:
        return _write_views(design, inst, tfs, out_dir, formats, gap)

    task = forked.start(exports, "exports")
    views_task = forked.start(views, "views")
    with forked.cancel_on_error(task, views_task):
        _step(progress, "every pair at the centre, flotor over the motion range", 3, total)
        itf = family.check_assembly(inst, tfs)
        cl = _motion(design, g, inst, fidelity)
        _raise_on_overlap(design, itf, cl, allow_interference)
        _step(progress, "exports", 4, total)
        files = task.result()
        more, viewer_glb = views_task.result()
        files += more

    _step(progress, "report", 5, total)
    rep = _report(
        design,
        act,
        ag,
        g,
        W,
        iso,
        W_com,
        flotor_mp,
        parts_mass,
        stator_mass_kg,
        itf,
        cl,
        bom,
        rig_bom,
        pv.rattle_clearances_mm(ag, acts),
        gain_per_At,
    )
    rep.update(fasteners)
    rep["part_materials"] = family.part_materials(inst)
    rep["fits"] = family.fits_report(inst)
    rep["placement"] = family.placement_report(inst, tfs, props)
    rep["files"] = sorted(files + ["report.md"])
    family.write_report_md(out_dir, f"{design.name} (powermouse)", _md_rows(rep), bom, rep["notes"])
    family.write_assembly_md(out_dir, f"{design.name} (powermouse)", inst, ASSEMBLY_PLAN,
                             [f"the flotor moves freely by +-{design.motion.range_mm:g} mm and "
                              f"+-{design.motion.range_deg:g} deg about the centre, touching only "
                              "at the limits (clearances in report.md)"])
    rep["_viewer_glb"] = viewer_glb  # popped by the dispatcher: embedded in report.html
    _step(progress, "done", total, total)
    return rep


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


#: This builder writes glb and 3mf (:mod:`cad.pipeline.views`).
VIEW_EXPORT = True


def stroke_poses(design) -> dict[str, np.ndarray]:
    """The flotor over its motion range for the animation, ``{body: (N, 4, 4)}`` mm: out
    to +range and -range along x, y, z, then +-range_deg about x, y, z (the cube centre),
    through the centre pose between each (:func:`cad.actuators.powermouse.rot_about`)."""
    from cad.actuators.powermouse import rot_about

    r_mm, r_rad = design.motion.range_mm, np.deg2rad(design.motion.range_deg)
    poses = [np.eye(4)]
    for kind in ("t", "r"):
        for axis in np.eye(3):
            for s in (1.0, 0.0, -1.0, 0.0):
                T = np.eye(4)
                if kind == "t":
                    T[:3, 3] = s * r_mm * axis
                else:
                    T[:3, :3] = rot_about(axis, s * r_rad)
                poses.append(T)
    flotor = np.stack(poses)
    return {"flotor": flotor, "ground": np.repeat(np.eye(4)[None], len(flotor), axis=0)}


def _write_files(design, inst, tfs, rig, bom, rig_bom, out_dir, formats) -> list[str]:
    """Part files, assembly STEP, BOM and preview of the device; the rig in ``rig/``."""
    from cad.pipeline import family

    files = family.write_outputs(
        inst,
        tfs,
        out_dir,
        formats,
        name=design.name,
        title=f"{design.name}: PowerMouse at the centre pose",
        bom=bom,
    )
    return files + [
        "rig/" + f
        for f in family.write_outputs(
            rig,
            {"rig": np.eye(4)},
            out_dir / "rig",
            formats,
            name=f"{design.name}_rig",
            title="single-actuator test rig (Fig. 7), not part of the device",
            bom=rig_bom,
            preview=False,
        )
    ]


def _write_views(design, inst, tfs, out_dir, formats, gap) -> tuple[list[str], bytes]:
    """The viewer files (:func:`cad.pipeline.views.write_viewer_outputs`) and Fig. 8; returns
    (files, glb)."""
    from cad.pipeline.views import write_viewer_outputs

    view_files, glb = write_viewer_outputs(
        inst,
        tfs,
        out_dir,
        formats,
        name=design.name,
        title=f"{design.name} (powermouse)",
        stroke=stroke_poses(design),
    )
    return _fig8_chart(design, gap, out_dir) + view_files, glb


def _motion(design, g, inst, fidelity):
    from cad.actuators import powermouse as pm
    from cad.parts import powermouse as pp

    poses = pm.workspace_poses(design.motion.range_mm, design.motion.range_deg)
    poses += pp.combined_poses(g)  # translation + rotation: the handle's and post's worst
    if fidelity != "fabrication":
        poses = [
            p
            for p in pm.workspace_poses(design.motion.range_mm, design.motion.range_deg)
            if p[0].startswith("t")
            and sorted(map(abs, p[2])) == [0.0, 0.0, design.motion.range_mm]
            or p[0].startswith("r(")
            and p[0][1:10] in ("(1, 0, 0)", "(0, 1, 0)", "(0, 0, 1)")
        ]
    fl = {i.name: (i.kind.shape, "", i.tf_body_part) for i in inst if i.body == "flotor"}
    st = {i.name: (i.kind.shape, "", i.tf_body_part) for i in inst if i.body == "ground"}
    return pp.motion_clearances(g, design.motion.range_mm, design.motion.range_deg, fl, st, poses)


def _raise_on_overlap(design, itf, cl, allow: bool) -> None:
    if allow:
        return
    if itf["collisions"]:
        c = itf["collisions"][0]
        raise InterferenceError(
            f"{c['parts'][0]} / {c['parts'][1]} overlap {c['overlap_volume_mm3']:.3f} mm^3 at the "
            f"centre pose; {len(itf['collisions'])} overlapping pair(s) (use --allow-interference)"
        )
    if cl.minimum_mm < 0:
        bad = [k for k, v in cl.poses.items() if v[0] < 0]
        pair = f": {cl.poses[bad[0]][1]}" if bad else ""
        raise InterferenceError(
            f"flotor overlaps the stator at {len(bad)} pose(s) of the +-{design.motion.range_mm:g} mm / "
            f"+-{design.motion.range_deg:g} deg range (e.g. {bad[0] if bad else 'centre'}{pair}); "
            "enlarge actuator.rattle_mm or reduce motion.range_mm / range_deg, or pass "
            "--allow-interference"
        )


def _report(
    design,
    act,
    ag,
    g,
    W,
    iso,
    W_com,
    flotor_mp,
    parts_mass,
    stator_mass_kg,
    itf,
    cl,
    bom,
    rig_bom,
    rattle_single,
    gain_per_At,
) -> dict:
    from cad.actuators import powermouse as pm
    from cad.data.materials import get_material

    peak_F = pm.peak_force_N(act["peak_force_N"])
    acc = pm.peak_acceleration_m_s2(act["peak_force_N"], flotor_mp.mass_kg)
    return {
        "name": design.name,
        "family": design.family,
        "source": Path(design.source).name,  # the file name: no path of this machine
        "actuator": act,
        "actuator_geometry_mm": {
            "gap_mm": ag.gap_mm,
            "coil_width_mm": ag.coil_width_mm,
            "plate_thickness_mm": ag.plate_thickness_mm,
            "height_mm": ag.height_mm,
            "rattle_clearances_mm": rattle_single,
        },
        "geometry_mm": {
            "flotor_edge_mm": g.flotor_edge_mm,
            "coil_plane_half_mm": g.coil_plane_half_mm,
            "core_half_mm": g.core_half_mm,
            "housing_inner_half_mm": g.housing_inner_half_mm,
        },
        "wrench_map": W.tolist(),
        "wrench_map_units": "columns per ampere-turn of each coil; rows F (N), tau about the cube centre (N m)",
        "wrench_map_singular_values": iso.singular_values.tolist(),
        "isotropy": {
            "force_singular_values": iso.force_sv.tolist(),
            "torque_singular_values": iso.torque_sv.tolist(),
            "force_spread": iso.force_spread,
            "torque_spread": iso.torque_spread,
            "force_torque_coupling": iso.coupling,
            "coupling_about_flotor_com": pm.isotropy(W_com).coupling,
        },
        "flotor": {
            **flotor_mp.to_dict(),
            "parts_mass_kg": parts_mass,
            "coil_density_kg_m3": design.actuator.eta_pack
            * get_material(design.flotor.coil_material).density_kg_m3,
        },
        "flotor_mass_g": flotor_mp.mass_kg * 1e3,
        "stator_mass_kg": stator_mass_kg,
        "continuous_force_N": pm.peak_force_N(act["force_N"]),
        "peak_force_N": peak_F,
        "peak_acceleration_m_s2": acc,
        "peak_acceleration_G": acc / pm.G0_M_S2,
        "interference": itf,
        "overlap_volume_mm3": itf["overlap_volume_mm3"],
        "clearances_mm": {
            "nominal_mm": cl.nominal_mm,
            "translation_mm": cl.translation_mm,
            "rotation_mm": cl.rotation_mm,
            "worst_translation": cl.worst_translation,
            "worst_rotation": cl.worst_rotation,
            "combined_mm": None if cl.combined_mm != cl.combined_mm else cl.combined_mm,
            "worst_combined": cl.worst_combined,
            "poses_checked": len(cl.poses),
            "range_mm": design.motion.range_mm,
            "range_deg": design.motion.range_deg,
            "poses": {k: {"clearance_mm": v[0], "closest": v[1]} for k, v in cl.poses.items()},
        },
        "min_clearance_mm": cl.minimum_mm,
        "paper_table4": PAPER_TABLE4,
        "bom": bom,
        "rig_bom": rig_bom,
        "notes": [
            "Fig. 6 is lost: the cyclic coil layout, the inner core and the diagonal post/handle are our reconstruction.",
            "Forces use eq (8) with B_g of the chosen field model; peak force = 2 x actuator force at peak_power_W "
            "(the guaranteed zero-torque force in any direction).",
            f"touching (clearance 0) at the +-{design.motion.range_mm:g} mm limit is by design: rattle_mm/2 = "
            f"{design.actuator.rattle_mm / 2:g} mm.",
            "Assembly: the steps are in assembly.md (generated from the part instances and the "
            "fastener records, cad.assembly.steps, in the order of ASSEMBLY_PLAN).",
            "Finding the core's tapped hole: hold the housing with its (-,-,-) corner down (the diagonal "
            "vertical). The flotor then rests on the three lower outer magnet groups and the core on the "
            "flotor's three lower walls, each moved d_r/2 on every axis, i.e. along the diagonal: the "
            "post's tip meets the core's hole on its axis. Screw it in until its shoulder seats, draw the "
            "post out until its end is flush with the collar's end (the core is then centred), tighten "
            "the set screw. Magnets and iron plates are bonded (structural epoxy).",
            "rig/ holds the single-actuator test rig of Fig. 7 (one coil between two magnet pairs): a bench "
            "fixture to measure one actuator's force against eq (8), not part of the PowerMouse.",
            "Clearances over the motion range: fcl mesh distances at every pose, exact OCCT where the mesh "
            "distance is within 0.15 mm of contact and at the closest pose of each group.",
        ],
        "gain_N_per_ampere_turn": gain_per_At,
    }


def _md_rows(r: dict) -> list[tuple[str, str]]:
    c = r["clearances_mm"]
    return [
        ("actuator gap d (mm)", f"{r['actuator']['gap_mm']:.3f} ({r['actuator']['gap_source']})"),
        ("flotor mass (g)", f"{r['flotor_mass_g']:.1f}"),
        ("peak force (N), paper", f"{r['peak_force_N']:.1f}, {PAPER_TABLE4['peak_force_N']:g}"),
        ("peak acceleration (G)", f"{r['peak_acceleration_G']:.2f}"),
        (
            "clearance centre / translations / rotations / combined (mm)",
            f"{c['nominal_mm']:.3f} / {c['translation_mm']:.3f} / {c['rotation_mm']:.3f} / "
            + ("–" if c["combined_mm"] is None else f"{c['combined_mm']:.3f}"),
        ),
        (
            "solids / pairs checked exactly at the centre",
            f"{r['interference']['parts']} / {r['interference']['exact_pairs']}",
        ),
        ("overlap volume at the centre (mm^3)", f"{r['overlap_volume_mm3']:.4g}"),
    ]
