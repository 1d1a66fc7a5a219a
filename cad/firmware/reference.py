"""hapticad's own numpy model of a :class:`~cad.firmware.spec.DeviceSpec`: the values the
generated C code is tested against (test vectors) -- built on :mod:`cad.kinematics`.

Every function is vectorized over N joint-angle rows ``q`` (N, n_joints) rad and returns
SI values in the device frame: ``forward`` -> (X (N, n_task) m [rad], status (N,)),
``jacobian`` -> dX/dq (N, n_task, n_joints), ``joint_torques`` -> tau (N, n_joints) N m for a
task force/wrench F (N, n_task), ``gravity_torques`` -> tau_g (N, n_joints) N m, the motor
torques that hold the device against gravity (= dV/dq), ``mass_matrix`` -> M (N, n_task,
n_task), the task-space mass matrix for feed-forward (kg; the twin's theta entries kg m and
kg m^2).
Status codes are those of the C code (:data:`STATUS`); rows that are not ok carry zeros.
"""

from __future__ import annotations

import numpy as np

from cad.kinematics import fivebar as fb5
from cad.kinematics import fourbar as k4
from cad.kinematics import twin_pantograph as tw

#: C status codes (HC_OK ...), shared by the generator and the reference.
#: The four moving links of a 5-bar (body names of report.json, prefixed knob_/crank_ in the twin).
FIVEBAR_LINKS = ("proximal_left", "proximal_right", "distal_left", "distal_right")
STATUS = {"HC_OK": 0, "HC_ERR_RANGE": 1, "HC_ERR_CLOSURE": 2, "HC_ERR_SINGULAR": 3,
          "HC_ERR_MODE": 4, "HC_ERR_CRANK": 5}


def fourbar_of(p: dict) -> k4.FourBar:
    """The :class:`~cad.kinematics.fourbar.FourBar` (mm) of the spec's ``params`` (m)."""
    return k4.FourBar(p["l1"] * 1e3, p["l2"] * 1e3, p["l3"] * 1e3, p["l4"] * 1e3, p["l5"] * 1e3,
                      p["le"] * 1e3, p["phi_e"], int(p["branch"]))


def fivebar_of(p: dict, pre: str = "") -> fb5.FiveBar:
    """The :class:`~cad.kinematics.fivebar.FiveBar` (mm) of the ``params`` with prefix ``pre``."""
    g = {k[len(pre):]: v for k, v in p.items() if k.startswith(pre)}
    return fb5.FiveBar((g["b1x"] * 1e3, g["b1y"] * 1e3), (g["b2x"] * 1e3, g["b2y"] * 1e3),
                       g["l2l"] * 1e3, g["l2r"] * 1e3, g["l3l"] * 1e3, g["l3r"] * 1e3)


def _perp(v):
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def _rot(a, c):
    ca, sa = np.cos(a), np.sin(a)
    return np.stack([ca * c[0] - sa * c[1], sa * c[0] + ca * c[1]], axis=-1)


# ------------------------------------------------------------------ four-bar
def _fourbar(spec, q):
    p = spec.params
    fb = fourbar_of(p)
    phi = q[:, 0]
    # the crank pose repeats every turn: range-checked in q_min - q_slack + [0, 2 pi), as the C
    # code; q_slack = half an encoder count (a reading at a range end rounds to within it)
    lo, hi = p["q_min"] - p["q_slack"], p["q_max"] + p["q_slack"]
    turnable = np.abs(phi) <= 1e4  # NaN, inf: refused
    ph = np.where(turnable, phi, p["q_min"])
    phi = np.where(turnable, ph - 2 * np.pi * np.floor((ph - lo) / (2 * np.pi)), np.nan)
    ok = (phi >= lo) & (phi <= hi)
    safe = np.where(ok, phi, 0.5 * (p["q_min"] + p["q_max"]))
    P, J = k4.coupler_point_and_jacobian(fb, safe)
    pose = k4.solve(fb, safe)
    a2, a3 = k4.velocity_ratios(fb, pose)
    return ok, P * 1e-3, J * 1e-3, pose, a2, a3


