"""Mass properties from triangulations (OCCT meshing, trimesh, manifold3d; all imported lazily).

Three methods, compared against the exact B-rep integration in ``cad.bench.massprops``:

(a) :func:`occt_triangulation_mass_props` -- mesh a fresh copy of the shape with
    ``BRepMesh_IncrementalMesh`` at an ABSOLUTE linear deflection (mm) and an angular
    deflection (rad), then let OCCT integrate over that triangulation
    (``BRepGProp.VolumeProperties_s(..., UseTriangulation=True)``). Fastest mesh method.
(b) :func:`trimesh_mass_props` -- the same triangulation pulled into numpy, vertices
    merged, and handed to ``trimesh.Trimesh.mass_properties`` (full tensor).
(c) :func:`manifold_volume_mm3` -- manifold3d ``Mesh64`` volume (volume only; manifold3d
    has no COM or inertia).

A fresh copy is meshed because build123d's ``Shape.mesh()`` reuses any finer mesh
already stored on the shape and its ``tessellate()`` takes a relative tolerance with a
fixed 0.1 rad angle (SPEC "Measured pitfalls"). The mesh is a chordal approximation:
it lies inside convex curved faces, so volumes come out low by O(tolerance / radius).

Watertightness: a mesh with an open edge gives a meaningless volume. Methods (b) and
(c) and :func:`mesh_arrays_mass_props` raise :class:`cad.errors.MeshError` on a
non-watertight mesh unless ``allow_open=True``, in which case the trimesh result carries
``watertight=False`` and the caller must warn (manifold3d has no volume for an open
mesh and raises regardless). Always a MeshError, open or not: non-finite or
out-of-range input, inconsistent winding (a flipped triangle leaves a box
"watertight" with half its volume), and an enclosed volume <= 0 (inside-out or flat).

Shells (:mod:`cad.massprops.shells`, issue 21 §4): :func:`mesh_arrays_mass_props` drops
triangles written twice (noted), winds every closed shell for its nesting (a cavity wound
outwards is read as a cavity, noted; an outermost shell wound inwards or shells crossing
each other are MeshErrors).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cad.errors import GeometryError, MeshError
from cad.massprops import shells
from cad.massprops.occt import (
    DEFAULT_ANGULAR_DEFLECTION_RAD,
    MM3_TO_M3,
    MM5_TO_M5,
    MM_TO_M,
    extract_arrays,
    triangle_count,
    triangulate,
    volume_props_mm,
)
from cad.massprops.props import MassProps
from cad.tolerances import PART_EXTENT_MAX_MM, PART_EXTENT_MIN_MM

#: Largest |vertex coordinate| accepted, mm. trimesh merges vertices by hashing
#: coordinates / tol.merge (1e-8) as int64: beyond 2^63 * 1e-8 ~ 9.2e10 mm the hash
#: overflows and distinct vertices would be merged.
MAX_COORD_MM = 1e10


@dataclass(frozen=True)
class MeshMassResult:
    """Mass properties computed on a triangulation.

    Parameters
    ----------
    props : MassProps in SI, frame of the input (COM m, tensor about the COM kg m^2);
        ``None`` for volume-only methods.
    volume_mm3 : enclosed volume, mm^3.
    watertight : True/False when checked, ``None`` when the method did not check.
    n_triangles : number of triangles integrated.
    method : ``"occt-triangulation"``, ``"trimesh"`` or ``"manifold3d"``.
    notes : what was read differently from the file as written (duplicate triangles
        dropped, a cavity shell wound outwards read as a cavity); the caller warns.
    """

    props: MassProps | None
    volume_mm3: float
    watertight: bool | None
    n_triangles: int
    method: str
    notes: tuple[str, ...] = ()



def _merged_trimesh(vertices_mm, faces, what: str = "mesh"):
    import trimesh

    try:
        v = np.asarray(vertices_mm, dtype=float)
        f_in = np.asarray(faces)
    except (TypeError, ValueError):
        raise MeshError("mesh vertices and faces must be numeric arrays") from None
    if v.ndim != 2 or v.shape[1] != 3 or f_in.ndim != 2 or f_in.shape[1] != 3 or len(f_in) == 0:
        raise MeshError(
            f"mesh must be (N, 3) vertices and (M>0, 3) faces, got {v.shape} and {f_in.shape}"
        )
    if not np.all(np.isfinite(v)):
        i = int(np.flatnonzero(~np.all(np.isfinite(v), axis=1))[0])
        raise MeshError(f"{what}: vertex {i} is not finite: {v[i].tolist()}")
    if np.abs(v).max() > MAX_COORD_MM:
        raise MeshError(
            f"{what}: coordinates reach {np.abs(v).max():.3g} mm, beyond {MAX_COORD_MM:g} mm "
            "(vertex merging would fail): is the unit mm?"
        )
    if f_in.dtype.kind not in "iu":
        if f_in.dtype.kind != "f" or not np.all(f_in == np.round(f_in)):
            raise MeshError(f"mesh face indices must be integers, got dtype {f_in.dtype}")
    f = f_in.astype(np.int64)
    if f.min() < 0 or f.max() >= len(v):
        raise MeshError(f"mesh face indices must lie in [0, {len(v)}), got [{f.min()}, {f.max()}]")
    # process=True merges coincident vertices (trimesh.constants.tol.merge = 1e-8).
    return trimesh.Trimesh(vertices=v, faces=f, process=True)


def _signed_volume_mm3(tm) -> float:
    """Enclosed volume by the divergence theorem, sum of det(v0, v1, v2) / 6 (no division by it)."""
    t = np.asarray(tm.triangles, dtype=float)
    return float(np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() / 6.0)


def _require_closed(watertight: bool, allow_open: bool, what: str) -> None:
    if not watertight and not allow_open:
        raise MeshError(
            f"{what} is not watertight (open or non-manifold edges): its volume and inertia are "
            "meaningless; repair the mesh or pass allow_open=True to accept it with a warning"
        )


def mesh_arrays_mass_props(
    vertices_mm, faces, density_kg_m3: float, *, allow_open: bool = False, what: str = "mesh"
) -> MeshMassResult:
    """Mass properties of a closed triangle mesh in mm with uniform density (trimesh).

    Parameters
    ----------
    vertices_mm : (N, 3) vertex positions, mm (a triangle soup is fine: merged here).
    faces : (M, 3) vertex indices, counter-clockwise seen from outside.
    density_kg_m3 : density, kg/m^3.
    allow_open : accept a non-watertight mesh (result has ``watertight=False``).

    Triangles written twice are dropped and every closed shell is wound for its nesting
    (:func:`_checked_shells`); what was read differently is in ``notes``. MeshError for
    inside-out or crossing shells, inconsistent winding, a volume <= 0.

    trimesh integrates the divergence theorem over the triangles (Eberly, "Polyhedral
    Mass Properties"); its ``moment_inertia`` is about the centre of mass with the
    positive-definite sign convention, as here.
    """
    v = np.asarray(vertices_mm, dtype=float) if np.size(vertices_mm) else vertices_mm
    # integrate about a point near the part: integrals about a far origin cancel
    # catastrophically (a box at 1e6 mm came out 3.6 % wrong; issue 12 §2)
    origin = _local_origin(v)
    tm = _merged_trimesh(v - origin if origin is not None else v, faces, what)
    rho = float(density_kg_m3)
    if not np.isfinite(rho) or rho <= 0:
        raise GeometryError(f"density_kg_m3 must be finite and > 0, got {density_kg_m3!r}")
    tm, watertight, notes = _checked_shells(tm, allow_open, what,
                                            origin if origin is not None else 0.0)
    # the volume first: trimesh divides by it for the centre of mass (NaN at 0)
    vol = _signed_volume_mm3(tm)
    if not np.isfinite(vol) or vol <= 0:
        raise MeshError(f"{what} encloses volume {vol:.6g} mm^3 (<= 0): inside-out or degenerate")
    mp = tm.mass_properties  # unit density, mm units
    vol = float(mp["volume"])
    props = MassProps(
        mass_kg=rho * vol * MM3_TO_M3,
        com_m=(np.asarray(mp["center_mass"], dtype=float)
               + (origin if origin is not None else 0.0)) * MM_TO_M,
        inertia_com_kg_m2=rho * np.asarray(mp["inertia"], dtype=float) * MM5_TO_M5,
    )
    return MeshMassResult(props, vol, watertight, len(tm.faces), "trimesh", tuple(notes))


def _checked_shells(tm, allow_open: bool, what: str, origin):
    """``(trimesh, watertight, notes)``: exact duplicate triangles dropped, closedness and
    winding checked, then every closed shell wound for its nesting
    (:func:`cad.massprops.shells.orient_shells`; an open mesh has no inside to nest by)."""
    import trimesh


    notes: list[str] = []
    faces, n_dup = shells.drop_duplicate_faces(tm.faces)
    if n_dup:
        notes.append(f"{what}: dropped {n_dup} duplicate triangle{'s' if n_dup > 1 else ''} "
                     "(the same facet written twice would count its volume twice)")
        tm = trimesh.Trimesh(tm.vertices, faces, process=False)
    watertight = bool(tm.is_watertight)
    _require_closed(watertight, allow_open, what)
    if not tm.is_winding_consistent:
        # e.g. one triangle of a closed box flipped: still "watertight", volume 3000 of 6000
        raise MeshError(
            f"{what} has inconsistent winding (some triangles face inwards): its volume is "
            "wrong; repair it, e.g. in Python: m = trimesh.load(FILE); "
            "trimesh.repair.fix_normals(m); m.export(FILE_FIXED)"
        )
    if watertight:
        faces, more = shells.orient_shells(tm.vertices, tm.faces, what, origin)
        if more:
            notes += more
            tm = trimesh.Trimesh(tm.vertices, faces, process=False)
    return tm, watertight, notes


def unit_slip_note(vertices_mm, mass_kg: float, what: str = "mesh") -> str | None:
    """A warning when a mesh read as mm is too small or too large to be a device part
    (:data:`cad.tolerances.PART_EXTENT_MIN_MM` / ``_MAX_MM``), naming the likely unit and
    what the part would be in it; ``None`` when its extent is plausible.

    vertices_mm : (N, 3) finite vertices as read, mm; mass_kg : mass as computed from them.
    """
    v = np.asarray(vertices_mm, dtype=float)
    extent = float((v.max(axis=0) - v.min(axis=0)).max())
    if PART_EXTENT_MIN_MM <= extent <= PART_EXTENT_MAX_MM:
        return None
    unit, k = ("metres", 1e3) if extent < PART_EXTENT_MIN_MM else ("micrometres", 1e-3)
    return (f"{what}: the mesh is {extent:.3g} mm across, no device part: is the file in "
            f"{unit}? (x{k:g}: {extent * k:.3g} mm, {_mass_text(mass_kg * k**3)})")


def _mass_text(mass_kg: float) -> str:
    return f"{mass_kg * 1e3:.3g} g" if mass_kg < 1.0 else f"{mass_kg:.3g} kg"


def _local_origin(v) -> np.ndarray | None:
    """Centre of the bounding box of finite (N, 3) vertices (``None`` if not applicable)."""
    a = np.asarray(v)
    if a.ndim != 2 or a.shape[1:] != (3,) or len(a) == 0 or a.dtype.kind not in "fiu":
        return None
    a = a.astype(float)
    if not np.all(np.isfinite(a)):
        return None
    return 0.5 * (a.min(axis=0) + a.max(axis=0))


def occt_triangulation_mass_props(
    shape,
    density_kg_m3: float,
    linear_tol_mm: float,
    angular_tol_rad: float = DEFAULT_ANGULAR_DEFLECTION_RAD,
    *,
    check_watertight: bool = False,
    allow_open: bool = False,
) -> MeshMassResult:
    """Method (a): OCCT integration over its own triangulation of a fresh copy.

    Parameters
    ----------
    shape : build123d Shape or OCP TopoDS_Shape (mm).
    density_kg_m3 : density, kg/m^3.
    linear_tol_mm : absolute chordal deflection, mm.
    angular_tol_rad : angular deflection, rad.
    check_watertight : also pull the mesh out and check it is closed (costs about the
        meshing time again); otherwise ``watertight`` is ``None`` (BRepMesh meshes
        shared edges once, so a valid solid gives a closed mesh).
    allow_open : with ``check_watertight``, accept an open mesh instead of raising.
    """
    meshed = triangulate(shape, linear_tol_mm, angular_tol_rad)
    vol, com, inertia = volume_props_mm(meshed, use_triangulation=True)
    n_tri = triangle_count(meshed)
    watertight = None
    if check_watertight:
        v, f = extract_arrays(meshed)
        watertight = bool(_merged_trimesh(v, f).is_watertight)
        _require_closed(watertight, allow_open, "OCCT triangulation")
    rho = float(density_kg_m3)
    if not np.isfinite(rho) or rho <= 0:
        raise GeometryError(f"density_kg_m3 must be finite and > 0, got {density_kg_m3!r}")
    props = MassProps(rho * vol * MM3_TO_M3, com * MM_TO_M, rho * inertia * MM5_TO_M5)
    return MeshMassResult(props, vol, watertight, n_tri, "occt-triangulation")


def trimesh_mass_props(
    shape,
    density_kg_m3: float,
    linear_tol_mm: float,
    angular_tol_rad: float = DEFAULT_ANGULAR_DEFLECTION_RAD,
    *,
    allow_open: bool = False,
) -> MeshMassResult:
    """Method (b): OCCT mesh of a fresh copy, pulled into trimesh (vertices merged)."""
    v, f = extract_arrays(triangulate(shape, linear_tol_mm, angular_tol_rad))
    return mesh_arrays_mass_props(v, f, density_kg_m3, allow_open=allow_open, what="OCCT mesh")


def manifold_volume_mm3(vertices_mm, faces, *, allow_open: bool = False) -> MeshMassResult:
    """Method (c): enclosed volume (mm^3) by manifold3d ``Mesh64`` (volume only).

    The triangle soup is merged with trimesh first (manifold3d rejects unmerged soups as
    NotManifold). A mesh manifold3d refuses, or one enclosing a volume <= 0, is a
    MeshError even with ``allow_open`` (it used to return a NaN or negative volume).
    """
    import manifold3d

    tm = _merged_trimesh(vertices_mm, faces)
    watertight = bool(tm.is_watertight)
    _require_closed(watertight, allow_open, "mesh")
    mesh = manifold3d.Mesh64(
        vert_properties=np.ascontiguousarray(tm.vertices, dtype=np.float64),
        tri_verts=np.ascontiguousarray(tm.faces, dtype=np.uint64),
    )
    man = manifold3d.Manifold(mesh)
    status = man.status()
    if status != manifold3d.Error.NoError:
        # no volume to give, allow_open or not (it used to return NaN here)
        raise MeshError(f"manifold3d rejects the mesh ({status.name}): it has no enclosed volume")
    vol = float(man.volume())
    if not np.isfinite(vol) or vol <= 0:
        raise MeshError(f"mesh encloses volume {vol:.6g} mm^3 (<= 0): inside-out or degenerate")
    return MeshMassResult(None, vol, watertight, int(man.num_tri()), "manifold3d")


def manifold_shape_volume_mm3(
    shape, linear_tol_mm: float, angular_tol_rad: float = DEFAULT_ANGULAR_DEFLECTION_RAD
) -> MeshMassResult:
    """Method (c) on a B-rep: OCCT mesh of a fresh copy, volume by manifold3d."""
    v, f = extract_arrays(triangulate(shape, linear_tol_mm, angular_tol_rad))
    return manifold_volume_mm3(v, f)
