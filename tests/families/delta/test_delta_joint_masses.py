"""The frame model's masses at the rods' ends from the parts a delta draws there
(:func:`cad.families.delta.structure.sections_from_parts`, the build's first mode) against
independent references:

(1) the Falcon's knee end (g = 22.5 mm): each rod's lumped top-end mass equals the sum of the
    knee hinge's drawn parts read back by hand -- the clevis and the rod's eye as their
    solids' B-rep volume (OCCT's GProp, integrated here) x their material's density, the
    hinge pin as a cylinder pi/4 d^2 L x steel's density (closed form), the 623 bearing its
    catalog mass; the effector end the ball stud and socket's catalog mass (1.2 g);
(2) the frame's lumped masses sum to the default model's plus six times the extra knee mass
    (conservation of mass, closed form);
(3) the first mode with the drawn masses against the second assembly of the stiffness matrix
    (master-slave nodes at every release, tests/families/delta/test_delta_knee_structure.py),
    which agrees to 1e-9; and the Falcon's first mode with the drawn masses: a regression pin;
(4) without a knee (designs/delta.toml) the drawn ball joints are the default's (a stud and a
    socket at each end, hardware.design_ball_joint(design).mass_g: the catalog joint's).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import eigh

from cad.data.catalog import get_bearing
from cad.data.materials import get_material
from cad.design import load_design
from cad.families.delta import hardware as hw
from cad.families.delta.structure import (
    BOTTOM_JOINT_PARTS,
    TOP_JOINT_PARTS,
    default_sections,
    delta_frame,
    first_mode,
    rod_end_masses_kg,
    sections_from_parts,
)
from tests.families.delta.test_delta_knee_structure import master_slave

ROOT = Path(__file__).resolve().parents[3]
FALCON = load_design(ROOT / "designs" / "delta_falcon.toml")

#: Regression pin (our own run, 2026-12-05): the Falcon's first mode at its workspace centre
#: with the knee hinges' drawn masses (3.853 g at each knee end; the model counted half a ball
#: joint, 0.6 g, before: 329.83 Hz).
FALCON_PARTS_HZ = 312.4750374889737


def _joint_props(design):
    """(instances, {kind: MassProps}) of the kinds drawn at the rod ends only."""
    from cad.families.delta.assembly import assemble
    from cad.pipeline import family

    inst = assemble(design, "preview").instances
    names = {n.format(i=i, s=s) for n in TOP_JOINT_PARTS + BOTTOM_JOINT_PARTS for i in range(3) for s in "ab"}
    ks = {x.kind.name: x.kind for x in inst if x.name in names}
    return inst, {k: family.kind_mass_props(v) for k, v in ks.items()}, ks


@pytest.fixture(scope="module")
def falcon():
    return _joint_props(FALCON)


def _volume_mm3(shape) -> float:
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    g = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, g)
    return g.Mass()


def test_knee_end_mass_is_the_hinge_parts_by_hand(falcon):
    inst, props, ks = falcon
    rho = {k: get_material(ks[k].material).density_kg_m3 for k in ("knee_clevis", "rod_eye", "knee_hinge_pin")}
    h = hw.knee_hinge()
    pin = math.pi / 4 * h.pin_d_mm**2 * h.pin_length_mm * 1e-9 * rho["knee_hinge_pin"]
    assert _volume_mm3(ks["knee_hinge_pin"].shape) * 1e-9 * rho["knee_hinge_pin"] == pytest.approx(pin, rel=1e-9)
    by_hand = (_volume_mm3(ks["knee_clevis"].shape) * 1e-9 * rho["knee_clevis"]
               + _volume_mm3(ks["rod_eye"].shape) * 1e-9 * rho["rod_eye"]
               + pin + get_bearing("623", "test").mass_kg)
    m = rod_end_masses_kg(inst, props)
    np.testing.assert_allclose(m[:, :, 0], by_hand, rtol=1e-9)
    np.testing.assert_allclose(m[:, :, 1], hw.design_ball_joint(FALCON).mass_g * 1e-3, rtol=1e-12)
    sec = sections_from_parts(FALCON.mechanism.effector_radius_mm, FALCON.parallelogram_width_mm, inst, props)
    assert (sec.top_joint_kg, sec.bottom_joint_kg) == pytest.approx((by_hand, 1.2e-3), rel=1e-9)
    assert round(by_hand * 1e3, 3) == 3.853  # docs/families/delta.md (regression pin at the docs' precision)


def test_frame_masses_and_modes_with_the_drawn_joints(falcon):
    inst, props, _ = falcon
    d, w = FALCON.mechanism, FALCON.parallelogram_width_mm
    sec = sections_from_parts(d.effector_radius_mm, w, inst, props)
    base = default_sections(d.effector_radius_mm, w)
    P = FALCON.workspace["center_mm"]
    f, _ = delta_frame(d, P, w, sec)
    f0, _ = delta_frame(d, P, w, base)
    assert f.masses().sum() - f0.masses().sum() == pytest.approx(
        6 * (sec.top_joint_kg - base.top_joint_kg + sec.bottom_joint_kg - base.bottom_joint_kg), rel=1e-9)
    for Q in (P, [45.0, -45.0, -66.0]):
        f, _ = delta_frame(d, Q, w, sec)
        K, n = master_slave(f)
        fixed = {6 * a + q for a in f.clamped for q in range(6)}
        free = np.array([q for q in range(K.shape[0]) if q not in fixed])
        m = np.zeros(K.shape[0])
        m[[6 * p + q for p in range(n) for q in range(3)]] = np.repeat(f.masses(), 3)
        t, r = free[m[free] > 0], free[m[free] == 0]
        Kc = K[np.ix_(t, t)] - K[np.ix_(t, r)] @ np.linalg.solve(K[np.ix_(r, r)], K[np.ix_(r, t)])
        hz = np.sqrt(eigh(0.5 * (Kc + Kc.T), np.diag(m[t]), eigvals_only=True, subset_by_index=[0, 2])) / (2 * np.pi)
        np.testing.assert_allclose(hz, first_mode(d, Q, w, sec)["modes_Hz"], rtol=1e-9)
    r = first_mode(d, P, w, sec)
    assert r["first_mode_Hz"] == pytest.approx(FALCON_PARTS_HZ, rel=1e-6)
    assert r["first_mode_Hz"] < first_mode(d, P, w, base)["first_mode_Hz"]  # heavier knees, lower mode


def test_without_a_knee_the_drawn_joints_are_the_defaults():
    des = load_design(ROOT / "designs" / "delta.toml")
    inst, props, _ = _joint_props(des)
    m = rod_end_masses_kg(inst, props)
    np.testing.assert_allclose(m, hw.design_ball_joint(des).mass_g * 1e-3, rtol=1e-12)
    sec = sections_from_parts(des.mechanism.effector_radius_mm, des.parallelogram_width_mm, inst, props)
    base = default_sections(des.mechanism.effector_radius_mm, des.parallelogram_width_mm)
    assert (sec.top_joint_kg, sec.bottom_joint_kg) == pytest.approx((base.top_joint_kg, base.bottom_joint_kg),
                                                                    rel=1e-12)
