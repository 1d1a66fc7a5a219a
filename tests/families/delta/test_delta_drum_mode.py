"""The capstan drums in the delta's first mode (issue 36): a rigid body on a node of the frame
model (:meth:`cad.families.delta.structure.Frame3D.rigid_mass`) against the single-DOF closed
form, the drums in the delta's frame against a second assembly of the same drums as point
masses on stiff links, and the bundled capstan delta's drums from its solids."""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from cad.design import parse_design
from cad.device import resolve_device
from cad.families.delta import capstan as dcap
from cad.families.delta.structure import (
    Frame3D,
    default_sections,
    delta_frame,
    first_mode,
    pivot_spring,
    sections_from_parts,
)
from cad.kinematics.delta import ik
from cad.massprops.props import from_principal
from cad.structure.frame import Section

ROOT = Path(__file__).resolve().parents[3]
RAW = tomllib.loads((ROOT / "designs" / "delta_capstan.toml").read_text())


def _random_rotation(rng) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def test_rigid_mass_on_a_pivot_against_the_single_dof_closed_form():
    """A node on a pivot about a unit axis t with a rope spring k and a rigid body (mass m at
    offset r, inertia I_c about its centre): one DOF, f = sqrt(k / I_t) / 2 pi with
    I_t = t.I_c.t + m |r x t|^2 (parallel axes)."""
    rng = np.random.default_rng(36)
    for _ in range(5):
        t = rng.normal(size=3)
        t /= np.linalg.norm(t)
        m, r, k = 0.16, rng.normal(size=3) * 0.01, 4389.0
        Ic = from_principal(m, np.zeros(3), rng.uniform(0.5e-4, 1.5e-4, 3), _random_rotation(rng)).inertia_com_kg_m2
        f = Frame3D()
        a = f.node(rng.normal(size=3) * 0.1)
        f.ground_springs.append((a, pivot_spring(t, k)))
        f.rigid_mass(a, m, r, Ic)
        I_t = t @ Ic @ t + m * float(np.linalg.norm(np.cross(r, t)) ** 2)
        assert f.modes(1)[0][0] == pytest.approx(math.sqrt(k / I_t) / (2 * math.pi), rel=1e-6)


def _stiff_link() -> Section:
    """A link far stiffer than the frame (steel x 1e4): a rigid arm for the point masses."""
    return Section(A=1e-4, Iz=1e-8, Iy=1e-8, J=2e-8, cy=0.005, cz=0.005, t_torsion=0.005,
                   E=2e15, G=8e14, rho=0.0)


def _upper_frame(d, P_mm, i: int) -> tuple[np.ndarray, np.ndarray]:
    """(R, origin m) of upper_i at P, from the IK's motor angle and the layout's convention
    (x along the arm: cos theta u - sin theta z, y the motor axis t), recomputed here."""
    th = ik(d, np.asarray(P_mm, float)[None]).theta_rad[0, i]
    x = math.cos(th) * d.radial[i] - math.sin(th) * np.array([0.0, 0.0, 1.0])
    y = d.tangential[i]
    R = np.column_stack([x, y, np.cross(x, y)])
    return R, (d.base_radius_mm * d.radial[i] + d.axis_offset_mm * d.tangential[i]) * 1e-3


