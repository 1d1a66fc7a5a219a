"""Every part of a four-bar haptic display, placed on its rigid body (parts -> instances).

Input: the linkage (joint positions in each link's frame from
:func:`cad.kinematics.linkgeom.link_joints_mm`), the layer plan
(:func:`cad.families.fourbar.layers.choose_layers`) and the ``[parts]`` spec. Output: a list
of :class:`cad.parts.PartInstance` -- a part kind (solid in its own frame) carried by
a body ("ground", "crank", "coupler", "rocker") at a 4x4 placement. Bodies move with
the link transforms of :mod:`cad.kinematics.linkgeom`; z = 0 is the base plate's top.

Joint hardware belongs to the link that holds the pin (the LOWER link at A2/A3, the
ground at A4); the bearing belongs to the link with the seat, its inner ring's
collision envelope to the pin's link (see :mod:`cad.families.fourbar.layers`).

Fasteners are sized from their stacks (:mod:`cad.assembly.fasteners`): every screw
instance carries a :class:`cad.assembly.fasteners.Fastener` record, every tapped hole a
:class:`cad.assembly.fasteners.TappedHole`, and :func:`build_assembly` refuses two
screws in one hole or an engagement outside its hole's window.

One small function per group of parts (:class:`_Builder` holds the instances): bars,
joint hardware, motor and hub, base with post and legs, handle.

Called through :func:`cad.families.fourbar.assemble`, the one place the four-bar is laid
out (it plans the layers, calls :func:`build_assembly` and adds the bodies' poses and
motion: a :class:`cad.assembly.model.AssemblyModel`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from cad.assembly.fasteners import (
    MIN_ENGAGEMENT_ALU_D,
    MIN_ENGAGEMENT_BOUGHT_MM,
    Fastener,
    TappedHole,
    alu_hole,
    check_fasteners,
    iso7379_thread_mm,
    shoulder_screw_hole,
)
from cad.assembly.laser import as_laser
from cad.assembly.printed import as_printed
from cad.data import catalog as cat
from cad.data.fits import fit
from cad.design.parts import PartsSpec
from cad.errors import DesignError
from cad.families.fourbar.layers import (
    HUB_SCREWS,
    POST_THREAD_EXTRA_MM,
    TAP_LEADOUT_MM,
    LayerPlan,
    hub_bolt_circle_mm,
    post_bore_depth_mm,
    spacer_od_mm,
)
from cad.families.fourbar.sheet_tolerance import (
    handle_floor_mm,
    handle_min_engagement_mm,
    pin_rows,
    sheet_bands,
    size_over_band,
    thinnest_mm,
    warn_pins,
)
from cad.parts import PartInstance, PartKind, bars, base, flip_x, handle, joints, motor, translation
from cad.parts import tubebars as tb
from cad.printing import HEAT_SET_PILOT_MM

#: Smallest engagement of the handle screw in the coupler plate, in thread diameters: the
#: knob carries hand loads only (a few N), so a plate thinner than 1.5 d is tapped through
#: and taken whole down to 1 d.
HANDLE_MIN_ENGAGEMENT_D = 1.0
#: Clearance kept between the post screw head and the motor housing when the screw
#: passes through the motor mount plate (mm).
HEAD_CLEARANCE_MM = 0.5


@dataclass(frozen=True)
class Assembly:
    """All placed parts plus what the report needs about them."""

    instances: tuple[PartInstance, ...]
    base_rect_mm: tuple[float, float, float, float]
    notes: tuple[str, ...] = ()
    holes: tuple[TappedHole, ...] = ()

    def kinds(self) -> dict[str, PartKind]:
        out: dict[str, PartKind] = {}
        for inst in self.instances:
            out.setdefault(inst.kind.name, inst.kind)
        return out

    def quantities(self) -> dict[str, int]:
        q: dict[str, int] = {}
        for inst in self.instances:
            q[inst.kind.name] = q.get(inst.kind.name, 0) + 1
        return q

    def fasteners(self) -> dict[str, Fastener]:
        """Instance name -> fastener record, for every fastener instance."""
        return {i.name: i.fastener for i in self.instances if i.fastener is not None}


def _fmt(x: float) -> str:
    return f"{x:.2f}".rstrip("0").rstrip(".")


class _Builder:
    """Collects part kinds (one per distinct part) and instances, and the tapped holes."""

    def __init__(self, parts: PartsSpec, plan: LayerPlan, J, detailed: bool):
        self.parts, self.plan, self.J, self.detailed = parts, plan, J, detailed
        self.inst: list[PartInstance] = []
        self.kinds: dict[str, PartKind] = {}
        self.holes: dict[str, TappedHole] = {}
        self.bands = sheet_bands(parts)  # laser-cut plate parts: their thickness bands

    def kind(self, name, make, **kw) -> PartKind:
        if name not in self.kinds:
            self.kinds[name] = PartKind(name=name, shape=make(), **kw)
        return self.kinds[name]

    def place(self, name, k, body, tf, other=None, tf_other=None, fastener=None, part_of=None):
        self.inst.append(
            PartInstance(
                name,
                k,
                body,
                np.asarray(tf, dtype=float),
                other,
                None if tf_other is None else np.asarray(tf_other, dtype=float),
                fastener,
                part_of,
            )
        )

    def hole(self, h: TappedHole) -> TappedHole:
        self.holes[h.name] = h
        return h

    def cap_screw(self, size: str, length: float) -> PartKind:
        """A bought ISO 4762 socket head cap screw (one kind per size and length)."""
        name = f"cap_screw_{size}x{_fmt(length)}"
        if name not in self.kinds:
            self.kinds[name] = joints.cap_screw_kind(size, length, "parts")
        return self.kinds[name]

    def screw(self, name, size, clamp, hole, joint, field, body, tf, clamps, **blame):  # noqa: PLR0913
        """Size an ISO 4762 screw from its stack and place it with its fastener record
        (``blame``: ``hole_field`` / ``clamp_field`` of :func:`size_cap_screw`); in a laser
        build held over the sheets' thickness bands (:func:`size_over_band`)."""
        L, e = size_over_band(size, clamp, hole, joint, field, clamps, self.bands, **blame)
        f = Fastener("ISO 4762", size, L, tuple(clamps), hole.name, e)
        self.place(name, self.cap_screw(size, L), body, tf, fastener=f)
        return L


