"""PowerMouse: cubic flotor with six flat coils, its current-to-wrench map and isotropy.

Pure numpy. Isotropy paper section 5 (Fig. 6, Table 4): a handle on a cubic
"flotor" whose six faces carry the flat coils of six Lorentz actuators; 24
magnets on the stator (4 per actuator: an inner and an outer pair, see
:mod:`cad.actuators.voicecoil`). The paper's figure is lost; the layout here
is our reconstruction, chosen so that the map is isotropic "by design":

Flotor frame: origin at the cube centre, axes normal to the faces. The coil
on face n (outward normal) pushes along f(n), cyclically
    +-x faces -> f = y,   +-y faces -> f = z,   +-z faces -> f = x,
applied at the face centre p = a n (a: centre to coil mid-plane). The
wrench column of actuator i is g [f_i; p_i x f_i], so each force axis is
driven by an opposite pair whose torques a n x f cancel in sum and add in
difference: W W^T = 2 g^2 diag(1, 1, 1, a^2, a^2, a^2). Singular values:
sqrt(2) g three times (force, N/A) and sqrt(2) g a three times (torque, N m/A).

Each actuator's own frame (voicecoil convention) is R_flotor_act = [f, n x f, n]:
x = force, y = leg-A current, z = outward normal = polarisation of pair A.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from cad import tolerances as tol
from cad.errors import DesignError, SingularJacobianError

#: Faces in a fixed order (actuator index 0..5).
FACES = ("+x", "-x", "+y", "-y", "+z", "-z")
_AXES = {"x": np.array([1.0, 0, 0]), "y": np.array([0, 1.0, 0]), "z": np.array([0, 0, 1.0])}
#: Force axis of the coil in each face pair (cyclic layout, see module docstring).
_FORCE_AXIS = {"x": "y", "y": "z", "z": "x"}
#: Standard gravity (m/s^2) for accelerations quoted in G.
G0_M_S2 = 9.80665


@dataclass(frozen=True)
class CoilPlacement:
    """One face coil in the flotor frame.

    face: "+x" etc.; normal: outward unit normal (3,); force_dir: unit force
    direction for positive current (3,); centre_mm: coil centre (3,) at the
    coil mid-plane; R_flotor_act: (3,3) columns = actuator x (force), y (leg-A
    current), z (normal).
    """

    face: str
    normal: np.ndarray
    force_dir: np.ndarray
    centre_mm: np.ndarray

    @property
    def R_flotor_act(self) -> np.ndarray:
        return np.column_stack([self.force_dir, np.cross(self.normal, self.force_dir), self.normal])


def coil_layout(coil_plane_half_mm: float) -> tuple[CoilPlacement, ...]:
    """The six coils of the cyclic isotropic layout (module docstring).

    coil_plane_half_mm: a, cube centre to the coil mid-plane (> 0).
    """
    if not coil_plane_half_mm > 0:
        raise DesignError("coil_plane_half_mm", f"must be > 0, got {coil_plane_half_mm!r}")
    out = []
    for face in FACES:
        sign = 1.0 if face[0] == "+" else -1.0
        n = sign * _AXES[face[1]]
        f = _AXES[_FORCE_AXIS[face[1]]].copy()
        out.append(CoilPlacement(face, n, f, coil_plane_half_mm * n))
    return tuple(out)


def wrench_map(coils, gain_N_per_A, about_mm=(0.0, 0.0, 0.0)) -> np.ndarray:
    """6x6 current-to-wrench map W: [F (N); tau (N m)] = W @ I (A).

    coils: CoilPlacement sequence (6); gain_N_per_A: scalar or (6,) actuator
    force per ampere; about_mm: (3,) point the torque is taken about (flotor frame).
    Column i = g_i [f_i; (p_i - o) x f_i] with lengths in m.
    A gain of 0 (a coil missing or disconnected) gives a zero column; :func:`isotropy`
    names it. Gains and the point must be finite (DesignError).
    """
    try:
        g = np.broadcast_to(np.asarray(gain_N_per_A, dtype=float), (len(coils),))
    except ValueError:
        raise DesignError(
            "gain_N_per_A",
            f"must be one gain or one per coil ({len(coils)}), got shape {np.shape(gain_N_per_A)}",
        ) from None
    if not np.all(np.isfinite(g)):
        raise DesignError("gain_N_per_A", f"must be finite, got {g.tolist()}")
    o = np.asarray(about_mm, dtype=float)
    if o.shape != (3,) or not np.all(np.isfinite(o)):
        raise DesignError("about_mm", f"must be a finite (3,) point, got {about_mm!r}")
    W = np.zeros((6, len(coils)))
    for i, c in enumerate(coils):
        r_m = (c.centre_mm - o) * 1e-3
        W[:3, i] = g[i] * c.force_dir
        W[3:, i] = g[i] * np.cross(r_m, c.force_dir)
    return W


@dataclass(frozen=True)
class Isotropy:
    """Singular values of W split into force and torque groups.

    singular_values: all six, descending; force_sv: singular values of the
    force block W[:3] (N per ampere-turn); torque_sv: of the torque block W[3:];
    force_spread / torque_spread: (max - min) / max within each group;
    coupling: ||W[:3] W[3:]^T|| / (||W[:3]|| ||W[3:]||), 0 when force and
    torque are decoupled (then the groups are exactly the singular values).
    """

    singular_values: np.ndarray
    force_sv: np.ndarray
    torque_sv: np.ndarray
    force_spread: float
    torque_spread: float
    coupling: float


def _require_full_rank(W: np.ndarray, faces) -> None:
    """SingularJacobianError naming what is lost when W cannot produce every wrench.

    Rank is judged with the force rows and the torque rows each divided by their
    largest entry (they carry N/A and N m/A: a small flotor has legitimately small
    torque rows), against cad.tolerances.PINV_RCOND.
    """
    n = W.shape[1]
    names = (
        [str(f) for f in faces]
        if faces is not None and len(faces) == n
        else [f"#{i}" for i in range(n)]
    )
    zero = [names[i] for i in range(n) if not np.any(W[:, i])]
    if n < 6 or zero:
        what = f"coil(s) on {', '.join(zero)} produce no wrench (gain 0)" if zero else ""
        if n < 6:
            what = (what + "; " if what else "") + f"only {n} coils for 6 DOF"
        raise SingularJacobianError(
            f"the current-to-wrench map is rank deficient: {what}; the flotor cannot be "
            "driven (or levitated) in every direction"
        )
    Wn = W.copy()
    for rows in (slice(0, 3), slice(3, 6)):
        m = np.abs(Wn[rows]).max()
        if m > 0:
            Wn[rows] /= m
    U, sv, Vt = np.linalg.svd(Wn)
    if sv[-1] <= tol.PINV_RCOND * sv[0]:
        u, v = U[:, -1], Vt[-1]
        lost = ", ".join(
            f"{lab} {c:+.2f}"
            for lab, c in zip(("Fx", "Fy", "Fz", "Tx", "Ty", "Tz"), u, strict=True)
            if abs(c) > 1e-3
        )
        coils = ", ".join(f"{names[i]} {v[i]:+.2f}" for i in range(n) if abs(v[i]) > 1e-3)
        raise SingularJacobianError(
            f"the current-to-wrench map is rank deficient (sigma_min / sigma_max = "
            f"{sv[-1] / sv[0]:.1e}): no currents produce the wrench direction [{lost}]; "
            f"the currents [{coils}] produce no wrench (coils duplicated or parallel)"
        )


def isotropy(W: np.ndarray, faces=FACES) -> Isotropy:
    """Isotropy of a 6x6 wrench map (isotropy paper section 5: "two sets of equal singular values").

    faces: labels of W's columns (default :data:`FACES`, the order of
    :func:`coil_layout`), quoted in errors. A map that cannot produce every wrench
    (a coil missing, a zero gain, duplicated or parallel coils) raises
    :class:`SingularJacobianError` naming the coils and the lost wrench direction;
    a non-finite map or a shape other than (6, n) is a :class:`DesignError`.
    """
    W = np.asarray(W, dtype=float)
    if W.ndim != 2 or W.shape[0] != 6 or W.shape[1] > 6:
        raise DesignError(
            "wrench_map", f"must be 6x6 (rows F, tau; one column per coil), got shape {W.shape}"
        )
    if not np.all(np.isfinite(W)):
        raise DesignError("wrench_map", "has non-finite entries")
    _require_full_rank(W, faces)
    sv = np.linalg.svd(W, compute_uv=False)
    fs = np.linalg.svd(W[:3], compute_uv=False)
    ts = np.linalg.svd(W[3:], compute_uv=False)
    cpl = np.linalg.norm(W[:3] @ W[3:].T) / (np.linalg.norm(W[:3]) * np.linalg.norm(W[3:]))
    return Isotropy(
        singular_values=sv,
        force_sv=fs,
        torque_sv=ts,
        force_spread=float((fs.max() - fs.min()) / fs.max()),
        torque_spread=float((ts.max() - ts.min()) / ts.max()),
        coupling=float(cpl),
    )


# ------------------------------------------------------------ stator magnets


@dataclass(frozen=True)
class MagnetBox:
    """One stator magnet: centre (3,) mm and R_flotor_act (3,3) of its actuator;
    dims_mm (3,) along the actuator axes (w_m, l_m, t_m); pol_T (3,) in the flotor frame;
    actuator index and role ("inner"/"outer", "A"/"B")."""

    centre_mm: np.ndarray
    R: np.ndarray
    dims_mm: np.ndarray
    pol_T: np.ndarray
    actuator: int
    role: str


def stator_magnets(
    coils,
    gap_mm: float,
    magnet_length_mm: float,
    magnet_width_mm: float,
    magnet_thickness_mm: float,
    br_T: float,
) -> tuple[MagnetBox, ...]:
    """The 24 stator magnets: per actuator an inner and an outer pair (A at x_act = +w/2, B at -w/2).

    Pair A is polarised along +n (outward), pair B along -n; the inner magnet
    of each pair lies between z_act = a - d/2 - t and a - d/2, the outer
    between a + d/2 and a + d/2 + t. Both magnets of a pair have the same
    polarisation, so the gap field over leg A is +B n and over leg B -B n.
    """
    out = []
    d, w, lm, t = gap_mm, magnet_width_mm, magnet_length_mm, magnet_thickness_mm
    for i, c in enumerate(coils):
        R = c.R_flotor_act
        a = float(np.dot(c.centre_mm, c.normal))
        for pair, xs, s in (("A", w / 2, 1.0), ("B", -w / 2, -1.0)):
            for role, zc in (("inner", a - d / 2 - t / 2), ("outer", a + d / 2 + t / 2)):
                centre = R @ np.array([xs, 0.0, zc])
                out.append(
                    MagnetBox(
                        centre, R, np.array([w, lm, t]), s * br_T * c.normal, i, f"{role}-{pair}"
                    )
                )
    return tuple(out)


def ideal_gap_field_fn(magnets, bg_T: float, gap_mm: float) -> Callable[[np.ndarray], np.ndarray]:
    """Uniform-field model (eq 8's assumptions) built from the stator magnets alone.

    B = bg_T * (polarisation direction of the pair) inside the prism between
    the inner and outer magnet of each pair (the magnet footprint across the
    gap d), zero elsewhere (assumption ii: no fringing). Returns B(points_mm
    (M,3)) -> (M,3) T in the flotor frame.
    """
    pairs = {}
    for m in magnets:
        pairs.setdefault((m.actuator, m.role.split("-")[1]), []).append(m)
    prisms = []
    for ms in pairs.values():
        inner = next(m for m in ms if m.role.startswith("inner"))
        outer = next(m for m in ms if m.role.startswith("outer"))
        centre = 0.5 * (inner.centre_mm + outer.centre_mm)
        half = 0.5 * np.array([inner.dims_mm[0], inner.dims_mm[1], gap_mm])
        prisms.append((centre, inner.R, half, bg_T * inner.pol_T / np.linalg.norm(inner.pol_T)))

    def B(points_mm):
        P = np.atleast_2d(np.asarray(points_mm, dtype=float))
        out = np.zeros_like(P)
        for centre, R, half, b in prisms:
            local = (P - centre) @ R  # actuator axes
            inside = np.all(np.abs(local) <= half + 1e-12, axis=1)
            out[inside] += b
        return out

    return B


def coil_current_elements(
    coil: CoilPlacement,
    magnet_length_mm: float,
    magnet_width_mm: float,
    coil_width_mm: float,
    n_turns_model: int = 8,
    n_seg_leg: int = 20,
    n_seg_arc: int = 16,
    n_layers: int = 3,
):
    """Filament model of one racetrack coil: midpoints (M,3) mm and length vectors dl (M,3) mm.

    The coil's straight legs are w_m wide (x_act in [0, w] and [-w, 0]) and
    l_m long, joined by half-annuli (radii 0..w) at y_act = +-l_m/2; d_c
    thick. ``n_turns_model`` filaments across the leg width and ``n_layers``
    across d_c each carry 1/(n_turns_model n_layers) of the ampere-turns;
    positive current runs +y_act in leg A. Total current-weighted length per
    unit ampere-turn: 2 l_m + pi w_m (mean turn), eta_geom = 2 l_m/(2 l_m + pi w_m).
    """
    w, lm = magnet_width_mm, magnet_length_mm
    R = coil.R_flotor_act
    mids, dls = [], []
    share = 1.0 / (n_turns_model * n_layers)
    zs = (np.arange(n_layers) + 0.5) / n_layers * coil_width_mm - coil_width_mm / 2
    for k in range(n_turns_model):
        r = (k + 0.5) / n_turns_model * w  # filament radius (distance from the coil axis x_act = 0)
        ys = np.linspace(-lm / 2, lm / 2, n_seg_leg + 1)
        for z in zs:
            # leg A at x = +r going +y, leg B at x = -r going -y
            for x, direction in ((r, 1.0), (-r, -1.0)):
                y0, y1 = (ys[:-1], ys[1:]) if direction > 0 else (ys[1:], ys[:-1])
                m = np.stack([np.full(n_seg_leg, x), 0.5 * (y0 + y1), np.full(n_seg_leg, z)], 1)
                d = np.stack([np.zeros(n_seg_leg), y1 - y0, np.zeros(n_seg_leg)], 1)
                mids.append(m)
                dls.append(d * share)
            # end arcs: from leg A end (r, l/2) over the top to leg B (-r, l/2), and back at the bottom
            for yc, th0, th1 in ((lm / 2, 0.0, np.pi), (-lm / 2, np.pi, 2 * np.pi)):
                th = np.linspace(th0, th1, n_seg_arc + 1)
                p = np.stack([r * np.cos(th), yc + r * np.sin(th), np.full_like(th, z)], 1)
                mids.append(0.5 * (p[1:] + p[:-1]))
                dls.append((p[1:] - p[:-1]) * share)
    M = np.concatenate(mids) @ R.T + coil.centre_mm
    D = np.concatenate(dls) @ R.T
    return M, D


def lorentz_wrench(coils, currents_At, field_fn, elements_fn, about_mm=(0.0, 0.0, 0.0), pose=None):
    """Wrench [F (N); tau (N m)] on the flotor as a finite sum of I dl x B over filaments.

    coils: CoilPlacement (6); currents_At: (6,) ampere-turns per coil;
    field_fn: B(points_mm (M,3)) -> (M,3) T (stator frame = flotor frame at the
    nominal pose); elements_fn(coil) -> (mids_mm, dl_mm) per unit ampere-turn;
    pose: optional (R (3,3), t_mm (3,)) moving the flotor (points x -> R x + t);
    torque about ``about_mm`` carried with the flotor.
    """
    o = np.asarray(about_mm, dtype=float)
    Rp, tp = (
        (np.eye(3), np.zeros(3))
        if pose is None
        else (np.asarray(pose[0], float), np.asarray(pose[1], float))
    )
    F = np.zeros(3)
    T = np.zeros(3)
    o_w = Rp @ o + tp
    for c, amp_turns in zip(coils, currents_At, strict=True):
        mids, dl = elements_fn(c)
        mids = mids @ Rp.T + tp
        dl = dl @ Rp.T
        dF = amp_turns * np.cross(dl * 1e-3, field_fn(mids))  # N
        F += dF.sum(axis=0)
        T += np.cross((mids - o_w) * 1e-3, dF).sum(axis=0)
    return np.concatenate([F, T])


def peak_force_N(actuator_peak_force_N: float) -> float:
    """Largest force the flotor can produce along ANY direction with zero torque (N).

    Zero torque forces equal currents in each opposite pair, so F = 2 F_act
    (c1 x + c2 y + c3 z) with |c_i| <= 1: a cube whose smallest support is
    2 F_act (along the axes; 2 sqrt(3) F_act along the diagonals).
    """
    f = float(actuator_peak_force_N)
    if not (np.isfinite(f) and f >= 0):
        raise DesignError(
            "actuator_peak_force_N", f"must be finite and >= 0, got {actuator_peak_force_N!r}"
        )
    return 2.0 * f


def peak_acceleration_m_s2(actuator_peak_force_N: float, moving_mass_kg: float) -> float:
    """Guaranteed peak acceleration (m/s^2) = peak_force_N / moving mass (Table 4: > 10 G)."""
    if not (np.isfinite(moving_mass_kg) and moving_mass_kg > 0):
        raise DesignError("moving_mass_kg", f"must be > 0, got {moving_mass_kg!r}")
    return peak_force_N(actuator_peak_force_N) / moving_mass_kg


def rot_about(axis, angle_rad: float) -> np.ndarray:
    """Rotation matrix about a unit axis (Rodrigues)."""
    k = np.asarray(axis, dtype=float)
    k = k / np.linalg.norm(k)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle_rad) * K + (1 - np.cos(angle_rad)) * K @ K


def workspace_poses(range_mm: float, range_deg: float, *, combined: bool = False):
    """Extreme poses of the motion range as (label, R (3,3), t_mm (3,)).

    Translations: the 26 vertices/edge/face points of the cube |t_i| <= range_mm
    (no rotation); rotations: +-range about the 3 axes and the 4 body diagonals
    and 6 face diagonals (no translation). combined=True adds translation
    vertices combined with rotations (not part of the paper's stated range).
    """
    poses = []
    rng = np.deg2rad(range_deg)
    for i in (-1, 0, 1):
        for j in (-1, 0, 1):
            for k in (-1, 0, 1):
                if (i, j, k) != (0, 0, 0):
                    poses.append(
                        (f"t{i:+d}{j:+d}{k:+d}", np.eye(3), range_mm * np.array([i, j, k], float))
                    )
    axes = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1), (1, 1, -1), (1, -1, 1), (-1, 1, 1)]
    axes += [(1, 1, 0), (1, -1, 0), (1, 0, 1), (1, 0, -1), (0, 1, 1), (0, 1, -1)]
    for ax in axes:
        for s in (1, -1):
            poses.append((f"r{ax}{'+' if s > 0 else '-'}", rot_about(ax, s * rng), np.zeros(3)))
    if combined:
        for i in (-1, 1):
            for j in (-1, 1):
                for k in (-1, 1):
                    for ax in axes[:3]:
                        for s in (1, -1):
                            poses.append(
                                (
                                    f"c{i:+d}{j:+d}{k:+d}{ax}{s:+d}",
                                    rot_about(ax, s * rng),
                                    range_mm * np.array([i, j, k], float),
                                )
                            )
    return poses


@dataclass(frozen=True)
class Excursion:
    """Largest lateral excursion of a point of the diagonal (1,1,1)/sqrt3 over the motion
    the coil gaps allow (:func:`diagonal_excursion_mm`): ``excursion_mm`` and the pose that
    gives it, ``R`` (3x3, about the cube centre) and ``t_mm``."""

    excursion_mm: float
    R: np.ndarray
    t_mm: np.ndarray


def _fibonacci_sphere(n: int) -> np.ndarray:
    i = np.arange(n) + 0.5
    phi, ga = np.arccos(1 - 2 * i / n), np.pi * (1 + 5**0.5) * i
    return np.stack([np.cos(ga) * np.sin(phi), np.sin(ga) * np.sin(phi), np.cos(phi)], 1)


def _rotations(range_deg: float, n_dirs: int, n_steps: int) -> np.ndarray:
    """Rotation matrices ``(n_dirs * n_steps, 3, 3)`` about Fibonacci-sphere axes through
    the cube centre, angles 0..range_deg (Rodrigues)."""
    ax = _fibonacci_sphere(n_dirs)
    ang = np.repeat(np.deg2rad(range_deg) * np.linspace(0.0, 1.0, n_steps), n_dirs)
    k = np.tile(ax, (n_steps, 1))
    K = np.zeros((len(k), 3, 3))
    K[:, 0, 1], K[:, 0, 2], K[:, 1, 2] = -k[:, 2], k[:, 1], -k[:, 0]
    K -= K.transpose(0, 2, 1)
    s, c = np.sin(ang)[:, None, None], np.cos(ang)[:, None, None]
    return np.eye(3) + s * K + (1 - c) * K @ K


def gap_vertices_mm(coils, magnet_width_mm, magnet_length_mm, gap_mm, coil_width_mm, Rs):
    """Vertices ``(len(Rs), 8, 3)`` (mm) of the translations the coil gaps allow with each
    rotation of ``Rs`` (about the cube centre): the flotor's outer face of each coil
    (n.x = a + d_c/2) must stay inside the outer magnets' inner faces and its inner face
    (a - d_c/2) outside the inner magnets' (n.x = a -+ d/2), at the corners of the magnets'
    footprint (+-w_m, +-l_m/2 in the coil frame), with the face normal n' = R n exactly. For
    a fixed R those are pairs of parallel planes per axis, so the allowed set is a
    parallelepiped: its 8 corners are returned (exact for flat faces against the magnets)."""
    a = coils[0].centre_mm @ coils[0].normal
    up, inn = {}, {}
    for c in coils:
        n = c.normal
        corners = [c.centre_mm + c.R_flotor_act @ (sx * magnet_width_mm, sy * magnet_length_mm / 2, 0)
                   for sx in (-1, 1) for sy in (-1, 1)]
        out_m = np.array([p + n * gap_mm / 2 for p in corners])
        in_m = np.array([p - n * gap_mm / 2 for p in corners])
        nn = Rs @ n  # (N, 3)
        up[c.face] = (nn @ out_m.T).min(axis=1) - (a + coil_width_mm / 2)
        inn[c.face] = (a - coil_width_mm / 2) - (nn @ in_m.T).max(axis=1)
    U = np.stack([np.minimum(up[f"+{x}"], inn[f"-{x}"]) for x in "xyz"], 1)
    L = np.stack([np.minimum(up[f"-{x}"], inn[f"+{x}"]) for x in "xyz"], 1)
    N = Rs.transpose(0, 2, 1)  # rows: R e_x, R e_y, R e_z
    Ninv = np.linalg.inv(N)
    signs = np.array([[sx, sy, sz] for sx in (0, 1) for sy in (0, 1) for sz in (0, 1)])
    v = np.where(signs[None, :, :] == 1, U[:, None, :], -L[:, None, :])  # (N, 8, 3)
    return np.einsum("nij,nkj->nki", Ninv, v)


def diagonal_excursion_mm(coils, magnet_width_mm, magnet_length_mm, gap_mm, coil_width_mm,
                          range_mm, range_deg, s_mm, backoff_mm: float = 0.0,
                          n_dirs: int = 1500, n_steps: int = 11) -> Excursion:
    """Largest distance from the diagonal (1,1,1)/sqrt3 of the flotor's point ``s_mm`` along
    it (mm), over every pose the coil gaps allow (:func:`gap_vertices_mm`, the gaps less
    ``backoff_mm``) within +-range_mm per axis and rotations up to range_deg about any axis
    through the cube centre. For the handle stem in the housing's corner hole and the stator
    post in the flotor's corner hole (the relative motion is the same, reversed).

    The distance is convex in the translation, so for each rotation (Fibonacci-sphere axes
    x ``n_steps`` angles) its maximum is at a vertex of the allowed parallelepiped, or of
    the +-range_mm box, whichever gives less (the allowed set lies in both). Pure numpy."""
    u = np.ones(3) / np.sqrt(3.0)
    Rs = _rotations(range_deg, n_dirs, n_steps)
    Vg = gap_vertices_mm(coils, magnet_width_mm, magnet_length_mm, gap_mm - 2 * backoff_mm,
                         coil_width_mm, Rs)
    box = range_mm * np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    rot = (Rs @ (s_mm * u)) - s_mm * u  # (N, 3)

    def perp(T):  # (N, 8, 3) translations -> distances from the diagonal
        d = T + rot[:, None, :]
        return np.linalg.norm(d - (d @ u)[..., None] * u, axis=-1)

    dg, db = perp(Vg), perp(np.broadcast_to(box, Vg.shape))
    per_R = np.minimum(dg.max(axis=1), db.max(axis=1))
    i = int(np.argmax(per_R))
    T = Vg if dg[i].max() <= db[i].max() else np.broadcast_to(box, Vg.shape)
    j = int(np.argmax(perp(T)[i]))
    return Excursion(float(per_R[i]), Rs[i], np.array(T[i, j]))
