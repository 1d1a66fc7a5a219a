"""The haptic pen's firmware model (issue 32 §3): ``hapticad build --formats firmware`` writes
``firmware/hapticad_device.h`` / ``.c``, the test vectors, ``test_device.c``, the wall sketch
and the CHAI3D file through the :class:`cad.firmware.model.KinematicModel` :data:`PEN` (the
generic writers of :mod:`cad.firmware` do the rest).

Kinematics (isotropy paper §4.2, our reading in :mod:`cad.kinematics.haptic_pen`): joints
q = (waist A, lower shoulder A, upper shoulder A, waist B, lower B, upper B) rad, the motors
of ``report.json`` ``device.motors`` in that order; each arm is a symmetric 5-bar in the
plane through its vertical waist axis (x0 = -l4/2 for A, +l4/2 for B), in-plane coordinates
(z, rho); its end P = (x0 + rho cos psi, rho sin psi, z). The forward kinematics is closed
form: each arm's 5-bar (the circle intersection of :mod:`cad.kinematics.fivebar` in the
working modes of the home pose), then the pen from its two ends: c = (P_A + P_B) / 2,
u = (P_B - P_A) / |P_B - P_A|, task X = (c_x, c_y, c_z [m], yaw = atan2(u_y, u_x),
pitch = asin(u_z) [rad]). Two readings whose ends lie off the pen length l6 by more than
:data:`cad.tolerances.FIRMWARE_PEN_LENGTH_TOL_M` are refused (HC_ERR_CRANK: a rigid length
the encoders disagree on), a pen end on its waist axis or a vertical pen is singular.

J = dX/dq (5 x 6) is the derivative of that closed form; tau = J^T F renders the task force
F = (F_x, F_y, F_z [N], M_yaw [N m] about the base z axis, M_pitch [N m] about u x e_pitch,
the pen's horizontal normal): J maps joint rates to task rates on the device's motions, so
J^T F is a set of motor torques giving F; a stretch of the pen (P_B - P_A along u) moves no
task coordinate, so these torques never squeeze the pen.

Gravity (-z, the layout's z up): each arm's four links through the 5-bar COM rates in its
plane (:func:`cad.families.pantograph.firmware.link_com_rates` with the in-plane gravity
(-g, 0)); the yoke and ring at each pen end (their COM height above the end is constant:
the yoke's x and the ring's z stay vertical); the pen (its COM height z_A + c_x sin(pitch) -
c_y cos(pitch) in its frame x = u, y = -e_pitch). The waist brackets turn about vertical axes
and carry no gravity torque. The 5 x 5 mass matrix needs the 3-D body Jacobians of
:mod:`cad.families.pen.dynamics`: ``hc_mass_matrix`` refuses (HC_ERR_RANGE, zeros); the
report's effective mass is the figure. No CAD import.
"""

from __future__ import annotations

import math

import numpy as np

from cad import tolerances as tol
from cad.errors import DesignError
from cad.families.pantograph import firmware as pf
from cad.firmware.csrc import JT_F, lit
from cad.firmware.model import KinematicModel, SpecParams
from cad.firmware.reference import STATUS
from cad.firmware.spec import G0_M_S2, Body
from cad.kinematics import fivebar as fb5
from cad.kinematics import haptic_pen as hp
from cad.kinematics.pantograph_tolerances import ON_WAIST_AXIS_MM

MM = 1e-3
#: The pen's gravity in its base frame (z up): m/s^2.
GRAVITY_M_S2 = (0.0, 0.0, -G0_M_S2)
#: (prefix, sign of the waist axis x0 = sign l4 / 2, column of the waist joint in q).
ARMS = (("A_", -1.0, 0), ("B_", 1.0, 3))
#: report.json body of each 5-bar link (lower shoulder = the 5-bar's left, at z = -l1/2).
LINK_BODIES = {"proximal_left": "proximal_lower", "proximal_right": "proximal_upper",
               "distal_left": "distal_lower", "distal_right": "distal_upper"}