def build_assembly(
    joints_link: dict[str, dict[str, np.ndarray]],
    plan: LayerPlan,
    parts: PartsSpec,
    footprint_mm,
    fidelity: str = "fabrication",
    handle_shape=None,
    design_label: str = "",
    motor_spec=None,
) -> Assembly:
    """Build every part and place it (module docstring).

    ``handle_shape``: a user handle (OCP shape, knob frame) replacing the built-in knob.
    ``motor_spec``: the resolved device's motor (:class:`cad.data.catalog.MotorSpec`, the
    ``[motor]`` table applied, :func:`cad.device.resolve_device`): its name and mass go on the
    motor's BOM line; the mount geometry stays ``parts.motor``'s. None: the catalog motor.
    ``fidelity``: "fabrication" builds bd_warehouse bearings with balls and the knob's
    cosmetic round; "inertia" and "preview" use plain bearing rings and no round.
    Raises DesignError naming the joint when a fastener cannot be sized.
    """
    b = _Builder(parts, plan, joints_link, fidelity == "fabrication")
    _bars(b, design_label)
    _joint_hardware(b)
    warn_pins(pin_rows(plan, parts, b.bands))
    _motor_and_hub(b, motor_spec)
    rect = _base_post_legs(b, footprint_mm)
    _handle(b, handle_shape)
    check_fasteners({i.name: i.fastener for i in b.inst if i.fastener}, b.holes)
    return as_laser(as_printed(Assembly(tuple(b.inst), rect, holes=tuple(b.holes.values())), parts),
                    parts)


def _bars(b: _Builder, design_label: str) -> None:
    parts, plan, J = b.parts, b.plan, b.J
    t = parts.bar_thickness_mm
    brg = cat.get_bearing(parts.bearing)
    pin = cat.get_shoulder_screw(parts.pin)
    m = cat.get_motor(parts.motor)
    printed = parts.bar_style == "plate" and parts.printed(parts.bar_material)
    d = _printed_diameters(parts) if printed else {}
    seat = bars.Feature("seat", d_mm=brg.Da_mm, cb_d_mm=d.get("seat", brg.D_mm), cb_depth_mm=brg.B_mm)
    pin_hole = bars.Feature("pin", d_mm=d.get("pin", pin.ds_mm))
    hub_feat = bars.Feature(
        "hub",
        d_mm=m.shaft_diameter_mm + 1.0 + d.get("comp", 0.0),
        bolt_circle_mm=hub_bolt_circle_mm(parts),
        bolt_hole_mm=cat.clearance_hole_mm(parts.hub_screw) + d.get("comp", 0.0),
        bolt_count=HUB_SCREWS,
    )
    p_feat = bars.Feature(
        "tapped", d_mm=d.get("tapped", cat.tap_drill_mm(parts.handle_screw)),
        keep_r_mm=parts.handle_diameter_mm / 2
    )

    def feat(link: str, j: str) -> bars.Feature:
        return seat if plan.joints[j].upper == link else pin_hole

    bar_joints = {
        "crank": {
            "A1": (J["crank"]["A1"], hub_feat),
            "A2": (J["crank"]["A2"], feat("crank", "A2")),
        },
        "coupler": {
            "A2": (J["coupler"]["A2"], feat("coupler", "A2")),
            "A3": (J["coupler"]["A3"], feat("coupler", "A3")),
            "P": (J["coupler"]["P"], p_feat),
        },
        "rocker": {
            "A4": (J["rocker"]["A4"], feat("rocker", "A4")),
            "A3": (J["rocker"]["A3"], feat("rocker", "A3")),
        },
    }
    if parts.bar_style == "tube":
        _tube_bars(b, bar_joints, design_label)
        return
    for link, jd in bar_joints.items():
        seats = sum(f.kind == "seat" for _, f in jd.values())
        pins = sum(f.kind == "pin" for _, f in jd.values())
        if printed:
            proc, fits = _printed_bar_ops(parts, link, seats, pins, d)
        else:
            proc, fits = _machined_bar_ops(parts, link, seats, pins, brg, pin)
        k = b.kind(
            link,
            lambda jd=jd: bars.bar_shape(jd, parts),
            material=parts.bar_material,
            made=True,
            plate=True,
            description=f"{link} bar {_fmt(t)} mm{(' ' + design_label) if design_label else ''}",
            process="; ".join(proc),
            fits=tuple(fits),
        )
        b.place(link, k, link, translation(z=plan.z_mm[link]))