def test_drums_in_the_delta_frame_against_point_masses_on_stiff_links():
    """The capstan delta's frame with a drum (mass, offset centre, full inertia tensor) on each
    arm's motor-axis node, against a second assembly: the same frame without drums and each
    drum as six point masses m/6 at +-a_k along its principal axes (2 (m/6) a_k^2 = tr(I)/2 -
    I_k: the same mass, centre and inertia tensor) on stiff links from the motor-axis node,
    the solver's translational-mass path only. Same three lowest modes."""
    d = parse_design(copy.deepcopy(RAW), "v.toml")
    m, P, w = d.mechanism, np.asarray(d.workspace["center_mm"], float), d.parallelogram_width_mm
    dev = resolve_device(d)
    k = dcap.rope_stiffness_Nm_per_rad(d, dev)
    rng = np.random.default_rng(7)
    drums = [from_principal(0.16, np.array([0.005, -0.0105, 0.007]) + rng.normal(size=3) * 1e-3,
                            np.array([0.9e-4, 1.1e-4, 1.9e-4]) * (1 + 0.1 * i), _random_rotation(rng))
             for i in range(3)]
    sec = default_sections(m.effector_radius_mm, w)
    hz = first_mode(m, P, w, sec, rope_k_Nm_per_rad=k, drums=drums)["modes_Hz"]
    f, _ = delta_frame(m, P, w, sec, rope_k_Nm_per_rad=k)
    for i, dr in enumerate(drums):
        R, o = _upper_frame(m, P, i)
        (a,) = [n for n, _ in f.ground_springs if np.allclose(f.nodes[n], o)]
        c = o + R @ dr.com_m
        lam, V = np.linalg.eigh(R @ dr.inertia_com_kg_m2 @ R.T)
        S = lam.sum() / 2 - lam
        for kk in range(3):
            for s in (-1.0, 1.0):
                p = f.node(c + s * math.sqrt(3 * S[kk] / dr.mass_kg) * V[:, kk])
                ref = np.eye(3)[int(np.argmin(np.abs(f.nodes[p] - f.nodes[a])))]
                f.beam(a, p, _stiff_link(), ref)
                f.add_mass(p, dr.mass_kg / 6)
    hz2 = f.modes(3)[0]
    assert hz2 == pytest.approx(hz, rel=1e-5)
    # and the drums lower it: the rope model without them is the bound above
    assert hz[0] < first_mode(m, P, w, sec, rope_k_Nm_per_rad=k)["first_mode_Hz"]


def test_the_bundled_capstan_deltas_drums_from_its_solids():
    """designs/delta_capstan.toml: the drums' mass properties from the solids (the parts
    upper_i.capstan_*, the per-kind properties Lambda(x) sums) on the three arms, alike, the
    drum's centre in the rope's plane off the arm's plane; the first mode with them (docs/
    families/delta.md "Capstan": a regression pin at the docs' precision, recorded from this
    model, whose parts are checked above) below the ropes-only 159.6 Hz and above the limit."""
    from cad.families.delta.assembly import assemble
    from cad.families.delta.build import drum_props
    from cad.pipeline import family

    d = parse_design(copy.deepcopy(RAW), "v.toml")
    inst = assemble(d, "preview").instances
    drums = drum_props(inst, family.kind_props(inst))
    assert drum_props([x for x in inst if ".capstan_" not in x.name], family.kind_props(inst)) is None
    share = sum(s["mass_g"] for s in family.body_shares(inst, family.kind_props(inst))["upper_0"]
                if s["part"].startswith("upper_0.capstan_"))
    assert drums[0].mass_kg * 1e3 == pytest.approx(share, rel=1e-12)
    assert [dr.mass_kg for dr in drums] == pytest.approx([drums[0].mass_kg] * 3, rel=1e-9)
    dev = resolve_device(d)
    k = dcap.rope_stiffness_Nm_per_rad(d, dev)
    c = np.asarray(d.workspace["center_mm"], float)
    sec = sections_from_parts(d.mechanism.effector_radius_mm, d.parallelogram_width_mm, inst,
                              family.kind_props(inst))  # the rods' end joints as drawn, as the build
    r = first_mode(d.mechanism, c, d.parallelogram_width_mm, sec, rope_k_Nm_per_rad=k, drums=drums)
    assert round(r["first_mode_Hz"], 1) == 158.3 and round(drums[0].mass_kg * 1e3) == 163  # with the rope groove
    assert 150.0 <= r["first_mode_Hz"] < 159.6
    assert "drum sector" in r["boundary"]
