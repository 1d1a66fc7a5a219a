"""STEP export with a fixed header so that the same model gives the same bytes.

What the format forces and how it is handled (measured with OCCT 7.9.3 / build123d 0.12):

* ``FILE_NAME`` carries a time stamp: we write the fixed :data:`STEP_TIMESTAMP`
  and the part name (never the temporary path used for the atomic write: the file is
  written to memory first).
* ``NEXT_ASSEMBLY_USAGE_OCCURRENCE`` ids of an assembly come from a counter that
  OCCT keeps for the whole process, so a second export in the same process numbers
  them differently. They are set to 1, 2, ... in file order in the STEP model before it is
  written (:func:`_number_nauo`): renumbering the text afterwards kept the line wrapping of
  the counter's wider id, so the pantograph's ``assembly.step`` depended on how many STEP
  files the process had written before -- i.e. on what the cache held (issue 22 §6).
  :func:`_normalise_nauo` stays as a check of the same order on the text.

* the colour styles of an assembly (one ``MECHANICAL_DESIGN_GEOMETRIC_PRESENTATION_REPRESENTATION``
  block per part at the end of the file) come out in an order that changes from run to
  run (OCCT iterates a map keyed by memory addresses), and a colour shared by two parts
  is defined in whichever block comes first; :func:`_canonical_styles` renumbers that
  tail canonically (blocks sorted by the part they style, entities numbered depth-first).

With these, a part or an assembly STEP is byte-identical run to run (tests/unit/export/test_export.py).
"""

from __future__ import annotations

import io
import re

from cad.export.shapes import count_solids

#: Fixed ISO 8601 time stamp written in every STEP header.
STEP_TIMESTAMP = "2000-01-01T00:00:00"

_NAUO = re.compile(rb"NEXT_ASSEMBLY_USAGE_OCCURRENCE\('(\d+)'")


def _normalise_nauo(data: bytes) -> bytes:
    counter = iter(range(1, 1 << 30))
    return _NAUO.sub(lambda m: b"NEXT_ASSEMBLY_USAGE_OCCURRENCE('%d'" % next(counter), data)


_REF = re.compile(rb"#(\d+)")
_MDGPR = b"MECHANICAL_DESIGN_GEOMETRIC_PRESENTATION_REPRESENTATION"


def _canonical_styles(data: bytes) -> bytes:
    """Renumber the presentation (colour) tail of a STEP file canonically (module docstring)."""
    first = data.find(_MDGPR)
    if first < 0:
        return data
    # the tail starts at the line of the first MDGPR entity and ends at ENDSEC
    line_start = data.rfind(b"\n", 0, first) + 1
    end = data.find(b"ENDSEC;", first)
    head, tail, rest = data[:line_start], data[line_start:end], data[end:]
    ents: dict[int, bytes] = {}
    order: list[int] = []
    matched = 0
    for m in re.finditer(rb"#(\d+) = (.*?);\n", tail, re.S):
        ents[int(m.group(1))] = m.group(2)
        order.append(int(m.group(1)))
        matched += len(m.group(0))
    if not order or matched != len(tail):
        return data  # not the layout this canonicalisation understands: leave the file as it is
    roots = [k for k in order if ents[k].startswith(_MDGPR)]

    def root_key(k: int):
        outside = [int(r) for r in _REF.findall(ents[k]) if int(r) not in ents]
        return (outside, k)

    new_id: dict[int, int] = {}
    nxt = min(order)

    def visit(k: int) -> None:
        nonlocal nxt
        stack = [k]
        while stack:
            e = stack.pop()
            if e in new_id:
                continue
            new_id[e] = nxt
            nxt += 1
            refs = [
                int(r) for r in _REF.findall(ents[e]) if int(r) in ents and int(r) not in new_id
            ]
            stack.extend(reversed(refs))

    for r in sorted(roots, key=root_key):
        visit(r)
    for k in order:
        if k not in new_id:
            visit(k)
    out = []
    for k in sorted(ents, key=lambda e: new_id[e]):
        body = _REF.sub(lambda m: b"#%d" % new_id.get(int(m.group(1)), int(m.group(1))), ents[k])
        out.append(b"#%d = %s;\n" % (new_id[k], body))
    return head + b"".join(out) + rest


def labelled_shape(shape, name: str, color):
    """A build123d Solid/Compound wrapping ``shape`` with a label (and colour)."""
    from build123d import Color, Compound, Solid
    from OCP.TopAbs import TopAbs_SOLID


    if shape.ShapeType() == TopAbs_SOLID:
        obj = Solid(shape)
    elif count_solids(shape) == 1:
        from OCP.TopExp import TopExp_Explorer
        from OCP.TopoDS import TopoDS

        obj = Solid(TopoDS.Solid_s(TopExp_Explorer(shape, TopAbs_SOLID).Current()))
    else:
        obj = Compound(shape)
    obj.label = name
    if color is not None:
        obj.color = Color(*(float(c) for c in color))
    return obj


def _number_nauo(model) -> None:
    """Set the id of every ``NEXT_ASSEMBLY_USAGE_OCCURRENCE`` of the STEP ``model`` to 1, 2,
    ... in entity (= file) order, before writing: the text and its line wrapping are then
    the same whatever OCCT's process-wide counter held."""
    from OCP.TCollection import TCollection_HAsciiString

    k = 0
    for i in range(1, model.NbEntities() + 1):
        ent = model.Value(i)
        if ent.DynamicType().Name() == "StepRepr_NextAssemblyUsageOccurrence":
            k += 1
            ent.SetId(TCollection_HAsciiString(str(k)))