def _printed_diameters(parts) -> dict[str, float]:
    """Modelled diameters (mm) of a printed bar's features (:class:`cad.printing.PrintSettings`):
    holes ``comp`` over nominal, the bearing seat a press fit, the handle hole an insert pilot."""
    s = parts.print_settings()
    brg = cat.get_bearing(parts.bearing)
    c = s.hole_compensation_mm
    hs = parts.handle_screw.split("-")[0]
    return {"comp": c, "seat": brg.D_mm + c - s.press_fit_mm,
            "pin": cat.get_shoulder_screw(parts.pin).ds_mm + c,
            "tapped": HEAT_SET_PILOT_MM.get(hs, cat.tap_drill_mm(parts.handle_screw))}


def _machined_bar_ops(parts, link, seats, pins, brg, pin):
    """Process operations and fits of a machined plate bar."""
    proc = [f"waterjet/laser {_fmt(parts.bar_thickness_mm)} mm plate"]
    fits = []
    if seats:
        proc.append(f"mill bearing seat x{seats}")
        fits.append(fit("bearing seat", brg.D_mm))
    if pins:
        proc.append(f"ream pin bore x{pins}")
        fits.append(fit("pin bore", pin.ds_mm))
    if link == "coupler":
        proc.append(f"tap {parts.handle_screw.split('-')[0]} x1")
    return proc, fits


def _printed_bar_ops(parts, link, seats, pins, d):
    """Process operations and fits of a printed bar (diameters ``d``: :func:`_printed_diameters`)."""
    brg = cat.get_bearing(parts.bearing)
    pin = cat.get_shoulder_screw(parts.pin)
    s = parts.print_settings()
    proc, fits = [], []
    if seats:
        proc.append(f"bearing seat x{seats} printed {_fmt(d['seat'])} mm (press fit, "
                    f"{_fmt(s.hole_compensation_mm)} mm compensation - {_fmt(s.press_fit_mm)} mm)")
        fits.append(f"bearing seat {_fmt(brg.D_mm)} press fit (printed {_fmt(d['seat'])})")
    if pins:
        proc.append(f"pin bore x{pins} printed {_fmt(d['pin'])} mm (+{_fmt(s.hole_compensation_mm)} mm)")
        fits.append(f"pin bore {_fmt(pin.ds_mm)} printed {_fmt(d['pin'])} (slip fit, not H7)")
    if link == "coupler":
        hs = parts.handle_screw.split("-")[0]
        proc.append(f"{hs} heat-set insert x1 in the {_fmt(d['tapped'])} mm hole")
    if link == "crank":
        proc.append(f"hub bore and screw holes printed +{_fmt(s.hole_compensation_mm)} mm")
    return proc, fits


def _tube_bars(b: _Builder, bar_joints: dict, design_label: str) -> None:
    """Crank, coupler, rocker as carbon tubes bonded into clevises (:mod:`cad.parts.tubebars`)."""
    parts, plan = b.parts, b.plan
    t = parts.bar_thickness_mm
    brg = cat.get_bearing(parts.bearing)
    pin = cat.get_shoulder_screw(parts.pin)
    label = f" {design_label}" if design_label else ""
    for link, jd in bar_joints.items():
        tb.check_link(link, jd, parts)
        pts = {n: p for n, (p, _) in jd.items()}
        segs = tb.segments(link, pts)
        z = plan.z_mm[link]
        for n, (p, f) in jd.items():
            dirs = tb.directions_deg(n, pts, segs)
            proc = [f"CNC mill {_fmt(t)} mm clevis", f"bore {len(dirs)} tube socket(s)",
                    "bond the tube(s) in (structural epoxy)"]
            fits = []
            if f.kind == "seat":
                proc.append("mill bearing seat")
                fits.append(fit("bearing seat", brg.D_mm))
            elif f.kind == "pin":
                proc.append("ream pin bore")
                fits.append(fit("pin bore", pin.ds_mm))
            elif f.kind == "tapped":
                proc.append(f"tap {parts.handle_screw.split('-')[0]} x1")
            k = b.kind(
                f"{link}_clevis_{n}",
                lambda f=f, dirs=dirs: tb.clevis_shape(f, dirs, parts),
                material=parts.clevis_material,
                made=True,
                description=f"{link} clevis at {n} ({f.kind}){label}",
                process="; ".join(proc),
                fits=tuple(fits),
            )
            b.place(f"{link}_clevis_{n}", k, link, translation(p[0], p[1], z))
        for a, c in segs:
            L = tb.tube_length_mm(float(np.linalg.norm(pts[c] - pts[a])), parts)
            k = b.kind(
                f"{link}_tube_{a}{c}",
                lambda L=L: tb.tube_shape(L, parts),
                material=parts.tube_material,
                made=True,
                description=(f"{link} tube {_fmt(parts.tube_od_mm)}/{_fmt(parts.tube_id_mm)} x "
                             f"{_fmt(L)} mm{label}"),
                process=f"cut tube to {_fmt(L)} mm; bonded into the {a} and {c} clevises (epoxy)",
                revolution=False,
            )
            b.place(f"{link}_tube_{a}{c}", k, link, tb.tube_placement(pts[a], pts[c], z + t / 2, parts))