def _arm_fivebar(pen) -> fb5.FiveBar:
    return fb5.FiveBar.symmetric(pen.shoulder_base_mm, pen.proximal_mm, pen.distal_mm)


def _link_bodies(report: dict, pre: str, sign: float) -> dict[str, Body]:
    """The four links of one arm as 5-bar links (COM in the 5-bar's link frame: x along the
    link, y = +90 deg in the (z, rho) plane: the body frame's y for arm A (n_out = the plane's
    normal), minus it for arm B)."""
    out = {}
    for five, body in LINK_BODIES.items():
        e = report["bodies"][pre + body]
        c = e["com_mm"]
        out[pre + five] = Body(float(e["mass_kg"]), (c[0] * MM, -sign * c[1] * MM),
                               float(e["inertia_com_kg_m2"][2][2]))
    return out


def _end_params(report: dict, pre: str) -> dict[str, float]:
    """Mass (kg) of one arm's yoke and ring: their COM stays at a constant height above the
    pen end (the yoke's x and the ring's z are vertical), so only the end's height counts."""
    b = report["bodies"]
    return {pre + "end_kg": float(b[pre + "yoke"]["mass_kg"] + b[pre + "ring"]["mass_kg"])}


def spec_params(design, report: dict, device) -> SpecParams:
    """The pen's constants (arm 5-bars with their working modes at home, SI; the pen; the
    gravity bodies from report.json), the home pose (IK at the workspace centre, pen along
    +x) and gravity -z. DesignError when the home pose cannot be reached."""
    pen = design.mechanism
    X0 = np.array([*design.workspace["center_mm"], 0.0, 0.0])
    q, st = hp.ik(pen, X0[None])
    if st[0] != 0:
        raise DesignError("workspace.center_mm", f"{design.workspace['center_mm']} mm: the home "
                          f"pose is {hp.STATUS_NAMES[int(st[0])]}")
    u = hp.pen_directions(0.0, 0.0)[0]
    params = {"l6": pen.pen_mm * MM, "len_tol": tol.FIRMWARE_PEN_LENGTH_TOL_M,
              "on_axis": ON_WAIST_AXIS_MM * MM, "cos_pitch_min": tol.FIRMWARE_PEN_COS_PITCH_MIN}
    bodies: dict[str, Body] = {}
    for pre, sign, _ in ARMS:
        x0 = sign * pen.l4_mm / 2
        P = X0[:3] + sign * pen.pen_mm / 2 * u
        p, _ = pf.fivebar_params(_arm_fivebar(pen), (P[2], math.hypot(P[0] - x0, P[1])), pre)
        params.update(p, **{pre + "x0": x0 * MM}, **_end_params(report, pre))
        bodies.update(_link_bodies(report, pre, sign))
    pb = report["bodies"]["pen"]
    params.update(pen_kg=float(pb["mass_kg"]), pen_cx=pb["com_mm"][0] * MM, pen_cy=pb["com_mm"][1] * MM)
    return SpecParams(params, tuple(float(v) for v in q[0]), bodies, 6, 5, gravity_m_s2=GRAVITY_M_S2)


def _arm(spec, q, pre: str, col: int):
    """(P (N, 3) m, dP/dq_arm (N, 3, 3) m/rad, E (N, 2), Jx, status) of one arm."""
    p = spec.params
    E, Jx, st, _, _ = pf.state(p, q[:, col + 1:col + 3], pre)
    psi = q[:, col]
    c, s = np.cos(psi), np.sin(psi)
    rho = E[:, 1]
    st = np.where((st == 0) & (rho <= p["on_axis"]), STATUS["HC_ERR_SINGULAR"], st)
    P = np.stack([p[pre + "x0"] + rho * c, rho * s, E[:, 0]], axis=-1)
    dP = np.zeros((len(q), 3, 3))
    dP[:, 0, 0], dP[:, 1, 0] = -rho * s, rho * c
    dP[:, 0, 1:], dP[:, 1, 1:], dP[:, 2, 1:] = c[:, None] * Jx[:, 1], s[:, None] * Jx[:, 1], Jx[:, 0]
    return P, dP, st


