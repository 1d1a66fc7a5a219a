"""Exact mass properties of B-rep solids by OCCT's volume integration (OCP, imported lazily);
OCCT's triangulation of a shape (:func:`triangulate`, :func:`extract_arrays`, used by
:mod:`cad.massprops.mesh` and the STL writer) and STEP reading (:func:`read_step`,
:func:`read_step_named`, :func:`split_solids`, used by :mod:`cad.massprops.io`): the one
module of ``cad.massprops`` that imports OCP (issue 23; ``tests/architecture/test_import_graph.py``).

Shapes are in millimetres. OCCT integrates with unit density in model units:
``Mass()`` is the volume in mm^3, ``CentreOfMass()`` is in mm, ``MatrixOfInertia()``
is in mm^5. This module converts to SI exactly once (:func:`to_si`):
volume x 1e-9 -> m^3, COM x 1e-3 -> m, inertia x 1e-15 -> m^5, then x density.

Measured facts about ``GProp_GProps.MatrixOfInertia()`` (OCCT 7.9.3, checked by
``tests/unit/massprops/test_massprops_occt.py`` on a rotated, translated box):

* it is taken about the centre of mass (not the framework's reference point),
  with axes parallel to the global axes;
* it is already the positive-definite tensor ``integral (|r|^2 E - r r^T) dV``:
  OCCT stores the products of inertia negated (``I_xy = -integral x y dV``), so no
  sign change is applied here.

Default mode (``BRepGProp.VolumeProperties_s(shape, props)``, no ``Eps``) is exact
for planar, cylindrical, conical, spherical and toroidal faces to ~1e-15 relative
and is the fastest (SPEC "Measured pitfalls"); the adaptive ``eps`` mode is kept
for the benchmark only.
"""

from __future__ import annotations

import contextlib
import os
import sys
from collections import OrderedDict
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from cad.errors import GeometryError, MeshError
from cad.massprops.props import MassProps

#: mm^3 -> m^3
MM3_TO_M3 = 1e-9
#: mm -> m
MM_TO_M = 1e-3
#: mm^5 -> m^5 (volume-weighted second moments)
MM5_TO_M5 = 1e-15


def as_topods(shape):
    """Return the OCP ``TopoDS_Shape`` of a build123d/cadquery shape (or the shape itself)."""
    from OCP.TopoDS import TopoDS_Shape

    if isinstance(shape, TopoDS_Shape):
        return shape
    try:
        wrapped = getattr(shape, "wrapped", None)
    except AssertionError:  # build123d asserts on a shape with nothing inside
        raise GeometryError(
            f"{type(shape).__name__} is empty (null shape): the boolean or operation that made "
            "it produced nothing (disjoint operands of an intersection?)"
        ) from None
    if isinstance(wrapped, TopoDS_Shape):
        return wrapped
    raise GeometryError(
        f"expected a build123d/cadquery Shape or an OCP TopoDS_Shape, got {type(shape).__name__}"
    )


def _check_has_solid(s) -> None:
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    if s.IsNull():
        raise GeometryError("shape is empty (null TopoDS_Shape)")
    if not TopExp_Explorer(s, TopAbs_SOLID).More():
        raise GeometryError(
            "shape has no solid: volume integration needs closed solids "
            "(a face, shell or wire has no volume; make a solid first)"
        )


_CHECK_KINDS = ("SOLID", "SHELL", "FACE", "WIRE", "EDGE", "VERTEX")