def _joint_kinds(b: _Builder) -> dict[str, PartKind]:
    parts = b.parts
    brg = cat.get_bearing(parts.bearing)
    nut = cat.get_nut(parts.pin)
    washer = cat.get_washer(parts.pin)
    steel = cat.FASTENER_MATERIAL
    rings = joints.bearing_rings(parts.bearing)
    return {
        "bearing": b.kind(
            f"bearing_{parts.bearing}",
            lambda: joints.bearing_shape(parts.bearing, b.detailed),
            material=cat.BEARING_MATERIAL,
            made=False,
            description=f"deep groove ball bearing {brg.designation} ({brg.d_mm:g}x{brg.D_mm:g}x{brg.B_mm:g})",
            process="bought",
            inertia_model="ring",
            mass_kg=(parts.bearing_mass_g * 1e-3 if parts.bearing_mass_g else brg.mass_kg),
            ring_mm=(brg.d_mm / 2, brg.D_mm / 2, brg.B_mm),
            collision=(("other", rings[0]), ("self", rings[1])),
            revolution=True,
            hull=joints.bearing_shape(parts.bearing, False) if b.detailed else None,
        ),
        "nut": b.kind(
            f"nut_{parts.pin}",
            lambda: joints.nut_shape(parts.pin),
            material=steel,
            made=False,
            description=(
                f"retaining ring DIN 471 {cat.get_shoulder_screw(parts.pin).ds_mm:g}"
                if cat.is_dowel(parts.pin)
                else f"hex nut ISO 4032 {parts.pin}"
            ),
            process="bought",
            revolution=True,
            collision=(("self", joints.ring_shape(0.0, nut.s_mm / math.sqrt(3.0), nut.m_mm)),),
        ),
        "washer": b.kind(
            f"washer_{washer.size}",
            lambda: joints.washer_shape(parts.pin),
            material=steel,
            made=False,
            description=f"plain washer ISO 7089 {washer.size}",
            process="bought",
            revolution=True,
            collision=(("self", joints.ring_shape(0.0, washer.d2_mm / 2, washer.h_mm)),),
        ),
    }


def _spacer_kind(b: _Builder, role: str, h: float) -> PartKind:
    pin = cat.get_shoulder_screw(b.parts.pin)
    od = spacer_od_mm(b.parts)
    return b.kind(
        f"spacer_d{_fmt(od)}_h{_fmt(h)}",
        lambda: joints.spacer_shape(pin.ds_mm / 2, od / 2, h),
        material=b.parts.spacer_material,
        made=True,
        revolution=True,
        description=f"{role} spacer {_fmt(od)}/{_fmt(pin.ds_mm)} x {_fmt(h)} mm",
        process="turned",
        fits=(fit("spacer bore", pin.ds_mm, "bore"),),
    )


def _pin_kind(b: _Builder, L: float) -> PartKind:
    parts = b.parts
    pin = cat.get_shoulder_screw(parts.pin)
    env = joints.screw_envelope(pin.dk_mm, pin.k_mm, pin.ds_mm, L, pin.thread_mm, pin.b_mm)
    return b.kind(
        f"shoulder_screw_{parts.pin}x{_fmt(L)}",
        lambda: joints.shoulder_screw_shape(parts.pin, L),
        material=parts.pin_material,
        made=False,
        description=cat.pin_description(parts.pin, L),
        process="bought",
        revolution=True,
        collision=(("self", env),),
    )


