"""Every part of a four-bar haptic display, placed on its rigid body (parts -> instances).

Input: the linkage (joint positions in each link's frame from
:func:`cad.kinematics.linkgeom.link_joints_mm`), the layer plan
(:func:`cad.assembly.layers.choose_layers`) and the ``[parts]`` spec. Output: a list
of :class:`cad.parts.PartInstance` -- a part kind (solid in its own frame) carried by
a body ("ground", "crank", "coupler", "rocker") at a 4x4 placement. Bodies move with
the link transforms of :mod:`cad.kinematics.linkgeom`; z = 0 is the base plate's top.

Joint hardware belongs to the link that holds the pin (the LOWER link at A2/A3, the
ground at A4); the bearing belongs to the link with the seat, its inner ring's
collision envelope to the pin's link (see :mod:`cad.assembly.layers`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cad.assembly.layers import LayerPlan, hub_bolt_circle_mm, spacer_od_mm
from cad.design.parts import PartsSpec
from cad.parts import PartInstance, PartKind, flip_x, translation
from cad.parts import catalog as cat

#: Engagement of the motor screws in the motor face, of the mount screws in the base
#: plate and of the post / leg screws in their standoffs (mm).
MOTOR_SCREW_ENGAGEMENT_MM = 3.0
MOUNT_SCREW_ENGAGEMENT_MM = 4.5
STANDOFF_SCREW_ENGAGEMENT_MM = 9.0


@dataclass(frozen=True)
class Assembly:
    """All placed parts plus what the report needs about them."""

    instances: tuple[PartInstance, ...]
    base_rect_mm: tuple[float, float, float, float]
    notes: tuple[str, ...] = ()

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


def _fmt(x: float) -> str:
    return f"{x:.2f}".rstrip("0").rstrip(".")


def build_assembly(
    joints_link: dict[str, dict[str, np.ndarray]],
    plan: LayerPlan,
    parts: PartsSpec,
    footprint_mm,
    fidelity: str = "fabrication",
    handle_shape=None,
    design_label: str = "",
) -> Assembly:
    """Build every part and place it (module docstring).

    ``handle_shape``: a user handle (OCP shape, knob frame) replacing the built-in knob.
    ``fidelity``: "fabrication" builds bd_warehouse bearings with balls and the knob's
    cosmetic round; "inertia" and "preview" use plain bearing rings and no round.
    """
    from cad.parts import bars, base, handle, joints, motor

    detailed = fidelity == "fabrication"
    J = joints_link
    t = parts.bar_thickness_mm
    brg = cat.get_bearing(parts.bearing)
    pin = cat.get_shoulder_screw(parts.pin)
    nut = cat.get_nut(parts.pin)
    washer = cat.get_washer(parts.pin)
    m = cat.get_motor(parts.motor)
    inst: list[PartInstance] = []
    kinds: dict[str, PartKind] = {}

    def kind(name, make, **kw) -> PartKind:
        if name not in kinds:
            kinds[name] = PartKind(name=name, shape=make(), **kw)
        return kinds[name]

    def place(name, k, body, tf, other=None, tf_other=None):
        inst.append(
            PartInstance(
                name,
                k,
                body,
                np.asarray(tf, dtype=float),
                other,
                None if tf_other is None else np.asarray(tf_other, dtype=float),
            )
        )

    steel = cat.FASTENER_MATERIAL

    def cap_env(size: str, length: float):
        cs = cat.get_cap_screw(size, "parts")
        return (("self", joints.screw_envelope(cs.dk_mm, cs.k_mm, cs.d_mm, length)),)

    def cap_screw_kind(size: str, length: float) -> PartKind:
        """A bought ISO 4762 socket head cap screw (one kind per size and length)."""
        return kind(
            f"cap_screw_{size}x{_fmt(length)}",
            lambda: joints.cap_screw_shape(size, length),
            material=steel,
            made=False,
            description=f"socket head cap screw ISO 4762 {size} x {_fmt(length)}",
            process="bought",
            revolution=True,
            collision=cap_env(size, length),
        )

    # ---------------------------------------------------------------- bars
    seat = bars.Feature("seat", d_mm=brg.Da_mm, cb_d_mm=brg.D_mm, cb_depth_mm=brg.B_mm)
    pin_hole = bars.Feature("pin", d_mm=pin.ds_mm)
    hub_bc = hub_bolt_circle_mm(parts)
    hub_feat = bars.Feature(
        "hub",
        d_mm=m.shaft_diameter_mm + 1.0,
        bolt_circle_mm=hub_bc,
        bolt_hole_mm=cat.clearance_hole_mm(parts.hub_screw),
        bolt_count=3,
    )
    p_feat = bars.Feature(
        "tapped", d_mm=cat.tap_drill_mm(parts.handle_screw), keep_r_mm=parts.handle_diameter_mm / 2
    )

    def joint_feature(link: str, j: str) -> bars.Feature:
        return seat if plan.joints[j].upper == link else pin_hole

    bar_joints = {
        "crank": {
            "A1": (J["crank"]["A1"], hub_feat),
            "A2": (J["crank"]["A2"], joint_feature("crank", "A2")),
        },
        "coupler": {
            "A2": (J["coupler"]["A2"], joint_feature("coupler", "A2")),
            "A3": (J["coupler"]["A3"], joint_feature("coupler", "A3")),
            "P": (J["coupler"]["P"], p_feat),
        },
        "rocker": {
            "A4": (J["rocker"]["A4"], joint_feature("rocker", "A4")),
            "A3": (J["rocker"]["A3"], joint_feature("rocker", "A3")),
        },
    }
    for link, jd in bar_joints.items():
        k = kind(
            link,
            lambda jd=jd: bars.bar_shape(jd, parts),
            material=parts.bar_material,
            made=True,
            plate=True,
            description=f"{link} bar {_fmt(t)} mm{(' ' + design_label) if design_label else ''}",
            process=f"waterjet/laser {_fmt(t)} mm plate"
            + ("; mill bearing seats" if any(f.kind == "seat" for _, f in jd.values()) else ""),
        )
        place(link, k, link, translation(z=plan.z_mm[link]))

    # ---------------------------------------------------------------- joints
    sp_od = spacer_od_mm(parts)
    brg_kind = kind(
        f"bearing_{parts.bearing}",
        lambda: joints.bearing_shape(parts.bearing, detailed),
        material=cat.BEARING_MATERIAL,
        made=False,
        description=f"deep groove ball bearing {brg.designation} ({brg.d_mm:g}x{brg.D_mm:g}x{brg.B_mm:g})",
        process="bought",
        inertia_model="ring",
        mass_kg=(parts.bearing_mass_g * 1e-3 if parts.bearing_mass_g else brg.mass_kg),
        ring_mm=(brg.d_mm / 2, brg.D_mm / 2, brg.B_mm),
        collision=(
            ("other", joints.bearing_rings(parts.bearing)[0]),
            ("self", joints.bearing_rings(parts.bearing)[1]),
        ),
        revolution=True,
    )
    nut_k = kind(
        f"nut_{parts.pin}",
        lambda: joints.nut_shape(parts.pin),
        material=steel,
        made=False,
        description=(f"retaining ring DIN 471 {pin.ds_mm:g}" if cat.is_dowel(parts.pin)
                     else f"hex nut ISO 4032 {parts.pin}"),
        process="bought",
        revolution=True,
        collision=(("self", joints.ring_shape(0.0, nut.s_mm / math.sqrt(3.0), nut.m_mm)),),
    )
    washer_k = kind(
        f"washer_{washer.size}",
        lambda: joints.washer_shape(parts.pin),
        material=steel,
        made=False,
        description=f"plain washer ISO 7089 {washer.size}",
        process="bought",
        revolution=True,
        collision=(("self", joints.ring_shape(0.0, washer.d2_mm / 2, washer.h_mm)),),
    )
    for j, s in plan.joints.items():
        up, low = s.upper, s.lower
        px, py = J[low][j]
        ux, uy = J[up][j]
        place(
            f"bearing_{j}",
            brg_kind,
            up,
            translation(ux, uy, s.z_upper_mm),
            other=low,
            tf_other=translation(px, py, s.z_upper_mm),
        )
        if parts.pin_sleeve_material is not None:
            slk = kind(
                f"sleeve_{_fmt(pin.ds_mm)}x{_fmt(brg.d_mm)}x{_fmt(brg.B_mm)}",
                lambda: joints.ring_shape(pin.ds_mm / 2, brg.d_mm / 2, brg.B_mm),
                material=parts.pin_sleeve_material,
                made=True,
                revolution=True,
                description=f"sleeve {_fmt(brg.d_mm)}/{_fmt(pin.ds_mm)} x {_fmt(brg.B_mm)} mm in the bearing bore",
                process="turned",
            )
            place(f"sleeve_{j}", slk, low, translation(px, py, s.z_upper_mm))
        spk = kind(
            f"spacer_d{_fmt(sp_od)}_h{_fmt(s.spacer_mm)}",
            lambda s=s: joints.ring_shape(pin.ds_mm / 2, sp_od / 2, s.spacer_mm),
            material=parts.spacer_material,
            made=True,
            revolution=True,
            description=f"gap spacer {_fmt(sp_od)}/{_fmt(pin.ds_mm)} x {_fmt(s.spacer_mm)} mm",
            process="turned",
        )
        place(f"gap_spacer_{j}", spk, low, translation(px, py, s.z_lower_top_mm))
        shk = kind(
            f"spacer_d{_fmt(sp_od)}_h{_fmt(s.shim_mm)}",
            lambda s=s: joints.ring_shape(pin.ds_mm / 2, sp_od / 2, s.shim_mm),
            material=parts.spacer_material,
            made=True,
            revolution=True,
            description=f"head spacer {_fmt(sp_od)}/{_fmt(pin.ds_mm)} x {_fmt(s.shim_mm)} mm",
            process="turned",
        )
        place(f"head_spacer_{j}", shk, low, translation(px, py, s.z_upper_mm + brg.B_mm))
        pk = kind(
            f"shoulder_screw_{parts.pin}x{_fmt(s.pin_length_mm)}",
            lambda s=s: joints.shoulder_screw_shape(parts.pin, s.pin_length_mm),
            material=parts.pin_material,
            made=False,
            description=cat.pin_description(parts.pin, s.pin_length_mm),
            process="bought",
            revolution=True,
            collision=(
                (
                    "self",
                    joints.screw_envelope(
                        pin.dk_mm, pin.k_mm, pin.ds_mm, s.pin_length_mm, pin.thread_mm, pin.b_mm
                    ),
                ),
            ),
        )
        place(f"pin_{j}", pk, low, translation(px, py, s.head_face_mm))
        if s.nut:
            z_bot = s.z_lower_top_mm - t
            place(f"washer_{j}", washer_k, low, translation(px, py, z_bot - washer.h_mm))
            place(f"nut_{j}", nut_k, low, translation(px, py, z_bot - washer.h_mm - nut.m_mm))

    # ---------------------------------------------------------------- motor, hub
    hub_h = plan.hub_z_mm[1] - plan.hub_z_mm[0]
    hub_depth = plan.hub_screw_length_mm - t + 0.5
    engaged = min(plan.shaft_top_mm, plan.hub_z_mm[1]) - plan.hub_z_mm[0]
    hk = kind(
        "crank_hub",
        lambda: motor.hub_shape(
            m, parts.hub_diameter_mm, hub_h, hub_bc, parts.hub_screw, hub_depth, engaged
        ),
        material=parts.hub_material,
        made=True,
        description="direct-drive crank hub (set screw M3)",
        process="turned",
        revolution=True,
        collision=(
            ("self", joints.ring_shape(m.shaft_diameter_mm / 2, parts.hub_diameter_mm / 2, hub_h)),
        ),
    )
    place("crank_hub", hk, "crank", translation(0, 0, plan.hub_z_mm[0]))
    hs = cap_screw_kind(parts.hub_screw, plan.hub_screw_length_mm)
    for i in range(3):
        a = math.radians(90 + 120 * i)
        place(
            f"hub_screw_{i + 1}",
            hs,
            "crank",
            translation(hub_bc / 2 * math.cos(a), hub_bc / 2 * math.sin(a), plan.z_mm["crank"] + t),
        )
    zf = plan.flange_z_mm
    mk = kind(
        f"motor_{m.key}",
        lambda: motor.motor_housing_shape(m),
        material="steel-1018",
        made=False,
        description=m.description,
        process="bought",
        mass_kg=m.mass_kg,
        revolution=True,
    )
    place("motor", mk, "ground", translation(0, 0, zf))
    shk = kind(
        "motor_shaft",
        lambda: motor.motor_shaft_shape(m),
        material="steel-1018",
        made=False,
        description="motor shaft (inside the rotor inertia Jm)",
        inertia_model="none",
        listed=False,
        revolution=True,
    )
    place("motor_shaft", shk, "crank", translation(0, 0, zf))
    mm_k = kind(
        "motor_mount",
        lambda: motor.motor_mount_shape(m, parts.motor_mount_thickness_mm),
        material=parts.motor_mount_material,
        made=True,
        plate=True,
        description=f"motor mount plate for {m.key}",
        process=f"waterjet/laser {_fmt(parts.motor_mount_thickness_mm)} mm plate",
    )
    place("motor_mount", mm_k, "ground", translation(0, 0, zf))
    ms_L = cat.shortest_length(
        cat.get_cap_screw(m.bolt_size, "parts.motor").lengths_mm,
        parts.motor_mount_thickness_mm + MOTOR_SCREW_ENGAGEMENT_MM,
    )
    msk = cap_screw_kind(m.bolt_size, ms_L)
    for i, (x, y) in enumerate(motor.motor_bolt_xy_mm(m)):
        place(f"motor_screw_{i + 1}", msk, "ground", translation(x, y, -parts.base_thickness_mm))
    mo_L = cat.shortest_length(
        cat.get_cap_screw(motor.MOUNT_SCREW, "parts.motor").lengths_mm,
        parts.motor_mount_thickness_mm + MOUNT_SCREW_ENGAGEMENT_MM,
    )
    mok = cap_screw_kind(motor.MOUNT_SCREW, mo_L)
    for i, (x, y) in enumerate(motor.mount_hole_xy_mm(m)):
        place(f"mount_screw_{i + 1}", mok, "ground", translation(x, y, zf) @ flip_x())

    # ---------------------------------------------------------------- base, post, legs
    a4 = J["ground"]["A4"]
    rect = base.base_rect_mm(
        footprint_mm, a4, motor.mount_side_mm(m), parts.post_diameter_mm, parts.base_margin_mm
    )
    head_d = cat.get_cap_screw(m.bolt_size, "parts.motor").dk_mm
    opening = max(m.bolt_circle_mm + head_d + 2.0, m.pilot_diameter_mm + 2.0)
    bk = kind(
        "base_plate",
        lambda: base.base_plate_shape(
            rect,
            parts.base_thickness_mm,
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
        process=f"waterjet/laser {_fmt(parts.base_thickness_mm)} mm plate; tap M4 x4",
    )
    place("base_plate", bk, "ground", np.eye(4))
    s4 = plan.joints["A4"]
    post_h = s4.z_lower_top_mm
    bore_depth = s4.pin_length_mm - s4.clamp_mm + pin.g2_mm + 0.5
    pok = kind(
        "post_A4",
        lambda: base.post_shape(
            parts.post_diameter_mm,
            post_h,
            pin.ds_mm,
            bore_depth,
            parts.pin,
            pin.b_mm + 1.0,
            cat.standoff_screw(parts.pin),
        ),
        material=parts.post_material,
        made=True,
        description="A4 pivot post",
        process="turned",
        revolution=True,
    )
    place("post_A4", pok, "ground", translation(a4[0], a4[1], 0.0))
    st_cs = cat.get_cap_screw(cat.standoff_screw(parts.pin), "parts.pin")
    st_L = cat.shortest_length(
        st_cs.lengths_mm, parts.base_thickness_mm + STANDOFF_SCREW_ENGAGEMENT_MM
    )
    stk = cap_screw_kind(cat.standoff_screw(parts.pin), st_L)
    place(
        "post_screw", stk, "ground", translation(a4[0], a4[1], -parts.base_thickness_mm) @ flip_x()
    )
    leg_h = parts.motor_mount_thickness_mm + m.body_length_mm + base.LEG_GROUND_CLEARANCE_MM
    lk = kind(
        "leg",
        lambda: base.leg_shape(leg_h),
        material=parts.base_material,
        made=True,
        description=f"leg standoff d{_fmt(base.LEG_DIAMETER_MM)} x {_fmt(leg_h)}",
        process="turned",
    )
    for i, (x, y) in enumerate(base.leg_xy_mm(rect)):
        place(f"leg_{i + 1}", lk, "ground", translation(x, y, -parts.base_thickness_mm - leg_h))
        place(f"leg_screw_{i + 1}", stk, "ground", translation(x, y, 0.0))

    # ---------------------------------------------------------------- handle
    floor = plan.handle_screw_length_mm - t
    px, py = J["coupler"]["P"]
    if handle_shape is None:
        hk2 = kind(
            "handle",
            lambda: handle.knob_shape(parts, floor, cosmetic=detailed),
            material=parts.handle_material,
            made=True,
            description="handle knob",
            process="turned",
        )
    else:
        hk2 = kind(
            "handle",
            lambda: handle_shape,
            material=parts.handle_material,
            made=True,
            description="handle (user script)",
            process="3D print / turned",
        )
    place("handle", hk2, "coupler", translation(px, py, plan.handle_z_mm))
    hsk = cap_screw_kind(parts.handle_screw, plan.handle_screw_length_mm)
    place("handle_screw", hsk, "coupler", translation(px, py, plan.handle_z_mm + floor))
    return Assembly(tuple(inst), rect)
