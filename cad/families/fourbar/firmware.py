"""The four-bar's kinematic model for the generated firmware
(:class:`cad.firmware.model.KinematicModel`, :data:`MODEL`): loop closure on the design's
branch refusing angles outside the crank range, the Jacobian, the link COM rates for gravity,
the apparent mass (Hoeken paper eq 22), the C code, the test poses; and the family's firmware
hook :func:`files`. Numpy only (no CAD import)."""

from __future__ import annotations

import math

import numpy as np

from cad.dynamics.inertia import InertiaCoefficients, apparent_mass_matrix, equivalent_inertia
from cad.firmware import identify_c
from cad.firmware.csrc import JT_F, lit
from cad.firmware.model import KinematicModel, SpecParams, perp, rot
from cad.firmware.reference import STATUS
from cad.firmware.spec import body_from_report
from cad.kinematics import fourbar as k4
from cad.sim.identify_device import predict
from cad.sim.identify_kits import ONE_MOTOR
from cad.tolerances import TOGGLE_SIN


def fourbar_of(p: dict) -> k4.FourBar:
    """The :class:`~cad.kinematics.fourbar.FourBar` (mm) of the spec's ``params`` (m)."""
    return k4.FourBar(p["l1"] * 1e3, p["l2"] * 1e3, p["l3"] * 1e3, p["l4"] * 1e3, p["l5"] * 1e3,
                      p["le"] * 1e3, p["phi_e"], int(p["branch"]))


def state(spec, q):
    """(ok, P (N,2) m, J (N,2) m/rad, pose, a2, a3) of the crank angles q[:, 0] (range-checked
    as the C code)."""
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


def _com_rates(spec, q):
    """{body: (r_G (N,2) m, dr_G/dphi1 (N,2) m/rad)} of the crank, coupler and rocker."""
    ok, _, _, pose, a2, a3 = state(spec, q)
    b = spec.bodies
    rc = rot(pose.phi1_rad, b["crank"].com_m)
    A2 = pose.A2_mm * 1e-3
    ru = rot(pose.phi2_rad, b["coupler"].com_m)
    rr = rot(pose.phi3_rad, b["rocker"].com_m)
    A4 = np.asarray(pose.A4_mm) * 1e-3
    return ok, {"crank": (rc, perp(rc)),
                "coupler": (A2 + ru, perp(A2) + perp(ru) * a2[:, None]),
                "rocker": (A4 + rr, perp(rr) * a3[:, None])}


def forward(spec, q) -> tuple[np.ndarray, np.ndarray]:
    """(P (N, 2) m, status (N,)): the handle point, HC_ERR_RANGE outside the crank range."""
    ok, P, *_ = state(spec, q)
    return np.where(ok[:, None], P, 0.0), np.where(ok, 0, STATUS["HC_ERR_RANGE"])


def jacobian(spec, q) -> np.ndarray:
    """dP/dphi1 (N, 2, 1) m/rad (zeros outside the range)."""
    ok, _, J, *_ = state(spec, q)
    return np.where(ok[:, None], J, 0.0)[:, :, None]


def com_rates(spec, q):
    """(ok, {crank, coupler, rocker: (r_G (N,2) m, dr_G/dphi1 (N,2,1))})."""
    ok, rates = _com_rates(spec, q)
    return ok, {k: (r, d[:, :, None]) for k, (r, d) in rates.items()}


def mass_matrix(spec, q_ok, X_ok) -> np.ndarray:
    """M = J+^T D J+ (Hoeken paper eq 22, :func:`cad.dynamics.inertia.apparent_mass_matrix`,
    R0 axes) at ok crank angles."""
    p = spec.params
    fb = fourbar_of(p)
    H = InertiaCoefficients(p["H11"], p["H12"], p["H22"], p["H33"], p["beta2"])
    return apparent_mass_matrix(fb, k4.solve(fb, q_ok[:, 0]), H)