def _joint_hardware(b: _Builder) -> None:
    """Bearing, (sleeve,) spacers, shoulder screw and (between links) washer + nut at A2, A3, A4."""
    parts, J = b.parts, b.J
    t = parts.bar_thickness_mm
    brg = cat.get_bearing(parts.bearing)
    pin = cat.get_shoulder_screw(parts.pin)
    washer, nut = cat.get_washer(parts.pin), cat.get_nut(parts.pin)
    k = _joint_kinds(b)
    for j, s in b.plan.joints.items():
        up, low = s.upper, s.lower
        px, py = J[low][j]
        ux, uy = J[up][j]
        b.place(
            f"bearing_{j}",
            k["bearing"],
            up,
            translation(ux, uy, s.z_upper_mm),
            other=low,
            tf_other=translation(px, py, s.z_upper_mm),
        )
        if parts.pin_sleeve_material is not None:
            slk = b.kind(
                f"sleeve_{_fmt(pin.ds_mm)}x{_fmt(brg.d_mm)}x{_fmt(brg.B_mm)}",
                lambda: joints.ring_shape(pin.ds_mm / 2, brg.d_mm / 2, brg.B_mm),
                material=parts.pin_sleeve_material,
                made=True,
                revolution=True,
                description=f"sleeve {_fmt(brg.d_mm)}/{_fmt(pin.ds_mm)} x {_fmt(brg.B_mm)} mm in the bearing bore",
                process="turned",
            )
            b.place(f"sleeve_{j}", slk, low, translation(px, py, s.z_upper_mm))
        b.place(
            f"gap_spacer_{j}",
            _spacer_kind(b, "gap", s.spacer_mm),
            low,
            translation(px, py, s.z_lower_top_mm),
        )
        b.place(
            f"head_spacer_{j}",
            _spacer_kind(b, "head", s.shim_mm),
            low,
            translation(px, py, s.z_upper_mm + brg.B_mm),
        )
        clamps = [f"head_spacer_{j}", f"bearing_{j}", f"gap_spacer_{j}"]
        if s.nut:
            hole, engaged = f"nut_{j}", nut.m_mm
            b.hole(TappedHole(hole, hole, parts.pin, nut.m_mm, nut.m_mm))
            clamps += [low, f"washer_{j}"]
        else:
            hole, engaged = "post_A4:top", _post_engagement_mm(parts, s)
        dowel = cat.is_dowel(parts.pin)
        std = "ISO 2338 + DIN 471" if dowel else "ISO 7379"
        f = Fastener(std, parts.pin, s.pin_length_mm, tuple(clamps), hole, engaged,
                     fitted=(f"ring_{j}",) if dowel else ())
        b.place(
            f"pin_{j}",
            _pin_kind(b, s.pin_length_mm),
            low,
            translation(px, py, s.head_face_mm),
            fastener=f,
        )
        if dowel:  # its upper retaining ring (the pin's "head"), its own part
            b.place(f"ring_{j}", k["nut"], low, translation(px, py, s.head_face_mm))
        if s.nut:
            z_bot = s.z_lower_top_mm - t
            b.place(f"washer_{j}", k["washer"], low, translation(px, py, z_bot - washer.h_mm))
            b.place(f"nut_{j}", k["nut"], low, translation(px, py, z_bot - washer.h_mm - nut.m_mm))


def _post_engagement_mm(parts: PartsSpec, s4) -> float:
    """What the A4 pin holds in the post (mm): an ISO 7379 screw its whole thread b - g2 (the
    reamed bore ends where the relief ends, :func:`cad.families.fourbar.layers.post_bore_depth_mm`);
    a plain pin its pressed length, shoulder entry L - c plus b (the post's hole is the pin's
    diameter all the way)."""
    pin = cat.get_shoulder_screw(parts.pin)
    if cat.is_dowel(parts.pin):
        return s4.pin_length_mm - s4.clamp_mm + pin.b_mm
    return iso7379_thread_mm(parts.pin)


