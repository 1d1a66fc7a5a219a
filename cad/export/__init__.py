"""Fabrication exports: STEP (fixed header), binary STL (watertight-checked), DXF, BOM, manifest.

CAD libraries are imported inside the functions, never at module import.

* :func:`export_part` -- ``<name>.step``, ``<name>.stl``, ``<name>.dxf`` (plates) of one part,
  each in the part's own frame (the frame a ``tf_body_part`` places it from; the STEP
  with its placements applied to the geometry, :func:`cad.export.shapes.in_own_frame`);
* :func:`export_assembly_step` -- one named, coloured solid per part;
* :func:`write_manifest` -- ``manifest.json`` with sha256 of every file;
* :func:`write_bom` -- ``bom.csv``.

Determinism: the same shape gives byte-identical STL and DXF; STEP is identical too
once its time stamp is fixed and OCCT's process-wide assembly counter renumbered
(see :mod:`cad.export.step`). Every file is written atomically (``cad.io.atomic``).
"""

from __future__ import annotations

from pathlib import Path

from cad.errors import DesignError
from cad.export.bom import BOM_COLUMNS, bom_csv, write_bom
from cad.export.manifest import MANIFEST_NAME, verify_manifest, write_manifest
from cad.io.atomic import write_bytes_atomic, write_text_atomic
from cad.tolerances import STL_ANGULAR_TOLERANCE_RAD, STL_TOLERANCE_MM  # re-exported

FORMATS = ("step", "stl", "dxf")
#: Every format ``--formats`` accepts: the default three plus the simulator models
#: (``mjcf``, ``urdf``: :mod:`cad.export.sim`; they reference the part STL files, so
#: asking for one of them writes the STL files too), glb = the posed assembly (binary
#: glTF, metres, with the stroke animation, :mod:`cad.export.gltf`) and 3mf = the made
#: parts for a slicer (:mod:`cad.export.threemf`) and firmware = the generated C kinematics,
#: test vectors, wall sketch and CHAI3D description (:mod:`cad.firmware`, folder firmware/).
KNOWN_FORMATS = (*FORMATS, "mjcf", "urdf", "glb", "3mf", "firmware", "drawings")

__all__ = [
    "BOM_COLUMNS",
    "FORMATS",
    "KNOWN_FORMATS",
    "MANIFEST_NAME",
    "bom_csv",
    "export_assembly_step",
    "export_part",
    "parse_formats",
    "verify_manifest",
    "write_bom",
    "write_manifest",
]


def parse_formats(text: str | None, field: str = "--formats") -> set[str]:
    """``"step,stl"`` -> ``{"step", "stl"}``; None -> :data:`FORMATS`; unknown names are a
    DesignError."""
    if text is None:
        return set(FORMATS)
    out = {t.strip().lower() for t in text.split(",") if t.strip()}
    bad = sorted(out - set(KNOWN_FORMATS))
    if bad or not out:
        raise DesignError(
            field,
            f"unknown format(s) {', '.join(bad) or repr(text)} (known: {', '.join(KNOWN_FORMATS)})",
        )
    if out & {"mjcf", "urdf"}:
        out.add("stl")  # the simulator models reference the part meshes
    return out


