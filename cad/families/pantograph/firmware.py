"""The pantographs' kinematic models for the generated firmware
(:class:`cad.firmware.model.KinematicModel`): the plain 5-bar (:data:`FIVEBAR`: the closed
form in the design's working modes) and the twin-pantograph haptic mouse (:data:`TWIN`: two
5-bars and the crank throw, isotropy paper eq 1), their C code and test poses; and the
family's firmware hook :func:`files`. Numpy only (no CAD import)."""

from __future__ import annotations

import math

import numpy as np

from cad import tolerances as tol
from cad.design import bounds
from cad.errors import DesignError
from cad.firmware import identify2_c
from cad.firmware.csrc import JT_F, lit
from cad.firmware.model import KinematicModel, SpecParams, perp, rot
from cad.firmware.reference import STATUS
from cad.firmware.spec import body_from_report
from cad.isotropy.gii import workspace_half_mm
from cad.kinematics import fivebar as fb5
from cad.kinematics import pantograph_tolerances as ptol
from cad.kinematics import twin_pantograph as tw
from cad.sim import identify_fivebar
from cad.sim.identify_kits import FIVEBAR as FIVEBAR_KIT

#: The four moving links of a 5-bar (body names of report.json, prefixed knob_/crank_ in the twin).
FIVEBAR_LINKS = ("proximal_left", "proximal_right", "distal_left", "distal_right")


# ------------------------------------------------------------------ five-bar
def fivebar_of(p: dict, pre: str = "") -> fb5.FiveBar:
    """The :class:`~cad.kinematics.fivebar.FiveBar` (mm) of the ``params`` with prefix ``pre``."""
    g = {k[len(pre):]: v for k, v in p.items() if k.startswith(pre)}
    return fb5.FiveBar((g["b1x"] * 1e3, g["b1y"] * 1e3), (g["b2x"] * 1e3, g["b2y"] * 1e3),
                       g["l2l"] * 1e3, g["l2r"] * 1e3, g["l3l"] * 1e3, g["l3r"] * 1e3)


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


def state(p, q, pre=""):
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


def link_com_rates(spec, q, pre=""):
    """{body: (r_G (N,2), dr_G/dq (N,2,2))} of the four links of one 5-bar (cad.kinematics
    link_twist_maps: COM velocity per end-effector velocity, times dE/dq)."""
    E_m, Jx, status, fb, E = state(spec.params, q, pre)
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
                r[ok] = B + rot(pose.q_rad[:, side], b[pre + link].com_m)
            else:
                C = (pose.C_left_mm, pose.C_right_mm)[side]
                d = pose.E_mm - C
                r[ok] = C * 1e-3 + rot(np.arctan2(d[:, 1], d[:, 0]), b[pre + link].com_m)
        out[pre + link] = (r, dr)
    return ok, E_m, Jx, status, out


#: First joint of each 5-bar of a device in the joint order (the twin: knob q0 q1, crank q2 q3).
_FIRST_JOINT = {"": 0, "knob_": 0, "crank_": 2}


def rotor_pair(spec, pre: str = "") -> tuple[float, float]:
    """(left, right) rotor inertia at the joints of the 5-bar ``pre`` (kg m^2): each motor's
    through its transmission (``spec.rotor_joints_kg_m2``, n^2 (J_m + J_capstan)), else the
    motor's own ``spec.rotor_kg_m2`` on both."""
    if not spec.rotor_joints_kg_m2:
        return (spec.rotor_kg_m2, spec.rotor_kg_m2)
    i = _FIRST_JOINT[pre]
    return tuple(float(v) for v in spec.rotor_joints_kg_m2[i:i + 2])


def link_masses(spec, pre=""):
    b, jm = spec.bodies, rotor_pair(spec, pre)
    links = [fb5.LinkMass(b[pre + n].mass_kg, b[pre + n].com_m, b[pre + n].izz_kg_m2) for n in
             FIVEBAR_LINKS]
    return fb5.FiveBarMass(*links, jm)


def fivebar_params(fb: fb5.FiveBar, home_mm, pre: str = "") -> tuple[dict, np.ndarray]:
    """SI parameters of one 5-bar with the working modes of its pose at ``home_mm``."""
    ik = fb5.ik(fb, np.asarray(home_mm, dtype=float)[None, :])
    fb5.require_ok(ik)
    pose = fb5.fk(fb, ik.q_rad, int(fb5.assembly_mode(ik)[0]))
    asm, ml, mr = working_modes(fb, pose)
    p = {"b1x": fb.base_left_mm[0], "b1y": fb.base_left_mm[1], "b2x": fb.base_right_mm[0],
         "b2y": fb.base_right_mm[1], "l2l": fb.proximal_left_mm, "l2r": fb.proximal_right_mm,
         "l3l": fb.distal_left_mm, "l3r": fb.distal_right_mm}
    out = {pre + k: v * 1e-3 for k, v in p.items()}
    out.update({pre + "assembly": float(asm), pre + "mode_l": float(ml), pre + "mode_r": float(mr)})
    return out, ik.q_rad[0]