def _fourbar_com_rates(spec, q):
    """{body: (r_G (N,2) m, dr_G/dphi1 (N,2) m/rad)} of the crank, coupler and rocker."""
    ok, _, _, pose, a2, a3 = _fourbar(spec, q)
    b = spec.bodies
    rc = _rot(pose.phi1_rad, b["crank"].com_m)
    A2 = pose.A2_mm * 1e-3
    ru = _rot(pose.phi2_rad, b["coupler"].com_m)
    rr = _rot(pose.phi3_rad, b["rocker"].com_m)
    A4 = np.asarray(pose.A4_mm) * 1e-3
    return ok, {"crank": (rc, _perp(rc)),
                "coupler": (A2 + ru, _perp(A2) + _perp(ru) * a2[:, None]),
                "rocker": (A4 + rr, _perp(rr) * a3[:, None])}


# ------------------------------------------------------------------ five-bar
def working_modes(fb: fb5.FiveBar, pose: fb5.FiveBarPose) -> tuple[int, int, int]:
    """(assembly, left, right) of each pose at row 0: the FK assembly mode and the sign of
    cross(u(q_i), E - C_i) of each arm (the elbow modes)."""
    asm = int(fb5.assembly_mode(pose)[0])
    s = []
    for i, C in enumerate((pose.C_left_mm, pose.C_right_mm)):
        q = pose.q_rad[:, i]
        d = pose.E_mm - C
        s.append(np.sign(np.cos(q) * d[:, 1] - np.sin(q) * d[:, 0]))
    return asm, int(s[0][0]), int(s[1][0])


def _fivebar(p, q, pre=""):
    """(E (N,2) m, Jx = dE/dq (N,2,2) m/rad, status (N,)) of one 5-bar in the spec."""
    fb = fivebar_of(p, pre)
    pose = fb5.fk(fb, q, int(p[pre + "assembly"]))
    status = np.where(pose.status == fb5.STATUS_NO_CLOSURE, STATUS["HC_ERR_CLOSURE"],
                      np.where(pose.status != fb5.STATUS_OK, STATUS["HC_ERR_SINGULAR"], 0))
    for i, C in enumerate((pose.C_left_mm, pose.C_right_mm)):
        d = pose.E_mm - C
        s = np.sign(np.cos(q[:, i]) * d[:, 1] - np.sin(q[:, i]) * d[:, 0])
        status = np.where((status == 0) & (s != p[pre + ("mode_l", "mode_r")[i]]),
                          STATUS["HC_ERR_MODE"], status)
    ok = status == 0
    E = np.where(ok[:, None], pose.E_mm, 0.0)
    Jq, _ = fb5.jacobian_rad_per_m(fb, np.where(ok[:, None], E, pose.E_mm))
    Jx = np.zeros_like(Jq)
    Jx[ok] = np.linalg.inv(Jq[ok])
    return E * 1e-3, Jx, status, fb, E


def _fivebar_com_rates(spec, q, pre=""):
    """{body: (r_G (N,2), dr_G/dq (N,2,2))} of the four links of one 5-bar (cad.kinematics
    link_twist_maps: COM velocity per end-effector velocity, times dE/dq)."""
    E_m, Jx, status, fb, E = _fivebar(spec.params, q, pre)
    ok = status == 0
    b = spec.bodies
    mass = fb5.FiveBarMass(*(fb5.LinkMass(b[pre + n].mass_kg, b[pre + n].com_m) for n in
                             FIVEBAR_LINKS))
    out = {}
    n = len(q)
    if ok.any():
        maps = fb5.link_twist_maps(fb, E[ok], mass)
        pose = fb5.ik(fb, E[ok])
    for link in FIVEBAR_LINKS:
        r, dr = np.zeros((n, 2)), np.zeros((n, 2, 2))
        if ok.any():
            dr[ok] = maps[link][:, :2, :] @ Jx[ok]
            side = 0 if link.endswith("left") else 1
            if link.startswith("proximal"):
                B = np.array((fb.base_left_mm, fb.base_right_mm)[side]) * 1e-3
                r[ok] = B + _rot(pose.q_rad[:, side], b[pre + link].com_m)
            else:
                C = (pose.C_left_mm, pose.C_right_mm)[side]
                d = pose.E_mm - C
                r[ok] = C * 1e-3 + _rot(np.arctan2(d[:, 1], d[:, 0]), b[pre + link].com_m)
        out[pre + link] = (r, dr)
    return ok, E_m, Jx, status, out