def validity_problems(shape, limit: int = 4) -> list[str]:
    """BRepCheck findings of ``shape``: ``["shell 0: NotClosed", ...]`` (empty when valid).

    Runs ``BRepCheck_Analyzer`` (topology and geometry) and lists the first ``limit``
    distinct statuses other than NoError, each with the kind and index (explorer
    order) of the sub-shape, including statuses reported in a context (a wire in
    its face). Costs ~1 ms for a box and ~5 ms for a pocketed bar (OCCT 7.9).
    """
    import OCP.TopAbs as TopAbs
    from OCP.BRepCheck import BRepCheck_Analyzer, BRepCheck_Status
    from OCP.TopExp import TopExp_Explorer

    s = as_topods(shape)
    analyzer = BRepCheck_Analyzer(s)
    if analyzer.IsValid():
        return []
    found: list[str] = []
    for kind in _CHECK_KINDS:
        exp = TopExp_Explorer(s, getattr(TopAbs, f"TopAbs_{kind}"))
        i = 0
        while exp.More() and len(found) < limit:
            res = analyzer.Result(exp.Current())
            if res is not None:
                statuses = list(res.Status())
                res.InitContextIterator()
                while res.MoreShapeInContext():
                    statuses += list(res.StatusOnShape())
                    res.NextShapeInContext()
                for st in statuses:
                    text = f"{kind.lower()} {i}: {st.name.removeprefix('BRepCheck_')}"
                    if st != BRepCheck_Status.BRepCheck_NoError and text not in found:
                        found.append(text)
            exp.Next()
            i += 1
    return found[:limit] or ["invalid (BRepCheck gives no detail)"]


def check_valid(shape, what: str = "shape") -> None:
    """Raise :class:`GeometryError` when BRepCheck finds ``shape`` invalid.

    An invalid solid (an open shell, a self-intersecting profile, the result of a
    boolean that failed on such an operand) integrates to a meaningless volume
    without any error from OCCT (measured: a box with one face missing gives
    4800 of 6000 mm^3; a box cut by a self-intersecting tool keeps all 27000 mm^3),
    so the mass properties must refuse it.
    """
    _check_has_solid(as_topods(shape))
    problems = validity_problems(shape)
    if problems:
        raise GeometryError(
            f"{what} is not a valid solid (BRepCheck: {'; '.join(problems)}): a boolean or a "
            "profile failed; fix the part parameters or the operands (ShapeFix may repair small gaps)"
        )


def volume_props_mm(shape, *, eps: float | None = None, use_triangulation: bool = False):
    """Raw OCCT volume integrals of ``shape`` in mm units, unit density.

    Parameters
    ----------
    shape : build123d Shape or OCP TopoDS_Shape (mm).
    eps : ``None`` for OCCT's default exact Gauss mode; a float selects the adaptive
        mode with that relative error target per face (OCCT ignores adaptivity for
        ``eps > 1e-3``).
    use_triangulation : integrate over the faces' existing triangulations instead of
        the exact surfaces (default mode only; see :mod:`cad.massprops.mesh`).

    Returns ``(volume_mm3, com_mm (3,), inertia_com_mm5 (3, 3))``.

    A shape farther from the origin than :data:`FAR_FACTOR` times its size is integrated
    solid by solid, each about its own box centre, and summed by the parallel-axis theorem:
    integrals about a far origin cancel catastrophically (a box at 1e9 mm came out "not
    positive definite"; a located compound at 1e9 mm even gave a zero tensor).
    """
    s = as_topods(shape)
    _check_has_solid(s)
    if eps is None and not use_triangulation and _far_centre(s) is not None:
        # each solid about its own box centre, then summed (OCCT's compound path cancels)
        return sum_volume_props([_volume_props_local(sol) for sol in solids(s)])
    return _volume_props_raw(s, eps, use_triangulation)


def _volume_props_local(solid):
    """``volume_props_mm`` of one solid, integrated with its box centre as the origin."""
    from OCP.gp import gp_Trsf, gp_Vec
    from OCP.TopLoc import TopLoc_Location

    c = _far_centre(solid, 0.0)
    if c is None:
        return _volume_props_raw(solid, None, False)
    t = gp_Trsf()
    t.SetTranslation(gp_Vec(*(-c)))
    vol, com, inertia = _volume_props_raw(solid.Moved(TopLoc_Location(t)), None, False)
    return vol, com + c, inertia


def sum_volume_props(parts):
    """Union of unit-density ``(volume_mm3, com_mm (3,), inertia about com (3, 3))`` integrals.

    Each part's tensor is shifted to the common COM by the parallel-axis theorem.
    """
    vol = float(sum(p[0] for p in parts))
    com = sum(p[0] * np.asarray(p[1], dtype=float) for p in parts) / vol
    inertia = np.zeros((3, 3))
    for v, c, i in parts:
        d = np.asarray(c, dtype=float) - com
        inertia += np.asarray(i, dtype=float) + v * (float(d @ d) * np.eye(3) - np.outer(d, d))
    return vol, com, inertia