def fivebar_forward(spec, q):
    """(E (N, 2) m, status (N,))."""
    E, _, status, _, _ = state(spec.params, q)
    return E, status


def fivebar_jacobian(spec, q) -> np.ndarray:
    """dE/dq (N, 2, 2) m/rad."""
    return state(spec.params, q)[1]


def fivebar_com_rates(spec, q):
    """(ok, rates) of the four links, plus the handle (translating with E) when built."""
    ok, _, Jx, _, rates = link_com_rates(spec, q)
    if "handle" in spec.bodies:
        E = fivebar_forward(spec, q)[0]
        rates["handle"] = (E + np.asarray(spec.bodies["handle"].com_m), Jx)
    return ok, rates


def fivebar_mass_matrix(spec, q_ok, X_ok) -> np.ndarray:
    """:func:`cad.kinematics.fivebar.mass_matrix_kg` with the rotors, plus the handle."""
    M = fb5.mass_matrix_kg(fivebar_of(spec.params), X_ok * 1e3, link_masses(spec))
    if "handle" in spec.bodies:
        M += spec.bodies["handle"].mass_kg * np.eye(2)
    return M


def fivebar_spec_params(design, report: dict, device) -> SpecParams:
    """The 5-bar's lengths and working modes at home, its bodies from report.json."""
    bodies = {k: body_from_report(v) for k, v in report["bodies"].items()}
    params, q = fivebar_params(design.mechanism, _home_mm(design))
    return SpecParams(params, tuple(float(v) for v in q), bodies, 2, 2)


def _home_mm(design):
    return design.workspace.get("home_mm", design.workspace["center_mm"])


def _workspace_points(design, rng, n: int) -> np.ndarray:
    ws = design.workspace
    (cx, cy), (hx, hy) = ws["center_mm"], workspace_half_mm(ws)
    return np.column_stack([rng.uniform(cx - hx, cx + hx, n), rng.uniform(cy - hy, cy + hy, n)])


def fivebar_poses_ok(spec, design, rng, n: int) -> np.ndarray:
    """IK of ``n`` points uniform over the workspace rectangle (the reachable ones)."""
    ik = fb5.ik(fivebar_of(spec.params), _workspace_points(design, rng, n))
    return ik.q_rad[ik.ok]


def _folded(q_ok, rng, n: int) -> tuple[np.ndarray, int]:
    q = q_ok[rng.integers(0, len(q_ok), n)].copy()
    third = n // 3
    q[:third, 0] += math.pi  # left arm folded back: no closure or the other mode
    q[third:2 * third, 1] -= rng.uniform(2.0, 3.0, third)  # arms crossed
    return q, third


def fivebar_poses_bad(spec, q_ok, rng, n: int) -> np.ndarray:
    """Poses with an arm folded back, arms crossed, both arms turned off the working modes."""
    q, third = _folded(q_ok, rng, n)
    q[2 * third:, :] += np.array([0.9, -0.9])
    return q


def fivebar_identify_files(design, report: dict, spec) -> dict[str, str]:
    """The 2-motor identification routine (:mod:`cad.firmware.identify2_c`), its constants from
    the same plan as the virtual bench (:func:`cad.sim.identify_fivebar.predict`); none, with a
    warning, for a vertical device whose weight takes the motors' continuous current."""
    try:
        pred = identify_fivebar.predict(design, report)
    except DesignError as exc:  # a vertical device too heavy to excite: the rest is written
        bounds.warn(f"firmware: no identify/ routine: {exc}")
        return {}
    return identify2_c.files(spec, pred.plan)


def workspace_radius_m(spec, design) -> float:
    """Radius of the largest circle inside the workspace (CHAI3D ``cHapticDeviceInfo::
    m_workspaceRadius``, src/devices/CGenericHapticDevice.h): half the shorter side, m."""
    return min(workspace_half_mm(design.workspace)) * 1e-3


# ------------------------------------------------------------------ twin pantograph
def twin_state(spec, q):
    """(X (N,3), J (N,3,4), status (N,)) of the twin: both 5-bars and the crank throw."""
    p = spec.params
    Pk, Jk, sk, _, _ = state(p, q[:, :2], "knob_")
    Pc, Jc, sc, _, _ = state(p, q[:, 2:], "crank_")
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
    X, _, _ = twin_state(spec, q)
    Pk, _, _, _, _ = state(p, q[:, :2], "knob_")
    Pc, _, _, _, _ = state(p, q[:, 2:], "crank_")
    Jk, _ = fb5.jacobian_rad_per_m(fivebar_of(p, "knob_"), Pk * 1e3)
    Jc, _ = fb5.jacobian_rad_per_m(fivebar_of(p, "crank_"), Pc * 1e3)
    J = np.zeros((len(q), 4, 3))
    J[:, :2, :2] = Jk
    J[:, 2:, :2] = Jc
    J[:, 2:, 2] = p["l6"] * (Jc[:, :, 0] * -np.sin(X[:, 2])[:, None]
                             + Jc[:, :, 1] * np.cos(X[:, 2])[:, None])
    return J


