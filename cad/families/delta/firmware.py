"""The delta's firmware model (issue 36 §5): ``hapticad build --formats firmware`` writes
``firmware/hapticad_device.h`` / ``.c`` and the rest of :mod:`cad.firmware` through the
:class:`cad.firmware.model.KinematicModel` :data:`DELTA` (the family's ``firmware_model``
hook; the generic writers do the header, the encoder counts -> angles, the motor currents,
the test vectors, ``test_device.c``, the wall sketch and the CHAI3D file).

The C (:func:`c_source`, C99, no allocation, ``double`` or ``float``): forward kinematics
(the three spheres, closed form; with Stamper's joint offset g > 0 that sphere point refined
by Newton's method, as :func:`cad.kinematics.delta.fk`), inverse kinematics ``hc_inverse``
(elbow out: the root with the larger cos theta), the Jacobian dX/dtheta (3x3, m/rad),
tau = J^T F, the gravity compensation of :func:`cad.dynamics.delta.gravity_torques_Nm` and
the task mass matrix of :func:`cad.dynamics.delta.mass_matrix_kg` (both with Stamper's knee
link for g > 0: its mass, centre and inertia about the knee pin; a
:class:`cad.dynamics.delta.DeltaMass` from the build's body mass properties,
:func:`cad.families.delta.dynamics.delta_mass_from_bodies`) plus each arm's rotor through its
own transmission, J^T diag(n_i^2 (J_m + J_capstan,i)) J (the resolved device's
:meth:`cad.device.ResolvedDevice.joint_rotor_inertia_kg_m2`, one per arm: the arms may have
different ratios; ``ARM_AXIS[i]`` in the C). The counts -> angles and torques -> currents go
through each joint's own ratio (``HC_GEAR``, :mod:`cad.firmware.csrc`). Symbols, frames and the status precedence (reach, joint limits, serial, parallel
singularity) are those of :mod:`cad.kinematics.delta`; units SI (m, rad, N, N m, kg).
Status codes: :data:`cad.firmware.reference.STATUS` (unreachable or no assembly:
HC_ERR_CLOSURE; joint limits: HC_ERR_RANGE; singular: HC_ERR_SINGULAR).

:func:`reference_vectors` evaluates IK, FK, the Jacobian and the torques with
:mod:`cad.kinematics.delta` and :mod:`cad.dynamics.delta` at given effector points (the
IK's own test; the build's ``test_vectors.json`` holds the FK side).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from cad import tolerances as tol
from cad.dynamics.delta import G_M_S2, DeltaMass, gravity_torques_Nm, mass_matrix_kg
from cad.errors import DesignError
from cad.families.delta.dynamics import delta_mass_from_bodies
from cad.firmware.csrc import JT_F
from cad.firmware.model import KinematicModel, SpecParams
from cad.firmware.reference import STATUS
from cad.io.escape import c_comment
from cad.kinematics import delta as D
from cad.massprops.props import MassProps

MM = 1e-3
#: The delta's gravity in its base frame (z up): m/s^2.
GRAVITY_M_S2 = (0.0, 0.0, -G_M_S2)
#: Design-file lengths and angles of :class:`cad.kinematics.delta.Delta` kept in the spec.
GEOMETRY = ("base_radius_mm", "effector_radius_mm", "upper_arm_mm", "lower_arm_mm",
            "theta_min_rad", "theta_max_rad", "joint_offset_mm", "axis_offset_mm")
MASS = ("upper_arm_kg_m2", "upper_arm_kg", "upper_arm_com_mm", "lower_arm_kg", "effector_kg",
        "rotor_kg_m2", "ratio", "knee_kg", "knee_com_mm", "knee_kg_m2")
#: Each arm's rotor through its own transmission, n_i^2 (J_m + J_capstan,i) (kg m^2) in the spec.
REFLECTED = ("reflected_0_kg_m2", "reflected_1_kg_m2", "reflected_2_kg_m2")


def _lit(x: float) -> str:
    return f"HC_R({float(x)!r})"


def delta_of(spec) -> D.Delta:
    """The :class:`cad.kinematics.delta.Delta` of a spec's ``params``."""
    p = spec.params
    return D.Delta(**{k: p[k] for k in GEOMETRY},
                   motor_azimuth_rad=(p["azimuth_0_rad"], p["azimuth_1_rad"], p["azimuth_2_rad"]))


def mass_of(spec) -> DeltaMass:
    """The :class:`cad.dynamics.delta.DeltaMass` of a spec's ``params``: the links (its rotor
    0; the rotors through each arm's ratio: :func:`reflected_of`)."""
    return DeltaMass(**{k: spec.params[k] for k in MASS})