def _volume_props_raw(s, eps, use_triangulation):
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    if eps is None:
        BRepGProp.VolumeProperties_s(s, props, False, False, use_triangulation)
    else:
        if use_triangulation:
            raise GeometryError("use_triangulation is only available in OCCT's default mode")
        BRepGProp.VolumeProperties_s(s, props, float(eps))
    vol = props.Mass()
    c = props.CentreOfMass()
    M = props.MatrixOfInertia()
    com = np.array([c.X(), c.Y(), c.Z()])
    inertia = np.array([[M.Value(i, j) for j in (1, 2, 3)] for i in (1, 2, 3)])
    if not (np.isfinite(vol) and np.all(np.isfinite(com)) and np.all(np.isfinite(inertia))):
        raise GeometryError(f"OCCT volume integration returned non-finite values (volume {vol})")
    if vol <= 0:
        raise GeometryError(
            f"solid volume is {vol:.6g} mm^3 (<= 0): the solid is inside-out or degenerate"
        )
    return float(vol), com, inertia


#: A shape whose bounding-box centre is farther from the origin than this many box sizes
#: is integrated about the box centre: OCCT's second moments about a far origin cancel
#: catastrophically (a box at 1e9 mm was refused as "not positive definite").
FAR_FACTOR = 10.0