def apparent_mass_kg(spec, phi1: np.ndarray) -> np.ndarray:
    """Four-bar: D(phi1) / |J|^2, the mass felt along the path (kg; Hoeken paper eq 22 reads
    D J+^T J+ in the direction of J): :func:`cad.dynamics.inertia.equivalent_inertia`."""
    p = spec.params
    fb = fourbar_of(p)
    H = InertiaCoefficients(p["H11"], p["H12"], p["H22"], p["H33"], p["beta2"])
    pose = k4.solve(fb, phi1)
    J = k4.jacobian_mm_per_rad(fb, pose) * 1e-3
    return equivalent_inertia(fb, pose, H) / np.einsum("ni,ni->n", J, J)


def _params(design, report: dict) -> dict:
    fb = design.linkage
    mm = 1e-3
    return {"l1": fb.l1_mm * mm, "l2": fb.l2_mm * mm, "l3": fb.l3_mm * mm, "l4": fb.l4_mm * mm,
            "l5": fb.l5_mm * mm, "le": fb.le_mm * mm, "phi_e": fb.phi_e_rad,
            "branch": float(fb.branch), "q_min": design.phi1_min_rad,
            "q_max": design.phi1_max_rad, "H11": report["H11_kg_m2"],
            "H12": report["H12_kg_m2"], "H22": report["H22_kg_m2"], "H33": report["H33_kg_m2"],
            "beta2": math.radians(report["beta2_deg"])}


def spec_params(design, report: dict, device) -> SpecParams:
    """The four-bar's constants (the linkage, crank range, H11..H33 of report.json, half an
    encoder count of slack at the range ends) and its links' masses and COMs."""
    params = _params(design, report)
    params["q_slack"] = math.pi / device.encoder.counts_per_rev  # half a count at the range ends
    q_home = (0.5 * (design.phi1_min_rad + design.phi1_max_rad),)
    bodies = {k: body_from_report(report["links"][k]) for k in ("crank", "coupler", "rocker")}
    return SpecParams(params, q_home, bodies, 1, 2)


def poses_ok(spec, design, rng, n: int) -> np.ndarray:
    """``n`` crank angles uniform over the crank range."""
    p = spec.params
    return rng.uniform(p["q_min"], p["q_max"], (n, 1))