def state(spec, q):
    """(X (N, 5), J = dX/dq (N, 5, 6), status (N,)) (module docstring); zeros where refused."""
    q = np.atleast_2d(np.asarray(q, float))
    (PA, dA, sA), (PB, dB, sB) = (_arm(spec, q, pre, col) for pre, _, col in ARMS)
    status = np.where(sA != 0, sA, sB)
    d = PB - PA
    L = np.linalg.norm(d, axis=1)
    status = np.where((status == 0) & (np.abs(L - spec.params["l6"]) > spec.params["len_tol"]),
                      STATUS["HC_ERR_CRANK"], status)
    u = d / np.where(L > 0, L, 1.0)[:, None]
    cp = np.hypot(u[:, 0], u[:, 1])
    status = np.where((status == 0) & (cp < spec.params["cos_pitch_min"]), STATUS["HC_ERR_SINGULAR"], status)
    ok = status == 0
    X = np.column_stack([(PA + PB) / 2, np.arctan2(u[:, 1], u[:, 0]), np.arcsin(np.clip(u[:, 2], -1, 1))])
    dPA, dPB = np.zeros((len(q), 3, 6)), np.zeros((len(q), 3, 6))
    dPA[:, :, 0:3], dPB[:, :, 3:6] = dA, dB
    dd = dPB - dPA
    du = (dd - u[:, :, None] * np.einsum("ni,nij->nj", u, dd)[:, None, :]) / np.where(L > 0, L, 1.0)[:, None, None]
    J = np.zeros((len(q), 5, 6))
    J[:, :3] = (dPA + dPB) / 2
    cp2 = np.where(cp > 0, cp * cp, 1.0)
    J[:, 3] = (u[:, 0, None] * du[:, 1] - u[:, 1, None] * du[:, 0]) / cp2[:, None]
    J[:, 4] = du[:, 2] / np.where(cp > 0, cp, 1.0)[:, None]
    return np.where(ok[:, None], X, 0.0), np.where(ok[:, None, None], J, 0.0), status


def forward(spec, q):
    """(X (N, 5): pen centre m, yaw, pitch rad; status (N,))."""
    X, _, st = state(spec, q)
    return X, st


def jacobian(spec, q) -> np.ndarray:
    """dX/dq (N, 5, 6): m/rad and rad/rad."""
    return state(spec, q)[1]


def com_rates(spec, q):
    """No body through the planar COM rates: every weight is in :func:`gravity_extra`."""
    return forward(spec, q)[1] == 0, {}


def gravity_extra(spec, q, g) -> tuple[np.ndarray, np.ndarray]:
    """(dV/dq (N, 6) N m, ok (N,)) of every moving body (module docstring); ``g`` must be
    :data:`GRAVITY_M_S2`."""
    if not np.allclose(g, GRAVITY_M_S2, rtol=0, atol=0):
        raise DesignError("firmware", f"the pen's gravity is {GRAVITY_M_S2} m/s^2, got {tuple(g)}")
    q = np.atleast_2d(np.asarray(q, float))
    X, J, status = state(spec, q)
    p, tau = spec.params, np.zeros((len(q), 6))
    g_plane = np.array([-G0_M_S2, 0.0])  # in the arm's (z, rho) plane
    for pre, _, col in ARMS:
        _, _, Jx, _, rates = pf.link_com_rates(spec, q[:, col + 1:col + 3], pre)
        sh = slice(col + 1, col + 3)
        for name, (_, dr) in rates.items():
            tau[:, sh] -= spec.bodies[name].mass_kg * np.einsum("i,nij->nj", g_plane, dr)
        tau[:, sh] += p[pre + "end_kg"] * G0_M_S2 * Jx[:, 0]  # yoke + ring: height of the end + dz
    pitch = X[:, 4]
    tau[:, 1:3] += p["pen_kg"] * G0_M_S2 * _arm(spec, q, "A_", 0)[1][:, 2, 1:]
    tau += (p["pen_kg"] * G0_M_S2 * (p["pen_cx"] * np.cos(pitch) + p["pen_cy"] * np.sin(pitch)))[:, None] * J[:, 4]
    ok = status == 0
    return np.where(ok[:, None], tau, 0.0), ok