def _motor_and_hub(b: _Builder, motor_spec=None) -> None:
    """Crank hub with its screws and set screw, the motor (housing and shaft; its BOM name and
    mass from ``motor_spec``, the resolved motor, when given), its mount plate and screws."""
    parts, plan = b.parts, b.plan
    t = parts.bar_thickness_mm
    m = cat.get_motor(parts.motor)
    hub_h = plan.hub_z_mm[1] - plan.hub_z_mm[0]
    hub_bc = hub_bolt_circle_mm(parts)
    engaged = min(plan.shaft_top_mm, plan.hub_z_mm[1]) - plan.hub_z_mm[0]
    hub_e = plan.hub_screw_length_mm - thinnest_mm(b.bands, "crank", t)  # a thin crank: deeper
    ss = plan.hub_set_screw.size.split("-")[0]
    hk = b.kind(
        "crank_hub",
        lambda: motor.hub_shape(m, parts.hub_diameter_mm, hub_h, hub_bc, parts.hub_screw,
                                hub_e + TAP_LEADOUT_MM, engaged, plan.hub_set_screw.size),
        material=parts.hub_material,
        made=True,
        description=f"direct-drive crank hub (set screw {ss})",
        process=f"turned; tap {parts.hub_screw.split('-')[0]} x{HUB_SCREWS}, tap {ss} x1 (radial)",
        fits=(fit("hub shaft bore", m.shaft_diameter_mm, "shaft bore"),),
        revolution=True,
        collision=(
            ("self", joints.ring_shape(m.shaft_diameter_mm / 2, parts.hub_diameter_mm / 2, hub_h)),
        ),
    )
    b.place("crank_hub", hk, "crank", translation(0, 0, plan.hub_z_mm[0]))
    for i, (x, y) in enumerate(cat.polar_points_mm(hub_bc / 2, HUB_SCREWS)):
        hole = b.hole(replace(alu_hole(f"crank_hub:screw_{i + 1}", "crank_hub", parts.hub_screw,
                                       hub_e), axis=(0.0, 0.0, 1.0), point_mm=(x, y, 0.0)))
        b.screw(
            f"hub_screw_{i + 1}",
            parts.hub_screw,
            t,
            hole,
            "A1 (crank to hub)",
            "parts.hub_screw",
            "crank",
            translation(x, y, plan.z_mm["crank"] + t),
            ["crank"],
            clamp_field="parts.bar_thickness_mm",
        )
    _set_screw(b, m, hub_h, engaged)
    zf = plan.flange_z_mm
    mk = b.kind(
        f"motor_{m.key}",
        lambda: motor.motor_housing_shape(m),
        material="steel-1018",
        made=False,
        description=(motor_spec or m).bom_description(),
        process=f"bought; face tapped {m.bolt_size.split('-')[0]} x{m.bolt_count}; with its shaft "
                "(solid motor_shaft in assembly.step)",
        mass_kg=(motor_spec or m).mass_kg,
        revolution=True,
    )
    b.place("motor", mk, "ground", translation(0, 0, zf))
    shk = b.kind(
        "motor_shaft",
        lambda: motor.motor_shaft_shape(m),
        material="steel-1018",
        made=False,
        description="motor shaft (inside the rotor inertia Jm)",
        inertia_model="none",
        listed=False,
        revolution=True,
    )
    b.place("motor_shaft", shk, "crank", translation(0, 0, zf), part_of="motor")  # the motor's own solid
    for i, (x, y) in enumerate(motor.motor_bolt_xy_mm(m)):
        st = _motor_screw_stack(parts, i + 1)
        b.hole(st["hole"])
        b.screw(f"motor_screw_{i + 1}", body="ground", tf=translation(x, y, -parts.base_thickness_mm),
                clamps=["motor_mount"], **st)


def _motor_screw_stack(parts: PartsSpec, i: int) -> dict:
    """Motor face screw ``i`` (ISO 4762, the motor's bolt size) through the mount plate into
    the maker's tapped face hole: the :meth:`_Builder.screw` stack arguments."""
    m = cat.get_motor(parts.motor)
    hole = TappedHole(f"motor:face_{i}", "motor", m.bolt_size, m.bolt_thread_depth_mm,
                      min(m.bolt_thread_depth_mm, MIN_ENGAGEMENT_BOUGHT_MM))
    return dict(size=m.bolt_size, clamp=parts.motor_mount_thickness_mm, hole=hole,
                joint="A1 (motor to mount plate)", field="parts.motor",
                clamp_field="parts.motor_mount_thickness_mm")


def _mount_screw_stack(parts: PartsSpec, i: int) -> dict:
    """Motor mount screw ``i`` (M3) through the mount plate into the base plate's tapped hole."""
    hole = alu_hole(f"base_plate:mount_{i}", "base_plate", motor.MOUNT_SCREW,
                    parts.base_thickness_mm)
    return dict(size=motor.MOUNT_SCREW, clamp=parts.motor_mount_thickness_mm, hole=hole,
                joint="motor mount to base plate", field="parts.motor_mount_thickness_mm",
                hole_field="parts.base_thickness_mm", clamp_field="parts.motor_mount_thickness_mm")


def _leg_screw_stack(parts: PartsSpec, i: int) -> dict:
    """Leg screw ``i`` through the base plate into the leg's top tapped hole."""
    hole = alu_hole(f"leg_{i}:top", f"leg_{i}", base.LEG_SCREW,
                    base.STANDOFF_TAP_DEPTH_MM - TAP_LEADOUT_MM)
    return dict(size=base.LEG_SCREW, clamp=parts.base_thickness_mm, hole=hole,
                joint=f"leg {i} to base plate", field="parts.base_thickness_mm",
                clamp_field="parts.base_thickness_mm")


def check_plate_screws(parts: PartsSpec) -> list:
    """Size the motor face, motor mount and leg screws before any CAD
    (:func:`cad.assembly.fasteners.size_cap_screw`): they depend on the ``[parts]`` plates
    only, so a plate no catalog screw fits is refused naming its field. In a laser build each
    is held over its sheets' thickness bands (:func:`size_over_band`: a warning where no catalog
    length does). Returns ``[(stack arguments, clamped parts, (length, engagement))]``."""
    bands, out = sheet_bands(parts), []
    for stack, clamps in ((_motor_screw_stack, ["motor_mount"]),
                          (_mount_screw_stack, ["motor_mount"]), (_leg_screw_stack, ["base_plate"])):
        st = stack(parts, 1)
        a = dict(st)
        got = size_over_band(st.pop("size"), st.pop("clamp"), st.pop("hole"), st.pop("joint"),
                             st.pop("field"), clamps, bands, **st)
        out.append((a, clamps, got))
    return out


