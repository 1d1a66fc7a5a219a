"""3MF (3D Manufacturing Format core spec 1.3) of the made parts, ready for a slicer.

One ``<object>`` per made part kind (named by the kind, its mesh in the part frame, mm),
one build ``<item>`` per instance (a part used twice is printed twice), laid out in a row
on the build plate (``GAP_MM`` apart, every part resting on z = 0). Bought parts
(screws, bearings, the motor) are left out: they are not printed.

A minimal writer of the core spec (model part, content types, relationships), zipped with
fixed time stamps so the bytes depend only on the meshes. Every mesh must be closed and
consistently wound (:func:`cad.export.stl.check_watertight` runs first).
Read back in the tests with lib3mf, the 3MF Consortium's reference implementation.
"""

from __future__ import annotations

import io
import zipfile
from xml.sax.saxutils import quoteattr

import numpy as np

from cad.export.stl import check_watertight

GAP_MM = 5.0

#: Decimals of every coordinate written (mm, fixed point): 1e-4 mm steps, so a vertex is
#: within 0.05 um of the mesh at ANY part size (6 significant digits, the old format, were
#: 0.01 mm on a 1 m part; issue 21 §4). Trailing zeros are dropped.
DECIMALS = 4


def _num(x: float) -> str:
    """``x`` (mm) to :data:`DECIMALS` decimals, trailing zeros dropped, never ``-0``."""
    s = f"{x:.{DECIMALS}f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s
_CONTENT_TYPES = (
    '<?xml version="1.0" encoding="UTF-8"?>\n'
    '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
    '<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
    '<Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>'
    "</Types>"
)
_RELS = (
    '<?xml version="1.0" encoding="UTF-8"?>\n'
    '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
    '<Relationship Target="/3D/3dmodel.model" Id="rel0" '
    'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>'
    "</Relationships>"
)


def _mesh_xml(v: np.ndarray, f: np.ndarray) -> str:
    vs = "".join(f'<vertex x="{_num(x)}" y="{_num(y)}" z="{_num(z)}"/>' for x, y, z in v)
    ts = "".join(f'<triangle v1="{a}" v2="{b}" v3="{c}"/>' for a, b, c in f)
    return f"<mesh><vertices>{vs}</vertices><triangles>{ts}</triangles></mesh>"


#: Namespace of the per-object print metadata (``hapticad:print_orientation``,
#: ``hapticad:print_settings``), declared on the model as the core spec asks of custom names.
HAPTICAD_NS = "https://github.com/hapticad/print"
#: Item rotation (3MF row order m00 m01 m02 m10 m11 m12 m20 m21 m22) of a part printed as
#: modelled (part z up) and flipped (180 deg about x: part z down, its top face on the bed).
_ROT = {False: (1, 0, 0, 0, 1, 0, 0, 0, 1), True: (1, 0, 0, 0, -1, 0, 0, 0, -1)}


def _print_meta(p: tuple) -> str:
    """``<metadatagroup>`` of a printed part ``(flip, settings text)``, else ''."""
    flip, text = p
    side = "flipped: part z down (its top face on the bed)" if flip else "as modelled: part z up"
    return ('<metadatagroup><metadata name="hapticad:print_orientation">'
            f'{_esc(side)}</metadata><metadata name="hapticad:print_settings">{_esc(text)}'
            '</metadata></metadatagroup>')


def model_xml(parts: list[tuple[str, np.ndarray, np.ndarray, int]], title: str,
              prints: dict[str, tuple[bool, str]] | None = None) -> str:
    """The ``3D/3dmodel.model`` document of ``[(name, vertices_mm, faces, quantity)]``.

    ``prints``: ``{name: (flip, settings text)}`` of the printed parts: each such item is
    rotated into its print orientation (:data:`_ROT`) and its object carries the
    orientation and settings as metadata. Without it the document is as before.
    """
    prints = prints or {}
    objs, items = [], []
    x = 0.0
    for oid, (name, v, f, qty) in enumerate(parts, start=1):
        v = np.asarray(v, dtype=float)
        p = prints.get(name)
        rot = _ROT[bool(p and p[0])]
        r = v * np.array([1.0, rot[4], rot[8]])
        lo, hi = r.min(axis=0), r.max(axis=0)
        meta = _print_meta(p) if p else ""
        objs.append(
            f'<object id="{oid}" name={quoteattr(name)} type="model">{meta}{_mesh_xml(v, f)}</object>'
        )
        for _ in range(qty):
            tx, ty, tz = x - lo[0], -lo[1], -lo[2]
            items.append(
                f'<item objectid="{oid}" transform="{" ".join(map(str, rot))} {_num(tx)} {_num(ty)} '
                f'{_num(tz)}"/>'
            )
            x += (hi[0] - lo[0]) + GAP_MM
    ns = f' xmlns:hapticad="{HAPTICAD_NS}"' if prints else ""
    return (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<model unit="millimeter" xml:lang="en-US" '
        f'xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02"{ns}>'
        f'<metadata name="Title">{_esc(title)}</metadata>'
        '<metadata name="Application">hapticad</metadata>'
        f"<resources>{''.join(objs)}</resources><build>{''.join(items)}</build></model>"
    )


def _esc(s: str) -> str:
    return quoteattr(s)[1:-1]


def threemf_bytes(parts: list[tuple[str, np.ndarray, np.ndarray, int]], title: str,
                  prints: dict[str, tuple[bool, str]] | None = None) -> bytes:
    """A ``.3mf`` package (zip) of ``[(name, vertices_mm, faces, quantity)]`` (``prints``:
    :func:`model_xml`)."""
    for name, v, f, _ in parts:
        check_watertight(v, f, name)
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        for arc, text in (
            ("[Content_Types].xml", _CONTENT_TYPES),
            ("_rels/.rels", _RELS),
            ("3D/3dmodel.model", model_xml(parts, title, prints)),
        ):
            info = zipfile.ZipInfo(arc, date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info, text)
    return buf.getvalue()


def printable_parts(instances, meshes: dict) -> list[tuple[str, np.ndarray, np.ndarray, int]]:
    """``[(kind name, vertices_mm, faces, quantity)]`` of the made, listed parts of an assembly."""
    qty: dict[str, int] = {}
    for inst in instances:
        if inst.kind.made and inst.kind.listed:
            qty[inst.kind.name] = qty.get(inst.kind.name, 0) + 1
    return [(n, *meshes[n], q) for n, q in qty.items()]


def print_orientations(instances) -> dict[str, tuple[bool, str]]:
    """``{kind name: (flip, print settings text)}`` of the printed made parts (``print_flip``
    not None, set by :func:`cad.assembly.printed.as_printed`)."""
    out = {}
    for inst in instances:
        k = inst.kind
        if k.made and k.listed and getattr(k, "print_flip", None) is not None:
            out[k.name] = (k.print_flip, k.process.split(";")[0])
    return out