def reflected_of(spec) -> np.ndarray:
    """(3,) each arm's reflected rotor inertia n_i^2 (J_m + J_capstan,i) (kg m^2) of a spec."""
    return np.array([spec.params[k] for k in REFLECTED])


def props_of(report: dict) -> dict:
    """``{body: MassProps}`` (SI, body frames of :mod:`cad.families.delta.layout`) of
    report.json ``bodies``."""
    return {k: MassProps(v["mass_kg"], np.asarray(v["com_mm"], float) * MM,
                         np.asarray(v["inertia_com_kg_m2"], float))
            for k, v in (report.get("bodies") or {}).items()}


def params_of(d: D.Delta, mass: DeltaMass, reflected_kg_m2=None) -> dict[str, float]:
    """The spec's ``params`` of delta ``d`` with moving masses ``mass`` and each arm's rotor
    through its transmission ``reflected_kg_m2`` (3,) kg m^2, n_i^2 (J_m + J_capstan,i)
    (None: ``mass``'s one rotor and ratio on every arm, n^2 J_m). The links go in with no
    rotor (:func:`mass_of`), the rotors per arm (:func:`reflected_of`). DesignError for a
    reflected inertia that is not (3,) finite and >= 0."""
    if reflected_kg_m2 is None:
        reflected_kg_m2 = (mass.ratio ** 2 * mass.rotor_kg_m2,) * 3
    r = np.asarray(reflected_kg_m2, float)
    if r.shape != (3,) or not np.all(np.isfinite(r) & (r >= 0)):
        raise DesignError("reflected_kg_m2", f"must be 3 finite values >= 0, got {reflected_kg_m2!r}")
    links = dataclasses.replace(mass, rotor_kg_m2=0.0, ratio=1.0)
    params = {k: float(getattr(d, k)) for k in GEOMETRY}
    params.update({f"azimuth_{i}_rad": float(a) for i, a in enumerate(d.motor_azimuth_rad)})
    params.update({k: float(getattr(links, k)) for k in MASS})
    params.update({k: float(v) for k, v in zip(REFLECTED, r, strict=True)})
    return params


def spec_params(design, report: dict, device) -> SpecParams:
    """The delta's constants (geometry mm/rad, :class:`DeltaMass` from report.json ``bodies``,
    each arm's rotor through its own transmission from the resolved device, n_i^2 (J_m +
    J_capstan,i)), the home pose (IK at the workspace centre) and gravity -z (with Stamper's
    knee, g > 0, the knee's mass too). DesignError for a workspace centre out of reach."""
    d = design.mechanism
    mass = delta_mass_from_bodies(d, props_of(report))
    reflected = [device.joint_rotor_inertia_kg_m2(f"theta_{i}") for i in range(3)]
    pose = D.ik(d, np.asarray(design.workspace["center_mm"], float)[None, :])
    if not pose.ok[0]:
        raise DesignError("workspace.center_mm", f"{design.workspace['center_mm']} mm: the home "
                          f"pose is {D.STATUS_NAMES[int(pose.status[0])]}")
    return SpecParams(params_of(d, mass, reflected), tuple(float(t) for t in pose.theta_rad[0]), {}, 3, 3,
                      gravity_m_s2=GRAVITY_M_S2)


_CODE = {D.STATUS_OK: STATUS["HC_OK"], D.STATUS_UNREACHABLE: STATUS["HC_ERR_CLOSURE"],
         D.STATUS_NO_ASSEMBLY: STATUS["HC_ERR_CLOSURE"], D.STATUS_JOINT_LIMIT: STATUS["HC_ERR_RANGE"],
         D.STATUS_SINGULAR_SERIAL: STATUS["HC_ERR_SINGULAR"],
         D.STATUS_SINGULAR_PARALLEL: STATUS["HC_ERR_SINGULAR"]}


def _codes(status) -> np.ndarray:
    return np.array([_CODE[int(s)] for s in np.atleast_1d(status)], dtype=int)


def forward(spec, q) -> tuple[np.ndarray, np.ndarray]:
    """(X (N, 3) m, C status (N,)) at joint angles q (N, 3) rad; X = 0 where refused."""
    f = D.fk(delta_of(spec), q)
    st = _codes(f.status)
    return np.where((st == 0)[:, None], f.P_mm * MM, 0.0), st


def jacobian(spec, q) -> np.ndarray:
    """dX/dtheta (N, 3, 3) m/rad (the inverse of :func:`cad.kinematics.delta.
    jacobian_rad_per_m`), zeros where refused."""
    X, st = forward(spec, q)
    out = np.zeros((len(X), 3, 3))
    ok = st == 0
    if ok.any():
        out[ok] = np.linalg.inv(D.jacobian_rad_per_m(delta_of(spec), X[ok] / MM)[0])
    return out