def twin_forward(spec, q):
    """(X (N, 3): main journal m, crank angle rad; status (N,))."""
    X, _, status = twin_state(spec, q)
    return X, status


def twin_jacobian(spec, q) -> np.ndarray:
    """dX/dq (N, 3, 4)."""
    return twin_state(spec, q)[1]


def twin_joint_torques(spec, q, F) -> np.ndarray:
    """The least-norm tau with Jq^T tau = F (Jq: q_dot = Jq X_dot), the same as tau = J^T F
    with J = pinv(Jq)."""
    _, _, status = twin_state(spec, q)
    ok = status == 0
    tau = np.zeros((len(q), 4))
    if ok.any():
        Jq = twin_task_jacobian(spec, q[ok])
        tau[ok] = np.einsum("nij,nj->ni", np.linalg.pinv(np.swapaxes(Jq, 1, 2)), F[ok])
    return tau


def twin_com_rates(spec, q):
    """(ok, rates) of the eight links (the crankshaft, a function of X, is left out)."""
    ok1, _, _, _, a = link_com_rates(spec, q[:, :2], "knob_")
    ok2, _, _, _, b = link_com_rates(spec, q[:, 2:], "crank_")
    out = {k: (r, np.concatenate([d, np.zeros_like(d)], axis=2)) for k, (r, d) in a.items()}
    out.update({k: (r, np.concatenate([np.zeros_like(d), d], axis=2)) for k, (r, d) in b.items()})
    return ok1 & ok2, out


def twin_gravity_extra(spec, q, g):
    """The crankshaft's weight rendered as a task wrench by the least-norm torques."""
    X, status = twin_forward(spec, q)
    cs = spec.bodies["crankshaft"]
    rc = rot(X[:, 2], cs.com_m)
    W = np.zeros((len(q), 3))
    W[:, :2] = -cs.mass_kg * g
    W[:, 2] = -cs.mass_kg * (perp(rc) @ g)
    return twin_joint_torques(spec, q, W), status == 0


def twin_mass_matrix(spec, q_ok, X_ok) -> np.ndarray:
    """:func:`cad.kinematics.twin_pantograph.task_mass_matrix` (kg; theta entries kg m, kg m^2)."""
    cs = spec.bodies["crankshaft"]
    mass = tw.TwinMass(link_masses(spec, "knob_"), link_masses(spec, "crank_"),
                       fb5.LinkMass(cs.mass_kg, cs.com_m, cs.izz_kg_m2))
    Xmm = np.column_stack([X_ok[:, :2] * 1e3, X_ok[:, 2]])
    return tw.task_mass_matrix(twin_of(spec.params), Xmm, mass)


def twin_spec_params(design, report: dict, device) -> SpecParams:
    """Both 5-bars' lengths and working modes at home, the crank throw and its tolerance."""
    bodies = {k: body_from_report(v) for k, v in report["bodies"].items()}
    tp, home = design.mechanism, _home_mm(design)
    th = math.radians(design.workspace["home_theta_deg"])
    pin = np.asarray(home) + tp.crank_mm * np.array([math.cos(th), math.sin(th)])
    params, qk = fivebar_params(tp.knob, home, "knob_")
    pc, qc = fivebar_params(tp.crank, pin, "crank_")
    params.update(pc, l6=tp.crank_mm * 1e-3, crank_tol=tol.FIRMWARE_CRANK_TOL_M)
    return SpecParams(params, tuple(float(v) for v in np.concatenate([qk, qc])), bodies, 4, 3)


def twin_poses_ok(spec, design, rng, n: int) -> np.ndarray:
    """IK of ``n`` workspace points at crank angles over the full turn (the reachable ones)."""
    X = np.column_stack([_workspace_points(design, rng, n), rng.uniform(0.0, 2 * math.pi, n)])
    ik = tw.ik(twin_of(spec.params), X)
    return ik.q_rad[ik.status == 0]


def twin_poses_bad(spec, q_ok, rng, n: int) -> np.ndarray:
    """As the 5-bar's, and a crank pin off its circle; a perturbed reading the FK still
    accepts (within FIRMWARE_CRANK_TOL_M) is no task pose of the model: left out."""
    q, third = _folded(q_ok, rng, n)
    q[2 * third:, 2] += rng.uniform(0.05, 0.2, n - 2 * third)  # crank pin off its circle
    return q[twin_forward(spec, q)[1] != 0]


def twin_force_jacobian(spec, q) -> np.ndarray:
    """pinv(Jq) translational rows (N, 2, 4)."""
    return np.linalg.pinv(twin_task_jacobian(spec, q))[:, :2, :]