def export_part(
    shape,
    name: str,
    out_dir: Path,
    formats: set[str],
    *,
    plate: bool = False,
    color: tuple[float, float, float] | None = None,
    stl: bool = True,
    tolerance_mm: float = STL_TOLERANCE_MM,
    angular_tolerance_rad: float = STL_ANGULAR_TOLERANCE_RAD,
    notes: tuple[str, ...] = (),
    holes: tuple = (),
    material: str = "",
    quantity: int | None = None,
    stock: str = "",
) -> list[Path]:
    """Write the files of one part and return their paths.

    Every file is in the part's frame: the coordinates of ``shape`` with its location
    applied. The STEP is written from :func:`cad.export.shapes.in_own_frame` (no nested
    placement, which a STEP reader may drop: a tube or bearing whose solid carries a
    location came out in its unplaced frame); the STL mesh and the DXF section apply the
    location themselves.

    Parameters
    ----------
    shape : build123d / cadquery object or OCP ``TopoDS_Shape``, mm.
    name : file stem (``<name>.step`` ...).
    formats : subset of {"step", "stl", "dxf"}.
    plate : write ``<name>.dxf`` (section at mid-thickness) when "dxf" is asked.
    stl : False for bought parts (only STEP is useful for those).
    tolerance_mm, angular_tolerance_rad : absolute STL deflections.
    notes : text lines written on the DXF's ``NOTES`` layer (fits of seats and bores).
    holes, material, quantity, stock : the DXF's shop data (:func:`cad.export.dxf.plate_profile_dxf`:
        reamed bores cut undersize, seats and threads noted; material, quantity and the stock
        of the BOM, :func:`cad.pipeline.family.kind_stock`, noted).

    The STL mesh is checked watertight (two independent checks, see
    :mod:`cad.export.stl`) before anything is written: a failure raises
    :class:`cad.errors.MeshError` and writes no file of this part.
    """
    from cad.export.shapes import in_own_frame, to_topods
    from cad.export.step import step_bytes
    from cad.export.stl import check_watertight, mesh_shape, stl_bytes

    topo = to_topods(shape, name)
    out_dir = Path(out_dir)
    payload: list[tuple[Path, bytes | str]] = []
    if "stl" in formats and stl:
        v, f = mesh_shape(topo, tolerance_mm, angular_tolerance_rad)
        check_watertight(v, f, name)
        payload.append((out_dir / f"{name}.stl", stl_bytes(v, f, name)))
    if "step" in formats:
        payload.append((out_dir / f"{name}.step", _cached_file(
            "part-step", [topo, name, color], lambda: step_bytes(in_own_frame(topo), name, color),
            ("cad.export.step", "cad.export.shapes"))))
    if "dxf" in formats and plate:
        from cad.export.dxf import plate_profile_dxf

        payload.append((out_dir / f"{name}.dxf", _cached_file(
            "part-dxf", [topo, name, list(notes), [repr(h) for h in holes], material, quantity, stock],
            lambda: plate_profile_dxf(topo, name, notes, holes, material=material,
                                      quantity=quantity, stock=stock),
            ("cad.export.dxf", "cad.data.fits"))))
    written = []
    for path, data in payload:
        if isinstance(data, str):
            write_text_atomic(path, data)
        else:
            write_bytes_atomic(path, data)
        written.append(path)
    return written


def export_assembly_step(
    items: list[tuple[str, object, tuple[float, float, float]]], path: Path, name: str | None = None
) -> Path:
    """Assembly STEP at ``path``: one named, coloured solid per ``(name, shape, rgb)`` item.

    Shapes must already be placed in the world frame (mm).
    """
    from cad.export.shapes import to_topods
    from cad.export.step import assembly_step_bytes

    topo_items = [(n, to_topods(s, n), c) for n, s, c in items]
    name = name or Path(path).stem
    data = _cached_file(
        "assembly-step", [name, [list(t) for t in topo_items]],
        lambda: assembly_step_bytes(topo_items, name), ("cad.export.step",))
    return write_bytes_atomic(Path(path), data)


def _cached_file(kind: str, key: list, make, code: tuple[str, ...]):
    """A file's content (bytes or str) through the derived cache (:mod:`cad.io.derived_cache`):
    every ``TopoDS_Shape`` in ``key`` is replaced by its content digest; the content is a
    deterministic function of the key (fixed STEP header, renumbered ids: module docstring)."""
    from OCP.TopoDS import TopoDS_Shape

    from cad.io import derived_cache

    if not derived_cache.enabled():
        return _to_bytes(make())

    def canon(x):
        if isinstance(x, TopoDS_Shape):
            return derived_cache.shape_digest(x)
        if isinstance(x, (list, tuple)):
            return [canon(v) for v in x]
        return x

    return derived_cache.cached_bytes(
        kind, canon(key), lambda: _to_bytes(make()), code=(*code, "cad.export"))


def _to_bytes(data) -> bytes:
    return data.encode() if isinstance(data, str) else data