def com_rates(spec, q):
    """No body's gravity through the planar COM rates: every weight is in
    :func:`gravity_extra`."""
    return forward(spec, q)[1] == 0, {}


def gravity_extra(spec, q, g) -> tuple[np.ndarray, np.ndarray]:
    """(J^-T grad_x V (N, 3) N m, ok (N,)): :func:`cad.dynamics.delta.gravity_torques_Nm`
    (g along -z of the base frame; ``g`` must be :data:`GRAVITY_M_S2`)."""
    if not np.allclose(g, GRAVITY_M_S2, rtol=0, atol=0):
        raise DesignError("firmware", f"a delta's gravity is {GRAVITY_M_S2} m/s^2, got {tuple(g)}")
    X, st = forward(spec, q)
    ok = st == 0
    tau = np.zeros((len(X), 3))
    if ok.any():
        tau[ok] = gravity_torques_Nm(delta_of(spec), X[ok] / MM, mass_of(spec))
    return tau, ok


def mass_matrix(spec, q_ok, X_ok) -> np.ndarray:
    """Lambda (n_ok, 3, 3) kg at the ok rows: :func:`task_mass_kg` of the spec's links and
    rotors."""
    return task_mass_kg(delta_of(spec), np.asarray(X_ok) / MM, mass_of(spec), reflected_of(spec))


def task_mass_kg(d: D.Delta, P_mm, mass: DeltaMass, reflected_kg_m2=None) -> np.ndarray:
    """Lambda (N, 3, 3) kg at effector points ``P_mm`` (N, 3): :func:`cad.dynamics.delta.
    mass_matrix_kg` of ``mass`` plus J^T diag(``reflected_kg_m2``) J (each arm's rotor through
    its own ratio, (3,) kg m^2; J: theta_dot = J x_dot, rad/m; None: ``mass``'s own rotor term
    only). KinematicsError naming a point not ok."""
    lam = mass_matrix_kg(d, P_mm, mass)
    if reflected_kg_m2 is None:
        return lam
    J, _ = D.jacobian_rad_per_m(d, np.asarray(P_mm, float).reshape(-1, 3))
    return lam + np.einsum("nik,i,nil->nkl", J, np.asarray(reflected_kg_m2, float), J)


def _extent_mm(design) -> tuple[np.ndarray, np.ndarray]:
    X = design.workspace_points()
    return X.min(axis=0), X.max(axis=0)


def poses_ok(spec, design, rng, n: int) -> np.ndarray:
    """n joint-angle rows (elbow out) of effector points drawn uniformly in the workspace's
    bounding box, kept where both the IK and the FK are ok."""
    d, (lo, hi) = delta_of(spec), _extent_mm(design)
    keep: list = []
    for _ in range(20):
        pose = D.ik(d, rng.uniform(lo, hi, (2 * n, 3)))
        th = pose.theta_rad[pose.ok]
        th = th[D.fk(d, th).ok] if len(th) else th
        keep.extend(th)
        if len(keep) >= n:
            return np.asarray(keep[:n])
    raise DesignError("workspace", f"fewer than {n} test poses reachable in the workspace box")