def _set_screw(b: _Builder, m, hub_h: float, engaged: float) -> None:
    """ISO 4026 set screw in the hub's radial tapped hole, flat point on the shaft, its end
    inside the hub (sized before any CAD: :func:`cad.families.fourbar.layers.hub_set_screw`)."""
    ss = b.plan.hub_set_screw
    L = ss.length_mm
    k = b.kind(
        f"set_screw_{ss.size}x{_fmt(L)}",
        lambda: motor.set_screw_shape(L, ss.size),
        material=cat.FASTENER_MATERIAL,
        made=False,
        description=f"set screw ISO 4026 {ss.size} x {_fmt(L)} (locks the hub on the shaft)",
        process="bought",
    )
    T = np.eye(4)
    T[:3, :3] = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]  # part z -> +x (radial)
    T[:3, 3] = (ss.shaft_radius_mm, 0.0, b.plan.hub_z_mm[0] + motor.set_screw_z_mm(hub_h, engaged))
    hole = b.hole(TappedHole("crank_hub:set_screw", "crank_hub", ss.size, ss.depth_mm,
                             ss.min_engagement_mm, axis=(1.0, 0.0, 0.0),
                             point_mm=(0.0, 0.0, motor.set_screw_z_mm(hub_h, engaged))))
    f = Fastener("ISO 4026", ss.size, L, ("motor_shaft",), hole.name, L)
    b.place("hub_set_screw", k, "crank", T, fastener=f)


def _post_through_mount(parts: PartsSpec, m, a4) -> bool:
    """Does the A4 post screw head (under the base plate) land on the motor mount plate? Then
    the screw passes through it too; DesignError when the head would meet the motor housing."""
    cs = cat.get_cap_screw(cat.standoff_screw(parts.pin), "parts.pin")
    half = motor.mount_side_mm(m) / 2 + HEAD_CLEARANCE_MM
    r = cs.dk_mm / 2
    if abs(a4[0]) - r >= half or abs(a4[1]) - r >= half:
        return False
    dist = math.hypot(a4[0], a4[1])
    if dist - r < m.body_diameter_mm / 2 + HEAD_CLEARANCE_MM:
        raise DesignError(
            "mechanism",
            f"A4: the post screw head under the motor mount plate would meet the {m.key} housing "
            f"(A1-A4 = {dist:.1f} mm < {m.body_diameter_mm / 2 + r + HEAD_CLEARANCE_MM:.1f} mm)",
        )
    return True


def _base_post_legs(b: _Builder, footprint_mm):
    """Base plate, motor mount plate (with its screws), A4 post and its screw, legs."""
    parts, plan = b.parts, b.plan
    m = cat.get_motor(parts.motor)
    pin = cat.get_shoulder_screw(parts.pin)
    a4 = b.J["ground"]["A4"]
    bt, mt = parts.base_thickness_mm, parts.motor_mount_thickness_mm
    rect = base.base_rect_mm(
        footprint_mm, a4, motor.mount_side_mm(m), parts.post_diameter_mm, parts.base_margin_mm
    )
    head_d = cat.get_cap_screw(m.bolt_size, "parts.motor").dk_mm
    opening = max(m.bolt_circle_mm + head_d + 2.0, m.pilot_diameter_mm + 2.0)
    ms = motor.MOUNT_SCREW.split("-")[0]
    bk = b.kind(
        "base_plate",
        lambda: base.base_plate_shape(
            rect,
            bt,
            a4,
            opening,
            motor.mount_hole_xy_mm(m),
            motor.MOUNT_SCREW,
            cat.standoff_screw(parts.pin),
        ),
        material=parts.base_material,
        made=True,
        plate=True,
        description="base plate",
        process=f"waterjet/laser {_fmt(bt)} mm plate; tap {ms} x4",
    )
    b.place("base_plate", bk, "ground", np.eye(4))
    through = _post_through_mount(parts, m, a4)
    extra = (
        [(a4[0], a4[1], cat.clearance_hole_mm(cat.standoff_screw(parts.pin)))] if through else []
    )
    mm_k = b.kind(
        "motor_mount",
        lambda: motor.motor_mount_shape(m, mt, extra),
        material=parts.motor_mount_material,
        made=True,
        plate=True,
        description=f"motor mount plate for {m.key}",
        process=f"waterjet/laser {_fmt(mt)} mm plate; bore the pilot seat",
        fits=(fit("pilot bore", m.pilot_diameter_mm),),
    )
    zf = plan.flange_z_mm
    b.place("motor_mount", mm_k, "ground", translation(0, 0, zf))
    for i, (x, y) in enumerate(motor.mount_hole_xy_mm(m)):
        st = _mount_screw_stack(parts, i + 1)
        b.hole(st["hole"])
        b.screw(f"mount_screw_{i + 1}", body="ground", tf=translation(x, y, zf) @ flip_x(),
                clamps=["motor_mount"], **st)
    _post(b, a4, pin, through)
    _legs(b, rect)
    return rect