# ------------------------------------------------------------------ C code
def c_params(spec, pre: str, cname: str) -> str:
    p = spec.params
    keys = ("b1x", "b1y", "b2x", "b2y", "l2l", "l2r", "l3l", "l3r", "assembly", "mode_l", "mode_r")
    vals = ", ".join(lit(p[pre + k]) for k in keys)
    mass = ", ".join(
        f"{lit(spec.bodies[pre + n].mass_kg)}, {lit(spec.bodies[pre + n].com_m[0])}, "
        f"{lit(spec.bodies[pre + n].com_m[1])}, {lit(spec.bodies[pre + n].izz_kg_m2)}"
        for n in FIVEBAR_LINKS)
    return (f"static const hc5_t {cname} = {{ {vals} }};\n"
            f"/* mass (kg), COM (m, link frame) and Izz about the COM (kg m^2) of proximal L, R,\n"
            f" * distal L, R */\n"
            f"static const hc_real {cname}_MASS[16] = {{ {mass} }};\n")


_FIVEBAR = """
/* one 5-bar: B1, B2 (m), proximal l2, distal l3 (m), FK assembly mode and the elbow modes
 * (sign of cross(u(q_i), E - C_i)) of the design's working pose */
typedef struct { hc_real b1x, b1y, b2x, b2y, l2l, l2r, l3l, l3r, asm_, mode_l, mode_r; } hc5_t;
typedef struct { hc_real c1x, c1y, c2x, c2y, ex, ey, den1, den2; hc_real Jx[4]; } hc5_pose_t;

#define ARM_SINGULAR_SIN @ARM@
#define DISTAL_SINGULAR_SIN @DIST@
#define REACH_REL_EPS @REACH@
#define ON_JOINT_M @ONJ@

static hc_real hc_sign(hc_real v) { return v > HC_R(0.0) ? HC_R(1.0) : (v < HC_R(0.0) ? HC_R(-1.0) : HC_R(0.0)); }

/* closed-form FK (two circles through the elbows) and dE/dq; isotropy paper eq 1 */
static int hc5_pose(const hc5_t *k, hc_real q1, hc_real q2, hc5_pose_t *p)
{
    hc_real vx, vy, d, a, h, ux, uy, d1x, d1y, d2x, d2y, s1, s2, s12, det;
    hc_real cq1 = HC_COS(q1), sq1 = HC_SIN(q1), cq2 = HC_COS(q2), sq2 = HC_SIN(q2);
    if (!(q1 == q1 && q2 == q2)) return HC_ERR_RANGE;  /* NaN */
    p->c1x = k->b1x + k->l2l * cq1; p->c1y = k->b1y + k->l2l * sq1;
    p->c2x = k->b2x + k->l2r * cq2; p->c2y = k->b2y + k->l2r * sq2;
    vx = p->c2x - p->c1x; vy = p->c2y - p->c1y;
    d = HC_SQRT(vx * vx + vy * vy);
    if (d > (k->l3l + k->l3r) * (HC_R(1.0) + REACH_REL_EPS) || d <= ON_JOINT_M
        || d < HC_FABS(k->l3l - k->l3r) * (HC_R(1.0) - REACH_REL_EPS)) return HC_ERR_CLOSURE;
    a = (k->l3l * k->l3l - k->l3r * k->l3r + d * d) / (HC_R(2.0) * d);
    h = k->l3l * k->l3l - a * a;
    h = h > HC_R(0.0) ? HC_SQRT(h) : HC_R(0.0);
    ux = vx / d; uy = vy / d;
    p->ex = p->c1x + a * ux - k->asm_ * h * uy;
    p->ey = p->c1y + a * uy + k->asm_ * h * ux;
    d1x = p->ex - p->c1x; d1y = p->ey - p->c1y; d2x = p->ex - p->c2x; d2y = p->ey - p->c2y;
    s1 = (cq1 * d1y - sq1 * d1x) / k->l3l;
    s2 = (cq2 * d2y - sq2 * d2x) / k->l3r;
    s12 = (d1x * d2y - d1y * d2x) / (k->l3l * k->l3r);
    if (HC_FABS(s1) < ARM_SINGULAR_SIN || HC_FABS(s2) < ARM_SINGULAR_SIN
        || HC_FABS(s12) < DISTAL_SINGULAR_SIN) return HC_ERR_SINGULAR;
    if (hc_sign(s1) != k->mode_l || hc_sign(s2) != k->mode_r) return HC_ERR_MODE;
    /* q_dot = Jq E_dot with rows (E - C_i)^T / den_i; dE/dq = Jq^-1 */
    p->den1 = k->l2l * k->l3l * s1; p->den2 = k->l2r * k->l3r * s2;
    det = (d1x * d2y - d1y * d2x) / (p->den1 * p->den2);
    p->Jx[0] = d2y / p->den2 / det; p->Jx[1] = -d1y / p->den1 / det;
    p->Jx[2] = -d2x / p->den2 / det; p->Jx[3] = d1x / p->den1 / det;
    return HC_OK;
}

/* dV/dq of the four links of one 5-bar (g in m/s^2), added to tau[0..1] */
static void hc5_gravity(const hc5_t *k, const hc_real *mass, const hc5_pose_t *p,
                        hc_real q1, hc_real q2, hc_real gx, hc_real gy, hc_real tau[2])
{
    hc_real q[2], l2[2], l3[2], cx[2], cy[2];
    int i, j;
    q[0] = q1; q[1] = q2; l2[0] = k->l2l; l2[1] = k->l2r; l3[0] = k->l3l; l3[1] = k->l3r;
    cx[0] = p->c1x; cy[0] = p->c1y; cx[1] = p->c2x; cy[1] = p->c2y;
    for (i = 0; i < 2; ++i) {
        hc_real cq = HC_COS(q[i]), sq = HC_SIN(q[i]);
        const hc_real *pm = mass + 4 * i, *dm = mass + 4 * (i + 2);
        /* proximal i: r = B_i + R(q_i) c, dr/dq_i = perp(R(q_i) c) */
        hc_real rx = cq * pm[1] - sq * pm[2], ry = sq * pm[1] + cq * pm[2];
        /* distal i: r = C_i + R(psi_i) c, R(psi_i) = [d, perp(d)] / l3 */
        hc_real dx = p->ex - cx[i], dy = p->ey - cy[i];
        hc_real wx = (dx * dm[1] - dy * dm[2]) / l3[i], wy = (dy * dm[1] + dx * dm[2]) / l3[i];
        tau[i] -= pm[0] * (gx * -ry + gy * rx);
        for (j = 0; j < 2; ++j) {
            hc_real dcx = (i == j) ? -l2[i] * sq : HC_R(0.0);
            hc_real dcy = (i == j) ? l2[i] * cq : HC_R(0.0);
            hc_real ex = p->Jx[j] - dcx, ey = p->Jx[2 + j] - dcy;   /* dE/dq_j - dC_i/dq_j */
            hc_real dpsi = (dx * ey - dy * ex) / (l3[i] * l3[i]);
            tau[j] -= dm[0] * (gx * (dcx - wy * dpsi) + gy * (dcy + wx * dpsi));
        }
    }
}

/* task mass matrix of one 5-bar (kg, 2x2 row-major), rotors jm included: the kinetic energy
 * of each link, v_G = A_v E_dot, omega = A_w E_dot (cad.kinematics.fivebar.link_twist_maps) */
static void hc5_mass(const hc5_t *k, const hc_real *mass, const hc_real jm[2], const hc5_pose_t *p,
                     hc_real q1, hc_real q2, hc_real M[4])
{
    hc_real q[2], l2[2], l3[2], cx[2], cy[2], den[2];
    int i, a, b;
    q[0] = q1; q[1] = q2; l2[0] = k->l2l; l2[1] = k->l2r; l3[0] = k->l3l; l3[1] = k->l3r;
    cx[0] = p->c1x; cy[0] = p->c1y; cx[1] = p->c2x; cy[1] = p->c2y; den[0] = p->den1; den[1] = p->den2;
    for (i = 0; i < 4; ++i) M[i] = HC_R(0.0);
    for (i = 0; i < 2; ++i) {
        hc_real cq = HC_COS(q[i]), sq = HC_SIN(q[i]);
        const hc_real *pm = mass + 4 * i, *dm = mass + 4 * (i + 2);
        hc_real dx = p->ex - cx[i], dy = p->ey - cy[i];
        hc_real r[2], Av[4], Aw[2], wx, wy, c2;
        r[0] = dx / den[i]; r[1] = dy / den[i];                 /* q_dot_i = r . E_dot */
        c2 = pm[1] * pm[1] + pm[2] * pm[2];                      /* proximal: |v_G| = |c| q_dot */
        for (a = 0; a < 2; ++a)
            for (b = 0; b < 2; ++b) M[2 * a + b] += (pm[0] * c2 + pm[3] + jm[i]) * r[a] * r[b];
        /* distal: C_dot = l2 perp(u) q_dot_i, psi_dot = n^T (E_dot - C_dot) / l3^2, n = perp(d) */
        for (a = 0; a < 2; ++a) {
            hc_real cdx = -l2[i] * sq * r[a], cdy = l2[i] * cq * r[a];   /* column a of C_dot */
            hc_real ex = (a == 0 ? HC_R(1.0) : HC_R(0.0)) - cdx, ey = (a == 1 ? HC_R(1.0) : HC_R(0.0)) - cdy;
            Aw[a] = (-dy * ex + dx * ey) / (l3[i] * l3[i]);
            Av[a] = cdx; Av[2 + a] = cdy;
        }
        wx = (dx * dm[1] - dy * dm[2]) / l3[i]; wy = (dy * dm[1] + dx * dm[2]) / l3[i];
        for (a = 0; a < 2; ++a) { Av[a] += -wy * Aw[a]; Av[2 + a] += wx * Aw[a]; }
        for (a = 0; a < 2; ++a)
            for (b = 0; b < 2; ++b)
                M[2 * a + b] += dm[0] * (Av[a] * Av[b] + Av[2 + a] * Av[2 + b]) + dm[3] * Aw[a] * Aw[b];
    }
}
"""


