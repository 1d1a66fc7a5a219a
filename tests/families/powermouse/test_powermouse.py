"""PowerMouse (isotropy paper section 5, Fig. 6, Table 4): wrench map, isotropy, clearances, solids, build."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from cad.actuators import powermouse as pm
from cad.design import load_design, parse_design
from cad.errors import DesignError

DESIGN_PATH = Path(__file__).resolve().parents[3] / "designs" / "powermouse.toml"


# ------------------------------------------------------------------ wrench map (pure math)


def test_wrench_map_isotropic_two_groups_closed_form():
    """Section 5: 'two sets of equal singular values, one for force, the other for torque'.

    Closed form of the cyclic layout: sqrt(2) g (x3) and sqrt(2) g a (x3).
    """
    a_mm, g = 29.6, 0.0116
    W = pm.wrench_map(pm.coil_layout(a_mm), g)
    iso = pm.isotropy(W)
    np.testing.assert_allclose(iso.singular_values[:3], math.sqrt(2) * g, rtol=1e-14)
    np.testing.assert_allclose(iso.singular_values[3:], math.sqrt(2) * g * a_mm * 1e-3, rtol=1e-14)
    np.testing.assert_allclose(iso.force_sv, math.sqrt(2) * g, rtol=1e-14)
    assert iso.coupling < 1e-15 and iso.force_spread < 1e-14 and iso.torque_spread < 1e-14
    # W W^T = 2 g^2 diag(1,1,1,a^2,a^2,a^2)
    np.testing.assert_allclose(
        W @ W.T, 2 * g**2 * np.diag([1, 1, 1] + [(a_mm * 1e-3) ** 2] * 3), atol=1e-18
    )


def test_wrench_map_about_another_point():
    """Moving the reference point o: tau_o = tau_0 - o x F (rigid-body identity)."""
    coils = pm.coil_layout(25.0)
    o = np.array([3.0, -2.0, 5.0])
    W0, Wo = pm.wrench_map(coils, 1.0), pm.wrench_map(coils, 1.0, about_mm=o)
    for i in range(6):
        np.testing.assert_allclose(Wo[3:, i], W0[3:, i] - np.cross(o * 1e-3, W0[:3, i]), atol=1e-17)
    assert pm.isotropy(Wo).coupling > 0.01  # about an off-centre point force and torque couple


def test_wrench_map_equals_sum_of_lorentz_forces():
    """W @ I equals sum of I dl x B over filaments of the six racetrack coils.

    The field comes only from the 24 stator magnets' placement and polarity
    (uniform B_g between each inner/outer pair, zero elsewhere); the gain per
    ampere-turn is B_g * 2 l_m (eq 8's derivation). Seeded random currents.
    """
    a, d, lm, w, t, bg = 29.6, 10.8, 20.0, 8.0, 4.0, 0.29
    coils = pm.coil_layout(a)
    mags = pm.stator_magnets(coils, d, lm, w, t, 1.2)
    assert len(mags) == 24
    field = pm.ideal_gap_field_fn(mags, bg, d)

    def elements(c):
        return pm.coil_current_elements(c, lm, w, d - 6.0)

    rng = np.random.default_rng(7)
    W = pm.wrench_map(coils, bg * 2 * lm * 1e-3)
    for _ in range(3):
        amps = rng.normal(size=6) * 300.0
        lor = pm.lorentz_wrench(coils, amps, field, elements)
        np.testing.assert_allclose(lor, W @ amps, rtol=1e-12, atol=1e-15 * np.abs(W @ amps).max())


def test_coil_filaments_mean_turn_matches_eta_geom():
    """The filament model's current-weighted length is 2 l_m + pi w_m per ampere-turn (eta_geom's denominator)."""
    c = pm.coil_layout(30.0)[0]
    _, dl = pm.coil_current_elements(c, 20.0, 8.0, 4.8, n_turns_model=8, n_seg_arc=400)
    assert np.linalg.norm(dl, axis=1).sum() == pytest.approx(2 * 20.0 + math.pi * 8.0, rel=1e-4)
    assert np.abs(dl.sum(axis=0)).max() < 1e-12  # a closed loop


def test_peak_acceleration_formula():
    assert pm.peak_acceleration_m_s2(11.0, 0.22) == pytest.approx(2 * 11.0 / 0.22)
    with pytest.raises(DesignError):
        pm.peak_acceleration_m_s2(11.0, 0.0)


# ------------------------------------------------------------------ design file


def test_design_loads_and_rejects_bad_values():
    d = load_design(DESIGN_PATH)
    assert d.family == "powermouse" and d.actuator.magnet_length_mm == 20.0
    raw = dict(d.raw)
    raw["actuator"] = {**raw["actuator"], "gap_mm": 5.0}
    with pytest.raises(DesignError, match="actuator.gap_mm"):
        parse_design(raw)
    raw = dict(d.raw)
    raw["motion"] = {"range_mm": 4.0}
    with pytest.raises(DesignError, match="motion.range_mm"):
        parse_design(raw)
    raw = dict(d.raw)
    raw["flotor"] = {**raw["flotor"], "material": "unobtainium"}
    with pytest.raises(DesignError, match="flotor.material"):
        parse_design(raw)


def test_geometry_rejects_a_too_small_flotor():
    from cad.families.powermouse import parts as pp

    d = load_design(DESIGN_PATH)
    raw = dict(d.raw)
    raw["flotor"] = {**raw["flotor"], "edge_mm": 40.0}
    with pytest.raises(DesignError, match="flotor.edge_mm"):
        pp.geometry(parse_design(raw), 10.8)


# ------------------------------------------------------------------ solids and clearances


@pytest.fixture(scope="module")
def solids():
    from cad.families.powermouse import parts as pp

    d = load_design(DESIGN_PATH)
    g = pp.geometry(d, 10.8)
    return d, g, pp.flotor_solids(g), pp.stator_solids(g)


def test_solids_volumes_and_masses(solids):
    """Coil = stadium (2 w l + pi w^2) d_c; magnets w l t; mass = volume x density from cad.data.materials."""
    from cad.data.materials import get_material
    from cad.massprops.occt import solid_mass_props

    d, g, fl, st = solids
    w, lm, t, dc = 8.0, 20.0, 4.0, 10.8 - 6.0
    assert sum(1 for k in st if k.startswith("magnet_")) == 24
    assert sum(1 for k in fl if k.startswith("coil_")) == 6
    for k, (s, _) in fl.items():
        assert s.is_valid, k
        if k.startswith("coil_"):
            assert s.volume == pytest.approx((2 * w * lm + math.pi * w * w) * dc, rel=1e-9)
    rho = get_material(d.stator.magnet_material).density_kg_m3
    mp = solid_mass_props(st["magnet_+y_outer-B"][0], rho)
    assert mp.mass_kg == pytest.approx(w * lm * t * 1e-9 * rho, rel=1e-12)


def _lid_screw_hole_fill(g, rho: float) -> list:
    """Mass properties of the material the four flotor lid screw holes remove, closed form:
    per screw an ISO 273 clearance cylinder through the d_c lid and a tap drill
    ``LID_TAP_DRILL_DEPTH_MM`` deep below it (m = rho pi r^2 h; I = m r^2 / 2 along the axis,
    m (3 r^2 + h^2) / 12 across)."""
    from cad.data import catalog
    from cad.massprops.props import MassProps
    from cad.families.powermouse import parts as pp

    z0 = -(g.flotor_edge_mm / 2 - g.coil_width_mm)  # the split: ends of the side walls
    size = pp.FLOTOR_LID_SCREW
    cyl = [(catalog.clearance_hole_mm(size) / 2, -g.flotor_edge_mm / 2, z0),
           (catalog.tap_drill_mm(size) / 2, z0, z0 + pp.LID_TAP_DRILL_DEPTH_MM)]
    out = []
    for x, y in pp.flotor_lid_screw_xy_mm(g):
        for r, za, zb in cyl:
            h = zb - za
            m = rho * math.pi * r**2 * h * 1e-9
            ix = m * (3 * r**2 + h**2) / 12 * 1e-6
            out.append(MassProps(m, np.array([x, y, (za + zb) / 2]) * 1e-3,
                                 np.diag([ix, ix, m * r**2 / 2 * 1e-6])))
    return out


def test_flotor_mass_props_have_the_diagonal_symmetry(solids):
    """Layout + handle share the 3-fold axis (1,1,1): COM on the diagonal, I_xx = I_yy = I_zz,
    equal products -- once the material drilled for the flotor lid screws (only in the -z lid
    and the side walls' tops, which breaks the symmetry) is added back in closed form."""
    from cad.massprops.occt import solid_mass_props
    from cad.massprops.props import combine

    _, g, fl, _ = solids
    drilled = combine([solid_mass_props(s, 1000.0) for s, _ in fl.values()])
    assert np.ptp(drilled.com_m) > 1e-9 * np.abs(drilled.com_m).max()  # the holes show
    m = combine([drilled, *_lid_screw_hole_fill(g, 1000.0)])
    c = m.com_m
    assert np.ptp(c) < 1e-9 * np.abs(c).max() and c[0] > 0  # handle pulls the COM towards +(1,1,1)
    J = m.inertia_com_kg_m2
    assert np.ptp(np.diag(J)) < 1e-8 * J[0, 0]
    assert np.ptp([J[0, 1], J[0, 2], J[1, 2]]) < 1e-8 * J[0, 0]


def test_clearances_match_analytic_values(solids):
    """Exact OCCT distances at poses with closed-form clearances.

    Centre: d_r/2. Translation along a face normal by delta: d_r/2 - delta
    (0 = touching at +-3 mm, no overlap). Rotation by theta about x: the
    +z outer magnet corner at y = l_m/2 meets the tilted shell face:
    (E/2 + d_r/2) cos(theta) - (l_m/2) sin(theta) - E/2.
    """
    from cad.families.powermouse import parts as pp

    _, g, fl, st = solids
    th = math.radians(5.0)
    poses = [
        ("t+2.9x", np.eye(3), np.array([2.9, 0, 0])),
        ("t+3z", np.eye(3), np.array([0, 0, 3.0])),
        ("r(1, 0, 0)+", pm.rot_about((1, 0, 0), th), np.zeros(3)),
    ]
    c = pp.motion_clearances(g, 3.0, 5.0, fl, st, poses)
    assert c.nominal_mm == pytest.approx(3.0, abs=1e-9)
    assert c.poses["t+2.9x"][0] == pytest.approx(0.1, abs=1e-9)
    assert c.poses["t+3z"][0] == 0.0
    E = g.flotor_edge_mm
    expect = (E / 2 + 3.0) * math.cos(th) - 10.0 * math.sin(th) - E / 2
    assert c.poses["r(1, 0, 0)+"][0] == pytest.approx(expect, abs=1e-7)
    # beyond the range the coil overlaps a magnet: the check can fail
    over = pp.motion_clearances(g, 3.0, 5.0, fl, st, [("t+3.5x", np.eye(3), np.array([3.5, 0, 0]))])
    assert over.translation_mm < 0


# ------------------------------------------------------------------ build


def test_build_report_and_exports(family_builds):
    d, out, rep = family_builds["powermouse"]
    sv = np.array(rep["wrench_map_singular_values"])
    np.testing.assert_allclose(sv[:3], sv[0], rtol=1e-12)
    np.testing.assert_allclose(sv[3:], sv[3], rtol=1e-12)
    a_m = rep["geometry_mm"]["coil_plane_half_mm"] * 1e-3
    assert sv[3] / sv[0] == pytest.approx(a_m, rel=1e-12)
    act = rep["actuator"]
    assert abs(act["gap_mm"] - 11.0) < 0.5  # Fig. 8 optimum used for the geometry
    fl = rep["flotor"]
    assert fl["mass_kg"] == pytest.approx(sum(fl["parts_mass_kg"].values()), rel=1e-12)
    assert rep["peak_acceleration_m_s2"] == pytest.approx(
        2 * act["peak_force_N"] / fl["mass_kg"], rel=1e-12
    )
    assert rep["clearances_mm"]["translation_mm"] >= 0 and rep["clearances_mm"]["rotation_mm"] > 0
    files = set(rep["files"])
    assert {
        "parts/pm_flotor_body.step",
        "parts/pm_coil.step",
        "assembly.step",
        "bom.csv",
        "rig/assembly.step",
    } <= files
    for f in files:
        assert (out / f).is_file()
    with (out / "bom.csv").open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    mag = next(r for r in rows if r["part"] == "pm_magnet")
    assert int(mag["quantity"]) == 24 and mag["made_or_bought"] == "bought"
    assert json.loads((out / "report.json").read_text())["name"] == "powermouse"


def test_combined_translation_and_rotation_range(solids):
    """Table 4's +-3 mm and +-5 deg are separate ranges: at +-3 mm the coils touch their
    magnets (d_r/2). Measured on the solids (exact OCCT near contact): with a 5 deg rotation
    about any of the 13 axes, translations along the face normals clear up to 1.76 mm (1.70
    mm clears, 1.82 mm collides, a coil or the shell against a magnet: the coil gap is the
    end stop, not the handle or the post in their corner holes); docs/families/pantograph-powermouse.md quotes this."""
    from cad.families.powermouse import parts as pp

    _, g, fl, st = solids
    th = math.radians(5.0)
    axes = [np.array(a, float) / np.linalg.norm(a) for a in (
        (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (1, 0, 1), (0, 1, 1), (1, -1, 0),
        (1, 0, -1), (0, 1, -1), (1, 1, 1), (1, 1, -1), (1, -1, 1), (-1, 1, 1))]
    normals = [s * e for e in np.eye(3) for s in (1.0, -1.0)]

    def worst(m: float):
        poses = [(f"{k}{s}{j}", pm.rot_about(a, s * th), m * n)
                 for k, a in enumerate(axes) for s in (1.0, -1.0) for j, n in enumerate(normals)]
        c = pp.motion_clearances(g, 3.0, 5.0, fl, st, poses)
        return min(c.poses.values())

    assert worst(1.70)[0] > 0.0
    gap, pair = worst(1.82)
    assert gap < 0.0 and "magnet" in pair and pair.split("/")[0].startswith(("coil", "flotor_")), pair


def test_flotor_mass_and_peak_acceleration_pinned(family_builds):
    """docs/papers.md "Voice-coil actuators and the PowerMouse": flotor 234 g from the solids, 9.7 G at
    36 W. Hand checks: each coil is a stadium (2 w l + pi w^2) d_c of density eta_pack rho_Cu;
    the flotor mass is the sum of its solids' volumes x their materials' densities plus the
    four lid screws' catalog masses; the peak
    force is eq (8) at 36 W (F ~ sqrt(P): the 8 W force x sqrt(36/8)), doubled by the opposite
    coil pair (peak_force_N). The totals 234 g / 9.7 G are a regression pin (our own run)."""
    from cad.actuators import voicecoil as vc
    from cad.data.materials import get_material
    from cad.families.powermouse import parts as pp

    d, _, rep = family_builds["powermouse"]
    gap = rep["actuator"]["gap_mm"]
    g = pp.geometry(d, gap)
    w, lm, dc = g.magnet_width_mm, g.magnet_length_mm, g.coil_width_mm
    rho_coil = d.actuator.eta_pack * get_material(d.flotor.coil_material).density_kg_m3
    coil_kg = (2 * w * lm + math.pi * w * w) * dc * 1e-9 * rho_coil
    masses = rep["flotor"]["parts_mass_kg"]
    coils = [v for k, v in masses.items() if "coil" in k]
    assert len(coils) == 6 and coils == pytest.approx([coil_kg] * 6, rel=1e-9)
    dens = {"shell": get_material(d.flotor.material).density_kg_m3, "coil": rho_coil,
            "handle": get_material(d.handle.material).density_kg_m3}
    parts_sum = sum(s.volume * 1e-9 * dens[role] for s, role in pp.flotor_solids(g).values())
    screws = [v for k, v in masses.items() if k.startswith("flotor_lid_screw_")]
    assert len(screws) == 4 and len(masses) == 13  # + the 4 M2.5 lid screws (catalog masses)
    parts_sum += sum(screws)
    assert rep["flotor"]["mass_kg"] == pytest.approx(parts_sum, rel=1e-6)
    p8 = vc.VoiceCoilParams(lm, w, g.magnet_thickness_mm, d.actuator.rattle_mm, power_W=8.0)
    f36 = float(vc.force_vs_gap_N(gap, p8, "closed-form")[0]) * math.sqrt(36.0 / 8.0)
    assert rep["peak_acceleration_m_s2"] == pytest.approx(2 * f36 / parts_sum, rel=1e-6)
    # regression pin (our own run): the numbers of docs/papers.md
    assert round(rep["flotor_mass_g"]) == 234 and round(rep["peak_acceleration_G"], 1) == 9.7


def test_one_interference_check_matches_analytic_clearances():
    """The one interference check (cad.assembly.interference.check_model) on the PowerMouse's
    model, with its motion replaced by poses of closed-form clearance (the cases of
    test_clearances_match_analytic_values): centre d_r/2 = 3 mm; a translation by delta
    along a face normal d_r/2 - delta (0.1 mm at 2.9 mm; touching, no volume, at 3 mm); a
    5 deg rotation about x (E/2 + d_r/2) cos(theta) - (l_m/2) sin(theta) - E/2; beyond the
    range (3.5 mm) a clash named with its pair, pose and a positive volume."""
    import dataclasses

    from cad.assembly import interference as itf
    from cad.design import load_design
    from cad.errors import InterferenceError
    from cad.families.powermouse import assemble

    d = load_design("designs/powermouse.toml")
    model = assemble(d, "preview")
    g = model.extra.geometry
    assert d.actuator.rattle_mm == 6.0 and d.actuator.magnet_length_mm == 20.0
    th = math.radians(5.0)
    poses = {"centre": np.eye(4)}
    for label, R, t in (("t+2.9x", np.eye(3), [2.9, 0, 0]), ("t+3z", np.eye(3), [0, 0, 3.0]),
                        ("r(1, 0, 0)+", pm.rot_about((1, 0, 0), th), [0, 0, 0]),
                        ("t+3.5x", np.eye(3), [3.5, 0, 0])):
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = R, t
        poses[label] = T
    m = dataclasses.replace(model, motion={"flotor": np.stack(list(poses.values()))},
                            pose_labels=tuple(poses))
    rep = itf.check_model(m, groups=lambda label: label)
    c = rep.poses
    assert c["centre"][0] == pytest.approx(3.0, abs=1e-9) and c["centre"][2] == "exact"
    assert c["t+2.9x"][0] == pytest.approx(0.1, abs=1e-9) and c["t+2.9x"][2] == "exact"
    assert c["t+3z"][0] == 0.0
    E = g.flotor_edge_mm
    expect = (E / 2 + 3.0) * math.cos(th) - 10.0 * math.sin(th) - E / 2
    assert c["r(1, 0, 0)+"][0] == pytest.approx(expect, abs=1e-7)
    assert {x["pose"] for x in rep.collisions} == {"t+3.5x"}
    clash = rep.collisions[0]
    assert clash["bodies"] == ["flotor", "ground"] and clash["overlap_volume_mm3"] > 0
    with pytest.raises(InterferenceError, match=r" / .* collide at pose t\+3\.5x \(overlap"):
        itf.raise_on_collision(rep, 0.0)