def _post(b: _Builder, a4, pin, through: bool) -> None:
    parts = b.parts
    s4 = b.plan.joints["A4"]
    post_h = s4.z_lower_top_mm
    bore_depth = post_bore_depth_mm(s4, parts)
    thread_depth = pin.b_mm + POST_THREAD_EXTRA_MM
    screw = cat.standoff_screw(parts.pin)
    dowel = cat.is_dowel(parts.pin)
    top = "press-fit bore" if dowel else f"tap {parts.pin.split('-')[0]}"
    pok = b.kind(
        "post_A4",
        lambda: base.post_shape(
            parts.post_diameter_mm, post_h, pin.ds_mm, bore_depth, parts.pin, thread_depth, screw
        ),
        material=parts.post_material,
        made=True,
        description="A4 pivot post",
        process=f"turned; ream top bore; {top} top; tap {screw.split('-')[0]} bottom",
        fits=(fit("post shoulder bore", pin.ds_mm, "shoulder bore"),),
        revolution=True,
    )
    b.place("post_A4", pok, "ground", translation(a4[0], a4[1], 0.0))
    z_up = dict(axis=(0.0, 0.0, 1.0), point_mm=(0.0, 0.0, 0.0))  # post frame: its axis
    if dowel:  # a plain pin is pressed, not screwed: the whole hole, no thread minimum
        b.hole(TappedHole("post_A4:top", "post_A4", parts.pin, bore_depth + thread_depth, 0.0,
                          **z_up))
    else:
        b.hole(replace(shoulder_screw_hole("post_A4:top", "post_A4", parts.pin, thread_depth),
                       **z_up))
    bottom = b.hole(replace(
        alu_hole("post_A4:bottom", "post_A4", screw, base.STANDOFF_TAP_DEPTH_MM - TAP_LEADOUT_MM),
        **z_up))
    clamp = parts.base_thickness_mm + (parts.motor_mount_thickness_mm if through else 0.0)
    b.screw(
        "post_screw",
        screw,
        clamp,
        bottom,
        "A4 (post to base plate)",
        "parts.pin",
        "ground",
        translation(a4[0], a4[1], -clamp) @ flip_x(),
        ["base_plate", "motor_mount"] if through else ["base_plate"],
    )


def _legs(b: _Builder, rect) -> None:
    parts = b.parts
    m = cat.get_motor(parts.motor)
    leg_h = parts.motor_mount_thickness_mm + m.body_length_mm + base.LEG_GROUND_CLEARANCE_MM
    if leg_h < 2 * base.STANDOFF_TAP_DEPTH_MM + 1.0:  # both tapped ends and 1 mm between
        raise DesignError(
            "parts.motor_mount_thickness_mm",
            f"legs of {leg_h:g} mm cannot hold two {base.STANDOFF_TAP_DEPTH_MM:g} mm tapped ends",
        )
    lk = b.kind(
        "leg",
        lambda: base.leg_shape(leg_h),
        material=parts.base_material,
        made=True,
        description=f"leg standoff d{_fmt(base.LEG_DIAMETER_MM)} x {_fmt(leg_h)}",
        process=f"turned; tap {base.LEG_SCREW.split('-')[0]} both ends",
    )
    for i, (x, y) in enumerate(base.leg_xy_mm(rect)):
        b.place(f"leg_{i + 1}", lk, "ground", translation(x, y, -parts.base_thickness_mm - leg_h))
        st = _leg_screw_stack(parts, i + 1)
        b.hole(st["hole"])
        b.screw(f"leg_screw_{i + 1}", body="ground", tf=translation(x, y, 0.0),
                clamps=["base_plate"], **st)


def _handle(b: _Builder, handle_shape) -> None:
    parts, plan = b.parts, b.plan
    t = parts.bar_thickness_mm
    floor = handle_floor_mm(plan, parts)  # tip flush with the (thinnest) coupler's bottom
    px, py = b.J["coupler"]["P"]
    if handle_shape is None:
        hk = b.kind(
            "handle",
            lambda: handle.knob_shape(parts, floor, cosmetic=b.detailed),
            material=parts.handle_material,
            made=True,
            description="handle knob",
            process="turned",
        )
    else:
        hk = b.kind(
            "handle",
            lambda: handle_shape,
            material=parts.handle_material,
            made=True,
            description="handle (user script)",
            process="3D print / turned",
        )
    b.place("handle", hk, "coupler", translation(px, py, plan.handle_z_mm))
    # the knob carries hand loads only: the full plate, at least 1 d (1.5 d when it fits)
    need = handle_min_engagement_mm(parts, MIN_ENGAGEMENT_ALU_D, HANDLE_MIN_ENGAGEMENT_D)
    hole = b.hole(TappedHole("coupler:P", "coupler", parts.handle_screw, t, need))
    b.screw(
        "handle_screw",
        parts.handle_screw,
        floor,
        hole,
        "P (handle to coupler)",
        "parts.handle_screw",
        "coupler",
        translation(px, py, plan.handle_z_mm + floor),
        ["handle"],
        hole_field="parts.bar_thickness_mm",
    )