#: The pantograph families have a mass matrix (hc_mass_matrix), no scalar apparent mass:
#: hc_apparent_mass refuses every pose there.
_NO_APPARENT_MASS = """
int hc_apparent_mass(const hc_real q[HC_N_JOINTS], hc_real *mass_kg)
{
    (void)q; (void)mass_kg;
    return HC_ERR_RANGE; /* a pantograph's mass is a matrix: hc_mass_matrix */
}
"""



def c_common() -> str:
    return (_FIVEBAR.replace("@ARM@", lit(ptol.ARM_SINGULAR_SIN))
            .replace("@DIST@", lit(ptol.DISTAL_SINGULAR_SIN))
            .replace("@REACH@", lit(ptol.REACH_REL_EPS))
            .replace("@ONJ@", lit(ptol.ON_JOINT_MM * 1e-3)))


def c_plain(spec) -> str:
    """The 5-bar's part of hapticad_device.c."""
    g = spec.gravity_m_s2 or (0.0, 0.0)
    h = spec.bodies.get("handle")
    hm, hx, hy = (h.mass_kg, *h.com_m) if h is not None else (0.0, 0.0, 0.0)
    return c_common() + c_params(spec, "", "K5") + f"""
#define GX {lit(g[0])}
#define GY {lit(g[1])}
#define M_HANDLE {lit(hm)}   /* the handle translates with E */
#define JM {lit(spec.rotor_kg_m2)}         /* rotor inertia of each motor (kg m^2) */
{_jm_line(spec, "JM2", "")}""" + """
int hc_forward(const hc_real q[2], hc_real X[2])
{
    hc5_pose_t p;
    int st = hc5_pose(&K5, q[0], q[1], &p);
    if (st) return st;
    X[0] = p.ex; X[1] = p.ey;
    return HC_OK;
}

int hc_jacobian(const hc_real q[2], hc_real J[4])
{
    hc5_pose_t p;
    int i, st = hc5_pose(&K5, q[0], q[1], &p);
    if (st) return st;
    for (i = 0; i < 4; ++i) J[i] = p.Jx[i];
    return HC_OK;
}

""" + JT_F + """
int hc_gravity_torques(const hc_real q[2], hc_real tau[2])
{
    hc5_pose_t p;
    int st = hc5_pose(&K5, q[0], q[1], &p);
    if (st) return st;
    tau[0] = -M_HANDLE * (GX * p.Jx[0] + GY * p.Jx[2]);
    tau[1] = -M_HANDLE * (GX * p.Jx[1] + GY * p.Jx[3]);
    hc5_gravity(&K5, K5_MASS, &p, q[0], q[1], GX, GY, tau);
    return HC_OK;
}

int hc_mass_matrix(const hc_real q[2], hc_real M[4])
{
    hc5_pose_t p;
    int st = hc5_pose(&K5, q[0], q[1], &p);
    if (st) return st;
    hc5_mass(&K5, K5_MASS, JM2, &p, q[0], q[1], M);
    M[0] += M_HANDLE; M[3] += M_HANDLE;
    return HC_OK;
}
""" + _NO_APPARENT_MASS