def poses_bad(spec, q_ok, rng, n: int) -> np.ndarray:
    """``n`` crank angles beyond either end of the range (and its half-count slack)."""
    p = spec.params
    span = p["q_max"] - p["q_min"]
    lo = p["q_min"] - p["q_slack"] - rng.uniform(1e-3, span, n // 2)
    hi = p["q_max"] + p["q_slack"] + rng.uniform(1e-3, span, n - n // 2)
    return np.concatenate([lo, hi])[:, None]


def workspace_radius_m(spec, design) -> float:
    """Half the stroke, |P(max) - P(min)| / 2 (m)."""
    P, _ = forward(spec, np.array([[spec.params["q_min"]], [spec.params["q_max"]]]))
    return float(np.linalg.norm(P[1] - P[0]) / 2)


def wall_normal(spec, qh) -> np.ndarray:
    """The direction of motion at home (the wall sketch's normal)."""
    return jacobian(spec, qh)[0][:2, 0]


def identify_files(design, report: dict, spec) -> dict[str, str]:
    """The identification routine (:mod:`cad.firmware.identify_c`), its constants from the
    same plan as the virtual bench (:func:`cad.sim.identify_device.predict`)."""
    H = InertiaCoefficients(report["H11_kg_m2"], report["H12_kg_m2"], report["H22_kg_m2"],
                            report["H33_kg_m2"], math.radians(report["beta2_deg"]))
    return identify_c.files(spec, predict(design, H, report).plan)


_FOURBAR_C = """
/* the loop closure on the design's branch (Hoeken paper eqs 3-11, atan2 form) */
typedef struct { hc_real c1, s1, c2, s2, c3, s3, s23, a2, a3; } hc_pose4_t;

static int hc_pose4(hc_real phi1, hc_pose4_t *p)
{
    hc_real dx, dy, A, B, C, R, ratio, phi2;
    if (!(HC_FABS(phi1) <= HC_R(1e4))) return HC_ERR_RANGE;  /* NaN, inf, no turn count */
    /* the same pose, in Q_MIN - Q_SLACK + [0, 2 pi); Q_SLACK = half an encoder count: a reading
     * of the crank at a range end rounds to within it (an encoder resolves no finer) */
    phi1 -= HC_TWO_PI * HC_FLOOR((phi1 - (Q_MIN - Q_SLACK)) / HC_TWO_PI);
    if (!(phi1 >= Q_MIN - Q_SLACK && phi1 <= Q_MAX + Q_SLACK)) return HC_ERR_RANGE;
    p->c1 = HC_COS(phi1); p->s1 = HC_SIN(phi1);
    dx = L1 * p->c1 - L5; dy = L1 * p->s1 - L4;             /* A2 - A4 */
    A = HC_R(2.0) * L2 * dx; B = HC_R(2.0) * L2 * dy;
    C = L3 * L3 - L2 * L2 - (dx * dx + dy * dy);
    R = HC_SQRT(A * A + B * B);
    if (!(R > HC_R(0.0))) return HC_ERR_CLOSURE;
    ratio = C / R;
    if (!(HC_FABS(ratio) <= HC_R(1.0) + HC_R(1e-12))) return HC_ERR_CLOSURE;
    if (ratio > HC_R(1.0)) ratio = HC_R(1.0);
    if (ratio < HC_R(-1.0)) ratio = HC_R(-1.0);
    phi2 = HC_ATAN2(B, A) + BRANCH * HC_ACOS(ratio);
    p->c2 = HC_COS(phi2); p->s2 = HC_SIN(phi2);
    p->c3 = (dx + L2 * p->c2) / L3; p->s3 = (dy + L2 * p->s2) / L3;  /* eqs 7-8 */
    p->s23 = p->s2 * p->c3 - p->c2 * p->s3;
    if (HC_FABS(p->s23) < TOGGLE_SIN) return HC_ERR_SINGULAR;        /* toggle */
    p->a2 = L1 * (p->s3 * p->c1 - p->c3 * p->s1) / (L2 * p->s23);   /* eq 11 */
    p->a3 = L1 * (p->s2 * p->c1 - p->c2 * p->s1) / (L3 * p->s23);
    return HC_OK;
}

int hc_forward(const hc_real q[1], hc_real X[2])
{
    hc_pose4_t p;
    int st = hc_pose4(q[0], &p);
    if (st) return st;
    X[0] = L1 * p.c1 + LE * (p.c2 * CE - p.s2 * SE);   /* eqs 9-10 */
    X[1] = L1 * p.s1 + LE * (p.s2 * CE + p.c2 * SE);
    return HC_OK;
}

int hc_jacobian(const hc_real q[1], hc_real J[2])
{
    hc_pose4_t p;
    int st = hc_pose4(q[0], &p);
    if (st) return st;
    J[0] = -L1 * p.s1 - LE * p.a2 * (p.s2 * CE + p.c2 * SE);   /* eq 12 */
    J[1] = L1 * p.c1 + LE * p.a2 * (p.c2 * CE - p.s2 * SE);
    return HC_OK;
}

""" + JT_F + """
int hc_gravity_torques(const hc_real q[1], hc_real tau[1])
{
    hc_pose4_t p;
    hc_real rx, ry, dV;
    int st = hc_pose4(q[0], &p);
    if (st) return st;
    /* crank: r = R(phi1) c, dr/dphi1 = perp(r) */
    rx = p.c1 * CX_CRANK - p.s1 * CY_CRANK; ry = p.s1 * CX_CRANK + p.c1 * CY_CRANK;
    dV = -M_CRANK * (GX * -ry + GY * rx);
    /* coupler: r = A2 + R(phi2) c, dr/dphi1 = perp(A2) + perp(R(phi2) c) a2 */
    rx = p.c2 * CX_COUPLER - p.s2 * CY_COUPLER; ry = p.s2 * CX_COUPLER + p.c2 * CY_COUPLER;
    dV -= M_COUPLER * (GX * (-L1 * p.s1 - ry * p.a2) + GY * (L1 * p.c1 + rx * p.a2));
    /* rocker: r = A4 + R(phi3) c, dr/dphi1 = perp(R(phi3) c) a3 */
    rx = p.c3 * CX_ROCKER - p.s3 * CY_ROCKER; ry = p.s3 * CX_ROCKER + p.c3 * CY_ROCKER;
    dV -= M_ROCKER * (GX * -ry + GY * rx) * p.a3;
    tau[0] = dV;
    return HC_OK;
}

int hc_apparent_mass(const hc_real q[1], hc_real *mass_kg)
{
    /* D(phi1) (Hoeken paper eqs 14-15 with the coupler COM angle beta2) over |J|^2 */
    hc_pose4_t p;
    hc_real J[2], cos12b, D;
    int st = hc_pose4(q[0], &p);
    if (st) return st;
    hc_jacobian(q, J);
    /* cos(phi1 - phi2 - beta2) */
    cos12b = (p.c1 * p.c2 + p.s1 * p.s2) * CB2 + (p.s1 * p.c2 - p.c1 * p.s2) * SB2;
    D = H11 + HC_R(2.0) * H12 * cos12b * p.a2 + H22 * p.a2 * p.a2 + H33 * p.a3 * p.a3;
    *mass_kg = D / (J[0] * J[0] + J[1] * J[1]);
    return HC_OK;
}

int hc_mass_matrix(const hc_real q[1], hc_real M[4])
{
    /* M = J+^T D J+ = m_app J J^T / |J|^2 (Hoeken paper eq 22), R0 axes */
    hc_real J[2], m, n2;
    int st = hc_apparent_mass(q, &m);
    if (st) return st;
    hc_jacobian(q, J);
    n2 = J[0] * J[0] + J[1] * J[1];
    M[0] = m * J[0] * J[0] / n2; M[1] = M[2] = m * J[0] * J[1] / n2; M[3] = m * J[1] * J[1] / n2;
    return HC_OK;
}
"""


def c_source(spec) -> str:
    """The four-bar's part of hapticad_device.c (constants + :data:`_FOURBAR_C`)."""
    p, b = spec.params, spec.bodies
    g = spec.gravity_m_s2 or (0.0, 0.0)
    H = spec.params
    consts = "\n".join(f"#define {k} {lit(v)}" for k, v in {
        "L1": p["l1"], "L2": p["l2"], "L3": p["l3"], "L4": p["l4"], "L5": p["l5"],
        "LE": p["le"], "CE": math.cos(p["phi_e"]),
        "SE": math.sin(p["phi_e"]), "BRANCH": p["branch"],
        "Q_MIN": p["q_min"], "Q_MAX": p["q_max"], "Q_SLACK": p["q_slack"], "TOGGLE_SIN": TOGGLE_SIN,
        "GX": g[0], "GY": g[1],
        "M_CRANK": b["crank"].mass_kg, "CX_CRANK": b["crank"].com_m[0],
        "CY_CRANK": b["crank"].com_m[1],
        "M_COUPLER": b["coupler"].mass_kg, "CX_COUPLER": b["coupler"].com_m[0],
        "CY_COUPLER": b["coupler"].com_m[1],
        "M_ROCKER": b["rocker"].mass_kg, "CX_ROCKER": b["rocker"].com_m[0],
        "CY_ROCKER": b["rocker"].com_m[1],
        "H11": H["H11"], "H12": H["H12"], "H22": H["H22"], "H33": H["H33"],
        "CB2": math.cos(H["beta2"]), "SB2": math.sin(H["beta2"]),
    }.items())
    return consts + _FOURBAR_C


MODEL = KinematicModel(
    kind="fourbar",
    frame=("R0 of the Hoeken paper (Fig. 1): origin at the crank pivot A1, rocker pivot "
    "A4 = (l5, l4), z out of the plane; task X = handle point P = (x, y); "
    "joint q0 = phi1, the crank angle from x0"),
    spec_params=spec_params, forward=forward, jacobian=jacobian, com_rates=com_rates,
    mass_matrix=mass_matrix, c_source=c_source, poses_ok=poses_ok, poses_bad=poses_bad,
    workspace_radius_m=workspace_radius_m, apparent_mass_kg=apparent_mass_kg,
    wall_normal=wall_normal, identify=identify_files, identification=ONE_MOTOR,
)


def model(design) -> KinematicModel:
    """The family's ``firmware_model`` hook: :data:`MODEL` for every four-bar."""
    return MODEL
