"""The PowerMouse's part kinds and instances: the flotor (its box, lid, coils, handle) and the
stator (core, post, housing, iron plates, magnets), their screws, set screw and legs, and
the single-actuator test rig of Fig. 7. Bodies ``flotor`` and ``ground``, mm."""

from __future__ import annotations

import numpy as np

from cad.actuators import powermouse as pm
from cad.assembly.fasteners import Fastener, TappedHole
from cad.data.catalog import FASTENER_MATERIAL
from cad.data.fits import fit
from cad.data.materials import get_material
from cad.export.shapes import placed
from cad.families.powermouse import parts as pp
from cad.massprops.occt import solid_mass_props
from cad.occ.bbox import tight_box
from cad.parts import PartInstance, PartKind, flip_x, joints, translation
from cad.parts.motor import set_screw_shape


def materials(design) -> dict[str, str]:
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
PARTS = {
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


def tf(R, t) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = np.asarray(R, float), np.asarray(t, float)
    return T


def part_labels(g) -> dict:
    """Thread sizes and lengths named in the BOM texts of :data:`PARTS`."""
    ss = pp.post_plan(g)["set_screw"]["size"]
    return {"ht": pp.HANDLE_THREAD.split("-")[0], "hl": g.handle_thread_mm,
            "pt": pp.POST_THREAD.split("-")[0], "pl": g.post_thread_mm, "st": ss.split("-")[0]}


def part_kind(name, shape, role, design, labels=None, **kw):
    desc, proc, made = PARTS[name]
    if labels:
        desc, proc = desc.format(**labels), proc.format(**labels)
    topo = getattr(shape, "wrapped", shape)
    mat = materials(design)[role]
    if role == "coil":  # wound coil: conductor fraction eta_pack (insulation neglected)

        rho = get_material(mat).density_kg_m3
        kw["mass_kg"] = design.actuator.eta_pack * solid_mass_props(topo, rho).mass_kg
    return PartKind(
        name=name, shape=topo, material=mat, made=made, description=desc, process=proc, **kw
    )


def assembly(design, g, acts) -> tuple[list, list]:
    """``(device instances, rig instances)``: :class:`cad.parts.PartInstance` lists.

    Device bodies: ``flotor`` (frame = the flotor frame of :mod:`cad.families.powermouse.parts`)
    and ``ground`` (the stator), both at the identity at the centre pose. Repeated parts
    (coils, magnets, iron plates) are one kind placed several times.
    """
    fl, st = pp.flotor_solids(g), pp.stator_solids(g)
    coils = g.coils()
    inst: list = []
    labels, tips, fits = part_labels(g), turned_tips(design, g), part_fits(g)

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
        kind = part_kind(kname, shape, role, design, labels, fits=fits.get(key, ()))
        inst.append(PartInstance(key, kind, body, np.eye(4), fastener=tips.get(key)))
    Tc = {c.face: tf(c.R_flotor_act, c.centre_mm) for c in coils}
    ck = part_kind("pm_coil", local(fl[f"coil_{coils[0].face}"][0], Tc[coils[0].face]), "coil", design)
    inst += [PartInstance(f"coil_{f}", ck, "flotor", T) for f, T in Tc.items()]
    a, d, t = g.coil_plane_half_mm, g.gap_mm, g.magnet_thickness_mm
    zc = a + d / 2 + t + g.plate_thickness_mm / 2
    Ti = {c.face: tf(c.R_flotor_act, c.normal * zc) for c in coils}
    ik = part_kind(
        "pm_iron_plate", local(st[f"iron_{coils[0].face}"][0], Ti[coils[0].face]), "iron", design
    )
    inst += [PartInstance(f"iron_{f}", ik, "ground", T) for f, T in Ti.items()]
    mags = pm.stator_magnets(coils, d, g.magnet_length_mm, g.magnet_width_mm, t, 1.0)
    Tm = {f"magnet_{coils[m.actuator].face}_{m.role}": tf(m.R, m.centre_mm) for m in mags}
    k0 = next(iter(Tm))
    mk = part_kind("pm_magnet", local(st[k0][0], Tm[k0]), "magnet", design)
    inst += [PartInstance(k, mk, "ground", T) for k, T in Tm.items()]
    return inst + lid_screws(design, g) + [post_set_screw_parts(g)] + leg_parts(design, g), rig_parts(design, acts)


def screw_uses(design, g) -> dict:
    """``{(size, length): "housing lid, legs"}``: what each ISO 4762 screw kind holds (one
    BOM row per kind, so screws of one size and length share its text)."""
    uses: dict = {}
    for sp, _, _, _, lid, _ in lid_plans(design, g).values():
        uses.setdefault((sp["size"], sp["length_mm"]), []).append(lid.replace("_", " "))
    lp = pp.leg_plan(design.stator.housing_wall_mm)
    uses.setdefault((lp["size"], lp["length_mm"]), []).append("legs")
    return {k: ", ".join(v) for k, v in uses.items()}


def leg_parts(design, g) -> list:
    """The four legs under the housing and their ISO 4762 screws (from inside the housing,
    head on the bottom wall's inner face), each screw with its fastener record."""
    sp = pp.leg_plan(design.stator.housing_wall_mm)
    Ho = g.housing_inner_half_mm + g.housing_wall_mm
    leg = part_kind("pm_leg", pp.leg_shape(g), "base", design)
    screw = joints.cap_screw_kind(sp["size"], sp["length_mm"], "stator.housing_wall_mm",
                                  screw_uses(design, g)[sp["size"], sp["length_mm"]])
    out = []
    for k, (x, y) in enumerate(pp.leg_xy_mm(g), start=1):
        out.append(PartInstance(f"leg_{k}", leg, "ground", translation(x, y, -Ho)))
        f = Fastener("ISO 4762", sp["size"], sp["length_mm"], ("housing_body",), f"leg_{k}:top",
                     sp["engagement_mm"])
        out.append(PartInstance(f"leg_screw_{k}", screw, "ground",
                                translation(x, y, -g.housing_inner_half_mm), fastener=f))
    return out


def part_fits(g) -> dict[str, tuple[str, ...]]:
    """ISO 286 fits of the two diagonal sliding fits (:data:`cad.data.fits.FITS`):
    the housing collar's post bore on the stator post and the flotor's handle socket on the
    handle stem, both H7/g6 (diameters: ``stator.post_diameter_mm``,
    ``handle.diameter_mm``). No bearings in the PowerMouse."""
    return {
        "housing_body": (fit("post bore", g.post_diameter_mm),),
        "post": (fit("post", g.post_diameter_mm),),
        "flotor_body": (fit("handle socket", g.handle_diameter_mm),),
        "handle": (fit("handle stem", g.handle_diameter_mm),),
    }


def turned_tips(design, g) -> dict:
    """Fastener records of the two turned parts screwed in along the diagonal: ``handle``
    (its tip in the flotor's corner boss) and ``post`` (its tip in the core)."""
    h, t = pp.handle_plan(g, design.flotor.material), pp.post_plan(g)["tip"]
    return {
        "handle": Fastener("turned tip", h["size"], h["engagement_mm"], (),
                           "flotor_body:handle", h["engagement_mm"]),
        "post": Fastener("turned tip", t["size"], t["engagement_mm"], (), "core:post",
                         t["engagement_mm"]),
    }


def post_set_screw_parts(g):
    """The ISO 4026 set screw locking the post in the housing's collar, with its record."""
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


def lid_plans(design, g) -> dict:
    """``{prefix: (plan, screw (x, y) list, z of the lid's outer face, body, lid, tapped
    part)}`` for the housing lid (+z wall, screws from above) and the flotor lid (-z wall,
    screws from below) (:mod:`cad.families.powermouse.parts`)."""
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
    engagement from :func:`cad.families.powermouse.parts.lid_screw_plan`), ``flotor_body:handle``,
    ``core:post`` and ``housing_body:post_set_screw``
    (:func:`cad.families.powermouse.parts.handle_plan`, :func:`cad.families.powermouse.parts.post_plan`)."""
    out = {}
    for sp, xy, _, _, _, part in lid_plans(design, g).values():
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


def lid_screws(design, g) -> list:
    """The ISO 4762 screws holding the housing lid and the flotor lid (heads on the lid,
    shanks through its clearance holes into the side walls), each with its fastener record."""
    out, uses = [], screw_uses(design, g)
    for prefix, (sp, xy, z, body, lid, part) in lid_plans(design, g).items():
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


def rig_parts(design, acts) -> list:
    """The Fig. 7 test rig: instances of translated copies share one kind."""
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
        c = tight_box(getattr(shape, "wrapped", shape)).mean(axis=0)
        if role not in first:
            kw = {"plate": role in ("iron", "base")}
            first[role] = (part_kind(groups[role], shape, role, design, **kw), c)
        kind, c0 = first[role]
        inst.append(PartInstance(key, kind, "rig", translation(*(c - c0))))
    return inst