_TWIN_C = """
typedef struct { hc5_pose_t k, c; hc_real dx, dy, r2; } hc_twin_t;

static int hc_twin(const hc_real q[4], hc_twin_t *t)
{
    int st = hc5_pose(&KNOB, q[0], q[1], &t->k);
    if (st) return st;
    st = hc5_pose(&CRANK, q[2], q[3], &t->c);
    if (st) return st;
    t->dx = t->c.ex - t->k.ex; t->dy = t->c.ey - t->k.ey;
    t->r2 = t->dx * t->dx + t->dy * t->dy;
    if (HC_FABS(HC_SQRT(t->r2) - L6) > CRANK_TOL_M) return HC_ERR_CRANK;
    return HC_OK;
}

int hc_forward(const hc_real q[4], hc_real X[3])
{
    hc_twin_t t;
    int st = hc_twin(q, &t);
    if (st) return st;
    X[0] = t.k.ex; X[1] = t.k.ey; X[2] = HC_ATAN2(t.dy, t.dx);
    return HC_OK;
}

int hc_jacobian(const hc_real q[4], hc_real J[12])
{
    hc_twin_t t;
    int j, st = hc_twin(q, &t);
    if (st) return st;
    for (j = 0; j < 2; ++j) {
        J[j] = t.k.Jx[j]; J[4 + j] = t.k.Jx[2 + j]; J[2 + j] = J[6 + j] = HC_R(0.0);
        /* theta = atan2(d): dtheta = cross(d, d_dot) / |d|^2, d = crank pin - journal */
        J[8 + j] = -(t.dx * t.k.Jx[2 + j] - t.dy * t.k.Jx[j]) / t.r2;
        J[10 + j] = (t.dx * t.c.Jx[2 + j] - t.dy * t.c.Jx[j]) / t.r2;
    }
    return HC_OK;
}

/* least-norm motor torques with Jq^T tau = W, Jq (4x3): q_dot = Jq X_dot (isotropy paper
 * eq 1); tau = Jq (Jq^T Jq)^-1 W, i.e. tau = J^T W with J = pinv(Jq) */
static void hc_twin_wrench(const hc_twin_t *t, const hc_real W[3], hc_real tau[4])
{
    hc_real Jq[12], A[9], Ai[9], y[3], det, ct, st;
    const hc5_pose_t *ps[2];
    int i, j, r, n;
    ps[0] = &t->k; ps[1] = &t->c;
    ct = t->dx / HC_SQRT(t->r2); st = t->dy / HC_SQRT(t->r2);
    for (n = 0; n < 2; ++n) {
        const hc5_pose_t *p = ps[n];
        hc_real d[4];
        d[0] = p->ex - p->c1x; d[1] = p->ey - p->c1y; d[2] = p->ex - p->c2x; d[3] = p->ey - p->c2y;
        for (i = 0; i < 2; ++i) {
            hc_real den = i ? p->den2 : p->den1;
            r = 3 * (2 * n + i);
            Jq[r] = d[2 * i] / den; Jq[r + 1] = d[2 * i + 1] / den;
            Jq[r + 2] = n ? L6 * (-st * Jq[r] + ct * Jq[r + 1]) : HC_R(0.0);
        }
    }
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j) {
            A[3 * i + j] = HC_R(0.0);
            for (r = 0; r < 4; ++r) A[3 * i + j] += Jq[3 * r + i] * Jq[3 * r + j];
        }
    Ai[0] = A[4] * A[8] - A[5] * A[7]; Ai[1] = A[2] * A[7] - A[1] * A[8];
    Ai[2] = A[1] * A[5] - A[2] * A[4]; Ai[3] = A[5] * A[6] - A[3] * A[8];
    Ai[4] = A[0] * A[8] - A[2] * A[6]; Ai[5] = A[2] * A[3] - A[0] * A[5];
    Ai[6] = A[3] * A[7] - A[4] * A[6]; Ai[7] = A[1] * A[6] - A[0] * A[7];
    Ai[8] = A[0] * A[4] - A[1] * A[3];
    det = A[0] * Ai[0] + A[1] * Ai[3] + A[2] * Ai[6];
    for (i = 0; i < 3; ++i) y[i] = (Ai[3 * i] * W[0] + Ai[3 * i + 1] * W[1] + Ai[3 * i + 2] * W[2]) / det;
    for (r = 0; r < 4; ++r) tau[r] = Jq[3 * r] * y[0] + Jq[3 * r + 1] * y[1] + Jq[3 * r + 2] * y[2];
}

int hc_joint_torques(const hc_real q[4], const hc_real F[3], hc_real tau[4])
{
    hc_twin_t t;
    int st = hc_twin(q, &t);
    if (st) return st;
    hc_twin_wrench(&t, F, tau);
    return HC_OK;
}

int hc_gravity_torques(const hc_real q[4], hc_real tau[4])
{
    hc_twin_t t;
    hc_real W[3], cs[4], ct, stt, rx, ry;
    int i, st = hc_twin(q, &t);
    if (st) return st;
    for (i = 0; i < 4; ++i) tau[i] = HC_R(0.0);
    hc5_gravity(&KNOB, KNOB_MASS, &t.k, q[0], q[1], GX, GY, tau);
    hc5_gravity(&CRANK, CRANK_MASS, &t.c, q[2], q[3], GX, GY, tau + 2);
    /* crankshaft weight as a task wrench: -(m g, m g . dr/dtheta), r = R(theta) c */
    ct = t.dx / HC_SQRT(t.r2); stt = t.dy / HC_SQRT(t.r2);
    rx = ct * CX_CS - stt * CY_CS; ry = stt * CX_CS + ct * CY_CS;
    W[0] = -M_CS * GX; W[1] = -M_CS * GY; W[2] = -M_CS * (GX * -ry + GY * rx);
    hc_twin_wrench(&t, W, cs);
    for (i = 0; i < 4; ++i) tau[i] += cs[i];
    return HC_OK;
}

int hc_mass_matrix(const hc_real q[4], hc_real M[9])
{
    /* M = Tk^T Mk Tk + Tc^T Mc Tc + crankshaft, Tk = [I 0], Tc = [I l6 perp(u)], Tg = [I perp(R c)]
     * (cad.kinematics.twin_pantograph.task_mass_matrix) */
    hc_twin_t t;
    hc_real Mk[4], Mc[4], Tc[6], Tg[6], ct, stt, rx, ry;
    int i, j, a, b, st = hc_twin(q, &t);
    if (st) return st;
    hc5_mass(&KNOB, KNOB_MASS, JM_KNOB, &t.k, q[0], q[1], Mk);
    hc5_mass(&CRANK, CRANK_MASS, JM_CRANK, &t.c, q[2], q[3], Mc);
    ct = t.dx / HC_SQRT(t.r2); stt = t.dy / HC_SQRT(t.r2);
    rx = ct * CX_CS - stt * CY_CS; ry = stt * CX_CS + ct * CY_CS;
    for (i = 0; i < 6; ++i) Tc[i] = Tg[i] = HC_R(0.0);
    Tc[0] = Tc[4] = Tg[0] = Tg[4] = HC_R(1.0);
    Tc[2] = -L6 * stt; Tc[5] = L6 * ct; Tg[2] = -ry; Tg[5] = rx;
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j) {
            hc_real v = HC_R(0.0);
            for (a = 0; a < 2; ++a) {
                if (i < 2 && j < 2 && a == i) v += Mk[2 * a + j];
                for (b = 0; b < 2; ++b) v += Tc[3 * a + i] * Mc[2 * a + b] * Tc[3 * b + j];
                v += M_CS * Tg[3 * a + i] * Tg[3 * a + j];
            }
            M[3 * i + j] = v;
        }
    M[8] += IZZ_CS;
    return HC_OK;
}
""" + _NO_APPARENT_MASS


