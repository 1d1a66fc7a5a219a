"""Voice-coil gap field from magpylib's exact cuboid fields, back iron as image magnets.

magpylib (and the optional magpylib-material-response) are imported lazily
inside the functions so that ``import cad.actuators`` stays light.

Frame and dimensions: see :mod:`cad.actuators.voicecoil` (z gap normal,
x actuation, y along the magnet length; mm; full magnet dimensions).

Ideal iron plates at z = +-(d/2 + t_m) are replaced by their images: two
parallel ideal plates give a periodic stack of 2 t_m slabs (magnet + first
image), period d + 2 t_m, all polarised alike (a magnet and its image in a
mu -> infinity plane share the polarisation perpendicular to the plane).
``n_slabs = 1`` is the paper's eq (9) configuration (one image per plate).
magpylib's field is length-unit free for magnets (its docstring: "independent
of the length units chosen"), so positions and dimensions stay in mm.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cad.actuators import voicecoil as vc  # a cycle: vc's names are read at call time only

#: Image slabs per side in the magpylib model: with the opposite-polarity
#: neighbour pair the far slabs cancel as quadrupoles (tail ~ 1/K^4), so 32
#: slabs leave < 1e-6 relative (measured in cad/bench/voicecoil.py).
MAGPYLIB_IMAGE_SLABS = 32


@dataclass(frozen=True)
class CuboidSet:
    """Uniformly polarised cuboids, axis-aligned (plain arrays).

    centres_mm: (N,3) actuator frame; dims_mm: (N,3) full side lengths (x,y,z);
    pol_T: (N,3) polarisation J (T).
    """

    centres_mm: np.ndarray
    dims_mm: np.ndarray
    pol_T: np.ndarray

    def __len__(self) -> int:
        return len(self.centres_mm)


def image_stack(
    gap_mm: float,
    length_mm: float,
    width_mm: float,
    thickness_mm: float,
    br_T: float,
    n_slabs: int = 1,
    neighbour: bool = False,
    split_images: bool = False,
) -> CuboidSet:
    """Magnets of one actuator plus their images in two ideal iron plates.

    gap_mm: d; length_mm/width_mm/thickness_mm: l_m (y), w_m (x), t_m (z).
    n_slabs: K slabs per side (K = 1: real magnet + one image per plate, eq 9).
    neighbour: False -> one magnet pair centred on x = 0 (the eq 9 model);
        True -> the whole actuator, pair A at x = +w/2 (+z) and pair B at
        x = -w/2 (-z).
    split_images: represent slab 0 as two t_m cuboids (magnet, image) instead
        of one 2 t_m cuboid (identical field; used to show the image literally).
    """
    d, t, p = float(gap_mm), float(thickness_mm), float(gap_mm) + 2.0 * float(thickness_mm)
    pairs = [(0.0, 1.0)] if not neighbour else [(width_mm / 2, 1.0), (-width_mm / 2, -1.0)]
    c, dims, pol = [], [], []
    for xc, sgn in pairs:
        for side in (1.0, -1.0):
            for k in range(n_slabs):
                z0 = d / 2 + k * p  # near face of slab k
                if split_images and k == 0:
                    for zc in (z0 + t / 2, z0 + 1.5 * t):
                        c.append((xc, 0.0, side * zc))
                        dims.append((width_mm, length_mm, t))
                        pol.append((0.0, 0.0, sgn * br_T))
                else:
                    c.append((xc, 0.0, side * (z0 + t)))
                    dims.append((width_mm, length_mm, 2 * t))
                    pol.append((0.0, 0.0, sgn * br_T))
    return CuboidSet(np.array(c, float), np.array(dims, float), np.array(pol, float))


def field_B_T(points_mm, cuboids: CuboidSet, chunk: int = 200_000) -> np.ndarray:
    """B (T) at points (M,3) mm from all cuboids, summed: magpylib's vectorised cuboid kernel.

    Uses ``magpylib.core.magnet_cuboid_Bfield`` (centred, axis-aligned cuboids),
    broadcasting every point against every cuboid. Returns (M,3).
    """
    import magpylib as magpy

    P = np.atleast_2d(np.asarray(points_mm, dtype=float))
    M, N = len(P), len(cuboids)
    out = np.zeros((M, 3))
    rows = max(1, chunk // max(N, 1))
    for i in range(0, M, rows):
        Pi = P[i : i + rows]
        m = len(Pi)
        obs = (Pi[:, None, :] - cuboids.centres_mm[None, :, :]).reshape(-1, 3)
        dims = np.broadcast_to(cuboids.dims_mm[None], (m, N, 3)).reshape(-1, 3)
        pol = np.broadcast_to(cuboids.pol_T[None], (m, N, 3)).reshape(-1, 3)
        B = magpy.core.magnet_cuboid_Bfield(observers=obs, dimensions=dims, polarizations=pol)
        out[i : i + m] = B.reshape(m, N, 3).sum(axis=1)
    return out


def bg_center_T(
    gap_mm: float,
    length_mm: float,
    width_mm: float,
    thickness_mm: float,
    br_T: float,
    n_slabs: int = 1,
    neighbour: bool = False,
    api: str = "core",
) -> float:
    """B_z (T) at the gap centre over magnet pair A.

    api: "core" -> vectorised kernel (:func:`field_B_T`); "object" ->
    magpylib ``magnet.Cuboid`` objects and ``getB`` (the public object API,
    slower; used as the independent check of eq 9). With n_slabs = 1 and
    neighbour = False this is the eq (9) configuration.
    """
    cs = image_stack(
        gap_mm, length_mm, width_mm, thickness_mm, br_T, n_slabs, neighbour, split_images=True
    )
    x0 = width_mm / 2 if neighbour else 0.0
    if api == "object":
        import magpylib as magpy

        src = [
            magpy.magnet.Cuboid(dimension=dm, polarization=pl, position=c)
            for c, dm, pl in zip(cs.centres_mm, cs.dims_mm, cs.pol_T, strict=True)
        ]
        return float(magpy.getB(src, (x0, 0.0, 0.0), sumup=True)[2])
    return float(field_B_T(np.array([[x0, 0.0, 0.0]]), cs)[0, 2])


def actuator_bz_fn(
    gap_mm: float,
    params: vc.VoiceCoilParams,
    n_slabs: int = MAGPYLIB_IMAGE_SLABS,
    neighbour: bool = True,
):
    """Return bz(points_mm (M,3)) -> (M,) T for the whole actuator with images (magpylib)."""
    cs = image_stack(
        gap_mm,
        params.magnet_length_mm,
        params.magnet_width_mm,
        params.magnet_thickness_mm,
        params.br_T,
        n_slabs,
        neighbour,
    )

    def bz(points_mm):
        return field_B_T(points_mm, cs)[:, 2]

    return bz


def coil_mean_bz_T(
    gap_mm: float,
    params: vc.VoiceCoilParams,
    n_slabs: int = MAGPYLIB_IMAGE_SLABS,
    neighbour: bool = True,
    n_quad: tuple[int, int, int] = (6, 4, 4),
) -> float:
    """Volume mean of B_z over coil leg A (w_m x l_m x d_c, mid-stroke) in T.

    By symmetry leg B sees -B_z and carries -I, so this mean is the B_g
    that makes eq (8) exact for the real field (under assumption ii).
    Gauss-Legendre product rule with n_quad points per axis.
    """
    (lo, hi), _ = vc.leg_boxes_mm(gap_mm, params, 0.0)
    pts, w = vc.gauss_box(lo, hi, n_quad)
    bz = actuator_bz_fn(gap_mm, params, n_slabs, neighbour)(pts)
    return float(np.dot(w, bz) / np.sum(w))


def material_response_available() -> bool:
    """True when the optional magpylib-material-response package imports."""
    try:
        import magpylib_material_response  # noqa: F401
    except ImportError:
        return False
    return True


def bg_finite_iron_T(
    gap_mm: float,
    params: vc.VoiceCoilParams,
    *,
    plate_thickness_mm: float,
    susceptibility: float = 1000.0,
    margin_mm: float = 2.0,
    cells: tuple[int, int, int] = (8, 10, 2),
) -> float:
    """Gap-centre B_z over pair A with FINITE, finite-permeability iron plates (optional).

    Needs magpylib-material-response (not a hard dependency; raises
    ImportError when missing). The whole actuator's four magnets (chi = 0,
    rigid) and two plates covering them with ``margin_mm`` on each side,
    meshed into ``cells`` cuboids each with linear susceptibility
    ``susceptibility`` (no saturation), are solved with ``apply_demag``.
    """
    import magpylib as magpy
    from magpylib_material_response.demag import apply_demag
    from magpylib_material_response.meshing import mesh_Cuboid

    d, t, w, lm, br = (
        float(gap_mm),
        params.magnet_thickness_mm,
        params.magnet_width_mm,
        params.magnet_length_mm,
        params.br_T,
    )
    coll = magpy.Collection()
    for xc, sgn in ((w / 2, 1.0), (-w / 2, -1.0)):
        for side in (1.0, -1.0):
            m = magpy.magnet.Cuboid(
                dimension=(w, lm, t),
                polarization=(0, 0, sgn * br),
                position=(xc, 0, side * (d / 2 + t / 2)),
            )
            m.susceptibility = 0.0
            coll.add(m)
    for side in (1.0, -1.0):
        plate = magpy.magnet.Cuboid(
            dimension=(2 * w + 2 * margin_mm, lm + 2 * margin_mm, plate_thickness_mm),
            polarization=(0, 0, 0),
            position=(0, 0, side * (d / 2 + t + plate_thickness_mm / 2)),
        )
        plate.susceptibility = susceptibility
        coll.add(mesh_Cuboid(plate, cells))
    solved = apply_demag(coll, min_log_time=1e9)
    return float(solved.getB((w / 2, 0.0, 0.0))[2])