def poses_bad(spec, q_ok, rng, n: int) -> np.ndarray:
    """n rows the C must refuse: random angles within the joint limits whose arms cannot
    meet or are singular (up to half; a delta with long lower arms has none), the rest an ok
    pose with one angle past a joint limit (every row refused by the FK)."""
    d = delta_of(spec)
    wild = rng.uniform(d.theta_min_rad, d.theta_max_rad, (40 * n, 3))
    wild = wild[D.fk(d, wild).status != D.STATUS_OK][: n // 2]
    q = q_ok[rng.integers(0, len(q_ok), n - len(wild))].copy()
    j = rng.integers(0, 3, len(q))
    past = rng.uniform(0.05, 0.5, len(q))
    q[np.arange(len(q)), j] = np.where(rng.random(len(q)) < 0.5, d.theta_max_rad + past,
                                       d.theta_min_rad - past)
    return np.concatenate([wild, q])


def workspace_radius_m(spec, design) -> float:
    """Half the smallest side of the workspace samples' bounding box (m)."""
    lo, hi = _extent_mm(design)
    return float(np.min(hi - lo)) / 2 * MM


def _constants(spec) -> str:
    d, mass = delta_of(spec), mass_of(spec)
    u, t = d.radial, d.tangential
    rows = lambda a: ", ".join(_lit(v) for v in a.ravel())  # noqa: E731
    return f"""
static const hc_real RR = {_lit((d.base_radius_mm - d.effector_radius_mm) * MM)};  /* R - r */
static const hc_real LA = {_lit(d.upper_arm_mm * MM)};
static const hc_real LB = {_lit(d.lower_arm_mm * MM)};
static const hc_real G_OFF = {_lit(d.joint_offset_mm * MM)};   /* Stamper's joint offset */
static const hc_real A_OFF = {_lit(d.axis_offset_mm * MM)};    /* motor axis offset along t_i */
static const hc_real U[9] = {{{rows(u)}}};   /* u_i radial (rows) */
static const hc_real T[9] = {{{rows(t)}}};   /* t_i motor axes (rows) */
static const hc_real TH_MIN = {_lit(d.theta_min_rad)}, TH_MAX = {_lit(d.theta_max_rad)};
static const hc_real EPS_REACH = {_lit(tol.REACH_REL_EPS)};
static const hc_real EPS_SERIAL = {_lit(tol.DELTA_SERIAL_SINGULAR)};
static const hc_real EPS_PARALLEL = {_lit(tol.DELTA_PARALLEL_SINGULAR)};
#ifdef HAPTICAD_USE_FLOAT
static const hc_real EPS_RESIDUAL = {_lit(tol.DELTA_FK_RESIDUAL_REL_FLOAT)};
#else
static const hc_real EPS_RESIDUAL = {_lit(tol.DELTA_FK_RESIDUAL_REL)};
#endif
#define NEWTON_STEPS {int(tol.DELTA_FK_NEWTON_STEPS)}
/* masses (from the solids): {c_comment(repr(mass))} */
static const hc_real G0 = {_lit(G_M_S2)};
static const hc_real M_ARM = {_lit(mass.upper_arm_kg)}, COM_ARM = {_lit(mass.upper_arm_com_mm * MM)};
static const hc_real M_LOWER = {_lit(mass.lower_arm_kg)}, M_EFF = {_lit(mass.effector_kg)};
/* each arm about its motor axis with its rotor through its own transmission: I_arm + n_i^2 J_m,i */
static const hc_real ARM_AXIS[3] = {{{", ".join(_lit(mass.upper_arm_kg_m2 + r) for r in reflected_of(spec))}}};
/* Stamper's knee (0 without): its mass, its centre along it, its inertia about the knee pin */
static const hc_real M_KNEE = {_lit(mass.knee_kg)}, COM_KNEE = {_lit(mass.knee_com_mm * MM)};
static const hc_real I_KNEE = {_lit(mass.knee_kg_m2)};
"""


def c_source(spec) -> str:
    """The delta's part of ``hapticad_device.c`` (module docstring)."""
    return _constants(spec) + _HELPERS + _IK + _FK + _JAC + JT_F


#: ``hc_inverse`` in ``hapticad_device.h`` (the delta's own function beside the common API).
HEADER_EXTRA = """/* delta: joint angles q (rad, elbow out) putting the effector centre at X (m); q = 0 and
 * HC_ERR_* when X is out of reach, past a joint limit or singular */
int hc_inverse(const hc_real X[HC_N_TASK], hc_real q[HC_N_JOINTS]);
"""


_HELPERS = r"""
static hc_real dot3(const hc_real a[3], const hc_real b[3])
{ return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static hc_real det3(const hc_real M[9])
{
    return M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6])
         + M[2] * (M[3] * M[7] - M[4] * M[6]);
}

/* x = M^-1 y by Cramer's rule; M row-major 3x3 with det != 0 */
static void solve3(const hc_real M[9], const hc_real y[3], hc_real x[3])
{
    int k, j;
    hc_real det = det3(M), Mk[9];
    for (k = 0; k < 3; ++k) {
        for (j = 0; j < 9; ++j) Mk[j] = M[j];
        for (j = 0; j < 3; ++j) Mk[3 * j + k] = y[j];
        x[k] = det3(Mk) / det;
    }
}

/* the shifted elbow C_i (m) at joint angle t */
static void shifted_elbow(int i, hc_real t, hc_real C[3])
{
    hc_real s = RR + LA * (hc_real)cos(t);
    C[0] = s * U[3 * i] + A_OFF * T[3 * i];
    C[1] = s * U[3 * i + 1] + A_OFF * T[3 * i + 1];
    C[2] = -LA * (hc_real)sin(t);
}

/* rows A_x (3x3) and b (3) of the arm constraints at (P, theta), cad.kinematics.delta */
static void constraint_jacobians(const hc_real P[3], const hc_real th[3], hc_real A[9], hc_real b[3])
{
    int i, j;
    for (i = 0; i < 3; ++i) {
        hc_real C[3], w[3], wp[3], dC[3], y, rho, k;
        shifted_elbow(i, th[i], C);
        for (j = 0; j < 3; ++j) w[j] = P[j] - C[j];
        y = dot3(w, &T[3 * i]);
        for (j = 0; j < 3; ++j) wp[j] = w[j] - y * T[3 * i + j];
        rho = (hc_real)sqrt(dot3(wp, wp));
        k = G_OFF / (rho > 0 ? rho : HC_R(1.0));
        for (j = 0; j < 3; ++j) A[3 * i + j] = w[j] - k * wp[j];
        dC[0] = -LA * (hc_real)sin(th[i]) * U[3 * i];
        dC[1] = -LA * (hc_real)sin(th[i]) * U[3 * i + 1];
        dC[2] = -LA * (hc_real)cos(th[i]);
        b[i] = -(1 - k) * dot3(wp, dC);
    }
}

/* status of a consistent (P, theta): joint limits, then serial, then parallel */
static int pose_status(const hc_real P[3], const hc_real th[3])
{
    hc_real A[9], b[3], bmin;
    int i;
    for (i = 0; i < 3; ++i)
        if (th[i] < TH_MIN || th[i] > TH_MAX) return HC_ERR_RANGE;
    constraint_jacobians(P, th, A, b);
    bmin = (hc_real)fabs(b[0]);
    for (i = 1; i < 3; ++i) if ((hc_real)fabs(b[i]) < bmin) bmin = (hc_real)fabs(b[i]);
    if (bmin / (LA * LB) < EPS_SERIAL) return HC_ERR_SINGULAR;
    if ((hc_real)fabs(det3(A)) / (LB * LB * LB) < EPS_PARALLEL) return HC_ERR_SINGULAR;
    return HC_OK;
}
"""

_IK = r"""
/* arm i's elbow-out angle at P; 0 when it cannot reach */
static int arm_ik(int i, const hc_real P[3], hc_real *t)
{
    hc_real xp = dot3(P, &U[3 * i]) - RR, yp = dot3(P, &T[3 * i]) - A_OFF, z = P[2];
    hc_real rho, A, B, K, nrm, c, base, ac, r1, r2, r;
    *t = HC_R(0.0);
    if ((hc_real)fabs(yp) > LB * (1 + EPS_REACH)) return HC_ERR_CLOSURE;
    rho = LB * LB - yp * yp;
    rho = G_OFF + (hc_real)sqrt(rho > 0 ? rho : HC_R(0.0));
    A = 2 * LA * xp; B = -2 * LA * z;
    K = xp * xp + z * z + LA * LA - rho * rho;
    nrm = (hc_real)sqrt(A * A + B * B);
    c = K / (nrm > 0 ? nrm : HC_R(1.0));
    if ((hc_real)fabs(c) > 1 + EPS_REACH) return HC_ERR_CLOSURE;
    c = c > 1 ? HC_R(1.0) : (c < -1 ? HC_R(-1.0) : c);
    base = (hc_real)atan2(B, A);
    ac = (hc_real)acos(c);
    r1 = base + ac; r2 = base - ac;
    r = (hc_real)cos(r1) >= (hc_real)cos(r2) ? r1 : r2;
    *t = (hc_real)atan2(sin(r), cos(r));
    return HC_OK;
}

int hc_inverse(const hc_real P[3], hc_real theta[3])
{
    int i, bad = 0;
    for (i = 0; i < 3; ++i) bad |= arm_ik(i, P, &theta[i]);
    if (bad) { theta[0] = theta[1] = theta[2] = HC_R(0.0); return HC_ERR_CLOSURE; }
    return pose_status(P, theta);
}
"""

_FK = r"""
/* the lower intersection of the spheres of radius rad about the shifted elbows */
static int sphere_point(const hc_real th[3], hc_real rad, hc_real P[3])
{
    hc_real C0[3], C1[3], C2[3], a[3], b[3], n[3], M[9], rhs[3], P0[3], h2, nl, d[3];
    int j;
    shifted_elbow(0, th[0], C0); shifted_elbow(1, th[1], C1); shifted_elbow(2, th[2], C2);
    for (j = 0; j < 3; ++j) { a[j] = C1[j] - C0[j]; b[j] = C2[j] - C0[j]; }
    n[0] = a[1] * b[2] - a[2] * b[1]; n[1] = a[2] * b[0] - a[0] * b[2]; n[2] = a[0] * b[1] - a[1] * b[0];
    nl = (hc_real)sqrt(dot3(n, n));
    if (nl <= HC_R(1e-12) * LA * LA) return HC_ERR_CLOSURE;
    for (j = 0; j < 3; ++j) n[j] /= (n[2] < 0 ? -nl : nl);
    for (j = 0; j < 3; ++j) { M[j] = 2 * a[j]; M[3 + j] = 2 * b[j]; M[6 + j] = n[j]; }
    rhs[0] = dot3(C1, C1) - dot3(C0, C0);
    rhs[1] = dot3(C2, C2) - dot3(C0, C0);
    rhs[2] = dot3(n, C0);
    solve3(M, rhs, P0);
    for (j = 0; j < 3; ++j) d[j] = P0[j] - C0[j];
    h2 = rad * rad - dot3(d, d);
    if (h2 < -EPS_REACH * rad * rad) return HC_ERR_CLOSURE;
    h2 = (hc_real)sqrt(h2 > 0 ? h2 : HC_R(0.0));
    for (j = 0; j < 3; ++j) P[j] = P0[j] - h2 * n[j];
    return HC_OK;
}

/* arm constraints f_i = (rho_i - g)^2 + y_i^2 - L_b^2 at P */
static void residual(const hc_real P[3], const hc_real th[3], hc_real f[3])
{
    int i, j;
    for (i = 0; i < 3; ++i) {
        hc_real C[3], w[3], y, rho;
        shifted_elbow(i, th[i], C);
        for (j = 0; j < 3; ++j) w[j] = P[j] - C[j];
        y = dot3(w, &T[3 * i]);
        for (j = 0; j < 3; ++j) w[j] -= y * T[3 * i + j];
        rho = (hc_real)sqrt(dot3(w, w));
        f[i] = (rho - G_OFF) * (rho - G_OFF) + y * y - LB * LB;
    }
}

static int newton(const hc_real th[3], hc_real P[3])
{
    hc_real A[9], b[3], f[3], dx[3];
    int s, j;
    for (s = 0; s < NEWTON_STEPS; ++s) {
        constraint_jacobians(P, th, A, b);
        if ((hc_real)fabs(det3(A)) <= HC_R(1e-12) * LB * LB * LB) return HC_ERR_CLOSURE;
        residual(P, th, f);
        for (j = 0; j < 9; ++j) A[j] *= 2;
        solve3(A, f, dx);
        for (j = 0; j < 3; ++j) P[j] -= dx[j];
    }
    residual(P, th, f);
    for (j = 0; j < 3; ++j)
        if ((hc_real)fabs(f[j]) > EPS_RESIDUAL * LB * LB) return HC_ERR_CLOSURE;
    return HC_OK;
}

int hc_forward(const hc_real theta[3], hc_real X[3])
{
    hc_real P[3];
    int st = sphere_point(theta, LB + G_OFF, P);
    if (!st && G_OFF > 0) st = newton(theta, P);
    if (!st) st = pose_status(P, theta);
    if (st) return st;                  /* X untouched when theta is refused */
    X[0] = P[0]; X[1] = P[1]; X[2] = P[2];
    return HC_OK;
}
"""

_JAC = r"""
int hc_jacobian(const hc_real theta[3], hc_real Jx[9])
{
    hc_real P[3], A[9], b[3], col[3], x[3];
    int st = hc_forward(theta, P), i, k;
    if (st) return st;
    constraint_jacobians(P, theta, A, b);
    for (k = 0; k < 3; ++k) {          /* A_x x_dot + diag(b) theta_dot = 0 */
        col[0] = col[1] = col[2] = HC_R(0.0);
        col[k] = -b[k];
        solve3(A, col, x);
        for (i = 0; i < 3; ++i) Jx[3 * i + k] = x[i];
    }
    return HC_OK;
}

/* P (m), Jx = dX/dtheta (m/rad) and Jt = Jx^-1 (rad/m, rows J_i) at theta */
static int task_rates(const hc_real theta[3], hc_real P[3], hc_real Jx[9], hc_real Jt[9])
{
    hc_real unit[3], col[3];
    int st = hc_jacobian(theta, Jx), i, a;
    if (st) return st;
    st = hc_forward(theta, P);
    if (st) return st;
    for (a = 0; a < 3; ++a) {
        unit[0] = unit[1] = unit[2] = HC_R(0.0);
        unit[a] = HC_R(1.0);
        solve3(Jx, unit, col);
        for (i = 0; i < 3; ++i) Jt[3 * i + a] = col[i];
    }
    return HC_OK;
}

/* arm i at (P, theta) with J_i = Ji: e = dE_i/dtheta_i (m/rad); with the knee (G_OFF > 0)
 * n = t_i x k_i (k_i the unit in-plane direction elbow -> effector joint) and the knee's rate
 * q = (n - (n.e) J_i) / rho_i (rad/s per m/s), else n = q = 0 (cad.dynamics.delta.arm_rates) */
static void arm_rates(int i, const hc_real P[3], const hc_real th[3], const hc_real Ji[3],
                      hc_real e[3], hc_real n[3], hc_real q[3])
{
    hc_real C[3], w[3], k[3], y, rho, ne;
    const hc_real *t = &T[3 * i];
    int j;
    e[0] = -LA * (hc_real)sin(th[i]) * U[3 * i];
    e[1] = -LA * (hc_real)sin(th[i]) * U[3 * i + 1];
    e[2] = -LA * (hc_real)cos(th[i]);
    for (j = 0; j < 3; ++j) n[j] = q[j] = HC_R(0.0);
    if (!(G_OFF > 0)) return;
    shifted_elbow(i, th[i], C);
    for (j = 0; j < 3; ++j) w[j] = P[j] - C[j];
    y = dot3(w, t);
    for (j = 0; j < 3; ++j) w[j] -= y * t[j];
    rho = (hc_real)sqrt(dot3(w, w));
    for (j = 0; j < 3; ++j) k[j] = w[j] / rho;
    n[0] = t[1] * k[2] - t[2] * k[1]; n[1] = t[2] * k[0] - t[0] * k[2]; n[2] = t[0] * k[1] - t[1] * k[0];
    ne = dot3(n, e);
    for (j = 0; j < 3; ++j) q[j] = (n[j] - ne * Ji[j]) / rho;
}

/* tau = Jx^T grad_x V, V = g [m_e z_P + sum_i (m_arm z_G,i + m_knee z_K,i + m_lower (z_S,i + z_P) / 2)]
 * (z_S the rods' top ends: the elbow for G_OFF = 0; cad.dynamics.delta.gravity_force_N) */
int hc_gravity_torques(const hc_real theta[3], hc_real tau[3])
{
    hc_real Jx[9], Jt[9], P[3], F[3], e[3], n[3], q[3];
    int st = task_rates(theta, P, Jx, Jt), i, j;
    if (st) return st;
    F[0] = F[1] = HC_R(0.0);
    F[2] = M_EFF + HC_R(1.5) * M_LOWER;
    for (i = 0; i < 3; ++i) {
        arm_rates(i, P, theta, &Jt[3 * i], e, n, q);
        for (j = 0; j < 3; ++j)
            F[j] += e[2] * Jt[3 * i + j] * (M_ARM * COM_ARM / LA + HC_R(0.5) * M_LOWER + M_KNEE)
                  + n[2] * q[j] * (HC_R(0.5) * M_LOWER * G_OFF + M_KNEE * COM_KNEE);
    }
    for (i = 0; i < 3; ++i) tau[i] = G0 * (Jx[i] * F[0] + Jx[3 + i] * F[1] + Jx[6 + i] * F[2]);
    return HC_OK;
}

/* Lambda = M_EFF I + sum_i [(I_ARM + n_i^2 J_m,i) J_i J_i^T + (M_LOWER / 3) (G^T G + (G + G^T) / 2 + I)
 *          + M_KNEE G_k^T G_k + (I_KNEE - M_KNEE COM_KNEE^2) q q^T],
 * G = e J_i^T + G_OFF n q^T (the rods' top ends), G_k = e J_i^T + COM_KNEE n q^T (the knee's
 * centre); J_i = row i of dtheta/dx, e = dE_i/dtheta_i (cad.dynamics.delta.mass_matrix_kg) */
int hc_mass_matrix(const hc_real theta[3], hc_real M[9])
{
    hc_real Jx[9], Jt[9], P[3];
    int st = task_rates(theta, P, Jx, Jt), i, a, b;
    if (st) return st;
    for (a = 0; a < 9; ++a) M[a] = HC_R(0.0);
    for (a = 0; a < 3; ++a) M[4 * a] = M_EFF + M_LOWER;   /* effector, and the rods' I term */
    for (i = 0; i < 3; ++i) {
        const hc_real *Ji = &Jt[3 * i];
        hc_real e[3], n[3], q[3], ee, s, cJq, cqq;
        arm_rates(i, P, theta, Ji, e, n, q);
        ee = dot3(e, e);
        s = dot3(e, n);
        cJq = (M_LOWER / 3 * G_OFF + M_KNEE * COM_KNEE) * s;
        cqq = M_LOWER / 3 * G_OFF * G_OFF + I_KNEE;
        for (a = 0; a < 3; ++a)
            for (b = 0; b < 3; ++b)
                M[3 * a + b] += (ARM_AXIS[i] + (M_LOWER / 3 + M_KNEE) * ee) * Ji[a] * Ji[b]
                                + M_LOWER / 6 * (e[a] * Ji[b] + e[b] * Ji[a])
                                + cJq * (Ji[a] * q[b] + q[a] * Ji[b]) + cqq * q[a] * q[b]
                                + M_LOWER / 6 * G_OFF * (n[a] * q[b] + q[a] * n[b]);
    }
    return HC_OK;
}

int hc_apparent_mass(const hc_real q[HC_N_JOINTS], hc_real *mass_kg)
{
    (void)q; (void)mass_kg;
    return HC_ERR_RANGE; /* a delta's mass is a matrix: hc_mass_matrix */
}
"""



#: The delta's kinematic model (the family's ``firmware_model``).
DELTA = KinematicModel(
    kind="delta",
    frame=("the delta's base frame: origin at the base centre, z up, the effector below; task "
           "X = the effector centre (x, y, z); joints q_i = theta_i, motor i's angle from the "
           "horizontal radial u_i, positive down; IK branch elbow out"),
    spec_params=spec_params, forward=forward, jacobian=jacobian, com_rates=com_rates,
    mass_matrix=mass_matrix, c_source=c_source, poses_ok=poses_ok, poses_bad=poses_bad,
    workspace_radius_m=workspace_radius_m, gravity_extra=gravity_extra, n_translation=3,
    header_extra=HEADER_EXTRA,
    workspace_note="delta: half the smallest side of the workspace box",
)


def model(design) -> KinematicModel:
    """The family's ``firmware_model`` hook: :data:`DELTA`."""
    return DELTA


def reference_vectors(d: D.Delta, mass: DeltaMass, P_mm, force_N,
                      reflected_kg_m2=None) -> dict[str, np.ndarray]:
    """Reference values (SI) at effector points ``P_mm`` (N, 3) mm and forces ``force_N``
    (N, 3) N, from :mod:`cad.kinematics.delta` and :mod:`cad.dynamics.delta` (the mass
    matrix :func:`task_mass_kg`, ``reflected_kg_m2`` each arm's rotor through its ratio):
    {"P_m", "theta_rad" and "ik_status" (C codes) of the IK at P; "P_fk_m" and "fk_status"
    of the FK at those angles (the lower assembly mode: a point above the elbows' plane
    comes back mirrored); at the FK point, where ok (0 elsewhere): "Jx_m_per_rad" (N, 3, 3)
    = J^-1, "F_N", "tau_Nm" = J^-T F, "tau_gravity_Nm", "M_kg" (N, 3, 3)}."""
    P = np.asarray(P_mm, float).reshape(-1, 3)
    F = np.asarray(force_N, float).reshape(-1, 3)
    pose = D.ik(d, P)
    fwd = D.fk(d, pose.theta_rad)
    ok = fwd.ok & pose.ok
    Jx = np.zeros((len(P), 3, 3))
    tg = np.zeros_like(P)
    M = np.zeros((len(P), 3, 3))
    if ok.any():
        J, _ = D.jacobian_rad_per_m(d, fwd.P_mm[ok])
        Jx[ok] = np.linalg.inv(J)
        tg[ok] = gravity_torques_Nm(d, fwd.P_mm[ok], mass)
        M[ok] = task_mass_kg(d, fwd.P_mm[ok], mass, reflected_kg_m2)
    tau = np.einsum("nik,ni->nk", Jx, F)
    return {"P_m": P * MM, "theta_rad": pose.theta_rad, "ik_status": _codes(pose.status),
            "P_fk_m": fwd.P_mm * MM, "fk_status": _codes(fwd.status), "Jx_m_per_rad": Jx,
            "F_N": F, "tau_Nm": tau, "tau_gravity_Nm": tg, "M_kg": M}


def vectors_c(vec: dict[str, np.ndarray]) -> str:
    """The vectors as C99 array initialisers (``static const double V_<key>[]``, row-major)
    and ``#define V_N`` rows, for a test program that includes ``hapticad_device.h``."""
    out = [f"#define V_N {len(vec['P_m'])}"]
    for k, v in vec.items():
        flat = np.asarray(v, float).ravel()
        body = ", ".join(repr(float(x)) if math.isfinite(x) else "0.0" for x in flat)
        out.append(f"static const double V_{k}[] = {{{body}}};")
    return "\n".join(out) + "\n"