def c_twin(spec) -> str:
    """The twin pantograph's part of hapticad_device.c."""
    g = spec.gravity_m_s2 or (0.0, 0.0)
    cs = spec.bodies["crankshaft"]
    p = spec.params
    return (c_common() + c_params(spec, "knob_", "KNOB")
            + c_params(spec, "crank_", "CRANK") + f"""
#define L6 {lit(p["l6"])}           /* crank throw, main journal to crank pin */
#define CRANK_TOL_M {lit(p["crank_tol"])}  /* refuse |crank pin - journal| off l6 by more */
#define GX {lit(g[0])}
#define GY {lit(g[1])}
#define M_CS {lit(cs.mass_kg)}      /* crankshaft body: origin main journal, x to the crank pin */
#define CX_CS {lit(cs.com_m[0])}
#define CY_CS {lit(cs.com_m[1])}
#define IZZ_CS {lit(cs.izz_kg_m2)}
#define JM {lit(spec.rotor_kg_m2)}         /* rotor inertia of each motor (kg m^2) */
{_jm_line(spec, "JM_KNOB", "knob_")}{_jm_line(spec, "JM_CRANK", "crank_")}""" + _TWIN_C)


def _jm_line(spec, name: str, pre: str) -> str:
    """The C array ``name`` of the (left, right) rotor inertias at the joints of the 5-bar
    ``pre`` (:func:`rotor_pair`: n^2 (J_m + J_capstan) behind a capstan)."""
    a, b = rotor_pair(spec, pre)
    return (f"static const hc_real {name}[2] = {{ {lit(a)}, {lit(b)} }};  /* rotor inertia at each "
            "joint, n^2 (J_m + J_capstan) through a capstan (kg m^2) */\n")