def mass_matrix(spec, q_ok, X_ok) -> np.ndarray:
    """Zeros (n_ok, 5, 5): the C refuses hc_mass_matrix (module docstring)."""
    return np.zeros((len(q_ok), 5, 5))


def task_samples(design, rng, n: int) -> np.ndarray:
    """n task poses (mm, rad) uniform over the workspace box and its yaw and pitch range."""
    ws = design.workspace
    c, s = np.asarray(ws["center_mm"], float), np.asarray(ws["size_mm"], float)
    r = math.radians(ws.get("rotation_deg", 0.0))
    return np.column_stack([rng.uniform(c - s / 2, c + s / 2, (n, 3)), rng.uniform(-r, r, (n, 2))])


def poses_ok(spec, design, rng, n: int) -> np.ndarray:
    """n joint rows: the IK of task poses uniform over the workspace box and its rotations,
    kept where the FK (the firmware's modes) gives them back."""
    keep: list = []
    for _ in range(20):
        q, st = hp.ik(design.mechanism, task_samples(design, rng, 2 * n))
        q = q[st == 0]
        keep.extend(q[forward(spec, q)[1] == 0] if len(q) else q)
        if len(keep) >= n:
            return np.asarray(keep[:n])
    raise DesignError("workspace", f"fewer than {n} test poses reachable in the pen's workspace")


def poses_bad(spec, q_ok, rng, n: int) -> np.ndarray:
    """Rows the C must refuse: an arm folded back or crossed (no closure, off its modes) and
    a waist turned so far that the ends lie off the pen length."""
    q = q_ok[rng.integers(0, len(q_ok), n)].copy()
    third = n // 3
    q[:third, 1] += math.pi
    q[third:2 * third, 5] -= rng.uniform(2.0, 3.0, third)
    q[2 * third:, 3] += rng.uniform(0.3, 0.6, n - 2 * third)
    return q[forward(spec, q)[1] != 0]


def workspace_radius_m(spec, design) -> float:
    """Half the smallest side of the workspace box (m)."""
    return float(min(design.workspace["size_mm"])) / 2 * MM


def _c_arm(spec, pre: str, cname: str) -> str:
    p = spec.params
    keys = ("b1x", "b1y", "b2x", "b2y", "l2l", "l2r", "l3l", "l3r", "assembly", "mode_l", "mode_r")
    links = ", ".join(f"{lit(spec.bodies[pre + n].mass_kg)}, {lit(spec.bodies[pre + n].com_m[0])}, "
                      f"{lit(spec.bodies[pre + n].com_m[1])}, {lit(spec.bodies[pre + n].izz_kg_m2)}"
                      for n in pf.FIVEBAR_LINKS)
    return (f"static const hc5_t {cname} = {{ {', '.join(lit(p[pre + k]) for k in keys)} }};\n"
            f"static const hc_real {cname}_MASS[16] = {{ {links} }};  /* proximal L, R, distal L, R */\n"
            f"static const hc_real {cname}_X0 = {lit(p[pre + 'x0'])};      /* waist axis x (m) */\n"
            f"static const hc_real {cname}_END_KG = {lit(p[pre + 'end_kg'])};  /* yoke + ring */\n")


def _fivebar_c() -> str:
    """The pantographs' 5-bar C (pose, gravity) without its mass matrix, which the pen does
    not use (a static function never called fails -Wall -Werror)."""
    head, sep, _ = pf.c_common().partition("\n/* task mass matrix of one 5-bar")
    if not sep:
        raise RuntimeError("cad.families.pantograph.firmware 5-bar C: its mass matrix moved")
    return head + "\n"