def _write_doc(doc, name: str | None, system: str, *, part: bool) -> bytes:
    """An XCAF ``doc`` as AP214 STEP bytes with the fixed header; ``part``: build123d's
    ``export_step`` settings (layers, precision mode, IGES controller), else the assembly's."""
    from OCP.APIHeaderSection import APIHeaderSection_MakeHeader
    from OCP.IFSelect import IFSelect_ReturnStatus
    from OCP.IGESControl import IGESControl_Controller
    from OCP.Interface import Interface_Static
    from OCP.Message import Message, Message_Gravity
    from OCP.STEPCAFControl import STEPCAFControl_Controller, STEPCAFControl_Writer
    from OCP.STEPControl import STEPControl_Controller, STEPControl_StepModelType
    from OCP.TCollection import TCollection_HAsciiString
    from OCP.XSControl import XSControl_WorkSession

    for printer in Message.DefaultMessenger_s().Printers():
        printer.SetTraceLevel(Message_Gravity.Message_Fail)
    writer = STEPCAFControl_Writer(XSControl_WorkSession(), False)
    writer.SetColorMode(True)
    if part:
        writer.SetLayerMode(True)
    writer.SetNameMode(True)
    header = APIHeaderSection_MakeHeader(writer.Writer().Model())
    if not header.IsDone():
        header = APIHeaderSection_MakeHeader(0)
        header.Apply(writer.Writer().Model())
    if name:
        header.SetName(TCollection_HAsciiString(name))
    header.SetTimeStamp(TCollection_HAsciiString(STEP_TIMESTAMP))
    header.SetOriginatingSystem(TCollection_HAsciiString(system))
    STEPCAFControl_Controller.Init_s()
    STEPControl_Controller.Init_s()
    if part:
        IGESControl_Controller.Init_s()
    Interface_Static.SetIVal_s("write.surfacecurve.mode", 1)
    if part:
        from build123d.build_enums import PrecisionMode

        Interface_Static.SetIVal_s("write.precision.mode", PrecisionMode.AVERAGE.value)
    writer.Transfer(doc, STEPControl_StepModelType.STEPControl_AsIs)
    _number_nauo(writer.Writer().Model())
    buf = io.BytesIO()
    if writer.WriteStream(buf) != IFSelect_ReturnStatus.IFSelect_RetDone:
        raise OSError("OCCT failed to write the STEP file")
    return _normalise_nauo(buf.getvalue())


def _write(obj) -> bytes:
    """``obj`` (a labelled build123d shape) as build123d's ``export_step`` writes it (its XCAF
    document, its writer settings), with the fixed header and canonical NAUO ids."""
    from build123d.build_enums import Unit
    from build123d.exporters3d import _create_xde  # the document export_step writes

    return _write_doc(_create_xde(obj, Unit.MM, auto_naming=True), obj.label, "build123d", part=True)


def step_bytes(shape, name: str, color: tuple[float, float, float] | None = None) -> bytes:
    """STEP (AP214, mm) of one part as bytes; ``shape`` is a ``TopoDS_Shape``."""
    return _write(labelled_shape(shape, name, color))


def assembly_step_bytes(items, name: str) -> bytes:
    """STEP of an assembly: one named, coloured solid per item.

    ``items`` : sequence of ``(part_name, TopoDS_Shape placed in the world, rgb 0..1)``.

    Written through an XCAF document built here rather than build123d's exporter: each
    item becomes its own product (name and colour) placed once in the assembly. (Through
    build123d, instances of one part -- identical geometry -- end up as one product named
    after the last instance.)
    """
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Copy
    from OCP.Quantity import Quantity_Color, Quantity_TOC_sRGB
    from OCP.TCollection import TCollection_ExtendedString
    from OCP.TDataStd import TDataStd_Name
    from OCP.TDocStd import TDocStd_Document
    from OCP.TopLoc import TopLoc_Location
    from OCP.XCAFApp import XCAFApp_Application
    from OCP.XCAFDoc import XCAFDoc_ColorType, XCAFDoc_DocumentTool

    doc = TDocStd_Document(TCollection_ExtendedString("XmlOcaf"))
    app = XCAFApp_Application.GetApplication_s()
    app.NewDocument(TCollection_ExtendedString("MDTV-XCAF"), doc)
    app.InitDocument(doc)
    XCAFDoc_DocumentTool.SetLengthUnit_s(doc, 0.001)
    shapes = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    colors = XCAFDoc_DocumentTool.ColorTool_s(doc.Main())
    shapes.SetAutoNaming_s(False)
    asm = shapes.NewShape()
    TDataStd_Name.Set_s(asm, TCollection_ExtendedString(name))
    for pname, shape, rgb in items:
        loc = shape.Location()
        # a fresh copy: XCAF merges parts that share their underlying shape
        part = shapes.AddShape(
            BRepBuilderAPI_Copy(shape.Located(TopLoc_Location()), True, False).Shape(), False, False
        )
        TDataStd_Name.Set_s(part, TCollection_ExtendedString(pname))
        if rgb is not None:
            colors.SetColor(
                part,
                Quantity_Color(*(float(c) for c in rgb), Quantity_TOC_sRGB),
                XCAFDoc_ColorType.XCAFDoc_ColorGen,
            )
        comp = shapes.AddComponent(asm, part, loc)
        TDataStd_Name.Set_s(comp, TCollection_ExtendedString(pname))
    shapes.UpdateAssemblies()
    return _canonical_styles(_write_doc(doc, name, "hapticad", part=False))