# ------------------------------------------------------------------ twin pantograph
def _twin(spec, q):
    p = spec.params
    Pk, Jk, sk, _, _ = _fivebar(p, q[:, :2], "knob_")
    Pc, Jc, sc, _, _ = _fivebar(p, q[:, 2:], "crank_")
    status = np.where(sk != 0, sk, sc)
    d = Pc - Pk
    r = np.hypot(d[:, 0], d[:, 1])
    bad = (status == 0) & (np.abs(r - p["l6"]) > p["crank_tol"])
    status = np.where(bad, STATUS["HC_ERR_CRANK"], status)
    ok = status == 0
    X = np.zeros((len(q), 3))
    X[:, :2] = Pk
    X[:, 2] = np.arctan2(d[:, 1], d[:, 0])
    X[~ok] = 0.0
    J = np.zeros((len(q), 3, 4))
    J[:, :2, :2] = Jk
    r2 = np.where(ok, r * r, 1.0)
    J[:, 2, :2] = -(d[:, 0, None] * Jk[:, 1, :] - d[:, 1, None] * Jk[:, 0, :]) / r2[:, None]
    J[:, 2, 2:] = (d[:, 0, None] * Jc[:, 1, :] - d[:, 1, None] * Jc[:, 0, :]) / r2[:, None]
    J[~ok] = 0.0
    return X, J, status


def twin_of(p: dict) -> tw.TwinPantograph:
    return tw.TwinPantograph(fivebar_of(p, "knob_"), fivebar_of(p, "crank_"), p["l6"] * 1e3)


def twin_task_jacobian(spec, q) -> np.ndarray:
    """q_dot = Jq X_dot (N, 4, 3) (isotropy paper eq 1) at joint angles q (N, 4): the rows of
    each pantograph at its own FK point (knob: the main journal, crank: the crank pin) and
    the theta column l6 (-sin theta, cos theta) through the crank rows
    (:func:`cad.kinematics.twin_pantograph.jacobian_arrays` at a consistent pose)."""
    p = spec.params
    X, _, _ = _twin(spec, q)
    Pk, _, _, _, _ = _fivebar(p, q[:, :2], "knob_")
    Pc, _, _, _, _ = _fivebar(p, q[:, 2:], "crank_")
    Jk, _ = fb5.jacobian_rad_per_m(fivebar_of(p, "knob_"), Pk * 1e3)
    Jc, _ = fb5.jacobian_rad_per_m(fivebar_of(p, "crank_"), Pc * 1e3)
    J = np.zeros((len(q), 4, 3))
    J[:, :2, :2] = Jk
    J[:, 2:, :2] = Jc
    J[:, 2:, 2] = p["l6"] * (Jc[:, :, 0] * -np.sin(X[:, 2])[:, None]
                             + Jc[:, :, 1] * np.cos(X[:, 2])[:, None])
    return J


# ------------------------------------------------------------------ public
def forward(spec, q) -> tuple[np.ndarray, np.ndarray]:
    q = np.atleast_2d(np.asarray(q, dtype=float))
    if spec.kind == "fourbar":
        ok, P, *_ = _fourbar(spec, q)
        return np.where(ok[:, None], P, 0.0), np.where(ok, 0, STATUS["HC_ERR_RANGE"])
    if spec.kind == "fivebar":
        E, _, status, _, _ = _fivebar(spec.params, q)
        return E, status
    X, _, status = _twin(spec, q)
    return X, status


def jacobian(spec, q) -> np.ndarray:
    q = np.atleast_2d(np.asarray(q, dtype=float))
    if spec.kind == "fourbar":
        ok, _, J, *_ = _fourbar(spec, q)
        return np.where(ok[:, None], J, 0.0)[:, :, None]
    if spec.kind == "fivebar":
        return _fivebar(spec.params, q)[1]
    return _twin(spec, q)[1]


def joint_torques(spec, q, F) -> np.ndarray:
    """tau = J^T F; the twin pantograph: the least-norm tau with Jq^T tau = F (Jq: q_dot =
    Jq X_dot), the same as tau = J^T F with J = pinv(Jq)."""
    q = np.atleast_2d(np.asarray(q, dtype=float))
    F = np.atleast_2d(np.asarray(F, dtype=float))
    if spec.kind != "twin":
        return np.einsum("nij,ni->nj", jacobian(spec, q), F)
    X, _, status = _twin(spec, q)
    ok = status == 0
    tau = np.zeros((len(q), 4))
    if ok.any():
        Jq = twin_task_jacobian(spec, q[ok])
        tau[ok] = np.einsum("nij,nj->ni", np.linalg.pinv(np.swapaxes(Jq, 1, 2)), F[ok])
    return tau