def _far_centre(s, factor: float | None = None):
    """Bounding-box centre (3,) mm of ``s`` when it lies farther than ``factor`` box sizes
    from the origin (default :data:`FAR_FACTOR`), else ``None``."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    box = Bnd_Box()
    BRepBndLib.Add_s(s, box, False)
    if box.IsVoid():
        return None
    x0, y0, z0, x1, y1, z1 = box.Get()
    c = 0.5 * np.array([x0 + x1, y0 + y1, z0 + z1])
    size = max(x1 - x0, y1 - y0, z1 - z0, 1e-9)
    f = FAR_FACTOR if factor is None else factor
    if not np.all(np.isfinite(c)) or np.linalg.norm(c) <= f * size:
        return None
    return c


def to_si(vol_mm3: float, com_mm, inertia_mm5, density_kg_m3: float) -> MassProps:
    """The single mm -> SI conversion of unit-density OCCT integrals, times density."""
    rho = float(density_kg_m3)
    if not np.isfinite(rho) or rho <= 0:
        raise GeometryError(f"density_kg_m3 must be finite and > 0, got {density_kg_m3!r}")
    return MassProps(
        mass_kg=rho * vol_mm3 * MM3_TO_M3,
        com_m=np.asarray(com_mm, dtype=float) * MM_TO_M,
        inertia_com_kg_m2=rho * np.asarray(inertia_mm5, dtype=float) * MM5_TO_M5,
    )


def solid_mass_props(
    shape, density_kg_m3: float, *, eps: float | None = None, check: bool = True
) -> MassProps:
    """Exact mass properties of a solid (or compound of solids) of uniform density.

    Parameters
    ----------
    shape : build123d Shape or OCP TopoDS_Shape, lengths in mm.
    density_kg_m3 : density, kg/m^3 (> 0).
    eps : ``None`` (default, exact Gauss integration); a float selects OCCT's adaptive
        mode (benchmark only, slower and less accurate on inertia).
    check : validate the shape with BRepCheck first (:func:`check_valid`, ~1-5 ms);
        ``False`` only where the shape is known valid (benchmarks timing the integration).

    Returns :class:`MassProps` in SI, in the shape's own frame (COM in m, tensor about
    the COM in kg m^2). For several disjoint solids the result is their union; solids
    that overlap are counted twice (fuse first).
    """
    if check:
        check_valid(shape)
    vol, com, inertia = volume_props_mm(shape, eps=eps)
    return to_si(vol, com, inertia, density_kg_m3)


def volume_mm3(shape) -> float:
    """Exact volume of ``shape`` in mm^3 (OCCT default mode)."""
    return volume_props_mm(shape)[0]


def solids(shape) -> list:
    """The OCP ``TopoDS_Solid`` s of ``shape`` in traversal order."""
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    s = as_topods(shape)
    out = []
    exp = TopExp_Explorer(s, TopAbs_SOLID)
    while exp.More():
        out.append(TopoDS.Solid_s(exp.Current()))
        exp.Next()
    return out


#: Unit-density integrals of the last shapes integrated by :func:`cached_solid_mass_props`,
#: by object identity (each entry holds its shape, so the id cannot be reused while cached).
PROPS_MEMO_MAX = 512
_PROPS_MEMO: OrderedDict = OrderedDict()


def cached_solid_mass_props(shape, density_kg_m3: float) -> MassProps:
    """:func:`solid_mass_props` (validated, exact), remembered per shape object.

    Part solids come from :mod:`cad.parts.part_cache` as the same objects for the same
    parameters, and hapticad never modifies an OCCT shape in place, so a repeated
    evaluation (``fit``, ``sweep``) validates and integrates only the parts that changed;
    the density is applied afterwards (a material change integrates nothing).
    """
    vol, com, inertia = cached_unit_props(shape)
    return to_si(vol, com, inertia, density_kg_m3)


def cached_unit_props(shape):
    """``(volume_mm3, com_mm, inertia_com_mm5)`` of ``shape`` at unit density, validated
    (:func:`check_valid`) and remembered per shape object (see :func:`cached_solid_mass_props`)."""
    hit = _PROPS_MEMO.get(id(shape))
    if hit is not None and hit[0] is shape:
        _PROPS_MEMO.move_to_end(id(shape))
        return hit[1]
    check_valid(shape)
    out = volume_props_mm(shape)
    _PROPS_MEMO[id(shape)] = (shape, out)
    while len(_PROPS_MEMO) > PROPS_MEMO_MAX:
        _PROPS_MEMO.popitem(last=False)
    return out


# ------------------------------------------------------------------------ meshing
# (was in cad/massprops/mesh.py) OCCT's triangulation of a fresh copy at an absolute
# deflection; the mesh methods of cad.massprops.mesh and the STL writer use it.
#: OCCT's own default angular deflection for BRepMesh_IncrementalMesh (rad). With an
#: absolute linear deflection below ~0.1 mm the linear criterion governs on the
#: radii of haptic parts (>= 1.5 mm): chord angle 2*sqrt(2*tol/r) < 0.5 rad.
DEFAULT_ANGULAR_DEFLECTION_RAD = 0.5


def _check_tolerances(linear_tol_mm: float, angular_tol_rad: float) -> None:
    if not np.isfinite(linear_tol_mm) or linear_tol_mm <= 0:
        raise GeometryError(f"mesh linear tolerance must be > 0 mm, got {linear_tol_mm!r}")
    if not np.isfinite(angular_tol_rad) or not 0 < angular_tol_rad <= np.pi:
        raise GeometryError(
            f"mesh angular tolerance must be in (0, pi] rad, got {angular_tol_rad!r}"
        )


def triangulate(
    shape, linear_tol_mm: float, angular_tol_rad: float = DEFAULT_ANGULAR_DEFLECTION_RAD
):
    """Mesh a fresh copy of ``shape`` with OCCT and return the meshed ``TopoDS_Shape``.

    Parameters
    ----------
    shape : build123d Shape or OCP TopoDS_Shape (mm). Left untouched (its own cached
        triangulation, if any, is neither used nor changed).
    linear_tol_mm : absolute linear (chordal) deflection, mm.
    angular_tol_rad : angular deflection, rad.

    Raises :class:`MeshError` when a face ends up without a triangulation.
    """
    from OCP.BRep import BRep_Tool
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Copy
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.BRepTools import BRepTools
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopoDS import TopoDS

    _check_tolerances(linear_tol_mm, angular_tol_rad)
    copy = BRepBuilderAPI_Copy(as_topods(shape), True, False).Shape()
    BRepTools.Clean_s(copy)
    mesher = BRepMesh_IncrementalMesh(
        copy, float(linear_tol_mm), False, float(angular_tol_rad), False
    )
    if not mesher.IsDone():
        raise MeshError(f"OCCT meshing failed at linear tolerance {linear_tol_mm} mm")
    exp = TopExp_Explorer(copy, TopAbs_FACE)
    i = 0
    while exp.More():
        loc = TopLoc_Location()
        if BRep_Tool.Triangulation_s(TopoDS.Face_s(exp.Current()), loc) is None:
            raise MeshError(
                f"OCCT left face #{i} without a triangulation (tolerance {linear_tol_mm} mm)"
            )
        exp.Next()
        i += 1
    return copy


def extract_arrays(meshed) -> tuple[np.ndarray, np.ndarray]:
    """Triangle soup of a meshed ``TopoDS_Shape``: ``(vertices_mm (N, 3), faces (M, 3) int64)``.

    Nodes are in the global frame (face locations applied); triangles of REVERSED faces
    are flipped so every normal points out of the solid. Vertices on shared edges are
    duplicated per face (merge before any topology check).
    """
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_FACE, TopAbs_REVERSED
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopoDS import TopoDS

    verts: list[np.ndarray] = []
    faces: list[np.ndarray] = []
    offset = 0
    exp = TopExp_Explorer(as_topods(meshed), TopAbs_FACE)
    while exp.More():
        face = TopoDS.Face_s(exp.Current())
        loc = TopLoc_Location()
        tri = BRep_Tool.Triangulation_s(face, loc)
        exp.Next()
        if tri is None:
            raise MeshError("a face has no triangulation; call triangulate() first")
        n = tri.NbNodes()
        nodes = np.array([tri.Node(i).Coord() for i in range(1, n + 1)], dtype=float).reshape(n, 3)
        trsf = loc.Transformation()
        if not loc.IsIdentity():
            A = np.array([[trsf.Value(r, c) for c in (1, 2, 3, 4)] for r in (1, 2, 3)])
            nodes = nodes @ A[:, :3].T + A[:, 3]
        t = np.array(
            [tri.Triangle(i).Get() for i in range(1, tri.NbTriangles() + 1)], dtype=np.int64
        )
        t = t.reshape(-1, 3) - 1 + offset
        if face.Orientation() == TopAbs_REVERSED:
            t = t[:, [0, 2, 1]]
        verts.append(nodes)
        faces.append(t)
        offset += n
    if not faces:
        raise MeshError("shape has no faces to mesh")
    return np.concatenate(verts), np.concatenate(faces)


def triangle_count(meshed) -> int:
    """Number of triangles of a meshed ``TopoDS_Shape`` (every face's triangulation)."""
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopoDS import TopoDS

    n_tri = 0
    exp = TopExp_Explorer(meshed, TopAbs_FACE)
    while exp.More():
        n_tri += BRep_Tool.Triangulation_s(
            TopoDS.Face_s(exp.Current()), TopLoc_Location()
        ).NbTriangles()
        exp.Next()
    return n_tri


# ------------------------------------------------------------------ STEP files
# (was in cad/massprops/io.py) STEP files read for ``hapticad massprops`` (mm assumed: STEP
# files written by build123d/cadquery are).
@contextlib.contextmanager
def _quiet_stdout() -> Iterator[None]:
    """Silence C++ writes to file descriptor 1 (OCCT's STEP parser prints errors there).

    Keeps stdout clean for ``--json`` output; our own error message says what failed.
    """
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        with open(os.devnull, "wb") as null:
            os.dup2(null.fileno(), 1)
            try:
                yield
            finally:
                os.dup2(saved, 1)
    finally:
        os.close(saved)


def read_step(path: str | Path):
    """Read a STEP file (mm) and return its shape as one OCP ``TopoDS_Shape``.

    Raises :class:`GeometryError` when the file cannot be read or holds no solid.
    """
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_Reader
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    p = Path(path)
    reader = STEPControl_Reader()
    with _quiet_stdout():
        status = reader.ReadFile(str(p))
        n_roots = reader.TransferRoots() if status == IFSelect_RetDone else 0
    if status != IFSelect_RetDone:
        raise GeometryError(f"{p.name}: not a readable STEP file (reader status {status.name})")
    if n_roots == 0:
        raise GeometryError(f"{p.name}: STEP file has no transferable shape")
    shape = reader.OneShape()
    if shape.IsNull() or not TopExp_Explorer(shape, TopAbs_SOLID).More():
        raise GeometryError(f"{p.name}: STEP file holds no solid (only surfaces or curves?)")
    return shape


def read_step_named(path: str | Path) -> list[tuple[str | None, object]]:
    """``[(name, placed shape)]`` of every leaf of a STEP file's product structure (XCAF).

    Names are the instance names of assembly components (hapticad's ``assembly.step`` names
    every solid after its part instance), else the product name, else ``None``. Raises
    :class:`GeometryError` when the file cannot be read.
    """
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPCAFControl import STEPCAFControl_Reader
    from OCP.TCollection import TCollection_ExtendedString
    from OCP.TDataStd import TDataStd_Name
    from OCP.TDF import TDF_Label, TDF_LabelSequence
    from OCP.TDocStd import TDocStd_Document
    from OCP.TopLoc import TopLoc_Location
    from OCP.XCAFApp import XCAFApp_Application
    from OCP.XCAFDoc import XCAFDoc_DocumentTool

    p = Path(path)
    doc = TDocStd_Document(TCollection_ExtendedString("XmlOcaf"))
    XCAFApp_Application.GetApplication_s().NewDocument(TCollection_ExtendedString("MDTV-XCAF"), doc)
    reader = STEPCAFControl_Reader()
    reader.SetNameMode(True)
    with _quiet_stdout():
        status = reader.ReadFile(str(p))
        ok = status == IFSelect_RetDone and reader.Transfer(doc)
    if status != IFSelect_RetDone:
        raise GeometryError(f"{p.name}: not a readable STEP file (reader status {status.name})")
    if not ok:
        raise GeometryError(f"{p.name}: STEP file has no transferable shape")
    tool = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())

    def name_of(label) -> str | None:
        attr = TDataStd_Name()
        if label.FindAttribute(TDataStd_Name.GetID_s(), attr):
            return attr.Get().ToExtString() or None
        return None

    out: list[tuple[str | None, object]] = []

    def walk(label, loc, name) -> None:
        if tool.IsAssembly_s(label):
            comps = TDF_LabelSequence()
            tool.GetComponents_s(label, comps)
            for i in range(1, comps.Length() + 1):
                comp = comps.Value(i)
                ref = TDF_Label()
                if tool.GetReferredShape_s(comp, ref):
                    walk(ref, loc.Multiplied(tool.GetLocation_s(comp)),
                         name_of(comp) or name_of(ref))
            return
        out.append((name, tool.GetShape_s(label).Moved(loc)))

    free = TDF_LabelSequence()
    tool.GetFreeShapes(free)
    for i in range(1, free.Length() + 1):
        lab = free.Value(i)
        walk(lab, TopLoc_Location(), name_of(lab))
    return out