def c_source(spec) -> str:
    """The pen's part of ``hapticad_device.c`` (module docstring)."""
    p = spec.params
    return (_fivebar_c() + _c_arm(spec, "A_", "ARM_A") + _c_arm(spec, "B_", "ARM_B") + f"""
#define L6 {lit(p["l6"])}              /* pen length between the two arm ends (m) */
#define PEN_LEN_TOL_M {lit(p["len_tol"])}   /* refuse ends off l6 by more */
#define ON_AXIS_M {lit(p["on_axis"])}     /* a pen end on its waist axis: singular */
#define COS_PITCH_MIN {lit(p["cos_pitch_min"])}
#define G0 {lit(G0_M_S2)}
#define PEN_KG {lit(p["pen_kg"])}   /* pen body: origin arm A's end, x = u, y = -e_pitch */
#define PEN_CX {lit(p["pen_cx"])}
#define PEN_CY {lit(p["pen_cy"])}
""" + _PEN_C + JT_F + _NO_MASS)


_PEN_C = """
typedef struct { hc5_pose_t f; hc_real P[3], dP[9]; } hc_arm_t;   /* dP row-major 3x3 */
typedef struct { hc_arm_t a, b; hc_real u[3], L, cp; } hc_pen_t;

/* one arm: its 5-bar in the (z, rho) plane at the shoulders q[1], q[2], turned by the waist q[0] */
static int hc_arm(const hc5_t *k, hc_real x0, const hc_real q[3], hc_arm_t *a)
{
    hc_real c = HC_COS(q[0]), s = HC_SIN(q[0]), rho;
    int j, st = hc5_pose(k, q[1], q[2], &a->f);
    if (st) return st;
    rho = a->f.ey;
    if (rho <= ON_AXIS_M) return HC_ERR_SINGULAR;
    a->P[0] = x0 + rho * c; a->P[1] = rho * s; a->P[2] = a->f.ex;
    a->dP[0] = -rho * s; a->dP[3] = rho * c; a->dP[6] = HC_R(0.0);
    for (j = 0; j < 2; ++j) {          /* f.Jx rows: dz/dq, drho/dq */
        a->dP[1 + j] = c * a->f.Jx[2 + j]; a->dP[4 + j] = s * a->f.Jx[2 + j]; a->dP[7 + j] = a->f.Jx[j];
    }
    return HC_OK;
}

static int hc_pen(const hc_real q[6], hc_pen_t *t)
{
    int i, st = hc_arm(&ARM_A, ARM_A_X0, q, &t->a);
    if (st) return st;
    st = hc_arm(&ARM_B, ARM_B_X0, q + 3, &t->b);
    if (st) return st;
    for (i = 0; i < 3; ++i) t->u[i] = t->b.P[i] - t->a.P[i];
    t->L = HC_SQRT(t->u[0] * t->u[0] + t->u[1] * t->u[1] + t->u[2] * t->u[2]);
    if (HC_FABS(t->L - L6) > PEN_LEN_TOL_M) return HC_ERR_CRANK;
    for (i = 0; i < 3; ++i) t->u[i] /= t->L;
    t->cp = HC_SQRT(t->u[0] * t->u[0] + t->u[1] * t->u[1]);
    if (t->cp < COS_PITCH_MIN) return HC_ERR_SINGULAR;
    return HC_OK;
}

int hc_forward(const hc_real q[6], hc_real X[5])
{
    hc_pen_t t;
    int i, st = hc_pen(q, &t);
    if (st) return st;
    for (i = 0; i < 3; ++i) X[i] = HC_R(0.5) * (t.a.P[i] + t.b.P[i]);
    X[3] = HC_ATAN2(t.u[1], t.u[0]);
    X[4] = HC_ATAN2(t.u[2], t.cp);    /* asin(u_z) */
    return HC_OK;
}

/* J = dX/dq (5x6): c = (P_A + P_B) / 2; du = (I - u u^T) dd / L, d = P_B - P_A;
 * dyaw = (u_x du_y - u_y du_x) / cp^2; dpitch = du_z / cp */
int hc_jacobian(const hc_real q[6], hc_real J[30])
{
    hc_pen_t t;
    int i, j, st = hc_pen(q, &t);
    if (st) return st;
    for (j = 0; j < 6; ++j) {
        hc_real dd[3], du[3], ud = HC_R(0.0);
        for (i = 0; i < 3; ++i) {
            hc_real a = j < 3 ? t.a.dP[3 * i + j] : HC_R(0.0), b = j < 3 ? HC_R(0.0) : t.b.dP[3 * i + j - 3];
            J[6 * i + j] = HC_R(0.5) * (a + b);
            dd[i] = b - a;
            ud += t.u[i] * dd[i];
        }
        for (i = 0; i < 3; ++i) du[i] = (dd[i] - t.u[i] * ud) / t.L;
        J[18 + j] = (t.u[0] * du[1] - t.u[1] * du[0]) / (t.cp * t.cp);
        J[24 + j] = du[2] / t.cp;
    }
    return HC_OK;
}

int hc_gravity_torques(const hc_real q[6], hc_real tau[6])
{
    hc_pen_t t;
    hc_real J[30], pitch, arm;
    int i, st = hc_jacobian(q, J);
    if (st) return st;
    hc_pen(q, &t);
    for (i = 0; i < 6; ++i) tau[i] = HC_R(0.0);
    /* each arm's links in its (z, rho) plane, gravity (-g, 0); yoke + ring at its end */
    hc5_gravity(&ARM_A, ARM_A_MASS, &t.a.f, q[1], q[2], -G0, HC_R(0.0), tau + 1);
    hc5_gravity(&ARM_B, ARM_B_MASS, &t.b.f, q[4], q[5], -G0, HC_R(0.0), tau + 4);
    for (i = 0; i < 2; ++i) {
        tau[1 + i] += ARM_A_END_KG * G0 * t.a.f.Jx[i];
        tau[4 + i] += ARM_B_END_KG * G0 * t.b.f.Jx[i];
    }
    /* pen: height z_A + c_x sin(pitch) - c_y cos(pitch) */
    pitch = HC_ATAN2(t.u[2], t.cp);
    arm = PEN_CX * HC_COS(pitch) + PEN_CY * HC_SIN(pitch);
    for (i = 0; i < 2; ++i) tau[1 + i] += PEN_KG * G0 * t.a.f.Jx[i];
    for (i = 0; i < 6; ++i) tau[i] += PEN_KG * G0 * arm * J[24 + i];
    return HC_OK;
}
"""