#: The plain 5-bar's model.
FIVEBAR = KinematicModel(
    kind="fivebar",
    frame=("the base frame: x from B1 (left motor) to B2 (right motor), y towards the "
           "workspace, z up; task X = end effector E = (x, y); joints q0, q1 = absolute "
           "angles of the left and right proximal links from x"),
    spec_params=fivebar_spec_params, forward=fivebar_forward, jacobian=fivebar_jacobian,
    com_rates=fivebar_com_rates, mass_matrix=fivebar_mass_matrix, c_source=c_plain,
    poses_ok=fivebar_poses_ok, poses_bad=fivebar_poses_bad,
    workspace_radius_m=workspace_radius_m, identify=fivebar_identify_files,
    identification=FIVEBAR_KIT,
)

#: The twin-pantograph haptic mouse's model.
TWIN = KinematicModel(
    kind="twin",
    frame=("the base frame of both pantographs: task X = (x, y, theta), the main journal "
           "(knob axis) and the crank angle; joints q0, q1 = knob pantograph (left, "
           "right), q2, q3 = crank pantograph (left, right), absolute link angles from x"),
    spec_params=twin_spec_params, forward=twin_forward, jacobian=twin_jacobian,
    com_rates=twin_com_rates, mass_matrix=twin_mass_matrix, c_source=c_twin,
    poses_ok=twin_poses_ok, poses_bad=twin_poses_bad, workspace_radius_m=workspace_radius_m,
    force_jacobian=twin_force_jacobian, joint_torques=twin_joint_torques,
    gravity_extra=twin_gravity_extra, force_scale=(1.0, 1.0, 0.01), senses_rotation=True,
)


def model(design) -> KinematicModel:
    """The family's ``firmware_model`` hook: :data:`TWIN` for the twin pantograph,
    :data:`FIVEBAR` for the plain 5-bar."""
    return TWIN if design.family == "twin-pantograph" else FIVEBAR