def split_solids(shape) -> tuple[list, dict[str, int]]:
    """``(closed solids, ignored)`` of a STEP shape: only solids bound volume.

    ``ignored`` counts what is not integrated: ``faces`` (free faces, e.g. construction
    surfaces), ``open_shells`` and ``closed_shells`` (shells that are not solids). A box plus
    a free face used to integrate to 106000 mm^3 instead of 6000 (issue 12 §2).
    """
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_FACE, TopAbs_SHELL, TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    solids = []
    exp = TopExp_Explorer(shape, TopAbs_SOLID)
    while exp.More():
        solids.append(TopoDS.Solid_s(exp.Current()))
        exp.Next()
    ignored = {"faces": 0, "open_shells": 0, "closed_shells": 0}
    exp = TopExp_Explorer(shape, TopAbs_SHELL, TopAbs_SOLID)
    while exp.More():
        shell = TopoDS.Shell_s(exp.Current())
        n_faces, fexp = 0, TopExp_Explorer(shell, TopAbs_FACE)
        while fexp.More():
            n_faces += 1
            fexp.Next()
        if n_faces == 1:  # a lone face (STEP readers wrap free faces in a shell)
            ignored["faces"] += 1
        else:
            closed = BRep_Tool.IsClosed_s(shell)
            ignored["closed_shells" if closed else "open_shells"] += 1
        exp.Next()
    exp = TopExp_Explorer(shape, TopAbs_FACE, TopAbs_SHELL)
    while exp.More():
        ignored["faces"] += 1
        exp.Next()
    return solids, {k: v for k, v in ignored.items() if v}