def com_rates(spec, q):
    """(ok (N,), {body: (r_G (N,2) m, dr_G/dq (N,2,n) m/rad)}) of the bodies whose COM moves
    with the joints only (the twin's crankshaft, a function of X, is left out)."""
    q = np.atleast_2d(np.asarray(q, dtype=float))
    if spec.kind == "fourbar":
        ok, rates = _fourbar_com_rates(spec, q)
        return ok, {k: (r, d[:, :, None]) for k, (r, d) in rates.items()}
    if spec.kind == "fivebar":
        ok, _, Jx, _, rates = _fivebar_com_rates(spec, q)
        if "handle" in spec.bodies:
            E = forward(spec, q)[0]
            rates["handle"] = (E + np.asarray(spec.bodies["handle"].com_m), Jx)
        return ok, rates
    ok1, _, _, _, a = _fivebar_com_rates(spec, q[:, :2], "knob_")
    ok2, _, _, _, b = _fivebar_com_rates(spec, q[:, 2:], "crank_")
    out = {k: (r, np.concatenate([d, np.zeros_like(d)], axis=2)) for k, (r, d) in a.items()}
    out.update({k: (r, np.concatenate([np.zeros_like(d), d], axis=2)) for k, (r, d) in b.items()})
    return ok1 & ok2, out


def gravity_torques(spec, q) -> np.ndarray:
    """Motor torques that hold the device against gravity, dV/dq (N, n_joints) N m (zeros for
    a horizontal device). The twin's crankshaft weight is rendered as a task wrench by the
    least-norm torques (:func:`joint_torques`)."""
    q = np.atleast_2d(np.asarray(q, dtype=float))
    tau = np.zeros((len(q), spec.n_joints))
    if spec.gravity_m_s2 is None:
        return tau
    g = np.asarray(spec.gravity_m_s2)
    ok, rates = com_rates(spec, q)
    for name, (_, dr) in rates.items():
        tau -= spec.bodies[name].mass_kg * np.einsum("i,nij->nj", g, dr)
    if spec.kind == "twin":
        X, status = forward(spec, q)
        cs = spec.bodies["crankshaft"]
        rc = _rot(X[:, 2], cs.com_m)
        W = np.zeros((len(q), 3))
        W[:, :2] = -cs.mass_kg * g
        W[:, 2] = -cs.mass_kg * (_perp(rc) @ g)
        tau += joint_torques(spec, q, W)
        ok &= status == 0
    return np.where(ok[:, None], tau, 0.0)


def _fivebar_mass(spec, pre=""):
    b, jm = spec.bodies, spec.rotor_kg_m2
    links = [fb5.LinkMass(b[pre + n].mass_kg, b[pre + n].com_m, b[pre + n].izz_kg_m2) for n in
             FIVEBAR_LINKS]
    return fb5.FiveBarMass(*links, jm)


def mass_matrix(spec, q) -> np.ndarray:
    """Task mass matrix at the ok rows of ``q`` (zeros elsewhere): four-bar M = J+^T D J+
    (Hoeken paper eq 22, :func:`cad.dynamics.inertia.apparent_mass_matrix`, R0 axes);
    5-bar :func:`cad.kinematics.fivebar.mass_matrix_kg` with the rotors plus the handle
    (translating with E); twin :func:`cad.kinematics.twin_pantograph.task_mass_matrix`."""
    from cad.dynamics.inertia import InertiaCoefficients, apparent_mass_matrix

    q = np.atleast_2d(np.asarray(q, dtype=float))
    X, status = forward(spec, q)
    ok = status == 0
    M = np.zeros((len(q), spec.n_task, spec.n_task))
    if not ok.any():
        return M
    p = spec.params
    if spec.kind == "fourbar":
        fb = fourbar_of(p)
        H = InertiaCoefficients(p["H11"], p["H12"], p["H22"], p["H33"], p["beta2"])
        M[ok] = apparent_mass_matrix(fb, k4.solve(fb, q[ok, 0]), H)
    elif spec.kind == "fivebar":
        M[ok] = fb5.mass_matrix_kg(fivebar_of(p), X[ok] * 1e3, _fivebar_mass(spec))
        if "handle" in spec.bodies:
            M[ok] += spec.bodies["handle"].mass_kg * np.eye(2)
    else:
        cs = spec.bodies["crankshaft"]
        mass = tw.TwinMass(_fivebar_mass(spec, "knob_"), _fivebar_mass(spec, "crank_"),
                           fb5.LinkMass(cs.mass_kg, cs.com_m, cs.izz_kg_m2))
        Xmm = np.column_stack([X[ok, :2] * 1e3, X[ok, 2]])
        M[ok] = tw.task_mass_matrix(twin_of(p), Xmm, mass)
    return M