_NO_MASS = """
int hc_mass_matrix(const hc_real q[6], hc_real M[25])
{
    int i;
    (void)q;
    for (i = 0; i < 25; ++i) M[i] = HC_R(0.0);
    return HC_ERR_RANGE; /* the pen's 5x5 mass matrix needs 3-D body Jacobians: report.json */
}

int hc_apparent_mass(const hc_real q[HC_N_JOINTS], hc_real *mass_kg)
{
    (void)q; (void)mass_kg;
    return HC_ERR_RANGE; /* a pen's mass is a matrix */
}
"""


#: The haptic pen's kinematic model (the family's ``firmware_model``).
PEN = KinematicModel(
    kind="pen",
    frame=("the pen's base frame (mm in the design, m here): z up, arm A's waist axis through "
           "(-l4/2, 0), arm B's through (+l4/2, 0); task X = the pen centre (x, y, z), yaw and "
           "pitch of the pen direction u = P_B - P_A; joints q = waist A, lower and upper "
           "shoulder A, waist B, lower and upper shoulder B"),
    spec_params=spec_params, forward=forward, jacobian=jacobian, com_rates=com_rates,
    mass_matrix=mass_matrix, c_source=c_source, poses_ok=poses_ok, poses_bad=poses_bad,
    workspace_radius_m=workspace_radius_m, gravity_extra=gravity_extra, n_translation=3,
    force_scale=(1.0, 1.0, 1.0, 0.035, 0.035), senses_rotation=True,
    workspace_note="haptic pen: half the smallest side of the workspace box",
)


def model(design) -> KinematicModel:
    """The family's ``firmware_model`` hook: :data:`PEN`."""
    return PEN
