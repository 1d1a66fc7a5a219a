"""Issue 24 §5: the device-level structure figures against second, independent models.

The device model (:mod:`cad.structure`) is a stiffness-method beam frame (12 x 12 element
matrices assembled, ties eliminated, supports removed, Guyan-condensed eigenproblem), its
plate bars' bending stiffnesses taken from plane-stress finite-element cantilevers
(``method = "fem"``). The models here share none of that code (nothing from
``cad.structure.frame`` nor ``cad.structure.graph``): they are the **force method** written out
by hand, i.e. rigid-link statics for the internal forces, the unit-load (virtual work)
integrals of each member's closed-form sections, compatibility for the redundants, and the
eigenproblem of the flexibility matrix for the first mode. What they share with the device
model is the physics stated for it: rigid revolute joints (every DOF but the rotation about
z), the supports of each figure, the bars' material and dimensions (E, G, density from
:mod:`cad.structure.elastic` and :mod:`cad.data.materials`, sourced data), the masses.

Agreement asked by the issue: within ``STRUCTURE_PROOF_REL`` (10 %). Where the hand model
is exactly the device model's mechanics (the pantograph's in-plane compliance and stress:
Euler-Bernoulli links, distal links two-force members) it must agree to round-off
(``STRUCTURE_SAME_MODEL_REL``).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cad.tolerances import STRUCTURE_PROOF_REL, STRUCTURE_SAME_MODEL_REL

ROOT = Path(__file__).resolve().parents[3]
KAPPA = 5.0 / 6.0  # Timoshenko shear coefficient of a rectangle
KNOB_KG = 0.030  # the knob at P of tests/unit/datasheet/test_datasheet.py's Rayleigh check
GAUSS = np.polynomial.legendre.leggauss(3)  # exact for M^2 (degree 2) on each piece


# ----------------------------------------------------------------- the Hoeken's pieces
def _hoeken():
    from cad.data import catalog
    from cad.data.materials import get_material
    from cad.design import load_design
    from cad.structure.elastic import get_elastic

    d = load_design(ROOT / "designs" / "hoeken.toml")
    p = d.parts
    el = get_elastic(p.bar_material)
    r_brg = catalog.get_bearing(p.bearing).D_mm / 2 + p.bar_pocket_web_mm
    end_r = {"A1": p.hub_diameter_mm / 2 + p.bar_pocket_web_mm, "A2": r_brg, "A3": r_brg,
             "A4": r_brg, "P": p.handle_diameter_mm / 2 + p.bar_pocket_web_mm}
    return d, el, get_material(p.bar_material).density_kg_m3, end_r


def _pieces(parts, L_mm: float, r0: float, r1: float) -> list[tuple[float, float, bool]]:
    """``[(s0, s1 (m), slotted)]`` along a bar L joint to joint: solid within the larger end
    radius of either joint, the pocket (width w - 2 web) between, when it is longer than
    its width (the bar geometry the FE cantilevers of the device model mesh)."""
    w, web = parts.bar_width_mm, parts.bar_pocket_web_mm
    wp = w - 2 * web
    a = max(r0, r1)
    if not (parts.bar_pockets and wp >= 2.0 and L_mm - 2 * a > wp):
        return [(0.0, L_mm * 1e-3, False)]
    return [(0.0, a * 1e-3, False), (a * 1e-3, (L_mm - a) * 1e-3, True), ((L_mm - a) * 1e-3, L_mm * 1e-3, False)]


def _props(parts, el, slotted: bool) -> dict:
    """Closed-form section of a plate bar (SI): EA, EI in plane (Iz) and out of plane (Iy),
    GJ, and the shear flexibility f_s = 1 / (kappa G A) per unit length. (The pockets' in-plane
    Vierendeel action is left to the coupler's FE, :func:`_coupler_fe_work_m_per_N`: a
    fixed-guided web formula, L_slot^2 / (24 E I_web), came out 19 % stiffer than a 2-D FE of
    one pocketed segment.)"""
    w, t, web = parts.bar_width_mm * 1e-3, parts.bar_thickness_mm * 1e-3, parts.bar_pocket_web_mm * 1e-3
    E, G = el.E_Pa, el.G_Pa
    if not slotted:
        A = w * t
        return {"EA": E * A, "EIz": E * t * w**3 / 12, "EIy": E * w * t**3 / 12,
                "GJ": G * _j_pocket(parts), "fs": 1 / (KAPPA * G * A)}
    wp = w - 2 * web
    A = 2 * web * t
    return {"EA": E * A, "EIz": E * t * (w**3 - wp**3) / 12, "EIy": E * A * t**2 / 12,
            "GJ": G * _j_pocket(parts), "fs": 1 / (KAPPA * G * A)}


def _j_pocket(parts) -> float:
    """Torsion constant of every piece: the pocket section's two webs, 2 J_rect(web, t), over
    the whole beam -- the device model's stated assumption (:mod:`cad.structure.device`),
    kept here so that the comparison tests the computation, not a different section (solid
    ends would raise the Hoeken's first mode by ~7 %: docs/datasheet.md)."""
    t, web = parts.bar_thickness_mm * 1e-3, parts.bar_pocket_web_mm * 1e-3
    return 2 * _j_rect(web, t) if parts.bar_pockets else _j_rect(parts.bar_width_mm * 1e-3, t)


def _j_rect(b: float, h: float) -> float:
    """Saint-Venant J of a b x h rectangle: Timoshenko & Goodier's series, 5 terms
    (J = a^3 b' / 3 (1 - 192 a / (pi^5 b') sum tanh(n pi b' / 2a) / n^5), a = min, b' = max)."""
    a, bb = min(b, h), max(b, h)
    s = sum(math.tanh(n * math.pi * bb / (2 * a)) / n**5 for n in (1, 3, 5, 7, 9))
    return a**3 * bb / 3 * (1 - 192 * a / (math.pi**5 * bb) * s)


def _hoeken_members(d, el, end_r, pose, beam: bool = False):
    """Members of the Hoeken at a pose, oriented away from the root A1 (world m):
    ``name -> (start, end, pieces with their section)``; the coupler's two collinear beams.
    ``beam``: the pocket section over each whole member (the device's ``beam`` method)."""
    J = {k: np.asarray(v, float).reshape(-1, 2)[0] * 1e-3 for k, v in
         (("A1", pose.A1_mm), ("A2", pose.A2_mm), ("A3", pose.A3_mm), ("A4", pose.A4_mm), ("P", pose.P_mm))}
    out = {}
    for name, a, b in (("crank", "A1", "A2"), ("coupler_23", "A2", "A3"), ("coupler_3P", "A3", "P"),
                       ("rocker", "A3", "A4")):
        L_mm = float(np.linalg.norm(J[b] - J[a])) * 1e3
        pcs = [(0.0, L_mm * 1e-3, True)] if beam else _pieces(d.parts, L_mm, end_r[a], end_r[b])
        out[name] = (J[a], J[b], [(s0, s1, _props(d.parts, el, sl)) for s0, s1, sl in pcs])
    return out, J


def _gauss(s0, s1):
    x, w = GAUSS
    return 0.5 * (s1 - s0) * x + 0.5 * (s1 + s0), 0.5 * (s1 - s0) * w


def _cross(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


# ----------------------------------------------------- (a) in plane: handle compliance
def _hoeken_inplane_compliance_m_per_N(d, el, end_r, pose, f) -> float:
    """Handle compliance along ``f`` (unit, world) by rigid-link statics (crank clamped at
    A1, rocker a two-force member pinned at A4 and A3, coupler pinned at A2: statically
    determinate in plane) and the unit-load method: the coupler's share from its own 2-D FE
    (:func:`_coupler_fe_work_m_per_N`), the solid crank's and the rocker's from the integral
    of (N^2 / EA + V^2 / (kappa G A) + M^2 / EI) over their pieces (Timoshenko)."""
    mem, J = _hoeken_members(d, el, end_r, pose)
    u34 = (J["A3"] - J["A4"]) / np.linalg.norm(J["A3"] - J["A4"])
    t = -_cross(J["P"] - J["A2"], f) / _cross(J["A3"] - J["A2"], u34)  # rocker on coupler: t u34
    loads = {  # member -> loads on its far side of a station [(point, force)]
        "coupler_3P": [(J["P"], f)],
        "coupler_23": [(J["P"], f), (J["A3"], t * u34)],
        "crank": [(J["P"], f), (J["A3"], t * u34)],  # what the coupler hands the crank at A2
        "rocker": [(J["A4"], t * u34)],  # a two-force member: the pin force at its far end
    }
    total = _coupler_fe_work_m_per_N(d, el, end_r, J, [(J["P"], f), (J["A3"], t * u34), (J["A2"], -f - t * u34)])
    for name, (p0, p1, pcs) in mem.items():
        if name.startswith("coupler"):
            continue
        e = (p1 - p0) / np.linalg.norm(p1 - p0)
        n = np.array([-e[1], e[0]])
        for s0, s1, sec in pcs:
            xs, ws = _gauss(s0, s1)
            for s, wq in zip(xs, ws, strict=True):
                x = p0 + s * e
                F = sum(fq for _, fq in loads[name])
                M = sum(_cross(q - x, fq) for q, fq in loads[name])
                if name == "rocker":
                    F, M = F, 0.0  # pinned both ends, no transverse load: axial only
                total += wq * ((F @ e) ** 2 / sec["EA"] + (F @ n) ** 2 * sec["fs"] + M**2 / sec["EIz"])
    return total


def _coupler_fe_work_m_per_N(d, el, end_r, J, loads_world) -> float:
    """Work (m per N of handle force) of the coupler's self-equilibrated joint loads on their
    own displacements, from a plane-stress FE of the whole coupler bar written here
    (scikit-fem, ``ElementQuad2``, ~2 mm cells, two across each web, thickness t): the bar A2 -> P with its
    pockets (the pieces of :func:`_pieces`) and square ends half a width beyond A2 and P;
    each joint load a uniform body force over the bearing seat's disc (radius D / 2: the
    bearing's steel ring spreads the pin load over the seat); statically determinate
    supports (A2: x, y; P: y across) carry nothing since the loads balance. Under loads
    ``[(point, force)]`` of a unit handle force, that work is the coupler's share of the
    unit-load integral (its bending, shear, the pockets' Vierendeel action and the load
    spreading, in place of any beam formula)."""
    from skfem import (
        Basis,
        BilinearForm,
        ElementQuad2,
        ElementVector,
        LinearForm,
        MeshQuad,
        asm,
        condense,
        solve,
    )
    from skfem.helpers import ddot, sym_grad, trace
    from skfem.helpers import eye as _eye

    from cad.data import catalog

    p = d.parts
    w, t = p.bar_width_mm, p.bar_thickness_mm
    wp = w - 2 * p.bar_pocket_web_mm
    e = (J["A3"] - J["A2"]) / np.linalg.norm(J["A3"] - J["A2"])
    n = np.array([-e[1], e[0]])
    loc = {k: np.array([(J[k] - J["A2"]) @ e, (J[k] - J["A2"]) @ n]) * 1e3 for k in ("A2", "A3", "P")}
    slots = []
    for a, b in (("A2", "A3"), ("A3", "P")):
        L = loc[b][0] - loc[a][0]
        slots += [(loc[a][0] + s0 * 1e3, loc[a][0] + s1 * 1e3) for s0, s1, sl in _pieces(p, L, end_r[a], end_r[b]) if sl]
    x_end = loc["P"][0] + w / 2
    xs = sorted({*np.linspace(-w / 2, x_end, int(np.ceil((x_end + w / 2) / 2.0)) + 1),
                 *[v for sl in slots for v in sl]})
    ys = sorted({*np.linspace(-w / 2, -wp / 2, 3), *np.linspace(-wp / 2, wp / 2, 8), *np.linspace(wp / 2, w / 2, 3)})
    m = MeshQuad.init_tensor(np.array(xs) * 1e-3, np.array(ys) * 1e-3)
    c = m.p[:, m.t].mean(axis=1) * 1e3
    cut = np.zeros(m.t.shape[1], bool)
    for x0, x1 in slots:
        cut |= (c[0] > x0) & (c[0] < x1) & (np.abs(c[1]) < wp / 2)
    m = m.remove_elements(np.nonzero(cut)[0])
    basis = Basis(m, ElementVector(ElementQuad2()))
    E, nu = el.E_Pa, el.nu
    lam, mu = E * nu / (1 - nu**2), E / (2 * (1 + nu))

    @BilinearForm
    def stiffness(u, v, _):
        eps = sym_grad(u)
        return t * 1e-3 * ddot(2 * mu * eps + lam * _eye(trace(eps), 2), sym_grad(v))

    r_seat = catalog.get_bearing(p.bearing).D_mm / 2 * 1e-3
    seats = []
    for q, F in loads_world:
        key = min(loc, key=lambda k: float(np.linalg.norm(J[k] - q)))
        seats.append((loc[key] * 1e-3, np.array([F @ e, F @ n]) / (math.pi * r_seat**2)))  # N / m^2

    @LinearForm
    def body(v, wv):
        out = 0.0
        for x0, fl in seats:
            inside = ((wv.x[0] - x0[0]) ** 2 + (wv.x[1] - x0[1]) ** 2) < r_seat**2
            out = out + inside * (fl[0] * v[0] + fl[1] * v[1])
        return out

    f = asm(body, basis)
    K = asm(stiffness, basis)
    locs = basis.doflocs

    def nearest(pt, comp):
        dofs = np.arange(comp, basis.N, 2)
        return int(dofs[np.argmin(np.linalg.norm(locs[:, dofs].T - pt * 1e-3, axis=1))])

    fixed = [nearest(loc["A2"], 0), nearest(loc["A2"], 1), nearest(loc["P"], 1)]
    u = solve(*condense(K, f, D=np.array(fixed)))
    return float(f @ u)


# -------------------------------------------- (a) out of plane: flexibility, first mode
def _tree_paths():
    """Members from the root A1 to each member (the load at a station reaches the root
    through these), for the Hoeken grillage released at A4."""
    return {"crank": ["crank"], "coupler_23": ["crank", "coupler_23"],
            "coupler_3P": ["crank", "coupler_23", "coupler_3P"], "rocker": ["crank", "coupler_23", "rocker"]}


def _unit_moments(mem, name, x, s, points):
    """(Mb, T) at station ``s`` of member ``name`` (world point ``x``, (3,)) of each unit load
    of ``points`` (only loads beyond the station, away from the root, reach it)."""
    paths = _tree_paths()
    p0, p1, _ = mem[name]
    e = np.r_[(p1 - p0) / np.linalg.norm(p1 - p0), 0.0]
    nb = np.cross([0.0, 0.0, 1.0], e)
    Mb, T = np.zeros(len(points)), np.zeros(len(points))
    for i, (m_i, s_i, kind) in enumerate(points):
        if name not in paths[m_i] or (m_i == name and s_i <= s):
            continue
        q0, q1, _ = mem[m_i]
        eq = (q1 - q0) / np.linalg.norm(q1 - q0)
        q = np.r_[q0 + s_i * eq, 0.0]
        mv = (np.cross(q - x, [0.0, 0.0, 1.0]) if kind == "Fz"
              else np.array([1.0, 0.0, 0.0]) if kind == "Mx" else np.array([0.0, 1.0, 0.0]))
        Mb[i], T[i] = mv @ nb, mv @ e
    return Mb, T


def _hoeken_grillage_flexibility(d, el, end_r, pose, points, beam: bool = False):
    """Out-of-plane flexibility (force method) of the Hoeken released at A4: ``points`` are
    generalized loads ``(member, s (m from the member's start), kind)`` with kind "Fz", "Mx"
    or "My"; returns F_ij = sum over pieces of the integral of (Mb_i Mb_j / E I_y + T_i T_j /
    G J), Mb / T the bending / twisting moment of unit load i at each station
    (:func:`_unit_moments`)."""
    mem, _ = _hoeken_members(d, el, end_r, pose, beam)
    n = len(points)
    F = np.zeros((n, n))
    for name, (p0, p1, pcs) in mem.items():
        e = (p1 - p0) / np.linalg.norm(p1 - p0)
        for s0, s1, sec in pcs:
            xs, ws = _gauss(s0, s1)
            for s, wq in zip(xs, ws, strict=True):
                Mb, T = _unit_moments(mem, name, np.r_[p0 + s * e, 0.0], s, points)
                F += wq * (np.outer(Mb, Mb) / sec["EIy"] + np.outer(T, T) / sec["GJ"])
    return F


def _hoeken_out_of_plane(d, el, rho, end_r, pose, n_mass: int = 8):
    """(handle compliance along z m/N, first out-of-plane mode Hz): redundants Fz, Mx, My at
    A4 (the rocker's support) by compatibility, the condensed flexibility C over the mass
    points; first mode from the eigenvalue of C M (lumped masses: exact for them). Masses:
    the bar's rho (w - w_p) t per metre (the device model's input: bars spread evenly) in
    ``n_mass`` lumps per member at the lump centres, the knob at P."""
    mem, _ = _hoeken_members(d, el, end_r, pose)
    p = d.parts
    lin = rho * (p.bar_width_mm - (p.bar_width_mm - 2 * p.bar_pocket_web_mm)) * p.bar_thickness_mm * 1e-6
    pts, mass = [], []
    for name, (p0, p1, _) in mem.items():
        L = float(np.linalg.norm(p1 - p0))
        for k in range(n_mass):
            pts.append((name, (k + 0.5) * L / n_mass, "Fz"))
            mass.append(lin * L / n_mass)
    L3P = float(np.linalg.norm(mem["coupler_3P"][1] - mem["coupler_3P"][0]))
    pts.append(("coupler_3P", L3P * (1 - 1e-12), "Fz"))  # P (just inside the member's end)
    mass.append(KNOB_KG)
    Lr = float(np.linalg.norm(mem["rocker"][1] - mem["rocker"][0]))
    red = [("rocker", Lr * (1 - 1e-12), k) for k in ("Fz", "Mx", "My")]
    F = _hoeken_grillage_flexibility(d, el, end_r, pose, pts + red)
    na = len(pts)
    C = F[:na, :na] - F[:na, na:] @ np.linalg.solve(F[na:, na:], F[na:, :na])
    lam = np.linalg.eigvals(C @ np.diag(mass)).real.max()
    return float(C[-1, -1]), math.sqrt(1 / lam) / (2 * math.pi)


@pytest.fixture(scope="module")
def hoeken_device():
    """The device model at the middle crank angle, fem method, the knob at P (analyse level)."""
    return hoeken_device_at_mid_stroke()


def hoeken_device_at_mid_stroke():
    """(design, elastic, density, end radius, pose, device figures) of :func:`hoeken_device`."""
    from cad.kinematics.fourbar import solve
    from cad.structure import device

    d, el, rho, end_r = _hoeken()
    st = device.analyse(d, [device.Lumped("coupler", (d.linkage.le_mm, 0.0), KNOB_KG)], {}, "fem", poses=1)
    pose = solve(d.linkage, np.array([0.5 * (d.phi1_min_rad + d.phi1_max_rad)]))
    return d, el, rho, end_r, pose, st


def test_hoeken_handle_compliance_along_the_path_against_the_unit_load_method(hoeken_device):
    from cad.kinematics.metrics import path_frame

    d, el, rho, end_r, pose, st = hoeken_device
    ex = path_frame(d.linkage, d.phi1_min_rad, d.phi1_max_rad).x_hat
    hand = _hoeken_inplane_compliance_m_per_N(d, el, end_r, pose, np.asarray(ex, float)) * 1e6
    assert st["compliance_um_per_N"]["x"] == pytest.approx(hand, rel=STRUCTURE_PROOF_REL)


def test_hoeken_first_mode_and_z_compliance_against_the_force_method(hoeken_device):
    d, el, rho, end_r, pose, st = hoeken_device
    cz, f1 = _hoeken_out_of_plane(d, el, rho, end_r, pose)
    assert st["compliance_um_per_N"]["z"] == pytest.approx(cz * 1e6, rel=STRUCTURE_PROOF_REL)
    assert st["first_mode_Hz"] == pytest.approx(f1, rel=STRUCTURE_PROOF_REL)


# ------------------------------------------------ (b), (c) the 5-bar pantograph at home
def _pantograph_home():
    """The bundled 5-bar at home: joints (m), the tube's closed-form section, the device
    figures (analyse level, no build: the masses do not enter a compliance or a stress)."""
    from cad.design import load_design
    from cad.kinematics import fivebar as fb5
    from cad.structure import pantograph as sp
    from cad.structure.elastic import get_elastic

    d = load_design(ROOT / "designs" / "pantograph.toml")
    fb = d.mechanism
    home = np.asarray(d.workspace.get("home_mm", d.workspace["center_mm"]), float)
    ik = fb5.ik(fb, home[None, :])
    B = [np.asarray(fb.base_left_mm, float) * 1e-3, np.asarray(fb.base_right_mm, float) * 1e-3]
    C = [ik.C_left_mm[0] * 1e-3, ik.C_right_mm[0] * 1e-3]
    E = ik.E_mm[0] * 1e-3
    p = d.parts
    el = get_elastic(p.tube_material)
    D, di = p.tube_od_mm * 1e-3, p.tube_id_mm * 1e-3
    sec = {"A": math.pi * (D**2 - di**2) / 4, "I": math.pi * (D**4 - di**4) / 64, "c": D / 2, "E": el.E_Pa}
    st = sp.analyse(d, {}, float(d.actuators["force_max_N"]), sp.WEB_WIDTH_MIN_MM)
    return d, B, C, E, sec, st


@pytest.fixture(scope="module")
def pantograph_home():
    return _pantograph_home()


def _distal_forces(C, E, f):
    """Axial forces s_i (N, tension > 0) of the two distal links, two-force members pinned at
    C_i and E (motors held): F = s_L u_L + s_R u_R, u_i the unit vector C_i -> E."""
    U = np.array([(E - c) / np.linalg.norm(E - c) for c in C])
    return np.linalg.solve(U.T, f), U


def test_pantograph_home_compliance_two_chains_in_parallel(pantograph_home):
    """(b) Handle compliance at home, x and y: each arm a proximal cantilever (clamped at B,
    its tip free to turn: the pin at C; tip compliance L/EA along it, L^3 / (3 EI) across) in
    series with its distal link (pinned both ends: axial L/EA only); the two chains in
    parallel at E: K = sum_i u_i u_i^T / c_i, c_i = L_d / EA + u_i^T C_prox,i u_i (hand model
    of exactly the frame's Euler-Bernoulli mechanics: round-off agreement)."""
    d, B, C, E, sec, st = pantograph_home
    EA, EI = sec["E"] * sec["A"], sec["E"] * sec["I"]
    K = np.zeros((2, 2))
    for b, c in zip(B, C, strict=True):
        u = (E - c) / np.linalg.norm(E - c)
        Lp, Ld = float(np.linalg.norm(c - b)), float(np.linalg.norm(E - c))
        ep = (c - b) / Lp
        npp = np.array([-ep[1], ep[0]])
        Cp = Lp / EA * np.outer(ep, ep) + Lp**3 / (3 * EI) * np.outer(npp, npp)
        K += np.outer(u, u) / (Ld / EA + u @ Cp @ u)
    Ch = np.linalg.inv(K) * 1e6  # um/N
    home = st["per_pose"]["home"]["compliance_um_per_N"]
    assert home["x"] == pytest.approx(Ch[0, 0], rel=STRUCTURE_SAME_MODEL_REL)
    assert home["y"] == pytest.approx(Ch[1, 1], rel=STRUCTURE_SAME_MODEL_REL)
    assert st["compliance_um_per_N"]["x"] >= home["x"] and st["compliance_um_per_N"]["y"] >= home["y"]


def test_pantograph_home_stress_is_m_c_over_i_of_the_critical_link(pantograph_home):
    """(c) Peak stress at home under force_max_N in the worst in-plane direction (the same
    24 directions over 180 deg as the device model): distal links sigma = |s| / A; proximal
    links at B, where the moment is largest, sigma = M c / I + |N| / A with M = |(C - B) x
    s u| the moment of the distal force about the clamp (c = OD / 2, I = pi (D^4 - d^4) / 64)."""
    d, B, C, E, sec, st = pantograph_home
    F = float(d.actuators["force_max_N"])
    worst = 0.0
    for a in np.linspace(0.0, math.pi, 24, endpoint=False):
        s, U = _distal_forces(C, E, F * np.array([math.cos(a), math.sin(a)]))
        for b, c, si, u in zip(B, C, s, U, strict=True):
            ep = (c - b) / np.linalg.norm(c - b)
            M = abs(_cross(c - b, si * u))
            worst = max(worst, abs(si) / sec["A"], M * sec["c"] / sec["I"] + abs(si * u @ ep) / sec["A"])
    assert st["per_pose"]["home"]["max_stress_in_plane_MPa"] == pytest.approx(worst * 1e-6, rel=STRUCTURE_SAME_MODEL_REL)
    assert st["max_stress_MPa"] >= st["per_pose"]["home"]["max_stress_in_plane_MPa"]


def test_hoeken_beam_stress_is_m_c_over_i_at_the_critical_section(hoeken_device):
    """(c) The Hoeken's peak stress at force_N (``beam`` method: the pocket section over every
    member, as that method states) by hand at every member end, where the linear moment
    diagrams peak: along the path, rigid-link statics, sigma = |N| / A + |M| c_y / I_z; out of
    plane, the grillage's redundants at A4 by compatibility (:func:`_hoeken_grillage_flexibility`),
    sigma = |Mb| c_z / I_y, tau = |T| t / J (t the web, the thinner side), von Mises
    sqrt(sigma^2 + 3 tau^2)."""
    device_MPa, hand_MPa = hoeken_beam_stress_MPa(hoeken_device)
    assert device_MPa == pytest.approx(hand_MPa, rel=STRUCTURE_PROOF_REL)


def hoeken_beam_stress_MPa(hoeken_device) -> tuple[float, float]:
    """(device model, by hand) peak stress of the Hoeken at force_N, ``beam`` method (MPa): the
    computation of :func:`test_hoeken_beam_stress_is_m_c_over_i_at_the_critical_section`."""
    from cad.kinematics.metrics import path_frame
    from cad.structure import device

    d, el, rho, end_r, pose, _ = hoeken_device
    st = device.analyse(d, [device.Lumped("coupler", (d.linkage.le_mm, 0.0), KNOB_KG)], {}, "beam", poses=1)
    p = d.parts
    w, t, web = p.bar_width_mm * 1e-3, p.bar_thickness_mm * 1e-3, p.bar_pocket_web_mm * 1e-3
    wp = w - 2 * web
    A, Iz, Iy, Jt = (w - wp) * t, t * (w**3 - wp**3) / 12, (w - wp) * t**3 / 12, _j_pocket(p)
    mem, J = _hoeken_members(d, el, end_r, pose, beam=True)
    ends = {name: (0.0, float(np.linalg.norm(p1 - p0)) * (1 - 1e-9)) for name, (p0, p1, _) in mem.items()}
    # along the path: statics as in _hoeken_inplane_compliance_m_per_N
    f = np.asarray(path_frame(d.linkage, d.phi1_min_rad, d.phi1_max_rad).x_hat, float)
    u34 = (J["A3"] - J["A4"]) / np.linalg.norm(J["A3"] - J["A4"])
    tr = -_cross(J["P"] - J["A2"], f) / _cross(J["A3"] - J["A2"], u34)
    loads = {"coupler_3P": [(J["P"], f)], "coupler_23": [(J["P"], f), (J["A3"], tr * u34)],
             "crank": [(J["P"], f), (J["A3"], tr * u34)], "rocker": [(J["A4"], tr * u34)]}
    sig_x = 0.0
    for name, (p0, p1, _) in mem.items():
        e = (p1 - p0) / np.linalg.norm(p1 - p0)
        for s in ends[name]:
            x = p0 + s * e
            F = sum(fq for _, fq in loads[name])
            M = 0.0 if name == "rocker" else sum(_cross(q - x, fq) for q, fq in loads[name])
            sig_x = max(sig_x, abs(F @ e) / A + abs(M) * (w / 2) / Iz)
    # out of plane: unit z at P, redundants at A4
    pts = [("coupler_3P", ends["coupler_3P"][1] * (1 - 1e-6), "Fz")]
    red = [("rocker", ends["rocker"][1] * (1 + 1e-10), k) for k in ("Fz", "Mx", "My")]
    Fl = _hoeken_grillage_flexibility(d, el, end_r, pose, pts + red, beam=True)
    X = -np.linalg.solve(Fl[1:, 1:], Fl[1:, :1])[:, 0]
    sig_z = 0.0
    for name, (p0, p1, _) in mem.items():
        e = (p1 - p0) / np.linalg.norm(p1 - p0)
        for s in ends[name]:
            Mb, T = _unit_moments(mem, name, np.r_[p0 + s * e, 0.0], s, pts + red)
            mb, tq = Mb[0] + Mb[1:] @ X, T[0] + T[1:] @ X
            sig_z = max(sig_z, math.hypot(abs(mb) * (t / 2) / Iy, math.sqrt(3) * abs(tq) * min(web, t) / Jt))
    return float(st["max_stress_MPa"]), float(d.force_N) * max(sig_x, sig_z) * 1e-6
