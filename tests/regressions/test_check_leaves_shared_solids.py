"""A part's drawing is a function of its solid alone: the interference check leaves shared solids untouched.

The defect: the haptic pen's ``drawings/ring.svg`` had other bytes on a cold shape cache
than on a warm one. On a cold cache the interference check ran OCCT's ``BRepAlgoAPI_Common``
on the ring and its pressed-in pins; that Boolean (destructive by default) raised the
tolerances of the ring's vertices and edges in place, on the ``TShape`` the ring's drawing
shares, and the hidden-line projection of the sheet read them. On a warm cache the volumes
came from the derived cache and no Boolean ran. Now every Boolean on a shared solid runs
on copies of its arguments (:mod:`cad.occ.boolean`).

References: the sheet drawn from the ring before any check (the bytes must not change), the
ring's BREP text (OCCT ``BRepTools::Write``) and its largest vertex and edge tolerances
before and after; the common volume of two boxes against its closed form.
"""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
#: The pen's ring and the four pins pressed into it (one body): the pairs the same-body
#: check and the exact pass intersect.
RING, PINS = "A_ring.ring0", ("A_ring.pin_ring_a1", "A_ring.pin_ring_a2",
                              "A_ring.pin_ring_b3", "A_ring.pin_ring_b4")


def _max_tolerances(shape) -> tuple[float, float]:
    """Largest vertex and edge tolerance of ``shape`` (mm)."""
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_VERTEX
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    out = []
    for kind, tol in ((TopAbs_VERTEX, lambda s: BRep_Tool.Tolerance_s(TopoDS.Vertex_s(s))),
                      (TopAbs_EDGE, lambda s: BRep_Tool.Tolerance_s(TopoDS.Edge_s(s)))):
        exp, m = TopExp_Explorer(shape, kind), 0.0
        while exp.More():
            m = max(m, tol(exp.Current()))
            exp.Next()
        out.append(m)
    return out[0], out[1]


def _ring_sheet(kind, out: Path) -> bytes:
    from cad.export.drawings import SheetPart, write_drawings

    part = SheetPart(kind.name, kind.shape, kind.material, 2, kind.process, kind.plate,
                     kind.fits, (), kind.description)
    write_drawings([part], out, "haptic_pen")
    return (out / "drawings" / "ring.svg").read_bytes()


@pytest.fixture(scope="module")
def pen_ring_body():
    """The pen's ring instance and its four pins (inertia fidelity)."""
    from cad.design import load_design
    from cad.families.pen import assemble

    model = assemble(load_design(ROOT / "designs" / "haptic_pen.toml"), "inertia")
    by_name = {i.name: i for i in model.instances}
    return by_name[RING], [by_name[p] for p in PINS]


@pytest.fixture(scope="module")
def sheet_before(pen_ring_body, tmp_path_factory) -> bytes:
    """The ring's sheet drawn from the solid as assembled, before any test below meshes or
    intersects it (the reference bytes of both tests: one drawing, not one per test)."""
    return _ring_sheet(pen_ring_body[0].kind, tmp_path_factory.mktemp("ring_before"))


def test_ring_sheet_is_the_same_after_the_check_meshed_and_intersected_it(pen_ring_body,
                                                                          sheet_before, tmp_path):
    from cad.export.shapes import placed
    from cad.massprops.occt import triangulate
    from cad.occ.distance import common_volume_mm3, min_distance_mm
    from cad.occ.shape_io import brep_bytes

    ring, pins = pen_ring_body
    shape = ring.kind.shape
    brep0, tol0 = brep_bytes(shape), _max_tolerances(shape)
    # what the interference check does to the ring on a cold cache: mesh it (prepare), then
    # the exact distance and the common volume with each pin it touches
    triangulate(shape, 0.05, 0.5)
    sa = placed(shape, ring.tf_body_part)
    for pin in pins:
        sb = placed(pin.kind.shape, pin.tf_body_part)
        assert min_distance_mm(sa, sb) == pytest.approx(0.0, abs=1e-6)  # pressed in: touching
        assert common_volume_mm3(sa, sb) < 1e-3  # a press fit at the nominal size: no overlap
    assert _max_tolerances(shape) == tol0
    assert brep_bytes(shape) == brep0
    assert _ring_sheet(ring.kind, tmp_path / "after") == sheet_before


def test_ring_sheet_ignores_a_triangulation_stored_on_the_solid(pen_ring_body, sheet_before,
                                                                tmp_path):
    """A mesh stored on the shared solid itself (BRepMesh in place, coarse) does not reach
    the sheet: the views are the exact hidden-line projection of the B-rep."""
    from OCP.BRepMesh import BRepMesh_IncrementalMesh

    ring, _ = pen_ring_body
    shape = ring.kind.shape
    BRepMesh_IncrementalMesh(shape, 0.5, False, 0.8, False)
    assert _ring_sheet(ring.kind, tmp_path / "after") == sheet_before


def test_common_leaves_its_arguments_and_measures_the_overlap():
    """Two 10 mm cubes offset by (4, 5, 6) mm share a 6 x 5 x 4 box (closed form 120 mm^3);
    the Boolean leaves both cubes' BREP text as it was."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
    from OCP.gp import gp_Pnt

    from cad.occ.distance import common_volume_mm3
    from cad.occ.shape_io import brep_bytes

    a = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(10, 10, 10)).Shape()
    b = BRepPrimAPI_MakeBox(gp_Pnt(4, 5, 6), gp_Pnt(14, 15, 16)).Shape()
    ba, bb = brep_bytes(a), brep_bytes(b)
    assert common_volume_mm3(a, b) == pytest.approx(6 * 5 * 4, rel=1e-12)
    assert (brep_bytes(a), brep_bytes(b)) == (ba, bb)
